#pragma once
// The debond onset surface of a bonded cell (docs/method.md §11). While every bond holds and
// every normal row has a strength, the cell is linear: each bond force is λ_r(σ̄) = a_r·σ̄ with
// a_r from three unit solves. Each strength bound (υ_r > 0 above, ℓ_r < 0 below) gives a facet
//
//   g·σ̄ ≤ 1,     g = a_r/υ_r  or  g = a_r/ℓ_r,
//
// and the stresses every bond carries form the convex polytope {σ̄ : g_k·σ̄ ≤ 1 for all k}.
// Along a unit stress N the first bond reaches its strength at s* = 1/max_k g_k·N. A structure
// evaluates φ(σ̄) = max_k g_k·σ̄ per cell: the cell's bonds start to break where φ reaches 1.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace dualcell::law {

struct OnsetSurface {
  Eigen::MatrixXd facets;       // K×3: rows g_k in (σxx, σyy, σxy), 1/stress
  std::vector<int> pair;        // interface node pair of each facet's bond
  std::vector<int> tangential;  // 1: a tangential strength bound, 0: a normal one
  // False (and no facets) when the bonded cell is not linear (normal rows without a normal
  // strength stay contact rows) or has no adhesion; `message` says why.
  bool linear = false;
  std::string message;
  // Checked against the sweep, one entry per sweep path: the signed unit stress sign·N, the
  // onset the polytope predicts along it, and the one the sweep solved for that path (NaN
  // where the path recorded none).
  std::vector<Eigen::Vector3d> path_stress;
  std::vector<double> path_onset, path_sweep_onset;
};

// φ(σ̄) = max_k g_k·σ̄: below 1 every bond holds (NaN for a surface that is not linear; −inf
// without facets).
double onset_measure(const OnsetSurface& surface, const Eigen::Vector3d& sigma);

// How well the surface predicts the onsets the sweep found: the largest relative difference
// over the swept paths that debonded, and how many those were (0, 0 when none did).
struct OnsetCheck {
  double worst_relative = 0;
  int paths = 0;
};
OnsetCheck check_against_sweep(const OnsetSurface& surface);

// s* along the unit stress N: 1/φ(N), +inf where no facet faces N, NaN where not linear.
double onset_along(const OnsetSurface& surface, const Eigen::Vector3d& N);

}  // namespace dualcell::law
