#include "core/scene.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "core/error.hpp"

namespace dualcell {

const char* to_string(Boundary b) {
  switch (b) {
    case Boundary::symmetry: return "symmetry";
    case Boundary::traction: return "traction";
    case Boundary::periodic: return "periodic";
  }
  return "?";
}

namespace {

std::string read_text(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open " + what + " file");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The value as the user wrote it (from the source text), so messages quote "0.7", not
// "0.69999999999999996"; falls back to toml++'s printing for values spanning lines.
std::string show(const toml::node& node, const std::vector<std::string>& lines) {
  const auto& region = node.source();
  if (region.begin.line > 0 && region.begin.line == region.end.line && region.begin.line <= lines.size() &&
      region.end.column > region.begin.column) {
    const std::string& line = lines[region.begin.line - 1];
    if (region.end.column - 1 <= line.size())
      return line.substr(region.begin.column - 1, region.end.column - region.begin.column);
  }
  std::ostringstream s;
  node.visit([&](const auto& value) { s << value; });
  return s.str();
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
  TableReader(const toml::table* table, std::string name, std::string file, const std::vector<std::string>& lines)
      : table_(table), name_(std::move(name)), file_(std::move(file)), lines_(lines) {}

  bool present() const { return table_ != nullptr; }
  bool has(std::string_view key) const { return table_ && table_->contains(key); }

  [[noreturn]] void fail(const toml::node* node, std::string_view key, const std::string& value,
                         const std::string& why) const {
    std::ostringstream s;
    s << file_;
    if (node && node->source().begin.line > 0)
      s << ':' << node->source().begin.line << ':' << node->source().begin.column;
    s << ": [" << name_ << "] " << key;
    if (!value.empty()) s << " = " << value;
    s << ": " << why;
    throw InputError(s.str());
  }

  const toml::node* node(std::string_view key) {
    used_.insert(std::string(key));
    return table_ ? table_->get(key) : nullptr;
  }

  // A finite real number (integers accepted) satisfying `ok`, else an error quoting `range`.
  double real(std::string_view key, double fallback, const std::function<bool(double)>& ok,
              const std::string& range, bool required = false) {
    const toml::node* n = node(key);
    if (!n) {
      if (required) fail(nullptr, key, "", "missing; required, " + range);
      return fallback;
    }
    double v;
    if (auto i = n->as_integer())
      v = static_cast<double>(i->get());
    else if (auto f = n->as_floating_point())
      v = f->get();
    else
      fail(n, key, show(*n, lines_), "must be a number, " + range);
    if (!std::isfinite(v) || !ok(v)) fail(n, key, show(*n, lines_), "out of range: " + range);
    return v;
  }

  long integer(std::string_view key, long fallback, long lo, long hi) {
    const toml::node* n = node(key);
    const std::string range = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!n) return fallback;
    auto i = n->as_integer();
    if (!i) fail(n, key, show(*n, lines_), "must be " + range);
    if (i->get() < lo || i->get() > hi) fail(n, key, show(*n, lines_), "out of range: " + range);
    return static_cast<long>(i->get());
  }

  std::vector<double> reals(std::string_view key, std::vector<double> fallback,
                            const std::function<bool(double)>& ok, const std::string& range,
                            std::size_t min_size, std::size_t max_size) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    auto a = n->as_array();
    const std::string what = "an array of " +
        (min_size == max_size ? std::to_string(min_size) : "at least " + std::to_string(min_size)) +
        " numbers, each " + range;
    if (!a || a->size() < min_size || a->size() > max_size) fail(n, key, show(*n, lines_), "must be " + what);
    std::vector<double> v;
    for (const toml::node& e : *a) {
      double x;
      if (auto i = e.as_integer())
        x = static_cast<double>(i->get());
      else if (auto f = e.as_floating_point())
        x = f->get();
      else
        fail(n, key, show(*n, lines_), "must be " + what);
      if (!std::isfinite(x) || !ok(x)) fail(n, key, show(*n, lines_), "out of range: must be " + what);
      v.push_back(x);
    }
    return v;
  }

