#include "fem/element.hpp"

#include <Eigen/LU>
#include <cmath>

namespace dualcell::fem {

PhaseStiffness phase_stiffness(const Material& m) {
  PhaseStiffness out;
  if (!m.axial) {
    const double nu = m.nu;
    const double scale = m.E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
    Eigen::Matrix3d D;
    D << 1, nu / (1 - nu), 0, nu / (1 - nu), 1, 0, 0, 0, (1 - 2 * nu) / (2 * (1 - nu));
    out.D = scale * D;
    const Lame L = lame(m);
    out.C13 = L.lambda;
    out.C33 = L.lambda + 2 * L.mu;
    out.G_L = L.mu;
    out.beta = (3 * L.lambda + 2 * L.mu) * m.alpha;
    out.beta33 = out.beta;
    return out;
  }
  const double a = -m.nu_LT / m.E_L;
  Eigen::Matrix3d S;
  S << 1 / m.E, -m.nu / m.E, a, -m.nu / m.E, 1 / m.E, a, a, a, 1 / m.E_L;
  const Eigen::Matrix3d C = S.inverse();
  out.D << C(0, 0), C(0, 1), 0, C(0, 1), C(0, 0), 0, 0, 0, m.E / (2 * (1 + m.nu));
  out.C13 = C(0, 2);
  out.C33 = C(2, 2);
  out.G_L = m.G_LT;
  out.beta = (C(0, 0) + C(0, 1)) * m.alpha + C(0, 2) * m.alpha_L;
  out.beta33 = 2 * C(0, 2) * m.alpha + C(2, 2) * m.alpha_L;
  return out;
}

Lame lame(const Material& m) { return {m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu)), m.E / (2 * (1 + m.nu))}; }

Matrix36 strain_displacement(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                             double& area) {
  // Shape function gradients: ∇φ_i = (y_j - y_k, x_k - x_j) / (2A) for (i, j, k) cyclic.
  const double two_area = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p2.x() - p0.x()) * (p1.y() - p0.y());
  area = 0.5 * two_area;
  const double b[3] = {p1.y() - p2.y(), p2.y() - p0.y(), p0.y() - p1.y()};
  const double c[3] = {p2.x() - p1.x(), p0.x() - p2.x(), p1.x() - p0.x()};
  Matrix36 B = Matrix36::Zero();
  for (int i = 0; i < 3; ++i) {
    B(0, 2 * i) = b[i] / two_area;
    B(1, 2 * i + 1) = c[i] / two_area;
    B(2, 2 * i) = c[i] / two_area;
    B(2, 2 * i + 1) = b[i] / two_area;
  }
  return B;
}

Matrix66 triangle_stiffness(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                            const Eigen::Matrix3d& D) {
  double area;
  const Matrix36 B = strain_displacement(p0, p1, p2, area);
  return std::abs(area) * B.transpose() * D * B;
}

}  // namespace dualcell::fem

