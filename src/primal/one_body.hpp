#pragma once
// Reference primal solver for the bonded case: the block as ONE body (coinciding nodes merged,
// Dirichlet DOFs eliminated with their prescribed values lifted, periodic nodes expressed
// through their masters and the macro strain), K_red = Tᵀ K T solved by CHOLMOD with iterative refinement in long
// double. Built from the mesh directly, not from B, so it shares no constraint code with the dual solver: the tests use
// it as an independent oracle, the benchmark as the linear-solve floor.
#include <Eigen/Core>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::primal {

// u over all global DOFs (dim u, + 3 macro DOFs εxx, εyy, γxy when periodic). With `holes` the
// fibres are left out (their DOFs stay 0): the block is the matrix with empty holes.
// `refine` = false skips the long-double refinement (the benchmark times one factorise+solve).
// `seconds_factorise_solve`, when given, receives the wall time of CHOLMOD's analyse,
// factorise and first solve alone (not the merging of nodes or the assembly of K_red).
// With Boundary::edges, `load_factor` scales the prescribed displacements (f is already scaled).
Eigen::VectorXd solve_one_body(const mesh::Mesh& m, const Scene& scene, const Eigen::VectorXd& f, bool holes = false,
                               bool refine = true, double* seconds_factorise_solve = nullptr, double load_factor = 1.0);

}  // namespace dualcell::primal
