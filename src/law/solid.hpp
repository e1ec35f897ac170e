#pragma once
// The 3D material of a fitted law, for codes whose elements are 3D (CalculiX/Abaqus cards, the
// umat's out-of-plane constants; the formats themselves are io/law_export.hpp).
//
// The 3D materials are in the material axes 1 = x, 2 = y (the plane of the cells),
// 3 = z = fibre direction, chosen so that plane-strain elements (ε33 = 0) reproduce the fitted
// plane-strain compliance S_ps exactly. Voigt order (11, 22, 33, 12, 13, 23), engineering shear.
//
//   out of plane, where the law's exact law carries the whole ply (law/ply.hpp), the cell's own
//   constants of the bonded state (with adhesion) or of the contact state of the same sign (without):
//     E3 = the ply's E1, ν31 = its ν12, ν32 = its ν13, G13 = its G12, G23 = its G13
//     (the ply's axis 1 is z, its 2 and 3 are x and y);
//   otherwise (a transverse law, which carries nothing along the fibres) the rule of mixtures
//   (Vf fibre volume fraction, f fibre, m matrix):
//     E3 = Vf E_f + (1 − Vf) E_m,   ν31 = ν32 = Vf ν_f + (1 − Vf) ν_m,
//     1/G13 = 1/G23 = Vf/G_f + (1 − Vf)/G_m,   G = E / (2 (1 + ν));
//   S13 = −ν31/E3, S23 = −ν32/E3, S33 = 1/E3;
//   in plane: ε33 = 0 ⇒ σ33 = −(S13 σ11 + S23 σ22)/S33, so the plane-strain compliance is
//     S_ps,ij = S_ij − S_i3 S_j3 / S33 (i, j ∈ {1, 2}) and the shear row is unchanged, hence
//     S11 = S_ps11 + S13²/S33,  S22 = S_ps22 + S23²/S33,  S12 = S_ps12 + S13 S23/S33,
//     S44 (γ12) = S_ps33,  S14 = S_ps13,  S24 = S_ps23   (no σ33–γ12 coupling: S34 = 0);
//   engineering constants (when S14 = S24 = 0):
//     E1 = 1/S11, E2 = 1/S22, ν12 = −S12 E1, ν13 = −S13 E1, ν23 = −S23 E2, G12 = 1/S44.
//
// The Schur complement of S33 in the 3D S is S_ps, so the 3D compliance is positive definite
// exactly when S_ps is and E3 > 0: an inadmissible fit is refused, not exported.
#include <Eigen/Core>
#include <string>

#include "law/law.hpp"

namespace dualcell::law {

struct OrthotropicConstants {
  double E1 = 0, E2 = 0, E3 = 0, nu12 = 0, nu13 = 0, nu23 = 0, G12 = 0, G13 = 0, G23 = 0;
};

// Normal–shear coupling c = max(|S_ps13|/√(S_ps11 S_ps33), |S_ps23|/√(S_ps22 S_ps33)) up to
// which engineering constants are written (the coupling dropped changes strains by at most
// c relative); above it the full stiffness is written as TYPE=ANISO.
inline constexpr double coupling_tolerance = 1e-6;

// The 3D material of one plane-strain compliance.
struct SolidMaterial {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  Matrix6d S = Matrix6d::Zero();  // 3D compliance (Voigt order above, engineering shear)
  Matrix6d C = Matrix6d::Zero();  // its inverse, the stiffness
  double coupling = 0;            // c above
  bool orthotropic = true;        // c ≤ coupling_tolerance: S14 = S24 = 0 and `constants` hold
  OrthotropicConstants constants;
};

// Builds the 3D material of S_ps (law.tension.S or law.compression.S, named `fit_name`, of the
// sign `sign`: +1 tension, −1 compression) with the law's out-of-plane constants (out_of_plane).
// Refuses with an InputError naming `file` and the object a compliance with NaN entries, an
// asymmetric one, one that is not positive definite, and missing or unphysical constituents.
SolidMaterial solid_material(const Eigen::Matrix3d& S_ps, const Law& law, const std::string& file,
                             const std::string& fit_name, int sign = 1);

// Refuses (InputError naming `file`) constituents that cannot give the out-of-plane constants.
void check_constituents(const Law& law, const std::string& file);

// The out-of-plane constants (formulas above): from the cell where the law carries the whole ply
// (from_cell), by the rule of mixtures otherwise; `sign` chooses the state of a cell without
// adhesion (the contact cell's tension or compression constants).
struct OutOfPlane {
  double E3, nu31, nu32, G13, G23;
  bool from_cell = false;
};
OutOfPlane rule_of_mixtures(const Law& law);
OutOfPlane out_of_plane(const Law& law, int sign = 1);

}  // namespace dualcell::law
