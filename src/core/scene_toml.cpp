// Reading a scene file (TOML, toml++): syntax, tables, keys and types, with the place and the
// text of every key remembered for validate()'s messages (core/scene.hpp).
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/scene.hpp"
#include "core/structure_scene.hpp"
#include "core/text.hpp"

namespace dualcell {

namespace {

// Largest scene or material file read: a bound on what /dev/zero or a mistaken path can cost.
constexpr std::size_t max_file_bytes = 16u << 20;

std::string read_text(const std::filesystem::path& file, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw InputError(file.string() + ": is a directory, not a " + what + " file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open " + what + " file");
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_file_bytes) throw InputError(file.string() + ": larger than 16 MiB, not a " + what + " file");
  }
  if (in.bad()) throw InputError(file.string() + ": cannot read " + what + " file");
  return text;
}

// Byte offset in `line` of 1-based `column`, which toml++ counts in code points (UTF-8).
std::size_t byte_of_column(const std::string& line, std::size_t column) {
  std::size_t byte = 0;
  for (std::size_t c = 1; c < column && byte < line.size(); ++c) {
    ++byte;
    while (byte < line.size() && (static_cast<unsigned char>(line[byte]) & 0xC0) == 0x80) ++byte;
  }
  return byte;
}

// toml++ 3.3 (Debian's) reaches __builtin_unreachable(), undefined behaviour, when its whitespace
// lookup meets some non-ASCII code points outside a value string: `rädius = 1`, a quoted key "ν",
// U+00A1..U+0499 among others (found by tests/fuzz/scene_fuzz.cpp; marzer/tomlplusplus#190 and
// #295, fixed upstream by PR #305). Scenes need non-ASCII text only in comments and in the
// material path, so toml++ reads a copy with every non-ASCII code point replaced by U+FFFD: one
// code point for one, so its line:column still point into the original text, from which the
// material path, the keys in messages and the character a syntax error names are read back
// (original_text, key_text, parse_toml). Invalid
// UTF-8 is left for toml++ to refuse; a leading byte order mark is kept.
constexpr std::string_view replacement = "\xEF\xBF\xBD";

std::string for_toml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  out += text.substr(0, i);
  while (i < text.size()) {
    const auto lead = static_cast<unsigned char>(text[i]);
    const std::size_t n = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 1;
    char32_t cp = n == 4 ? lead & 0x07u : n == 3 ? lead & 0x0Fu : lead & 0x1Fu;
    bool valid = n > 1 && lead < 0xF8 && i + n <= text.size();
    for (std::size_t k = 1; valid && k < n; ++k) {
      const auto b = static_cast<unsigned char>(text[i + k]);
      valid = (b & 0xC0) == 0x80;
      cp = (cp << 6) | (b & 0x3Fu);
    }
    valid = valid &&
            cp >= (n == 2   ? 0x80u
                   : n == 3 ? 0x800u
                            : 0x10000u) &&
            cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
    if (valid) {
      out += replacement;
      i += n;
    } else {
      out += text[i++];  // ASCII, or a byte toml++ refuses as invalid UTF-8
    }
  }
  return out;
}

// The text of `region` (one line) in the original `lines`, or empty.
std::string original_text(const toml::source_region& region, const std::vector<std::string>& lines) {
  if (region.begin.line == 0 || region.begin.line != region.end.line || region.begin.line > lines.size()) return {};
  const std::string& line = lines[region.begin.line - 1];
  const std::size_t begin = byte_of_column(line, region.begin.column), end = byte_of_column(line, region.end.column);
  return end > begin && end <= line.size() ? line.substr(begin, end - begin) : std::string{};
}

// A key for messages: as toml++ read it, or as written where for_toml replaced characters.
std::string key_text(const toml::key& key, const std::vector<std::string>& lines) {
  const std::string k(key.str());
  if (k.find(replacement) == std::string::npos) return k;
  const std::string written = original_text(key.source(), lines);
  return written.empty() ? k : written;
}