  // An array of 3-arrays of finite numbers, none all zero.
  std::vector<std::array<double, 3>> triples(std::string_view key) {
    const toml::node* n = node(key);
    std::vector<std::array<double, 3>> out;
    if (!n) return out;
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
        if (!std::isfinite(v[i])) fail(n, key, show(*n, lines_), "must be " + what);
      }
      if (v[0] == 0 && v[1] == 0 && v[2] == 0) fail(n, key, show(*n, lines_), "must be " + what);
      out.push_back(v);
    }
    return out;
  }

  std::string string(std::string_view key, std::string fallback,
                     const std::vector<std::string>& allowed = {}) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    auto s = n->as_string();
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
    if (!s) fail(n, key, show(*n, lines_), allowed.empty() ? "must be a string" : "must be one of " + list);
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
        fail(&value, key.str(), show(value, lines_), "unknown key; allowed keys: " + allowed);
      }
    }
  }

 private:
  const toml::table* table_;
  std::string name_;
  std::string file_;
  const std::vector<std::string>& lines_;
  std::set<std::string> used_;
};

auto positive = [](double v) { return v > 0; };
auto non_negative = [](double v) { return v >= 0; };
auto any_value = [](double) { return true; };

Material read_material(TableReader& t) {
  Material m;
  m.E = t.real("E", 0, positive, "E > 0", true);
  m.nu = t.real("nu", 0, [](double v) { return v > -1 && v < 0.5; }, "-1 < nu < 0.5", true);
  t.finish();
  return m;
}

toml::table parse_toml(std::string_view text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << file << ':' << e.source().begin.line << ':' << e.source().begin.column
      << ": TOML syntax error: " << e.description();
    throw InputError(s.str());
  }
}

const toml::table* sub_table(const toml::table& root, std::string_view name, const std::string& file) {
  const toml::node* n = root.get(name);
  if (!n) return nullptr;
  if (!n->is_table())
    throw InputError(file + ":" + std::to_string(n->source().begin.line) + ": [" +
                     std::string(name) + "] must be a table");
  return n->as_table();
}

}  // namespace

