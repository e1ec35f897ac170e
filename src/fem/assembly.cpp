#include "fem/assembly.hpp"

#include <cmath>
#include <vector>

#include "fem/element.hpp"

namespace dualcell::fem {

Eigen::SparseMatrix<double> assemble_stiffness(const mesh::Mesh& mesh, int s, const Material& material) {
  const mesh::Subdomain& sub = mesh.subdomains[s];
  const Eigen::Matrix3d D = plane_strain_D(material);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(36 * static_cast<std::size_t>(sub.n_triangles()));
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t) {
    const auto& tri = mesh.triangles[t];
    const Matrix66 Ke = triangle_stiffness(mesh.nodes[tri[0]], mesh.nodes[tri[1]], mesh.nodes[tri[2]], D);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int ca = 0; ca < 2; ++ca)
          for (int cb = 0; cb < 2; ++cb)
            triplets.emplace_back(2 * (tri[a] - sub.node_begin) + ca, 2 * (tri[b] - sub.node_begin) + cb,
                                  Ke(2 * a + ca, 2 * b + cb));
  }
  const int dim = 2 * sub.n_nodes();
  Eigen::SparseMatrix<double> K(dim, dim);
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

Eigen::MatrixXd rigid_body_modes(const mesh::Mesh& mesh, int s) {
  const mesh::Subdomain& sub = mesh.subdomains[s];
  const int n = sub.n_nodes();
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int v = sub.node_begin; v < sub.node_end; ++v) centroid += mesh.nodes[v];
  centroid /= n;
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2 * n, 3);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector2d x = mesh.nodes[sub.node_begin + v] - centroid;
    R(2 * v, 0) = 1;
    R(2 * v + 1, 1) = 1;
    R(2 * v, 2) = -x.y();
    R(2 * v + 1, 2) = x.x();
  }
  for (int c = 0; c < 3; ++c) R.col(c).normalize();
  return R;
}

void add_edge_traction(const mesh::Mesh& mesh, int a, int b, const Eigen::Vector2d& t_a, const Eigen::Vector2d& t_b,
                       Eigen::VectorXd& f) {
  // ∫ N_a t ds = L (2 t_a + t_b) / 6 for linear N and linear t on an edge of length L.
  const double L = (mesh.nodes[b] - mesh.nodes[a]).norm();
  const Eigen::Vector2d fa = L * (2 * t_a + t_b) / 6;
  const Eigen::Vector2d fb = L * (t_a + 2 * t_b) / 6;
  f.segment<2>(2 * a) += fa;
  f.segment<2>(2 * b) += fb;
}

void add_body_force(const mesh::Mesh& mesh, int s, const Eigen::Vector2d& body_force, Eigen::VectorXd& f) {
  const mesh::Subdomain& sub = mesh.subdomains[s];
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t) {
    const double share = std::abs(mesh::triangle_area(mesh, t)) / 3;
    for (int v : mesh.triangles[t]) f.segment<2>(2 * v) += share * body_force;
  }
}

Eigen::MatrixXd element_stresses(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                 const Eigen::VectorXd& u) {
  const Eigen::Matrix3d D_fibre = plane_strain_D(fibre), D_matrix = plane_strain_D(matrix);
  Eigen::MatrixXd stress(mesh.triangles.size(), 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    double area;
    const Matrix36 B = strain_displacement(mesh.nodes[tri[0]], mesh.nodes[tri[1]], mesh.nodes[tri[2]], area);
    Vector6 ue;
    for (int v = 0; v < 3; ++v) ue.segment<2>(2 * v) = u.segment<2>(2 * tri[v]);
    const bool is_fibre = mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre;
    stress.row(t) = ((is_fibre ? D_fibre : D_matrix) * (B * ue)).transpose();
  }
  return stress;
}

}  // namespace dualcell::fem
