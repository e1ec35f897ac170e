#pragma once
// Reading TOML scene files (toml++): the file's text with a size bound, the place and the text
// of a key or value as written, and TableReader, which reads one table's keys with their types
// and ranges and refuses anything unknown, naming file, line, key and value. Also the tables both
// scene kinds share: the edge conditions, supports, point loads, steps and watch point
// (core/edge_loads.hpp). Used by scene_toml.cpp (the cell scene) and structure_scene_toml.cpp.
#include <toml++/toml.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/edge_loads.hpp"
#include "core/error.hpp"
#include "core/scene.hpp"
#include "core/text.hpp"

namespace dualcell::reading {

// Largest scene or material file read: a bound on what /dev/zero or a mistaken path can cost.
inline constexpr std::size_t max_file_bytes = 16u << 20;
// What toml++ reads in place of every non-ASCII code point (U+FFFD; scene_toml.cpp's for_toml).
inline constexpr std::string_view replacement = "\xEF\xBF\xBD";

// The whole file, refused beyond max_file_bytes or when it is a directory ("<file>: ...").
std::string read_text(const std::filesystem::path& file, const std::string& what);
// The source text of `region` as written (toml++ read a copy with non-ASCII replaced).
std::string original_text(const toml::source_region& region, const std::vector<std::string>& lines);
// A key as written, for messages.
std::string key_text(const toml::key& key, const std::vector<std::string>& lines);
// A value as written, for messages.
std::string show(const toml::node& node, const std::vector<std::string>& lines);
std::vector<std::string> split_lines(std::string_view text);
// The parsed table, or an InputError "<file>:<line>:<column>: TOML syntax error: ...".
toml::table parse_toml(std::string_view text, const std::string& file);
// root[name] when it is a table, nullptr when absent; an InputError when it is something else.
const toml::table* sub_table(const toml::table& root, std::string_view name, const std::string& file);

// Reads the keys of one table, checking types and ranges, and remembers which keys it used so
// that finish() can reject anything unknown.
class TableReader {
 public:
  TableReader(const toml::table* table, std::string name, std::string file, const std::vector<std::string>& lines,
              std::map<std::string, WrittenKey>* written = nullptr)
      : table_(table), name_(std::move(name)), file_(std::move(file)), lines_(lines), written_(written) {}

  bool present() const { return table_ != nullptr; }
  const std::string& name() const { return name_; }
  bool has(std::string_view key) const { return table_ && table_->contains(key); }

  [[noreturn]] void fail(const toml::node* node, std::string_view key, const std::string& value,
                         const std::string& why) const {
    std::ostringstream s;
    s << file_;
    if (node && node->source().begin.line > 0)
      s << ':' << node->source().begin.line << ':' << node->source().begin.column;
    s << ": [" << name_ << "] " << clipped(std::string(key));
    if (!value.empty()) s << " = " << clipped(value);
    s << ": " << why;
    throw InputError(s.str());
  }

  const toml::node* node(std::string_view key) {
    used_.insert(std::string(key));
    return table_ ? table_->get(key) : nullptr;
  }

  // Where a key was written and its value as written, for validate()'s messages.
  void remember(std::string_view key, const toml::node& n) {
    if (!written_) return;
    std::ostringstream at;
    at << file_;
    if (n.source().begin.line > 0) at << ':' << n.source().begin.line << ':' << n.source().begin.column;
    (*written_)[name_ + "." + std::string(key)] = {at.str(), show(n, lines_)};
  }

  // A real number (integers accepted); its range is validate()'s business.
  double real(std::string_view key, double fallback, bool required = false, const std::string& what = "") {
    const toml::node* n = node(key);
    if (!n) {
      if (required) fail(nullptr, key, "", "missing; required, " + what);
      return fallback;
    }
    remember(key, *n);
    if (auto i = n->as_integer()) return static_cast<double>(i->get());
    if (auto f = n->as_floating_point()) return f->get();
    fail(n, key, show(*n, lines_), "must be a number");
  }

  // An integer, saturated to the range of `T` (validate() then refuses it, quoting it as written).
  template <typename T>
  T integer(std::string_view key, T fallback) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    remember(key, *n);
    auto i = n->as_integer();
    if (!i) fail(n, key, show(*n, lines_), "must be an integer");
    return static_cast<T>(
        std::clamp<std::int64_t>(i->get(), std::numeric_limits<T>::min(), std::numeric_limits<T>::max()));
  }

