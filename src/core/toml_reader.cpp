#include "core/toml_reader.hpp"

#include <fstream>

namespace dualcell::reading {

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

namespace {

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

}  // namespace

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

// A value printed by us, not by toml++: its printer converts log10 of a float to an integer to
// size the output, undefined for inf and nan (found by the fuzzer, `make -C pipelines fuzz`).
std::string printed(const toml::node& node) {
  if (const auto* array = node.as_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < array->size(); ++i) {
      if (i > 0) s += ", ";
      s += printed((*array)[i]);
      if (s.size() > 80) break;  // clipped anyway
    }
    return s + "]";
  }
  if (const auto* table = node.as_table()) {
    std::string s = "{";
    for (const auto& [key, value] : *table) {
      if (s.size() > 1) s += ", ";
      s.append(key.str()).append(" = ").append(printed(value));
      if (s.size() > 80) break;
    }
    return s + "}";
  }
  if (const auto x = node.value<double>(); x && node.is_floating_point()) return shortest(*x);
  std::ostringstream s;
  node.visit([&](const auto& value) { s << value; });
  return s.str();
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
  return clipped(printed(node));
}

std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in{std::string(text)};
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
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

}  // namespace dualcell::reading
