#pragma once
// Subdomain assembly (docs/method.md §3): each subdomain i gets its own stiffness K_i, its
// rigid-body kernel R_i and its slice of the load vector f. DOFs are node-interleaved, global
// DOF 2·node + c (c = 0: x, 1: y); subdomain i owns the contiguous range [2·node_begin,
// 2·node_end), so K = diag(K_1..K_s) is never formed as one matrix.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <span>

#include "core/scene.hpp"
#include "fem/element.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::fem {

// K_i of subdomain `s` with material `material`, in the subdomain's local DOF numbering.
Eigen::SparseMatrix<double> assemble_stiffness(const mesh::Mesh& mesh, int s, const Material& material);

// R_i: orthonormal basis (dim_i × 3) of ker K_i: two translations and the rotation about the
// subdomain's node centroid (a far-away rotation centre would make the rotation column nearly
// parallel to the translations); with the centroid as centre the three columns are orthogonal
// before normalisation.
Eigen::MatrixXd rigid_body_modes(const mesh::Mesh& mesh, int s);

// Consistent nodal forces ∫ φ_i t ds of a traction varying linearly (in the edge parameter)
// from t_a at end a to t_b at end b of a boundary edge (2 or 3 nodes), added to the global
// vector f (size dim u): fem::add_edge_traction (edge_conditions.hpp) on the mesh's edge.
void add_edge_traction(const mesh::Mesh& mesh, const mesh::Edge& edge, const Eigen::Vector2d& t_a,
                       const Eigen::Vector2d& t_b, Eigen::VectorXd& f);

// Consistent nodal forces ∫ φ_i b dA of a constant body force (per unit area) over subdomain s.
void add_body_force(const mesh::Mesh& mesh, int s, const Eigen::Vector2d& body_force, Eigen::VectorXd& f);

// Consistent nodal forces −∫ Bᵀ σ₀ dA of a constant eigen-stress σ₀ (Voigt) over subdomain s,
// added to f: the load of a stress σ = D ε + σ₀ (generalised plane strain: σ₀ = λ ε33 (1, 1, 0)).
void add_eigen_stress(const mesh::Mesh& mesh, int s, const Eigen::Vector3d& sigma0, Eigen::VectorXd& f);

// ∫ N_p ds over the edge with nodes x (2: straight, 3: a, b, mid on a parabola), per node: the
// consistent nodal weights of a unit line load.
std::array<double, 3> edge_weights(std::span<const Eigen::Vector2d> x);

// ∫ u ⊗ n ds over a boundary edge (n the outward normal of an edge oriented counter-clockwise
// around the domain), from the nodal displacements along it.
Eigen::Matrix2d edge_moment(const mesh::Mesh& mesh, const mesh::Edge& edge, const Eigen::VectorXd& u);

// Stresses of every triangle (Voigt: σxx, σyy, σxy) from the global displacement u, with each
// triangle's subdomain material: at the centroid (L₁ = L₂ = ⅓) and the volume average
// (1/A) ∫ σ dA; the two agree for p1 (constant strain). `area` is each triangle's area. With a
// longitudinal strain ε33 (generalised plane strain) the in-plane stresses carry λ ε33 (1, 1, 0)
// and `zz_average` is the average of σzz = λ (εxx + εyy) + (λ + 2μ) ε33 (plane strain: ε33 = 0).
struct ElementStresses {
  Eigen::MatrixXd centroid;    // T × 3
  Eigen::MatrixXd average;     // T × 3
  Eigen::VectorXd area;        // T
  Eigen::VectorXd zz_average;  // T
};
ElementStresses element_stresses(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                 const Eigen::VectorXd& u, const Uniform& z = {});

}  // namespace dualcell::fem