Scene parse_scene(std::string_view text, const std::filesystem::path& file) {
  const std::string fname = file.string();
  Scene scene;
  scene.file = file;
  scene.text = std::string(text);
  const toml::table root = parse_toml(text, fname);

  const std::vector<std::string> tables{"geometry", "fibre", "matrix", "interface", "load",
                                        "sweep", "solver"};
  const std::vector<std::string> lines = split_lines(text);
  TableReader top(&root, "top level", fname, lines);
  std::string material = top.string("material", "");
  for (const auto& [key, value] : root) {
    const std::string k(key.str());
    if (k == "material") continue;
    if (std::find(tables.begin(), tables.end(), k) == tables.end())
      top.fail(&value, k, "", "unknown table or key; allowed: material, [geometry], [fibre], "
               "[matrix], [interface], [load], [sweep], [solver]");
  }

  // [geometry]
  TableReader g(sub_table(root, "geometry", fname), "geometry", fname, lines);
  if (!g.present()) throw InputError(fname + ": missing table [geometry]");
  Geometry& geo = scene.geometry;
  const auto cells = g.reals("cells", {1, 1},
                             [](double v) { return v >= 1 && v <= 4096 && v == std::floor(v); },
                             "an integer in [1, 4096]", 2, 2);
  geo.cells = {static_cast<int>(cells[0]), static_cast<int>(cells[1])};
  geo.cell_size = g.real("cell_size", 1.0, positive, "cell_size > 0");
  geo.fibre_radius = g.real("fibre_radius", 0, positive, "fibre_radius > 0", true);
  const auto off = g.reals("fibre_offset", {0, 0}, any_value, "a finite number", 2, 2);
  geo.fibre_offset = {off[0], off[1]};
  geo.degree = static_cast<int>(g.integer("degree", 1, 1, 256));
  const double half = geo.cell_size / 2;
  for (int d = 0; d < 2; ++d) {
    if (!(geo.fibre_radius + std::abs(geo.fibre_offset[d]) < half)) {
      std::ostringstream s;
      s << "the fibre touches or crosses its cell's edge: need fibre_radius + |fibre_offset["
        << d << "]| = " << geo.fibre_radius + std::abs(geo.fibre_offset[d])
        << " < cell_size/2 = " << half;
      const toml::node* radius = g.node("fibre_radius");
      g.fail(radius, "fibre_radius", radius ? show(*radius, lines) : "", s.str());
    }
  }
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
    if (!std::filesystem::exists(mpath))
      top.fail(root.get("material"), "material", "\"" + material + "\"",
               "material file not found: " + mpath.string());
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
  const std::vector<std::string> material_lines = split_lines(material.empty() ? text : std::string_view(scene.material_text));
  TableReader ft(fibre_table, "fibre", material_name, material_lines);
  scene.fibre = read_material(ft);
  TableReader mt(matrix_table, "matrix", material_name, material_lines);
  scene.matrix = read_material(mt);

  // [interface]
  TableReader it(sub_table(root, "interface", fname), "interface", fname, lines);
  scene.interface.normal_strength = it.real("normal_strength", 0, non_negative, "normal_strength >= 0 (0: no adhesion)");
  scene.interface.tangential_strength =
      it.real("tangential_strength", 0, non_negative, "tangential_strength >= 0 (0: no adhesion)");
  it.finish();

  // [load]
  TableReader lt(sub_table(root, "load", fname), "load", fname, lines);
  const std::string boundary = lt.string("boundary", "symmetry", {"symmetry", "traction", "periodic"});
  scene.load.boundary = boundary == "symmetry" ? Boundary::symmetry
                        : boundary == "traction" ? Boundary::traction
                                                 : Boundary::periodic;
  const auto bf = lt.reals("body_force", {0, 0}, any_value, "a finite number", 2, 2);
  scene.load.body_force = {bf[0], bf[1]};
  // A body force is carried only by the symmetry edges' reactions, and the debond onset
  // formula s* = bound/λ(σ̄) assumes λ linear in σ̄ alone: refuse the combinations where either
  // would silently be wrong.
  if (bf[0] != 0 || bf[1] != 0) {
    if (scene.load.boundary != Boundary::symmetry)
      lt.fail(lt.node("body_force"), "body_force", "", "a body force needs boundary = \"symmetry\" (the traction and "
              "periodic boundaries have no reactions to carry its resultant)");
    if (scene.interface.has_adhesion())
      lt.fail(lt.node("body_force"), "body_force", "", "a body force cannot be combined with adhesion (the debond "
              "onset is computed for the macro stress alone)");
  }
  lt.finish();

  // [sweep]
  TableReader st(sub_table(root, "sweep", fname), "sweep", fname, lines);
  scene.sweep.directions_deg = st.reals("directions_deg", scene.sweep.directions_deg,
                                        [](double v) { return v >= -360 && v <= 360; },
                                        "in [-360, 360] degrees", 1, 3600);
  scene.sweep.magnitudes = st.reals("magnitudes", scene.sweep.magnitudes,
                                    [](double v) { return v != 0; }, "non-zero", 1, 100000);
  scene.sweep.stress_directions = st.triples("stress_directions");
  scene.sweep.fuse_tolerance = st.real("fuse_tolerance", scene.sweep.fuse_tolerance,
                                       [](double v) { return v > 0 && v < 1; }, "0 < fuse_tolerance < 1");
  st.finish();

  // [solver]
  TableReader sv(sub_table(root, "solver", fname), "solver", fname, lines);
  SolverSettings& so = scene.solver;
  so.tolerance = sv.real("tolerance", so.tolerance, [](double v) { return v >= 1e-15 && v < 1; },
                         "1e-15 <= tolerance < 1");
  so.max_outer_iterations = static_cast<int>(sv.integer("max_outer_iterations", so.max_outer_iterations, 1, 100000));
  so.max_operator_applications =
      sv.integer("max_operator_applications", so.max_operator_applications, 1, 1000000000L);
  so.rho_factor = sv.real("rho_factor", so.rho_factor, [](double v) { return v > 0 && v <= 1e6; },
                          "0 < rho_factor <= 1e6");
  so.Gamma = sv.real("Gamma", so.Gamma, [](double v) { return v > 0 && v <= 1e3; }, "0 < Gamma <= 1e3");
  so.max_debond_rounds = static_cast<int>(sv.integer("max_debond_rounds", so.max_debond_rounds, 1, 1000000));
  sv.finish();

  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw InputError(file.string() + ": scene file not found");
  if (std::filesystem::is_directory(file)) throw InputError(file.string() + ": is a directory, not a scene file");
  return parse_scene(read_text(file, "scene"), file);
}

}  // namespace dualcell