// The value as the user wrote it (from the source text), so messages quote "0.7", not
// "0.69999999999999996"; falls back to toml++'s printing for values spanning lines.
std::string show(const toml::node& node, const std::vector<std::string>& lines) {
  const auto& region = node.source();
  if (region.begin.line > 0 && region.begin.line == region.end.line && region.begin.line <= lines.size() &&
      region.end.column > region.begin.column) {
    const std::string& line = lines[region.begin.line - 1];
    const std::size_t begin = byte_of_column(line, region.begin.column), end = byte_of_column(line, region.end.column);
    if (end <= line.size() && end > begin) return clipped(line.substr(begin, end - begin));
  }
  std::ostringstream s;
  node.visit([&](const auto& value) { s << value; });
  return clipped(s.str());
}

std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in{std::string(text)};
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

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
    const std::string what =
        "an array of " + (min_size == max_size ? std::to_string(min_size) : "at least " + std::to_string(min_size)) +
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

  // An array of 3-arrays of numbers.
  std::vector<std::array<double, 3>> triples(std::string_view key) {
    const toml::node* n = node(key);
    std::vector<std::array<double, 3>> out;
    if (!n) return out;
    remember(key, *n);
    const std::string what = "an array of [sxx, syy, sxy] stress tensors, each finite and not all zero";
    auto a = n->as_array();
    if (!a) fail(n, key, show(*n, lines_), "must be " + what);
    for (const toml::node& e : *a) {
      auto t = e.as_array();
      if (!t || t->size() != 3) fail(n, key, show(*n, lines_), "must be " + what);
      std::array<double, 3> v{};
      for (std::size_t i = 0; i < 3; ++i) {
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

Material read_material(TableReader& t) {
  Material m;
  m.E = t.real("E", 0, true, "E > 0");
  m.nu = t.real("nu", 0, true, "-1 < nu < 0.5");
  t.finish();
  return m;
}

toml::table parse_toml(std::string_view text, const std::string& file) {
  try {
    return toml::parse(for_toml(text), file);
  } catch (const toml::parse_error& e) {
    std::string what(e.description());
    const std::size_t at = what.find(replacement);
    if (at != std::string::npos) {  // "saw '\uFFFD'": the character as written (see for_toml)
      toml::source_region one = e.source();
      one.end = {one.begin.line, one.begin.column + 1};
      const std::string written = original_text(one, split_lines(text));
      if (!written.empty()) what.replace(at, replacement.size(), written);
    }
    std::ostringstream s;
    s << file << ':' << e.source().begin.line << ':' << e.source().begin.column << ": TOML syntax error: " << what;
    throw InputError(s.str());
  }
}

const toml::table* sub_table(const toml::table& root, std::string_view name, const std::string& file) {
  const toml::node* n = root.get(name);
  if (!n) return nullptr;
  if (!n->is_table())
    throw InputError(file + ":" + std::to_string(n->source().begin.line) + ": [" + std::string(name) +
                     "] must be a table");
  return n->as_table();
}

// A point [x, y] that must be finite.
Eigen::Vector2d point(TableReader& t, std::string_view key, bool required, const std::string& what) {
  if (required && !t.has(key)) t.fail(nullptr, key, "", "missing; required, " + what);
  const auto v = t.reals(key, {0, 0}, 2, 2);
  if (!std::isfinite(v[0]) || !std::isfinite(v[1])) t.fail(t.node(key), key, "", "must be finite");
  return {v[0], v[1]};
}

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

// The edge conditions, supports, point loads, steps and output tables (core/edge_loads.hpp),
// shared by structure.toml and scene.toml with boundary = "edges".
const std::vector<std::string> edge_load_tables{"edges", "support", "point_load", "steps", "output"};

EdgeLoads read_edge_loads(const toml::table& root, const std::string& fname, const std::vector<std::string>& lines) {
  EdgeLoads loads;
  const toml::table* edges = sub_table(root, "edges", fname);
  if (edges)
    for (const auto& [key, value] : *edges) {
      const std::string k(key.str());
      if (std::find(edge_names.begin(), edge_names.end(), k) == edge_names.end() || !value.is_table())
        throw InputError(fname + ":" + std::to_string(value.source().begin.line) + ": [edges] " + key_text(key, lines) +
                         ": unknown edge; allowed: [edges.left], [edges.right], [edges.bottom], [edges.top]");
    }
  for (std::size_t e = 0; e < edge_names.size(); ++e) {
    const std::string name = std::string("edges.") + edge_names[e];
    TableReader t(edges ? sub_table(*edges, edge_names[e], fname) : nullptr, name, fname, lines);
    if (!t.present()) continue;
    EdgeCondition& c = loads.edges[e];
    const std::string type = t.string("type", "free", {"free", "fixed", "roller", "displacement", "traction"});
    c.kind = type == "fixed"          ? EdgeKind::fixed
             : type == "roller"       ? EdgeKind::roller
             : type == "displacement" ? EdgeKind::displacement
             : type == "traction"     ? EdgeKind::traction
                                      : EdgeKind::free;
    if (c.kind == EdgeKind::displacement) {
      if (!t.has("ux") && !t.has("uy"))
        t.fail(nullptr, "ux", "", "missing; type = \"displacement\" needs ux, uy or both (finite)");
      for (int k = 0; k < 2; ++k) {
        const char* key = k == 0 ? "ux" : "uy";
        if (!t.has(key)) continue;
        c.displacement(k) = t.real(key, 0);
        if (!std::isfinite(c.displacement(k))) t.fail(t.node(key), key, "", "must be finite");
      }
    }
    if (c.kind == EdgeKind::traction) {
      c.traction_start = point(t, "traction", true, "[tx, ty] at the edge's start (bottom or left end)");
      c.traction_end = t.has("traction_end") ? point(t, "traction_end", false, "") : c.traction_start;
    }
    t.finish();
  }
  // "<file>:<line>: [[name]] k" of the table a support or point load was written in.
  const auto where = [&](TableReader& t, const char* name) {
    return fname + ":" + std::to_string(t.node("at")->source().begin.line) + ": [[" + name + "]] " +
           t.name().substr(t.name().rfind(' ') + 1);
  };
  each_table(root, "support", fname, lines, [&](TableReader& t) {
    Support s;
    s.at = point(t, "at", true, "[x, y] of a node");
    s.where = where(t, "support");
    const std::string fix = t.string("fix", "xy", {"x", "y", "xy"});
    s.fix_x = fix.find('x') != std::string::npos;
    s.fix_y = fix.find('y') != std::string::npos;
    loads.supports.push_back(s);
  });
  each_table(root, "point_load", fname, lines, [&](TableReader& t) {
    PointLoad p;
    p.at = point(t, "at", true, "[x, y] of a node");
    p.force = point(t, "force", true, "[fx, fy]");
    p.where = where(t, "point_load");
    loads.point_loads.push_back(p);
  });
  TableReader steps(sub_table(root, "steps", fname), "steps", fname, lines);
  if (steps.present()) {
    loads.factors = steps.reals("factors", {1.0}, 1, 100000);
    for (double f : loads.factors)
      if (!std::isfinite(f)) steps.fail(steps.node("factors"), "factors", "", "must be finite numbers");
    steps.finish();
  }
  TableReader output(sub_table(root, "output", fname), "output", fname, lines);
  if (output.present()) {
    loads.watch = point(output, "watch", false, "");
    if (output.has("watch"))
      loads.watch_where = fname + ":" + std::to_string(output.node("watch")->source().begin.line) + ": [output] watch";
    output.finish();
  }
  return loads;
}

// Something must hold the structure and something must load it.
void check_held_and_loaded(const EdgeLoads& loads, const std::string& fname, const std::string& what) {
  bool held = !loads.supports.empty(), loaded = !loads.point_loads.empty();
  for (const auto& c : loads.edges) {
    held = held || c.kind == EdgeKind::fixed || c.kind == EdgeKind::roller || c.kind == EdgeKind::displacement;
    loaded = loaded || c.kind == EdgeKind::traction || c.kind == EdgeKind::displacement;
  }
  if (!held)
    throw InputError(fname + ": nothing holds " + what +
                     ": give an edge fixed, roller or displacement, or a [[support]]");
  if (!loaded)
    throw InputError(fname + ": nothing loads " + what +
                     ": give an edge traction or displacement, or a [[point_load]]");
}

}  // namespace

Scene parse_scene(std::string_view text, const std::filesystem::path& file) {
  const std::string fname = file.string();
  Scene scene;
  scene.file = file;
  scene.text = std::string(text);
  const toml::table root = parse_toml(text, fname);

  const std::vector<std::string> tables{"geometry", "fibre", "matrix", "interface", "load", "sweep", "solver"};
  const std::vector<std::string> lines = split_lines(text);
  TableReader top(&root, "top level", fname, lines);
  std::string material = top.string("material", "");
  if (material.find(replacement) != std::string::npos) {
    // A path with non-ASCII characters: decode the string as written (toml++ parses a value
    // string without the faulty lookup).
    const std::string written = original_text(root.get("material")->source(), lines);
    try {
      material = toml::parse("v = " + written + "\n")["v"].value_or(std::string());
    } catch (const toml::parse_error&) {
      material.clear();
    }
    if (material.empty())
      top.fail(root.get("material"), "material", written, "a path with non-ASCII characters must be one line");
  }
  for (const auto& [key, value] : root) {
    const std::string k(key.str());
    if (k == "material") continue;
    if (std::find(edge_load_tables.begin(), edge_load_tables.end(), k) != edge_load_tables.end()) continue;
    if (std::find(tables.begin(), tables.end(), k) == tables.end())
      top.fail(&value, key_text(key, lines), "",
               "unknown table or key; allowed: material, [geometry], [fibre], "
               "[matrix], [interface], [load], [sweep], [solver], and with [load] boundary = \"edges\" "
               "[edges.left|right|bottom|top], [[support]], [[point_load]], [steps], [output]");
  }

  // [geometry]
  TableReader g(sub_table(root, "geometry", fname), "geometry", fname, lines, &scene.written);
  if (!g.present()) throw InputError(fname + ": missing table [geometry]");
  Geometry& geo = scene.geometry;
  // Integers stored as int: a non-integral or huge value becomes 0, which validate() refuses
  // (quoting the value as written).
  const auto as_count = [](double v) { return v >= 1 && v <= 1e9 && v == std::floor(v) ? static_cast<int>(v) : 0; };
  const auto cells = g.reals("cells", {1, 1}, 2, 2);
  geo.cells = {as_count(cells[0]), as_count(cells[1])};
  geo.cell_size = g.real("cell_size", 1.0);
  geo.fibre_radius = g.real("fibre_radius", 0, true, "fibre_radius > 0");
  const auto off = g.reals("fibre_offset", {0, 0}, 2, 2);
  geo.fibre_offset = {off[0], off[1]};
  geo.degree = g.integer<int>("degree", 1);
  geo.element = g.string("element", "p2", {"p1", "p2"}) == "p1" ? Element::p1 : Element::p2;
  g.finish();

  // Materials: inline [fibre]/[matrix] tables, or `material = "file"` holding them.
  const toml::table* fibre_table = sub_table(root, "fibre", fname);
  const toml::table* matrix_table = sub_table(root, "matrix", fname);
  toml::table material_root;
  std::string material_name = fname;
  if (!material.empty()) {
    if (fibre_table || matrix_table)
      top.fail(root.get("material"), "material", "\"" + material + "\"",
               "give either `material = \"file\"` or the [fibre] and [matrix] tables, not both");
    std::filesystem::path mpath(material);
    if (mpath.is_relative()) mpath = file.parent_path() / mpath;
    std::error_code ec;  // e.g. a name too long for the file system: a message, not an exception
    const std::filesystem::file_status status = std::filesystem::status(mpath, ec);
    if (!std::filesystem::exists(status))
      top.fail(root.get("material"), "material", "\"" + material + "\"",
               ec && ec != std::errc::no_such_file_or_directory
                   ? "cannot access material file (" + ec.message() + "): " + mpath.string()
                   : "material file not found: " + mpath.string());
    if (std::filesystem::is_directory(status))
      top.fail(root.get("material"), "material", "\"" + material + "\"", mpath.string() + " is a directory");
    if (!std::filesystem::is_regular_file(status))
      top.fail(root.get("material"), "material", "\"" + material + "\"", mpath.string() + " is not a regular file");
    scene.material_file = mpath.lexically_normal().string();
    scene.material_text = read_text(mpath, "material");
    material_name = mpath.string();
    material_root = parse_toml(scene.material_text, material_name);
    for (const auto& [key, value] : material_root) {
      const std::string k(key.str());
      if (k != "fibre" && k != "matrix" && k != "source")
        throw InputError(material_name + ":" + std::to_string(value.source().begin.line) + ": " + k +
                         ": unknown key; allowed: [fibre], [matrix], source = \"...\"");
    }
    fibre_table = sub_table(material_root, "fibre", material_name);
    matrix_table = sub_table(material_root, "matrix", material_name);
  }
  if (!fibre_table) throw InputError(material_name + ": missing table [fibre] (E, nu)");
  if (!matrix_table) throw InputError(material_name + ": missing table [matrix] (E, nu)");
  const std::vector<std::string> material_lines =
      split_lines(material.empty() ? text : std::string_view(scene.material_text));
  TableReader ft(fibre_table, "fibre", material_name, material_lines, &scene.written);
  scene.fibre = read_material(ft);
  TableReader mt(matrix_table, "matrix", material_name, material_lines, &scene.written);
  scene.matrix = read_material(mt);

  // [interface]
  TableReader it(sub_table(root, "interface", fname), "interface", fname, lines, &scene.written);
  scene.interface.normal_strength = it.real("normal_strength", 0);
  scene.interface.tangential_strength = it.real("tangential_strength", 0);
  it.finish();

  // [load]
  TableReader lt(sub_table(root, "load", fname), "load", fname, lines, &scene.written);
  const std::string boundary = lt.string("boundary", "symmetry", {"symmetry", "traction", "periodic", "edges"});
  scene.load.boundary = boundary == "symmetry"   ? Boundary::symmetry
                        : boundary == "traction" ? Boundary::traction
                        : boundary == "periodic" ? Boundary::periodic
                                                 : Boundary::edges;
  if (scene.load.boundary == Boundary::edges) {
    scene.load.edge_loads = read_edge_loads(root, fname, lines);
    check_held_and_loaded(scene.load.edge_loads, fname, "the block");
  } else {
    for (const std::string& t : edge_load_tables)
      if (const toml::node* n = root.get(t))
        top.fail(n, t, "", "only with [load] boundary = \"edges\" (the boundary here is \"" + boundary + "\")");
  }
  const auto bf = lt.reals("body_force", {0, 0}, 2, 2);
  scene.load.body_force = {bf[0], bf[1]};
  lt.finish();

  // [sweep]
  TableReader st(sub_table(root, "sweep", fname), "sweep", fname, lines, &scene.written);
  scene.sweep.directions_deg = st.reals("directions_deg", scene.sweep.directions_deg, 1, 3600);
  scene.sweep.magnitudes = st.reals("magnitudes", scene.sweep.magnitudes, 1, 100000);
  scene.sweep.stress_directions = st.triples("stress_directions");
  scene.sweep.sphere = st.integer<int>("sphere", 0);
  scene.sweep.fuse_tolerance = st.real("fuse_tolerance", scene.sweep.fuse_tolerance);
  st.finish();

  // [solver]
  TableReader sv(sub_table(root, "solver", fname), "solver", fname, lines, &scene.written);
  SolverSettings& so = scene.solver;
  so.tolerance = sv.real("tolerance", so.tolerance);
  so.max_outer_iterations = sv.integer<int>("max_outer_iterations", so.max_outer_iterations);
  so.max_operator_applications = sv.integer<long>("max_operator_applications", so.max_operator_applications);
  so.rho_factor = sv.real("rho_factor", so.rho_factor);
  so.rho_growth = sv.real("rho_growth", so.rho_growth);
  so.rho_patience = sv.integer<int>("rho_patience", so.rho_patience);
  so.Gamma = sv.real("Gamma", so.Gamma);
  so.max_debond_rounds = sv.integer<int>("max_debond_rounds", so.max_debond_rounds);
  const std::string preconditioner = sv.string("preconditioner", "none", {"none", "lumped", "dirichlet"});
  so.preconditioner = preconditioner == "lumped"      ? Preconditioner::lumped
                      : preconditioner == "dirichlet" ? Preconditioner::dirichlet
                                                      : Preconditioner::none;
  sv.finish();

  validate(scene);
  scene.warnings = scene_warnings(scene);
  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status))
    throw InputError(file.string() + (ec && ec != std::errc::no_such_file_or_directory
                                          ? ": cannot access scene file: " + ec.message()
                                          : ": scene file not found"));
  if (std::filesystem::is_directory(status)) throw InputError(file.string() + ": is a directory, not a scene file");
  return parse_scene(read_text(file, "scene"), file);
}

