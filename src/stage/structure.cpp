#include "stage/structure.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/memory.hpp"
#include "core/progress.hpp"
#include "core/structure_scene.hpp"
#include "core/text.hpp"
#include "io/atomic_output.hpp"
#include "io/law_file.hpp"
#include "io/structure_file.hpp"
#include "law/form.hpp"

namespace dualcell::stage {

structure::CellLaw cell_law(const std::filesystem::path& law_file, std::string& form, double& cell_size,
                            std::string& note) {
  const law::Law law = io::read_law(law_file);
  cell_size = law.constituents.cell_size;
  if (!(cell_size >= min_structure_cell_size && cell_size <= max_structure_cell_size))
    throw InputError(law_file.string() + ": /law attribute cell_size = " + shortest(cell_size) +
                     ": a structure needs a cell size in [" + shortest(min_structure_cell_size) + ", " +
                     shortest(max_structure_cell_size) + "] (its positions are in that unit)");
  const law::LawForm picked = law::pick_form(law, form, law_file.string(), &note);
  form = law::to_string(picked);
  structure::CellLaw cell;
  if (picked != law::LawForm::cone) {  // both cells, evaluated alike at every quadrature point
    cell.cell = std::make_shared<const law::CondensedCell>(law::cell_of(law, picked));
    if (!cell.cell->adhesion()) note = "no bond breaks: the cell has no adhesion";
    return cell;
  }
  cell.bonded = cell.debonded = law.cone.law;
  const std::string prefix = note.empty() ? "" : note + "; ";
  if (!law.onset.linear) {
    note = prefix + "cells do not fuse: the law has no onset surface (" + law.onset.message + ")";
  } else if (!law.cone_after_fuse.ok) {
    note =
        prefix + "cells do not fuse: the law has no cone-wise law past the fuse (" + law.cone_after_fuse.message + ")";
  } else {
    cell.debonded = law.cone_after_fuse.law;
    cell.onset = law.onset;
  }
  return cell;
}

namespace {

// Bytes per node of a structure as it runs (the mesh, each quadrature point's ∇ˢ and state, the
// tangent and its Cholesky factor), measured by peak RSS from 200² to 400² cells, p1 and p2,
// k = 1 and 4: 4.8–6.0 kB; with a margin for the factor's n log n.
constexpr double bytes_per_node = 7000;

// What the structure will hold, from the scene and the law alone (before the mesh is built):
// refused with the figure when it exceeds this machine's memory.
void refuse_beyond_memory_of(const StructureScene& scene, const structure::CellLaw& law, const std::string& file) {
  const double k = element_order(scene.element), m = scene.elements_per_cell;
  const double nodes = (scene.nx * m * k + 1) * (scene.ny * m * k + 1);
  const double triangles = 2.0 * scene.nx * m * scene.ny * m;
  const double points = triangles * (scene.element == Element::p1 ? 1 : 6);
  double bytes = bytes_per_node * nodes;
  if (law.cell) {
    // Each bond unit's history (its bond states and the warm start of its QP), and per thread an
    // evaluator: 𝓗 and three QP workspaces of the cell's rows.
    const double rows = law.cell->n_rows() + law.cell->n_macro + static_cast<double>(law.cell->G.rows());
    const double units = scene.bond_unit == StructureScene::BondUnit::cell ? scene.nx * scene.ny : points;
    bytes += (points + units) * (law.cell->n_pairs + rows + 64.0);
    bytes += omp_get_max_threads() * 4 * rows * rows * 8;
  }
  refuse_beyond_memory(bytes,
                       file + ": the structure (" + std::to_string(std::lround(nodes)) + " nodes, " +
                           std::to_string(std::lround(points)) + " material points" +
                           (law.cell ? ", the exact law of " + std::to_string(law.cell->n_rows()) + " rows" : "") + ")",
                       "fewer cells or elements per cell");
}

}  // namespace

StructureSummary run_structure(const StructureOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  // Every output checked before any work, against the inputs it could destroy.
  io::check_outputs({options.out, io::xdmf_beside(options.out)}, {options.scene_file, options.law_file});
  StructureScene scene = load_structure_scene(options.scene_file);
  StructureSummary summary;
  summary.law_form = options.form;
  const structure::CellLaw law = cell_law(options.law_file, summary.law_form, scene.cell_size, summary.fuse_note);
  summary.cell_size = scene.cell_size;
  if (!law.cell && scene.bond_unit == StructureScene::BondUnit::point)
    throw InputError(options.scene_file.string() +
                     ": [structure] bonds = \"point\": only the exact law has bonds per material point; the cone-wise "
                     "law (--form cone) fuses whole cells (remove the key or use --form cell)");
  refuse_beyond_memory_of(scene, law, options.scene_file.string());
  // Positions are in the law's unit (its cell size), so the check waits for it.
  if (const std::string free = free_rigid_motion(scene, scene.nx * scene.cell_size, scene.ny * scene.cell_size);
      !free.empty())
    throw InputError(options.scene_file.string() + ": the edges and supports leave a rigid-body motion free, " + free);
  Progress progress("dualcell-structure", options.progress);
  structure::HomogenisedStructure structure(scene, law);
  structure.set_progress(&progress);
  const auto& mesh = structure.mesh();
  summary.n_nodes = static_cast<int>(mesh.nodes.rows());
  summary.n_triangles = static_cast<int>(mesh.triangles.rows());
  summary.n_cells = scene.nx * scene.ny;
  summary.first_fuse_factor = structure.first_fuse_factor();
  for (std::size_t k = 0; k < scene.factors.size(); ++k) {
    summary.steps.push_back(structure.solve_step(scene.factors[k]));
    const auto& s = summary.steps.back();
    char line[200];
    std::snprintf(line, sizeof line,
                  "step %zu/%zu factor %g: %d Newton steps, %d newly %s, %d/%d triangles open/closed, %s", k + 1,
                  scene.factors.size(), s.factor, s.newton_steps, law.cell ? s.newly_broken_units : s.newly_fused_cells,
                  !law.cell                                           ? "fused cells"
                  : scene.bond_unit == StructureScene::BondUnit::cell ? "broken cells"
                                                                      : "broken points",
                  s.open_triangles, s.closed_triangles, s.converged ? "converged" : "NOT converged");
    progress.message(line);
  }
  for (std::uint8_t f : structure.fused_cells()) summary.fused_cells += f;
  summary.n_units = structure.n_units();
  if (law.cell) summary.broken_units = structure.broken_units();
  summary.bond_unit = scene.bond_unit == StructureScene::BondUnit::cell ? "cell" : "point";
  Provenance provenance;
  provenance.scene_text = scene.text;
  provenance.scene_file = options.scene_file.string();
  provenance.law_file = options.law_file.string();
  provenance.law_hash = file_hash(options.law_file);
  io::write_structure(options.out, mesh, summary.steps, summary.first_fuse_factor, summary.law_form,
                      law.cell ? summary.bond_unit : std::string(), provenance);
  summary.seconds = seconds_since(t0);
  return summary;
}

}  // namespace dualcell::stage
