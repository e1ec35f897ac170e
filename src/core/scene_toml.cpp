// Reading a cell scene file (TOML): syntax, tables, keys and types, with the place and the
// text of every key remembered for validate()'s messages (core/scene.hpp). The generic reading
// is core/toml_reader.hpp.
#include "core/toml_reader.hpp"

namespace dualcell {

using namespace reading;

namespace {

// E and nu; a transversely isotropic phase adds E_L, nu_LT and G_LT, all three (E, nu are then
// the transverse plane's).
Material read_material(TableReader& t) {
  Material m;
  m.E = t.real("E", 0, true, "E > 0");
  m.nu = t.real("nu", 0, true, "-1 < nu < 0.5");
  m.axial = t.has("E_L") || t.has("nu_LT") || t.has("G_LT");
  if (m.axial) {
    const std::string what = "a transversely isotropic phase gives E_L, nu_LT and G_LT";
    m.E_L = t.real("E_L", 0, true, what);
    m.nu_LT = t.real("nu_LT", 0, true, what);
    m.G_LT = t.real("G_LT", 0, true, what);
  }
  m.expands = t.has("alpha");
  if (m.expands) {
    m.alpha = t.real("alpha", 0);
    m.alpha_L = m.axial ? t.real("alpha_L", m.alpha) : m.alpha;
  }
  if (!m.axial && t.has("alpha_L"))
    t.fail(t.node("alpha_L"), "alpha_L", "",
           "only for a transversely isotropic phase (with E_L, nu_LT, G_LT); an isotropic one has alpha alone");
  if (!m.expands && t.has("alpha_L"))
    t.fail(t.node("alpha_L"), "alpha_L", "", "needs alpha, the expansion across the fibres, beside it");
  t.finish();
  return m;
}

// What each section reader of a cell scene needs: the parsed file, its name, text and lines,
// the scene being filled, and the reader of the top level (which refusals of top-level keys use).
struct SceneReading {
  const toml::table& root;
  const std::filesystem::path& file;
  const std::string& fname;
  std::string_view text;
  const std::vector<std::string>& lines;
  TableReader& top;
  Scene& scene;

