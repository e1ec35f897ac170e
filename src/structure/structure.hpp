#pragma once
// A structure of homogeneous cells (docs/method.md §15): a rectangle of nx × ny cells of the
// fitted cell, each meshed with m × m squares of two triangles (p1 or p2), every element with
// one of two laws of its cell:
// - the cone-wise law (law/cone.hpp) and the fuse: a cell whose average stress leaves the onset
//   surface (law/onset.hpp) switches to the law past the fuse, irreversibly;
// - the exact law (law/condensed.hpp) at every quadrature point, with the bond history of its
//   cell (StructureScene::bond_unit: the cell's debond cascade runs at its mean strain) or of
//   the point itself; a Newton iterate holds every bond state (BondMode::held), and once a step has
//   converged each unit runs its debond cascade; where a bond broke, the step is solved again,
//   until nothing more breaks.
//
// The energy Π(u) = Σ_e ∫ W(ε(u)) dA − fᵀu is convex and piecewise quadratic in the free
// displacements, so Newton's method with the one-sided tangent K_T = Σ ∫ ∇ˢᵀ C(ε) ∇ˢ dA and a
// backtracking line search on Π terminates in finitely many steps. K_T has a fixed pattern:
// CHOLMOD analyses it once and factorises it per Newton step.
//
//   symbol | variable            | meaning
//   -------+---------------------+------------------------------------------------------
//   u      | StepResult::u       | nodal displacements (ux, uy per node)
//   f      | (load vector)       | edge tractions and point loads times the step's factor
//   r      | (residual)          | ∂Π/∂u = internal forces − f over the free DOFs
//   K_T    | (tangent)           | ∂r/∂u over the free DOFs
//   φ      | onset measure       | max_k g_k·σ̄_cell; the cell fuses where φ ≥ 1
#include <Eigen/Core>
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "core/structure_scene.hpp"
#include "law/condensed.hpp"
#include "law/cone.hpp"
#include "law/onset.hpp"

namespace dualcell::structure {

using dualcell::edge_names;
using dualcell::EdgeCondition;
using dualcell::EdgeKind;
using dualcell::PointLoad;
using dualcell::StructureScene;
using dualcell::Support;

// The mesh: nodes on a grid, triangles (3 or 6 nodes: corners counter-clockwise, then the
// mid-sides of (0,1), (1,2), (2,0)), the cell of each triangle.
struct StructureMesh {
  Eigen::Matrix<double, Eigen::Dynamic, 2> nodes;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> triangles;
  std::vector<int> cell;                        // per triangle, i + nx·j
  std::array<std::vector<int>, 4> edge_nodes;   // per edge, its nodes from start to end
  int node_at(const Eigen::Vector2d& x) const;  // −1 when none is there (node_reach of the structure's size)
};
StructureMesh build_structure_mesh(const StructureScene& scene);

// The cell law: the cone-wise law while bonded, the law past the fuse, and the onset surface
// that switches one to the other (not linear: cells never fuse); or, when `cell` is set, the
// exact law, which carries its own bonds and replaces all three.
struct CellLaw {
  law::ConeLaw bonded, debonded;
  law::OnsetSurface onset;
  std::shared_ptr<const law::CondensedCell> cell;
};

struct StepResult {
  double factor = 0;
  Eigen::VectorXd u;                                // 2 per node
  Eigen::Matrix<double, Eigen::Dynamic, 3> stress;  // per triangle, area average (σxx, σyy, σxy)
  // per triangle: the law's open planes at its centroid (bits); exact law: the most open gaps
  // (normal rows at force 0) of its points
  std::vector<std::uint32_t> open;
  std::vector<std::uint8_t> fused;  // per triangle: its cell has fused (exact law: a point of it has a broken bond)
  std::vector<float> broken;        // per triangle, exact law: broken pairs over all pairs, mean of its points
  // The force the constraints exert on the structure, per edge (edge_names) and for the point
  // supports last; a DOF held by two edges (a corner) counts for the first in that order.
  std::array<Eigen::Vector2d, 5> reactions;
  Eigen::Vector2d watch_displacement = Eigen::Vector2d::Zero();
  int newton_steps = 0;  // all fuse rounds of the step
  int fuse_rounds = 0;   // re-solves after new fuses
  int newly_fused_cells = 0;
  int newly_broken_units = 0;  // exact law: units (cells or points, StructureScene::bond_unit) where a bond broke
  // Triangles on each side of the cone at their centroid: some plane open (the stiffer side of
  // that plane), or every plane closed (C_c). Exact law: some interface row of a point of the
  // triangle has an open gap (normal force 0), or none has.
  int open_triangles = 0, closed_triangles = 0;
  double energy = 0;           // Π at the solution
  double energy_decrease = 0;  // Π at the start of the step minus Π at its end
  double residual = 0;         // ‖r‖ / scale at the end
  bool converged = false;
  std::string message;  // why not converged, when a law evaluation failed (empty otherwise)
};

class HomogenisedStructure {
 public:
  HomogenisedStructure(const StructureScene& scene, const CellLaw& law);
  ~HomogenisedStructure();
  // Solves the load step `factor` from the state reached, fuses included (irreversible).
  StepResult solve_step(double factor);
  // t*: the load factor at which the first cell leaves the onset surface, from the unfused,
  // unloaded state (exact: one solve at t = 1, every cell's stress then scales with t). +inf
  // when no cell ever fuses along the load (or the law has no onset surface); NaN when that
  // solve did not converge. The structure's state is left as it was. Exact law: the first
  // bond of any point reaches its strength, from one solve at t = 1 with the strengths lifted
  // (BondMode::lifted: the intact cells are linear in the load, so every force scales with t).
  double first_fuse_factor();
  const StructureMesh& mesh() const;
  const std::vector<std::uint8_t>& fused_cells() const;
  // Exact law: the units (cells or quadrature points, StructureScene::bond_unit) with a broken
  // bond, of n_units().
  int broken_units() const;
  int n_units() const;
  // Shows every Newton iteration (its residual against the tolerance) while a step works; it
  // must outlive the structure's use of it.
  void set_progress(Progress* progress);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dualcell::structure
