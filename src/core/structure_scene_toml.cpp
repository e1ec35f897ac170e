// Reading a structure scene file (structure.toml, core/structure_scene.hpp) with the generic
// reading of core/toml_reader.hpp.
#include "core/structure_scene.hpp"
#include "core/toml_reader.hpp"

namespace dualcell {

using namespace reading;

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
    scene.quadrature = count(st, "quadrature", 6, 3, 6);
    if (scene.quadrature != 3 && scene.quadrature != 6)
      st.fail(st.node("quadrature"), "quadrature", show(*st.node("quadrature"), lines), "must be 3 or 6");
    if (scene.quadrature == 3 && scene.element != Element::p2)
      st.fail(st.node("quadrature"), "quadrature", show(*st.node("quadrature"), lines),
              "a p1 triangle has one point: quadrature = 3 is for element = \"p2\"");
    scene.bond_unit = st.string("bonds", "cell", {"cell", "point"}) == "cell" ? StructureScene::BondUnit::cell
                                                                              : StructureScene::BondUnit::point;
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