namespace dualcell::fem {

const std::array<TrianglePoint, 6>& triangle_rule() {
  // Symmetric 6-point rule of degree 4 (docs/method.md §3): two orbits (a, a, 1 − 2a), weights for a
  // reference triangle of area 1 halved to area ½.
  constexpr double a1 = 0.44594849091596488632, w1 = 0.22338158967801146570 / 2;
  constexpr double a2 = 0.09157621350977074346, w2 = 0.10995174365532186764 / 2;
  static const std::array<TrianglePoint, 6> rule{{{a1, a1, w1},
                                                  {1 - 2 * a1, a1, w1},
                                                  {a1, 1 - 2 * a1, w1},
                                                  {a2, a2, w2},
                                                  {1 - 2 * a2, a2, w2},
                                                  {a2, 1 - 2 * a2, w2}}};
  return rule;
}

const std::array<TrianglePoint, 3>& triangle_rule_3() {
  static const std::array<TrianglePoint, 3> rule{
      {{1.0 / 6, 1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 2.0 / 3, 1.0 / 6}}};
  return rule;
}

void triangle_shape(int n, double L1, double L2, double* phi, double* dphi_dL1, double* dphi_dL2) {
  // Barycentric coordinates L0 = 1 − L1 − L2, L1, L2 (L1, L2 also the reference coordinates).
  const double L[3] = {1 - L1 - L2, L1, L2};
  const double dL_dxi[3] = {-1, 1, 0}, dL_deta[3] = {-1, 0, 1};
  if (n == 3) {
    for (int i = 0; i < 3; ++i) {
      phi[i] = L[i];
      dphi_dL1[i] = dL_dxi[i];
      dphi_dL2[i] = dL_deta[i];
    }
    return;
  }
  // Corners φ_i = L_i (2 L_i − 1); mid-side of edge (i, j): φ = 4 L_i L_j.
  for (int i = 0; i < 3; ++i) {
    phi[i] = L[i] * (2 * L[i] - 1);
    dphi_dL1[i] = (4 * L[i] - 1) * dL_dxi[i];
    dphi_dL2[i] = (4 * L[i] - 1) * dL_deta[i];
    const int j = (i + 1) % 3;
    phi[3 + i] = 4 * L[i] * L[j];
    dphi_dL1[3 + i] = 4 * (dL_dxi[i] * L[j] + L[i] * dL_dxi[j]);
    dphi_dL2[3 + i] = 4 * (dL_deta[i] * L[j] + L[i] * dL_deta[j]);
  }
}

Eigen::MatrixXd strain_displacement_at(std::span<const Eigen::Vector2d> x, double L1, double L2, double& det_J) {
  const int n = static_cast<int>(x.size());
  double phi[6], dL1[6], dL2[6];
  triangle_shape(n, L1, L2, phi, dL1, dL2);
  // J = ∂x/∂(L₁, L₂): column 0 = Σ x_i dφ_i/dL₁, column 1 = Σ x_i dφ_i/dL₂.
  Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
  for (int i = 0; i < n; ++i) {
    J.col(0) += x[i] * dL1[i];
    J.col(1) += x[i] * dL2[i];
  }
  det_J = J.determinant();
  const Eigen::Matrix2d J_inv_T = J.inverse().transpose();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 2 * n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d g = J_inv_T * Eigen::Vector2d(dL1[i], dL2[i]);  // ∇φ_i
    B(0, 2 * i) = g.x();
    B(1, 2 * i + 1) = g.y();
    B(2, 2 * i) = g.y();
    B(2, 2 * i + 1) = g.x();
  }
  return B;
}

Eigen::MatrixXd element_stiffness(std::span<const Eigen::Vector2d> x, const Eigen::Matrix3d& D) {
  if (x.size() == 3) return triangle_stiffness(x[0], x[1], x[2], D);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(2 * x.size(), 2 * x.size());
  for (const TrianglePoint& q : triangle_rule()) {
    double det_J;
    const Eigen::MatrixXd B = strain_displacement_at(x, q.L1, q.L2, det_J);
    K.noalias() += (q.weight * std::abs(det_J)) * B.transpose() * D * B;
  }
  return K;
}

double element_area(std::span<const Eigen::Vector2d> x) {
  double area = 0;
  for (const TrianglePoint& q : triangle_rule()) {
    double det_J;
    strain_displacement_at(x, q.L1, q.L2, det_J);
    area += q.weight * std::abs(det_J);
  }
  return area;
}

void edge_shape(int n, double s, double* phi, double* dphi_ds) {
  if (n == 2) {
    phi[0] = 1 - s, phi[1] = s;
    dphi_ds[0] = -1, dphi_ds[1] = 1;
    return;
  }
  phi[0] = (1 - s) * (1 - 2 * s), phi[1] = s * (2 * s - 1), phi[2] = 4 * s * (1 - s);
  dphi_ds[0] = 4 * s - 3, dphi_ds[1] = 4 * s - 1, dphi_ds[2] = 4 - 8 * s;
}

const std::array<EdgePoint, 5>& edge_rule() {
  // Gauss–Legendre on [−1, 1] mapped to [0, 1]: s = (1 + x)/2, weight w/2.
  constexpr double x1 = 0.53846931010568309104, x2 = 0.90617984593866399280;
  constexpr double w0 = 128.0 / 225, w1 = 0.47862867049936646804, w2 = 0.23692688505618908751;
  static const std::array<EdgePoint, 5> rule{
      {{(1 - x2) / 2, w2 / 2}, {(1 - x1) / 2, w1 / 2}, {0.5, w0 / 2}, {(1 + x1) / 2, w1 / 2}, {(1 + x2) / 2, w2 / 2}}};
  return rule;
}

}  // namespace dualcell::fem