  // The reader of the scene's table [name] (absent: an empty table; scene.written records each key).
  TableReader table(const char* name) const {
    return TableReader(sub_table(root, name, fname), name, fname, lines, &scene.written);
  }
};

// `material = "..."` as written (a path with non-ASCII characters decoded), or "".
std::string read_material_path(SceneReading& r) {
  const toml::table& root = r.root;
  const std::vector<std::string>& lines = r.lines;
  TableReader& top = r.top;
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
  return material;
}

// Every top-level key is a known table (the edge-load tables are checked with [load]).
void check_top_level_keys(SceneReading& r) {
  const toml::table& root = r.root;
  const std::vector<std::string>& lines = r.lines;
  TableReader& top = r.top;
  const std::vector<std::string> tables{"geometry",  "fibres", "fibre", "matrix",
                                        "interface", "load",   "sweep", "solver"};
  for (const auto& [key, value] : root) {
    const std::string k(key.str());
    if (k == "material") continue;
    if (std::find(edge_load_tables.begin(), edge_load_tables.end(), k) != edge_load_tables.end()) continue;
    if (std::find(tables.begin(), tables.end(), k) == tables.end())
      top.fail(&value, key_text(key, lines), "",
               "unknown table or key; allowed: material, [geometry], [[fibres]], [fibre], "
               "[matrix], [interface], [load], [sweep], [solver], and with [load] boundary = \"edges\" "
               "[edges.left|right|bottom|top], [[support]], [[point_load]], [steps], [output]");
  }
}

// A periodic RVE: [geometry] size = [Lx, Ly], kind = "list" (the [[fibres]] tables: centre,
// radius) or "random" (volume_fraction, radius = [mean, sd], min_gap, seed); min_gap for both
// (random fibres without it keep the gap the mesher needs at the degree, rve_default_min_gap).
void read_rve(SceneReading& r, TableReader& g) {
  Geometry& geo = r.scene.geometry;
  for (const char* key : {"cells", "cell_size", "fibre_radius", "fibre_offset"})
    if (g.has(key)) g.fail(g.node(key), key, "", "not with size: an RVE (size = [Lx, Ly]) has its fibres, not cells");
  const auto size = g.reals("size", {0, 0}, 2, 2);
  geo.size = {size[0], size[1]};
  const toml::node* fibres = r.root.get("fibres");
  const std::string kind = g.string("kind", "list", {"list", "random"});
  geo.layout = kind == "list" ? FibreLayout::list : FibreLayout::random;
  geo.random.min_gap = g.real("min_gap", 0);
  if (geo.layout == FibreLayout::random) {
    if (fibres)
      throw InputError(r.fname + ":" + std::to_string(fibres->source().begin.line) +
                       ": [[fibres]] with kind = \"random\": give the list (kind = \"list\") or the random spec");
    geo.random.volume_fraction = g.real("volume_fraction", 0, true, "0 < volume_fraction < 0.9");
    const auto radius = g.reals("radius", {0, 0}, 1, 2);
    geo.random.radius_mean = radius[0];
    geo.random.radius_sd = radius.size() > 1 ? radius[1] : 0;
    if (!g.has("min_gap")) geo.random.min_gap = rve_default_min_gap(geo.random.radius_mean, geo.degree);
    const auto seed = g.integer<std::int64_t>("seed", 1);
    if (seed < 0) g.fail(g.node("seed"), "seed", std::to_string(seed), "must be an integer >= 0");
    geo.random.seed = static_cast<std::uint64_t>(seed);
    return;
  }
  for (const char* key : {"volume_fraction", "radius", "seed"})
    if (g.has(key)) g.fail(g.node(key), key, "", "only with kind = \"random\" (a list gives its [[fibres]])");
  if (!fibres)
    throw InputError(r.fname + ": [geometry] size without [[fibres]]: give the list of fibres or kind = \"random\"");
  reading::each_table(r.root, "fibres", r.fname, r.lines, [&](TableReader& t) {
    FibreCircle f;
    const Eigen::Vector2d c = reading::point(t, "centre", true, "[x, y] of the fibre's centre");
    f.centre = {c.x(), c.y()};
    f.radius = t.real("radius", 0, true, "radius > 0");
    geo.fibres.push_back(f);
  });
}

void read_geometry(SceneReading& r) {
  const toml::table& root = r.root;
  const std::string& fname = r.fname;
  const std::vector<std::string>& lines = r.lines;
  Scene& scene = r.scene;
  // [geometry]
  TableReader g = r.table("geometry");
  if (!g.present()) throw InputError(fname + ": missing table [geometry]");
  Geometry& geo = scene.geometry;
  // Integers stored as int: a non-integral or huge value becomes 0, which validate() refuses
  // (quoting the value as written).
  const auto as_count = [](double v) { return v >= 1 && v <= 1e9 && v == std::floor(v) ? static_cast<int>(v) : 0; };
  geo.degree = g.integer<int>("degree", 1);
  geo.element = g.string("element", "p2", {"p1", "p2"}) == "p1" ? Element::p1 : Element::p2;
  const toml::node* fibres = root.get("fibres");
  if (g.has("size")) {
    read_rve(r, g);
  } else {
    for (const char* key : {"kind", "volume_fraction", "radius", "min_gap", "seed"})
      if (g.has(key)) {
        const toml::node* n = g.node(key);
        g.fail(n, key, show(*n, lines),
               "unknown key for a block of cells (allowed: cells, cell_size, fibre_radius, fibre_offset, degree, "
               "element); it is a key of a periodic RVE, which gives size = [Lx, Ly] instead of cells");
      }
    if (fibres)
      throw InputError(fname + ":" + std::to_string(fibres->source().begin.line) +
                       ": [[fibres]] only for a periodic RVE: give [geometry] size = [Lx, Ly]");
    const auto cells = g.reals("cells", {1, 1}, 2, 2);
    geo.cells = {as_count(cells[0]), as_count(cells[1])};
    geo.cell_size = g.real("cell_size", 1.0);
    geo.fibre_radius = g.real("fibre_radius", 0, true, "fibre_radius > 0");
    const auto off = g.reals("fibre_offset", {0, 0}, 2, 2);
    geo.fibre_offset = {off[0], off[1]};
  }
  g.finish();
}

void read_materials(SceneReading& r, const std::string& material) {
  const toml::table& root = r.root;
  const std::filesystem::path& file = r.file;
  const std::string& fname = r.fname;
  const std::string_view text = r.text;
  TableReader& top = r.top;
  Scene& scene = r.scene;
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
}

void read_interface_and_load(SceneReading& r) {
  const toml::table& root = r.root;
  const std::string& fname = r.fname;
  const std::vector<std::string>& lines = r.lines;
  TableReader& top = r.top;
  Scene& scene = r.scene;
  // [interface]
  TableReader it = r.table("interface");
  scene.interface.normal_strength = it.real("normal_strength", 0);
  scene.interface.tangential_strength = it.real("tangential_strength", 0);
  it.finish();

  // [load]
  TableReader lt = r.table("load");
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
  scene.load.delta_T = lt.real("delta_T", 0);
  const std::string macro = lt.string("macro", "transverse", {"transverse", "full"});
  scene.load.macro = macro == "full" ? Macro::full : Macro::transverse;
  if (scene.load.macro == Macro::full && scene.load.boundary == Boundary::edges)
    lt.fail(lt.node("macro"), "macro", "\"full\"", "a cell's law only: boundary = \"edges\" is a structure");
  lt.finish();
}

void read_sweep_and_solver(SceneReading& r) {
  Scene& scene = r.scene;
  // [sweep]
  TableReader st = r.table("sweep");
  scene.sweep.directions_deg = st.reals("directions_deg", scene.sweep.directions_deg, 1, 3600);
  scene.sweep.magnitudes = st.reals("magnitudes", scene.sweep.magnitudes, 1, 100000);
  scene.sweep.stress_directions = st.triples("stress_directions");
  scene.sweep.sphere = st.integer<int>("sphere", 0);
  scene.sweep.eps33 = st.reals("eps33", {}, 0, 100);
  scene.sweep.gamma = st.tuples<2>("gamma", "an array of [gamma_xz, gamma_yz] shears along the fibres");
  scene.sweep.fuse_tolerance = st.real("fuse_tolerance", scene.sweep.fuse_tolerance);
  st.finish();

  // [solver]
  TableReader sv = r.table("solver");
  SolverSettings& so = scene.solver;
  so.tolerance = sv.real("tolerance", so.tolerance);
  so.max_outer_iterations = sv.integer<int>("max_outer_iterations", so.max_outer_iterations);
  so.max_operator_applications = sv.integer<long>("max_operator_applications", so.max_operator_applications);
  so.rho_factor = sv.real("rho_factor", so.rho_factor);
  so.rho_growth = sv.real("rho_growth", so.rho_growth);
  so.rho_patience = sv.integer<int>("rho_patience", so.rho_patience);
  so.Gamma = sv.real("Gamma", so.Gamma);
  so.max_debond_rounds = sv.integer<int>("max_debond_rounds", so.max_debond_rounds);
  so.subdomain_dofs = sv.integer<int>("subdomain_dofs", so.subdomain_dofs);
  const std::string preconditioner = sv.string("preconditioner", "none", {"none", "lumped", "dirichlet"});
  so.preconditioner = preconditioner == "lumped"      ? Preconditioner::lumped
                      : preconditioner == "dirichlet" ? Preconditioner::dirichlet
                                                      : Preconditioner::none;
  const std::string dual_operator = sv.string("dual_operator", "auto", {"auto", "implicit", "explicit"});
  so.dual_operator = dual_operator == "implicit"   ? DualOperator::implicit
                     : dual_operator == "explicit" ? DualOperator::explicit_
                                                   : DualOperator::automatic;
  sv.finish();
}

}  // namespace

Scene parse_scene(std::string_view text, const std::filesystem::path& file) {
  const std::string fname = file.string();
  Scene scene;
  scene.file = file;
  scene.text = std::string(text);
  const toml::table root = parse_toml(text, fname);
  const std::vector<std::string> lines = split_lines(text);
  TableReader top(&root, "top level", fname, lines);
  SceneReading reading{root, file, fname, text, lines, top, scene};
  const std::string material = read_material_path(reading);
  check_top_level_keys(reading);
  read_geometry(reading);
  read_materials(reading, material);
  read_interface_and_load(reading);
  read_sweep_and_solver(reading);
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

}  // namespace dualcell
