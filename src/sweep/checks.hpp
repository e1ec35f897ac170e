#pragma once
// The sweep's checks of the exact law and the cell on a basis of its own solutions: the solves a
// sweep runs besides its paths, so that the fit can hold the law to the full solver where the
// paths alone do not reach (docs/theory/exact-law.md §16a, docs/theory/small-cell.md §16c).
#include <vector>

#include "core/progress.hpp"
#include "core/scene.hpp"
#include "feti/solver.hpp"
#include "law/onset.hpp"
#include "mesh/mesh.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::sweep {

// The solutions, along sphere directions (sphere_directions), whose interface forces are the
// columns of /cell_basis: the fit's greedy picks up to 32 rows from this cell's own solutions.
inline constexpr int basis_solutions = 64;

// The cell on the interface forces of basis_solutions full solves along sphere directions, at the
// sphere paths' load (the law is homogeneous: any load gives the same columns), into
// header.cell_basis, or header.cell_basis_note saying why not; the solves' progress on a line of
// its own when `show`.
void build_basis(feti::ContactSolver& solver, const Scene& scene, SweepHeader& header, bool show);

// The exact law's checks along the fibres (/longitudinal_check): full solves of generalised plane
// strain below every strength, and past the fuse from the intact cell (details at the definition).
std::vector<LongitudinalPoint> longitudinal_points(feti::ContactSolver& solver, const Scene& scene,
                                                   const std::vector<PathSpec>& specs, const law::OnsetSurface& onset);

// The exact law's checks of the shear along the fibres (/shear_check): the one-body antiplane
// solve's cascade along four paths of Γ (details at the definition).
std::vector<ShearPoint> shear_points(const mesh::Mesh& mesh, const Scene& scene);

}  // namespace dualcell::sweep