  // An array of numbers (integers accepted) of a size in [min_size, max_size].
  std::vector<double> reals(std::string_view key, std::vector<double> fallback, std::size_t min_size,
                            std::size_t max_size) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    remember(key, *n);
    auto a = n->as_array();
    const std::string what = "an array of " +
                             (min_size == max_size ? std::to_string(min_size)
                              : min_size == 0      ? "at most " + std::to_string(max_size)
                                                   : std::to_string(min_size) + " to " + std::to_string(max_size)) +
                             " numbers";
    if (!a || a->size() < min_size || a->size() > max_size) fail(n, key, show(*n, lines_), "must be " + what);
    std::vector<double> v;
    for (const toml::node& e : *a) {
      if (auto i = e.as_integer())
        v.push_back(static_cast<double>(i->get()));
      else if (auto f = e.as_floating_point())
        v.push_back(f->get());
      else
        fail(n, key, show(*n, lines_), "must be " + what);
    }
    return v;
  }

  // An array of N-arrays of numbers; `what` names them in the message.
  template <std::size_t N>
  std::vector<std::array<double, N>> tuples(std::string_view key, const std::string& what) {
    const toml::node* n = node(key);
    std::vector<std::array<double, N>> out;
    if (!n) return out;
    remember(key, *n);
    auto a = n->as_array();
    if (!a) fail(n, key, show(*n, lines_), "must be " + what);
    for (const toml::node& e : *a) {
      auto t = e.as_array();
      if (!t || t->size() != N) fail(n, key, show(*n, lines_), "must be " + what);
      std::array<double, N> v{};
      for (std::size_t i = 0; i < N; ++i) {
        const toml::node& x = *t->get(i);
        if (auto iv = x.as_integer())
          v[i] = static_cast<double>(iv->get());
        else if (auto fv = x.as_floating_point())
          v[i] = fv->get();
        else
          fail(n, key, show(*n, lines_), "must be " + what);
      }
      out.push_back(v);
    }
    return out;
  }

  // An array of 3-arrays of numbers (stress tensors).
  std::vector<std::array<double, 3>> triples(std::string_view key) {
    return tuples<3>(key, "an array of [sxx, syy, sxy] stress tensors, each finite and not all zero");
  }

  std::string string(std::string_view key, std::string fallback, const std::vector<std::string>& allowed = {}) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    auto s = n->as_string();
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
    if (!s) fail(n, key, show(*n, lines_), allowed.empty() ? "must be a string" : "must be one of " + list);
    remember(key, *n);
    std::string v = s->get();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end())
      fail(n, key, show(*n, lines_), "must be one of " + list);
    return v;
  }

  void finish() const {
    if (!table_) return;
    for (const auto& [key, value] : *table_) {
      if (!used_.count(std::string(key.str()))) {
        std::string allowed;
        for (const auto& u : used_) allowed += (allowed.empty() ? "" : ", ") + u;
        fail(&value, key_text(key, lines_), show(value, lines_), "unknown key; allowed keys: " + allowed);
      }
    }
  }

 private:
  const toml::table* table_;
  std::string name_;
  std::string file_;
  const std::vector<std::string>& lines_;
  std::set<std::string> used_;
  std::map<std::string, WrittenKey>* written_;
};

// A point [x, y] that must be finite.
Eigen::Vector2d point(TableReader& t, std::string_view key, bool required, const std::string& what);

// The tables of an array of tables `name` ([[name]]), each read by `read`.
template <typename Read>
void each_table(const toml::table& root, std::string_view name, const std::string& file,
                const std::vector<std::string>& lines, Read read) {
  const toml::node* n = root.get(name);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    throw InputError(file + ":" + std::to_string(n->source().begin.line) + ": [[" + std::string(name) +
                     "]] must be an array of tables");
  for (std::size_t k = 0; k < a->size(); ++k) {
    TableReader t(a->get(k)->as_table(), std::string(name) + " " + std::to_string(k + 1), file, lines);
    read(t);
    t.finish();
  }
}

// The tables of core/edge_loads.hpp, shared by structure.toml and scene.toml with boundary =
// "edges": their names, their reading, and the check that something holds and something loads.
extern const std::vector<std::string> edge_load_tables;
EdgeLoads read_edge_loads(const toml::table& root, const std::string& fname, const std::vector<std::string>& lines);
void check_held_and_loaded(const EdgeLoads& loads, const std::string& fname, const std::string& what);

}  // namespace dualcell::reading
