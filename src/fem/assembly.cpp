#include "fem/assembly.hpp"

#include <cmath>
#include <vector>

#include "fem/edge_conditions.hpp"
#include "fem/element.hpp"

namespace dualcell::fem {

namespace {

// Nodes of a boundary edge in edge_shape's order: (a, b) or (a, b, mid).
int edge_nodes(const mesh::Edge& edge, int v[3]) {
  v[0] = edge.a, v[1] = edge.b, v[2] = edge.mid;
  return edge.mid >= 0 ? 3 : 2;
}

}  // namespace

Eigen::SparseMatrix<double> assemble_stiffness(const mesh::Mesh& mesh, int s, const Material& material) {
  const mesh::Subdomain& sub = mesh.subdomains[s];
  const Eigen::Matrix3d D = plane_strain_D(material);
  const int n = mesh.triangles.width();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(4 * n * n * static_cast<std::size_t>(sub.n_triangles()));
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t) {
    const auto tri = mesh.triangles[t];
    const std::vector<Eigen::Vector2d> x = mesh::triangle_points(mesh, t);
    const Eigen::MatrixXd Ke = element_stiffness(x, D);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
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

void add_edge_traction(const mesh::Mesh& mesh, const mesh::Edge& edge, const Eigen::Vector2d& t_a,
                       const Eigen::Vector2d& t_b, Eigen::VectorXd& f) {
  int v[3];
  const int n = edge_nodes(edge, v);
  const Eigen::Vector2d x[3] = {mesh.nodes[v[0]], mesh.nodes[v[1]], n == 3 ? mesh.nodes[v[2]] : Eigen::Vector2d()};
  add_edge_traction(std::span<const Eigen::Vector2d>(x, n), std::span<const int>(v, n), t_a, t_b, f);
}

std::array<double, 3> edge_weights(std::span<const Eigen::Vector2d> x) {
  const int n = static_cast<int>(x.size());
  std::array<double, 3> w{0, 0, 0};
  for (const EdgePoint& q : edge_rule()) {
    double phi[3], dphi[3];
    edge_shape(n, q.s, phi, dphi);
    Eigen::Vector2d dx = Eigen::Vector2d::Zero();
    for (int i = 0; i < n; ++i) dx += dphi[i] * x[i];
    for (int i = 0; i < n; ++i) w[i] += q.weight * dx.norm() * phi[i];
  }
  return w;
}

Eigen::Matrix2d edge_moment(const mesh::Mesh& mesh, const mesh::Edge& edge, const Eigen::VectorXd& u) {
  // n ds = (y'(s), −x'(s)) ds for an edge oriented counter-clockwise; the integrand is a
  // polynomial of degree ≤ 3, so the rule is exact.
  int v[3];
  const int n = edge_nodes(edge, v);
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
  for (const EdgePoint& q : edge_rule()) {
    double phi[3], dphi[3];
    edge_shape(n, q.s, phi, dphi);
    Eigen::Vector2d dx = Eigen::Vector2d::Zero(), u_q = Eigen::Vector2d::Zero();
    for (int i = 0; i < n; ++i) {
      dx += dphi[i] * mesh.nodes[v[i]];
      u_q += phi[i] * u.segment<2>(2 * v[i]);
    }
    H += q.weight * u_q * Eigen::Vector2d(dx.y(), -dx.x()).transpose();
  }
  return H;
}

namespace {

// Adds to f, per node i of every triangle of subdomain s and quadrature point (the 6-point
// rule), force(w, φ_i, B_i): w the point's weight times |det J|, B_i node i's two columns of B.
template <class Force>
void add_volume_load(const mesh::Mesh& mesh, int s, Eigen::VectorXd& f, Force&& force) {
  const mesh::Subdomain& sub = mesh.subdomains[s];
  const int n = mesh.triangles.width();
  for (int t = sub.triangle_begin; t < sub.triangle_end; ++t) {
    const auto tri = mesh.triangles[t];
    const std::vector<Eigen::Vector2d> x = mesh::triangle_points(mesh, t);
    for (const TrianglePoint& q : triangle_rule()) {
      double phi[6], dL1[6], dL2[6], det_J;
      triangle_shape(n, q.L1, q.L2, phi, dL1, dL2);
      const Eigen::MatrixXd B = strain_displacement_at(x, q.L1, q.L2, det_J);
      const double w = q.weight * std::abs(det_J);
      for (int i = 0; i < n; ++i) f.segment<2>(2 * tri[i]) += force(w, phi[i], B.middleCols<2>(2 * i));
    }
  }
}

}  // namespace

void add_body_force(const mesh::Mesh& mesh, int s, const Eigen::Vector2d& body_force, Eigen::VectorXd& f) {
  add_volume_load(mesh, s, f, [&](double w, double phi, const auto&) { return ((w * phi) * body_force).eval(); });
}

void add_eigen_stress(const mesh::Mesh& mesh, int s, const Eigen::Vector3d& sigma0, Eigen::VectorXd& f) {
  add_volume_load(mesh, s, f,
                  [&](double w, double, const auto& B_i) { return (-w * (B_i.transpose() * sigma0)).eval(); });
}

ElementStresses element_stresses(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                 const Eigen::VectorXd& u, const Uniform& z) {
  const PhaseStiffness stiff_fibre = phase_stiffness(fibre), stiff_matrix = phase_stiffness(matrix);
  const std::size_t T = mesh.triangles.size();
  const int n = mesh.triangles.width();
  ElementStresses out{Eigen::MatrixXd(T, 3), Eigen::MatrixXd(T, 3), Eigen::VectorXd(T), Eigen::VectorXd(T)};
  Eigen::VectorXd ue(2 * n);
  for (std::size_t t = 0; t < T; ++t) {
    const auto tri = mesh.triangles[t];
    for (int v = 0; v < n; ++v) ue.segment<2>(2 * v) = u.segment<2>(2 * tri[v]);
    const bool is_fibre = mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre;
    const PhaseStiffness& P = is_fibre ? stiff_fibre : stiff_matrix;
    const Eigen::Matrix3d& D = P.D;
    const Eigen::Vector3d sigma0 = eigen_stress(P, z);
    const std::vector<Eigen::Vector2d> x = mesh::triangle_points(mesh, static_cast<int>(t));
    double det_J;
    const Eigen::Vector3d e_centroid = strain_displacement_at(x, 1.0 / 3, 1.0 / 3, det_J) * ue;
    out.centroid.row(t) = (D * e_centroid).transpose();
    if (!z.zero()) out.centroid.row(t) += sigma0.transpose();
    const auto zz = [&](const Eigen::Vector3d& e) { return stress_zz(P, e, z); };
    if (n == 3) {
      out.average.row(t) = out.centroid.row(t);
      out.area(t) = std::abs(det_J) / 2;
      out.zz_average(t) = zz(e_centroid);
      continue;
    }
    Eigen::Vector3d integral = Eigen::Vector3d::Zero(), strain = Eigen::Vector3d::Zero();
    double area = 0;
    for (const TrianglePoint& q : triangle_rule()) {
      const Eigen::MatrixXd B = strain_displacement_at(x, q.L1, q.L2, det_J);
      const Eigen::Vector3d e = B * ue;
      integral += (q.weight * std::abs(det_J)) * (D * e);
      strain += (q.weight * std::abs(det_J)) * e;
      area += q.weight * std::abs(det_J);
    }
    out.average.row(t) = (integral / area).transpose();
    if (!z.zero()) out.average.row(t) += sigma0.transpose();
    out.area(t) = area;
    out.zz_average(t) = zz(strain / area);
  }
  return out;
}

}  // namespace dualcell::fem
