#pragma once
// Subdomain assembly (docs/method.md §3): each subdomain i gets its own stiffness K_i, its rigid-body
// kernel R_i and its slice of the load vector f. DOFs are node-interleaved and global DOF
// 2·node + c (c = 0: x, 1: y); subdomain i owns the contiguous range
// [2·node_begin, 2·node_end), so K = diag(K_1..K_s) is never formed as one matrix.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::fem {

// K_i of subdomain `s` with material `material`, in the subdomain's local DOF numbering.
Eigen::SparseMatrix<double> assemble_stiffness(const mesh::Mesh& mesh, int s, const Material& material);

// R_i: orthonormal basis (dim_i × 3) of ker K_i: two translations and the rotation about the
// subdomain's node centroid (a far-away rotation centre would make the rotation column nearly parallel to the
// translations); with the
// centroid as centre the three columns are orthogonal before normalisation.
Eigen::MatrixXd rigid_body_modes(const mesh::Mesh& mesh, int s);

// Consistent nodal forces of a traction varying linearly from t_a at node a to t_b at node b
// along the straight edge (a, b), added to the global vector f (size dim u).
void add_edge_traction(const mesh::Mesh& mesh, int a, int b, const Eigen::Vector2d& t_a, const Eigen::Vector2d& t_b,
                       Eigen::VectorXd& f);

// Consistent nodal forces of a constant body force (per unit area) over subdomain s.
void add_body_force(const mesh::Mesh& mesh, int s, const Eigen::Vector2d& body_force, Eigen::VectorXd& f);

// Constant stress of every triangle of the mesh (Voigt: σxx, σyy, σxy) from the global
// displacement u, using each triangle's subdomain material.
Eigen::MatrixXd element_stresses(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                 const Eigen::VectorXd& u);

}  // namespace dualcell::fem
