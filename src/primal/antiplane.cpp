#include "primal/antiplane.hpp"

#include <Eigen/SparseCore>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/union_find.hpp"
#include "fem/element.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::primal {

LongitudinalShear longitudinal_shear(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                     const std::vector<char>& bonded) {
  if (!bonded.empty() && bonded.size() != mesh.interface_pairs.size())
    throw std::invalid_argument("longitudinal_shear: " + std::to_string(bonded.size()) + " bond states for " +
                                std::to_string(mesh.interface_pairs.size()) + " interface pairs");
  // The body's points: periodic partners one point (w̃ periodic), a bonded pair one point.
  UnionFind points(mesh.n_points());
  for (const mesh::PeriodicPair& pair : mesh.periodic_pairs) points.join(pair.point, pair.partner);
  for (std::size_t p = 0; p < mesh.interface_pairs.size(); ++p)
    if (bonded.empty() || bonded[p]) {
      const auto [f, m] = mesh.interface_pairs[p];
      points.join(mesh.point_of[f], mesh.point_of[m]);
    }
  // Unknowns: one per body point; pieces: the body points an element connects.
  std::vector<int> unknown(mesh.n_points(), -1);
  int n = 0;
  for (int q = 0; q < mesh.n_points(); ++q)
    if (points.find(q) == q) unknown[q] = n++;
  const auto dof = [&](int node) { return unknown[points.find(mesh.point_of[node])]; };
  UnionFind pieces(n);
  const double mu_fibre = fem::lame(fibre).mu, mu_matrix = fem::lame(matrix).mu;
  const int nodes = mesh.triangles.width();
  // Every quadrature point of every triangle: point(tri, w, ∇φ) with w its weight times |det J|
  // times the phase's μ, and ∇φ (2 × nodes) the shape functions' gradients (rows 0 and 1 of B at
  // each node's x and y columns).
  const auto for_each_point = [&](auto&& point) {
    Eigen::Matrix2Xd grad_phi(2, nodes);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto tri = mesh.triangles[t];
      const double mu = mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre ? mu_fibre : mu_matrix;
      const std::vector<Eigen::Vector2d> x = mesh::triangle_points(mesh, static_cast<int>(t));
      for (const fem::TrianglePoint& q : fem::triangle_rule()) {
        double det_J;
        const Eigen::MatrixXd B = fem::strain_displacement_at(x, q.L1, q.L2, det_J);
        for (int i = 0; i < nodes; ++i) grad_phi.col(i) = Eigen::Vector2d(B(0, 2 * i), B(1, 2 * i + 1));
        point(tri, q.weight * std::abs(det_J) * mu, grad_phi);
      }
    }
  };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n, 2);  // −∫ μ ∇φ·Γ dA for Γ = e_x, e_y
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int i = 1; i < nodes; ++i) pieces.join(dof(mesh.triangles[t][0]), dof(mesh.triangles[t][i]));
  for_each_point([&](const auto& tri, double w, const Eigen::Matrix2Xd& grad_phi) {
    for (int i = 0; i < nodes; ++i) {
      f.row(dof(tri[i])) -= w * grad_phi.col(i).transpose();
      for (int j = 0; j < nodes; ++j)
        entries.emplace_back(dof(tri[i]), dof(tri[j]), w * grad_phi.col(i).dot(grad_phi.col(j)));
    }
  });
  // One held unknown per piece (w̃ = 0 there): the others are solved for.
  std::vector<int> free_index(n, -1);
  std::vector<char> held(n, 0);
  int n_free = 0;
  for (int d = 0; d < n; ++d)
    if (pieces.find(d) == d) held[d] = 1;
  for (int d = 0; d < n; ++d)
    if (!held[d]) free_index[d] = n_free++;
  std::vector<Eigen::Triplet<double>> kept;
  kept.reserve(entries.size());
  for (const auto& e : entries)
    if (!held[e.row()] && !held[e.col()]) kept.emplace_back(free_index[e.row()], free_index[e.col()], e.value());
  Eigen::SparseMatrix<double> K(n_free, n_free);
  K.setFromTriplets(kept.begin(), kept.end());
  linalg::SparseCholesky cholesky;
  if (const linalg::CholeskyStatus status = cholesky.compute(K); status != linalg::CholeskyStatus::ok)
    throw std::runtime_error("longitudinal_shear: the factorisation failed: " + std::string(linalg::to_string(status)));
  LongitudinalShear out;
  out.w_tilde = Eigen::MatrixXd::Zero(mesh.n_nodes(), 2);
  Eigen::VectorXd b(n_free), z(n_free);
  for (int c = 0; c < 2; ++c) {
    for (int d = 0; d < n; ++d)
      if (!held[d]) b(free_index[d]) = f(d, c);
    cholesky.solve(b, z);
    for (int v = 0; v < mesh.n_nodes(); ++v) {
      const int d = dof(v);
      out.w_tilde(v, c) = held[d] ? 0.0 : z(free_index[d]);
    }
  }
  // G_cd = (1/|Ω|) Σ ∫ μ (e_c + ∇w̃_c)·(e_d + ∇w̃_d) dA: the energy form, symmetric by
  // construction; at the discrete solution it is ⟨τ⟩ of unit shear d along c (∫ μ ∇φ·(e_d + ∇w̃_d)
  // vanishes on every unknown: the Galerkin equations).
  for_each_point([&](const auto& tri, double w, const Eigen::Matrix2Xd& grad_phi) {
    Eigen::Matrix2d grad = Eigen::Matrix2d::Identity();  // column c: Γ + ∇w̃ of unit shear c
    for (int i = 0; i < nodes; ++i) grad += grad_phi.col(i) * out.w_tilde.row(tri[i]);
    out.G += w * grad.transpose() * grad;
  });
  // Averaged with its transpose: symmetric to the last bit, not only to round-off.
  out.G = (out.G + out.G.transpose()).eval() / (2 * mesh.block_width() * mesh.block_height());
  return out;
}

}  // namespace dualcell::primal
