#pragma once
// Plane-strain linear (constant-strain) triangle (docs/method.md §1, §3).
// Pure functions: coordinates and material in, element matrices out; no assembly here.
//
//   D  = E(1-ν)/((1+ν)(1-2ν)) [[1, ν/(1-ν), 0], [ν/(1-ν), 1, 0], [0, 0, (1-2ν)/(2(1-ν))]]
//   ε  = B_e u_e    (Voigt: εxx, εyy, γxy = 2εxy, engineering shear)
//   K_e = A Bᵀ D B  (unit thickness)
// Element DOFs are node-interleaved: (u0x, u0y, u1x, u1y, u2x, u2y).
#include <Eigen/Core>

#include "core/scene.hpp"

namespace dualcell::fem {

using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Matrix66 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Plane-strain elasticity matrix D (Voigt, engineering shear).
Eigen::Matrix3d plane_strain_D(const Material& material);

// Strain-displacement matrix B_e of the triangle (p0, p1, p2); returns its signed area in `area`.
Matrix36 strain_displacement(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                             double& area);

// Element stiffness K_e = |A| B_eᵀ D B_e.
Matrix66 triangle_stiffness(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                            const Eigen::Matrix3d& D);

}  // namespace dualcell::fem
