#pragma once
// The fit stage: from sweep paths to the effective bilinear law (law::Law).
//
//   per direction θ (uniaxial paths), on the points before any bond breaks:
//     E   : ε_nn = s / E, least squares through the origin (GSL gsl_fit_mul on ε_nn = k·s,
//           E = 1/k, se(E) = se(k)/k², R² = 1 − SSR/Σε_nn²)
//     ν   : ε_tt = −ν ε_nn, through the origin (gsl_fit_mul)
//   past the largest jump of the tension path (the fuse): E_after_fuse, the tangent modulus
//     of s against ε_nn with intercept (gsl_fit_linear)
//   over all directions at once: S_tension, S_compression, 3×3 with engineering shear,
//     (εxx, εyy, γxy) = S (σxx, σyy, σxy), S symmetric: 6 unknowns, each point giving 3
//     equations normalised by its load so that every point weighs alike (gsl_multifit_linear,
//     or its truncated SVD when the directions do not determine all six entries: the
//     undetermined entries are NaN).
//   cone-wise linear check (docs/method.md §14): ΔC = S_t⁻¹ − S_c⁻¹ rank-one?
#include <stdexcept>
#include <vector>

#include "core/progress.hpp"
#include "law/law.hpp"
#include "sweep/sweep.hpp"

namespace dualcell::fit {

// The largest exact law (interface rows) against which the compact law is checked on the dense
// sphere of directions; above it the exact law is kept and the compact one checked on held-out
// sweep directions (the dense check's cost grows as rows³: docs/method.md §16a).
inline constexpr int max_checked_rows = 1000;
// Above it (or without an exact law), with the cell on a basis of its own solutions from the
// sweep, every held_out_every-th sphere path is held out of the compact laws as their check, at
// least min_held_out of them: a sweep of fewer than 2·min_held_out sphere paths gets no such
// check and no small cell (docs/method.md §16c).
inline constexpr int held_out_every = 10;
inline constexpr int min_held_out = 50;

// The largest stress error over the sphere the small cell is fitted to (dualcell-fit
// --law-tolerance): m grows until its error over the fit's directions is within it.
inline constexpr double default_law_tolerance = 0.02;

// What the fit makes and how far it checks (dualcell-fit's options).
struct FitOptions {
  int checked_rows = max_checked_rows;           // the dense check's largest exact law (tests lower it)
  double law_tolerance = default_law_tolerance;  // the small cell's (--law-tolerance)
  // false: no small cell (--no-small-cell; Law::small_note says so). With adhesion its ladder is
  // most of a fit (13 of 18 s on a two-fibre RVE); the exact law and the cone-wise laws are
  // fitted and checked as ever.
  bool small_cell = true;
};

// The law of a sweep; its provenance is the sweep's (the caller adds the sweep file and hash).
// `progress`: where the fit's long parts (sampling the exact law, the small cell's ladder) say
// how far they are.
law::Law fit_law(const std::vector<sweep::PathResult>& paths, const sweep::SweepHeader& header,
                 const FitOptions& options = {}, Progress* progress = nullptr);

// The exact law replayed through every converged point of the paths, each path from the unloaded
// cell with its bonds carried (law::CellReplay); the limit is 1e3 × the sweep's QP tolerance.
// Throws ExactLawFailed where the law's QP does not solve a point (fit_law then keeps no exact
// law and says why in Law::cell_note).
struct ExactLawFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// `path_stride`: every path_stride-th path only (replay_stride).
law::CellReplay replay_cell(const law::CondensedCell& cell, const std::vector<sweep::PathResult>& paths,
                            double qp_tolerance, int path_stride = 1);

// The exact law at the sweep's checks of the strain along the fibres (docs/method.md §16a): per
// point the larger of ‖ε̄ − ε̄_solve‖/(‖ε̄_solve‖ + |ε33|) and |σ33 − σ33_solve|/(|σ33_solve| + ‖σ̄‖),
// from the intact cell; limit 1e3 × the QP tolerance, as the replay of the paths.
law::CellReplay replay_longitudinal(const law::CondensedCell& cell, const std::vector<sweep::LongitudinalPoint>& points,
                                    double qp_tolerance);
// The exact law's shear along the fibres against the sweep's one-body checks (sweep::ShearPoint),
// each path replayed from the intact cell with its history: the relative error of ⟨τ⟩ per point
// (worst_path the check's path, worst_step its index) and the points whose broken pairs differ.
law::CellReplay replay_shear(const law::CondensedCell& cell, const std::vector<sweep::ShearPoint>& points,
                             double qp_tolerance);
// The exact law's temperature change (a cell with thermal = 1 and longitudinal = 1) against the
// sweep's full solves of the bonded ply's expansion (feti::ContactSolver::bonded_expansion): the
// law at zero strain and ΔT = 1 with the bonds lifted gives σ_T and the bonded tangent C over
// (εxx, εyy, γxy, ε33), so α = −C⁻¹σ_T; one point, ‖α − α_solve‖/‖α_solve‖ (γxy left out on the
// symmetry boundary); limit 1e3 × the QP tolerance, as the others.
law::CellReplay replay_expansion(const law::CondensedCell& cell, const law::PlyExpansion& solved, double qp_tolerance);

// Above checked_rows every point of the replay is a dense QP of the cell's size (0.1–1 s at
// 1 500 rows): the replay then takes every k-th path, k the least that leaves at most
// max_replayed_points points (1 otherwise).
inline constexpr int max_replayed_points = 200;
int replay_stride(const std::vector<sweep::PathResult>& paths, int rows, int checked_rows);

}  // namespace dualcell::fit
