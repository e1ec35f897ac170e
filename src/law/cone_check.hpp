#pragma once
// The compact law measured against the exact one (docs/method.md §16a): the cone-wise law fitted
// to the sweep (law/cone.hpp) and the cell condensed onto its interface rows (law/condensed.hpp)
// at directions no sweep needs to have contained, as many as the exact law makes cheap.
//
// Per unit macro stress N of a dense set (the sphere of (σxx, σyy, √2σxy), or the circle of
// (σxx, σyy) for a cell without shear), at the load s = 1 without adhesion (both laws are
// homogeneous) and s = ½ s*(N) with it (below the exact onset: bonded): the exact strain
// ε = ε_cell(sN), the compact law's stress σ_cone(ε) there, and the relative stress error
// ‖σ_cone(ε) − sN‖ / s — what a structure code with the compact law gets wrong at a strain the
// cell really takes.
#include <Eigen/Core>
#include <vector>

#include "law/condensed.hpp"
#include "law/cone.hpp"

namespace dualcell::law {

struct ConeCheck {
  std::vector<Eigen::Vector3d> stress;  // the unit directions N, in the order evaluated
  std::vector<double> error;            // per direction
  double max_error = 0, rms_error = 0;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  // the N of max_error
  // The exact law's apparent plane-strain moduli around the circle (uniaxial n⊗n, n =
  // (cos θ, sin θ), as law::apparent_modulus gives the compact law's), θ = 0, 1, …, 179°.
  std::vector<double> polar_deg, polar_E_tension, polar_E_compression;
};

// About `n` directions (n on the sphere; n/2, at least 180, on the circle without shear),
// ordered along a path so that each evaluation warm-starts from its neighbour.
ConeCheck check_cone_against_cell(const ConeLaw& cone, const CondensedCell& cell, int n = 1000);

}  // namespace dualcell::law
