#pragma once
// Plane-strain triangles (docs/method.md §1, §3): the linear 3-node triangle (p1, constant
// strain) and the quadratic isoparametric 6-node triangle (p2). Pure functions: coordinates and
// material in, element matrices out; no assembly here.
//
//   D  = E(1-ν)/((1+ν)(1-2ν)) [[1, ν/(1-ν), 0], [ν/(1-ν), 1, 0], [0, 0, (1-2ν)/(2(1-ν))]]
//   ε  = ∇ˢ u_e     (Voigt: εxx, εyy, γxy = 2εxy, engineering shear; ∇ˢ the 3 × 2n
//                    strain-displacement matrix of the element's n nodes)
//   K_e = ∫ ∇ˢᵀ D ∇ˢ dA  (unit thickness): exact A ∇ˢᵀ D ∇ˢ for p1; for p2 the 6-point
//                    degree-4 rule on the reference triangle with the isoparametric map x(L₁, L₂)
//                    (exact for straight-sided elements, whose integrand is of degree 2)
// Element DOFs are node-interleaved: (u0x, u0y, u1x, u1y, ...), nodes in the order of
// mesh::Triangles (corners, then mid-sides of (0,1), (1,2), (2,0)).
#include <Eigen/Core>
#include <array>
#include <span>

#include "core/scene.hpp"

namespace dualcell::fem {

using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Matrix66 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// A phase's stiffness in generalised plane strain (a uniform ε33 along the fibres, docs/method.md
// §3a) and in the shear along them: the in-plane stress is D ε + C13 ε33 (1, 1, 0), σzz =
// C13 (εxx + εyy) + C33 ε33, and the shear along the fibres τ = G_L ∇w. Isotropic: D the
// plane-strain matrix, C13 = λ, C33 = λ + 2μ, G_L = μ (Lamé's constants, lame below).
// Transversely isotropic about z: the inverse of the normal compliance
//   [1/E, −ν/E, −ν_LT/E_L; −ν/E, 1/E, −ν_LT/E_L; −ν_LT/E_L, −ν_LT/E_L, 1/E_L]
// gives C11 = C22, C12, C13, C33; D = [C11, C12, 0; C12, C11, 0; 0, 0, E/(2(1+ν))], G_L = G_LT.
// A temperature change ΔT adds the thermal strain (α_T, α_T, 0 | α_L) to be subtracted: the
// in-plane stress gains −ΔT β (1, 1, 0) and σzz gains −ΔT β33, with β = (C11 + C12) α_T + C13 α_L
// and β33 = 2 C13 α_T + C33 α_L (isotropic: both 3Kα, K the bulk modulus; docs/theory/model.md §1a).
struct PhaseStiffness {
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();  // Voigt, engineering shear
  double C13 = 0, C33 = 0, G_L = 0;
  double beta = 0, beta33 = 0;  // the thermal stress per kelvin, in the plane and along z
};
PhaseStiffness phase_stiffness(const Material& material);

// What a cell's phases feel uniformly besides the in-plane strain: the strain ε33 along the
// fibres (generalised plane strain, docs/method.md §3a) and the temperature change ΔT.
struct Uniform {
  double eps33 = 0, delta_T = 0;
  bool zero() const { return eps33 == 0 && delta_T == 0; }
};
// The phase's in-plane eigen-stress σ0 = (C13 ε33 − β ΔT)(1, 1, 0) (the stress of ε = 0) and its σzz
// at the in-plane strain e: C13 (exx + eyy) + C33 ε33 − β33 ΔT.
inline Eigen::Vector3d eigen_stress(const PhaseStiffness& P, const Uniform& z) {
  return (P.C13 * z.eps33 - P.beta * z.delta_T) * Eigen::Vector3d(1, 1, 0);
}
inline double stress_zz(const PhaseStiffness& P, const Eigen::Vector3d& e, const Uniform& z) {
  return P.C13 * (e(0) + e(1)) + P.C33 * z.eps33 - P.beta33 * z.delta_T;
}

// Its plane-strain matrix D alone.
inline Eigen::Matrix3d plane_strain_D(const Material& material) { return phase_stiffness(material).D; }

// Lamé's constants of an isotropic material: λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)).
struct Lame {
  double lambda = 0, mu = 0;
};
Lame lame(const Material& material);

// Strain-displacement matrix of the p1 triangle (p0, p1, p2); returns its signed area in `area`.
Matrix36 strain_displacement(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                             double& area);

// Element stiffness K_e = |A| ∇ˢᵀ D ∇ˢ of the p1 triangle.
Matrix66 triangle_stiffness(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                            const Eigen::Matrix3d& D);

// A point of the 6-point degree-4 rule on the reference triangle {L₁, L₂ ≥ 0, L₁ + L₂ ≤ 1}: weights
// sum to the reference area ½.
struct TrianglePoint {
  double L1, L2, weight;
};
const std::array<TrianglePoint, 6>& triangle_rule();
// The 3-point rule of degree 2 at (1/6, 1/6), (2/3, 1/6), (1/6, 2/3), weights 1/6: what CalculiX's
// CPE6 and C3D15 (in the plane) integrate with, for a structure that compares with them.
const std::array<TrianglePoint, 3>& triangle_rule_3();

// Shape functions of the p1 (n = 3) or p2 (n = 6) triangle at (L₁, L₂), and their derivatives
// dφ/dL₁, dφ/dL₂; arrays of length n.
void triangle_shape(int n, double L1, double L2, double* phi, double* dphi_dL1, double* dphi_dL2);

// The isoparametric map at (L₁, L₂) of an element with nodes x (3 or 6): the strain-displacement
// matrix (3 × 2n) and det J (positive for a counter-clockwise element).
Eigen::MatrixXd strain_displacement_at(std::span<const Eigen::Vector2d> x, double L1, double L2, double& det_J);

// Element stiffness of a p1 or p2 element (2n × 2n) with nodes x.
Eigen::MatrixXd element_stiffness(std::span<const Eigen::Vector2d> x, const Eigen::Matrix3d& D);

// Area ∫ dA of a p1 or p2 element (exact: det J is of degree ≤ 2).
double element_area(std::span<const Eigen::Vector2d> x);

// Shape functions of an edge with n = 2 nodes (a, b) or n = 3 (a, b, mid) at s ∈ [0, 1] from a
// to b, and their derivatives d/ds.
void edge_shape(int n, double s, double* phi, double* dphi_ds);
// 5-point Gauss–Legendre rule on [0, 1] (exact to degree 9): the rule of every edge integral.
struct EdgePoint {
  double s, weight;
};
const std::array<EdgePoint, 5>& edge_rule();

}  // namespace dualcell::fem
