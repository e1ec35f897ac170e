#pragma once
// The whole ply's law sampled along strain paths, and a compact law measured on them
// (docs/method.md §16e): what a 3D element gets wrong with the small cell at strains the exact
// law really takes, all six components at once.
//
// Directions: n unit vectors ν of the six stresses (xx, yy, xy, zz, xz, yz), drawn from a fixed
// seed (the same on every machine), each turned into a strain direction d = C_o⁻¹ ν with C_o the
// open cell's 6 × 6 stiffness (every pair free: σ̄ = C₀(ε̄ − A33 ε33), σ33 = −A33·σ̄ + C33 ε33,
// τ = D0z Γ), so that the stress of each component is of the order of the others along every
// path (a strain of the same size in each would load σ33 with the fibres' modulus, tens of times
// the rest). Along d, from the intact cell, strain-driven with its history:
//   without adhesion one point, t = 1 (the law is homogeneous of degree one);
//   with adhesion t = ½ t* (bonded), just past t* and in past_fuse_steps steps to
//   past_fuse_load_ratio · t*, where t* is the onset along d: the first bond (in the plane or
//   along z) at its strength, 1/(strength use) of the lifted cell at t = 1.
// A compact law is evaluated the same way along the same strains; a direction's error is the
// largest over its points of ‖σ_compact − σ_exact‖/‖σ_exact‖ (the six components, shears once).
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/fields.hpp"
#include "law/condensed.hpp"

namespace dualcell::law {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The open cell's 6 × 6 stiffness C_o above (the cell must carry longitudinal = 1 and shear = 2).
Matrix6d open_ply_stiffness(const CondensedCell& cell);

struct PlySample {
  std::vector<Vector6d> direction;                    // ν, unit
  std::vector<std::vector<Vector6d>> strain, stress;  // per direction its points (none: the exact law failed)
  std::vector<int> bonded_points;                     // per direction, how many of its first points are bonded
};
// n directions from `seed` (two seeds give two independent samples: training and check).
PlySample sample_ply(const CondensedCell& cell, int n, unsigned seed);

// A compact law of the whole ply against the exact law: along the paths of a check sample
// (check_ply), and what its fit of the strain along the fibres left on its own training points
// (fit::fit_small_ply; NaN where nothing was fitted).
struct PlyCheck {
  int directions = 0, points = 0;  // measured (directions with points)
  double max_error = 0, rms_error = 0;
  double bonded_max_error = 0;        // over the points below the onset (0 without adhesion)
  Vector6d worst = Vector6d::Zero();  // ν of max_error
  int training_points = 0;
  double training_max_error = std::numeric_limits<double>::quiet_NaN();
  double training_rms_error = std::numeric_limits<double>::quiet_NaN();
};
// Its members, listed once (core/fields.hpp): law.h5's /law/small_ply_check and the JSON.
inline constexpr Field<PlyCheck, int, double, Vector6d> ply_check_fields[] = {
    {"directions", &PlyCheck::directions},
    {"points", &PlyCheck::points},
    {"max_error", &PlyCheck::max_error},
    {"rms_error", &PlyCheck::rms_error},
    {"bonded_max_error", &PlyCheck::bonded_max_error},
    {"training_points", &PlyCheck::training_points},
    {"training_max_error", &PlyCheck::training_max_error},
    {"training_rms_error", &PlyCheck::training_rms_error},
    {"worst", &PlyCheck::worst},
};

// The compact law `compact` (a cell with the same macro parts) along the sample's paths.
PlyCheck check_ply(const CondensedCell& compact, const PlySample& sample);

}  // namespace dualcell::law
