#pragma once
// Homogenised quantities (docs/method.md §12).
#include <Eigen/Core>
#include <vector>

#include "core/scene.hpp"
#include "fem/assembly.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::feti {

// ε̄ = (1/|Ω|) ∮ sym(u ⊗ n) ds over the block's outer boundary, u interpolated along each
// edge by the edge's shape functions. It counts interface openings, which a volume average of
// element strains misses. Returns (εxx, εyy, εxy) with tensor shear.
Eigen::Vector3d boundary_strain(const mesh::Mesh& mesh, const Eigen::VectorXd& u);
// The same as a matrix: boundary_strain(mesh, u) = W u for every u of size n_dofs (≥ dim u; the
// columns past dim u, the periodic boundary's macro DOFs, are zero). 3 × n_dofs, dense: only the
// exact law's condensation needs it, once per cell.
Eigen::MatrixXd boundary_strain_matrix(const mesh::Mesh& mesh, int n_dofs);

// (1/|Ω|) Σ_e ∫_e σ dA over all triangles: equals the applied σ̄ when the forces are in
// equilibrium (Hill–Mandel); returns (σxx, σyy, σxy). With a longitudinal strain ε33 or a
// temperature change (z) the stresses of generalised plane strain and the thermal stresses
// (fem::element_stresses), and `zz`, when given, receives the average of σzz.
Eigen::Vector3d average_stress(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                               const Eigen::VectorXd& u, const fem::Uniform& z = {}, double* zz = nullptr);

// The fields a solution shows besides u and the pairs' forces (solution.h5, computed here so that
// its writer only writes): every element's stress, at its centroid and its volume average, and
// every interface pair's opening n·(u_m − u_f), > 0 where it is open.
struct SolutionFields {
  fem::ElementStresses stress;
  std::vector<double> opening;
};
SolutionFields solution_fields(const mesh::Mesh& mesh, const Scene& scene, const Eigen::VectorXd& u,
                               const fem::Uniform& z = {});

}  // namespace dualcell::feti