// ---------------------------------------------------------------------------------------------
// structure.toml

namespace {}  // namespace

StructureScene parse_structure_scene(std::string_view text, const std::filesystem::path& file) {
  const std::string fname = file.string();
  StructureScene scene;
  scene.text = std::string(text);
  const toml::table root = parse_toml(text, fname);
  const std::vector<std::string> lines = split_lines(text);
  TableReader top(&root, "top level", fname, lines);
  for (const auto& [key, value] : root) {
    const std::string k(key.str());
    if (k != "structure" && k != "edges" && k != "support" && k != "point_load" && k != "steps" && k != "output" &&
        k != "solver")
      top.fail(&value, key_text(key, lines), "",
               "unknown table or key; allowed: [structure], [edges.left|right|bottom|top], [[support]], "
               "[[point_load]], [steps], [output], [solver]");
  }
  const auto count = [&lines](TableReader& t, std::string_view key, int fallback, int lo, int hi) {
    const std::int64_t v = t.integer<std::int64_t>(key, fallback);
    if (v < lo || v > hi)  // quoted as written: a value beyond 64 bits is not clamped in the message
      t.fail(t.node(key), key, show(*t.node(key), lines),
             "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  };

  TableReader st(sub_table(root, "structure", fname), "structure", fname, lines);
  if (!st.present()) throw InputError(fname + ": missing table [structure]");
  {
    if (!st.has("cells")) st.fail(nullptr, "cells", "", "missing; required, [nx, ny], integers >= 1");
    const auto cells = st.reals("cells", {1, 1}, 2, 2);
    for (double c : cells)
      if (!(c >= 1 && c <= 100000 && c == std::floor(c)))
        st.fail(st.node("cells"), "cells", "", "must be two integers in [1, 100000]");
    scene.nx = static_cast<int>(cells[0]);
    scene.ny = static_cast<int>(cells[1]);
    scene.elements_per_cell = count(st, "elements_per_cell", 2, 1, 64);
    scene.element = st.string("element", "p2", {"p1", "p2"}) == "p1" ? Element::p1 : Element::p2;
    // The same bound as a cell scene's mesh: (nx·m·k + 1)(ny·m·k + 1) nodes for m elements per
    // cell of order k, checked before anything is allocated.
    const double k = element_order(scene.element), m = scene.elements_per_cell;
    const double nodes = (scene.nx * m * k + 1) * (scene.ny * m * k + 1);
    if (nodes > max_mesh_nodes)
      st.fail(st.node("cells"), "cells", show(*st.node("cells"), lines),
              "with elements_per_cell = " + std::to_string(scene.elements_per_cell) + " (" + to_string(scene.element) +
                  ") the structure would have " + shortest(std::round(nodes)) + " nodes, more than the limit " +
                  std::to_string(max_mesh_nodes) + ": fewer cells or elements per cell");
    st.finish();
  }

  static_cast<EdgeLoads&>(scene) = read_edge_loads(root, fname, lines);
  TableReader solver(sub_table(root, "solver", fname), "solver", fname, lines);
  if (solver.present()) {
    scene.tolerance = solver.real("tolerance", 1e-10);
    if (!(scene.tolerance >= 1e-15 && scene.tolerance <= 1e-2))
      solver.fail(solver.node("tolerance"), "tolerance", "", "must be in [1e-15, 1e-2]");
    scene.max_newton_steps = count(solver, "max_newton_steps", 100, 1, 100000);
    scene.max_fuse_rounds = count(solver, "max_fuse_rounds", 1000, 0, 1000000);
    solver.finish();
  }
  check_held_and_loaded(scene, fname, "the structure");
  // In units of cells: whether a rigid motion is free does not depend on the cell size.
  if (const std::string free = free_rigid_motion(scene, scene.nx, scene.ny); !free.empty())
    throw InputError(fname + ": the edges and supports leave a rigid-body motion free, " + free);
  return scene;
}

StructureScene load_structure_scene(const std::filesystem::path& file) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) throw InputError(file.string() + ": structure scene file not found");
  if (std::filesystem::is_directory(status))
    throw InputError(file.string() + ": is a directory, not a structure scene file");
  return parse_structure_scene(read_text(file, "structure scene"), file);
}

}  // namespace dualcell
