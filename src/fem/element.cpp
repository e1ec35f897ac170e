#include "fem/element.hpp"

#include <cmath>

namespace dualcell::fem {

Eigen::Matrix3d plane_strain_D(const Material& m) {
  const double nu = m.nu;
  const double scale = m.E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  Eigen::Matrix3d D;
  D << 1, nu / (1 - nu), 0, nu / (1 - nu), 1, 0, 0, 0, (1 - 2 * nu) / (2 * (1 - nu));
  return scale * D;
}

Matrix36 strain_displacement(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                             double& area) {
  // Shape function gradients: ∇N_i = (y_j - y_k, x_k - x_j) / (2A) for (i, j, k) cyclic.
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
