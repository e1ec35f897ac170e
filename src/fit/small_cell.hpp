#pragma once
// The compact law as a small cell fitted to the exact law (docs/method.md §16c).
//
// Strain-driven, a cell of m rows is
//   W(ε) = ½ εᵀC₀ε + max over μ ≥ 0 of [ μᵀDε − ½ μᵀMμ ] / |Ω|,   σ = C₀ε + Dᵀμ/|Ω|,
// C₀ = S₀⁻¹ the open cell's stiffness, D (m × 3) and M (m × m) its rows. For every D and every
// positive definite M this is convex in ε (a quadratic plus a maximum of affine functions),
// homogeneous of degree 2 and C¹, with a stress that is piecewise linear on polyhedral cones:
// the form of the exact law, which is the case m = n, D = Y C₀, M = H − Y C₀ Yᵀ/|Ω|. In the exact
// law's own terms (law/condensed.hpp) it is the CondensedCell with Y = D S₀,
// H = M + D S₀ Dᵀ/|Ω| and no equality rows, so every evaluator of the exact law takes it.
//
// The fit starts from the exact law on m of its own solutions (law::reduce_cell) and moves D and
// M = L Lᵀ (L lower triangular: M stays positive semidefinite, plus a compliance of 1e-9 of its
// largest diagonal entry per row) to minimise Σ_i |σ(ε_i) − σ_i|²/|σ_i|² over the training
// sample of the exact law: Levenberg–Marquardt with the Jacobian in closed form (on each point's
// active set μ_F = M_FF⁻¹ D_F ε).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "law/condensed.hpp"
#include "law/cone_check.hpp"

namespace dualcell::fit {

struct SmallCellOptions {
  int rows = 16;                 // m
  int max_iterations = 200;      // Levenberg–Marquardt steps per round
  int minimax_rounds = 6;        // Lawson reweightings toward the smallest largest error
  Progress* progress = nullptr;  // where a long fit says how far it is
};

struct SmallCell {
  bool ok = false;
  std::string message;
  law::CondensedCell cell;                                // m rows, the exact law's form
  double start_max_error = 0, start_rms_error = 0;        // the starting basis, over the training sample
  double training_max_error = 0, training_rms_error = 0;  // the fitted cell, same sample
  int iterations = 0;
  double seconds = 0;
};

// `start_sample`: the sample of `cell` itself (law::sample_cell, with its forces) that the
// starting greedy runs on, where the training points are not the cell's own (the cell on a basis
// of its solutions, fitted to full solves: docs/method.md §16c); by default `training`.
// `previous`: a small cell of fewer rows fitted to the same training points (the ladder's last
// rung): its rows with the greedy's further ones are the start where they miss the training points
// by less than the greedy's cell does.
SmallCell fit_small_cell(const law::CondensedCell& cell, const law::CellSample& training,
                         const SmallCellOptions& options = {}, const law::CellSample* start_sample = nullptr,
                         const law::CondensedCell* previous = nullptr);

// The fit's residuals (σ(ε_i) − σ_i)_k/|σ_i| over the training points with a finite strain, and
// when J is given their Jacobian, at the parameters x of an m-row cell (D column by column, then
// L's lower triangle column by column); false where the cell cannot be evaluated. Exposed so that
// the closed form can be checked against finite differences.
bool small_cell_residuals(const law::CondensedCell& cell, const law::CellSample& training, int m,
                          const Eigen::VectorXd& x, Eigen::VectorXd& f, Eigen::MatrixXd* J);

}  // namespace dualcell::fit
