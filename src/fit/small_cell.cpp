#include "fit/small_cell.hpp"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include "core/progress.hpp"
#include "core/text.hpp"
#include "fit/levenberg_marquardt.hpp"
#include "law/reduced.hpp"

namespace dualcell::fit {

namespace {

// The parameters x = (D column by column, then L's lower triangle column by column).
struct Layout {
  int m, nm;  // rows, macro components
  int size() const { return m * nm + m * (m + 1) / 2; }
};

struct Rows {
  Eigen::MatrixXd D, L, M;  // M = L Lᵀ + δI
};

Rows rows_of(const Layout& layout, const double* x) {
  Rows r;
  r.D = Eigen::Map<const Eigen::MatrixXd>(x, layout.m, layout.nm);
  r.L = Eigen::MatrixXd::Zero(layout.m, layout.m);
  int k = layout.m * layout.nm;
  for (int j = 0; j < layout.m; ++j)
    for (int i = j; i < layout.m; ++i) r.L(i, j) = x[k++];
  r.M = r.L * r.L.transpose();
  r.M.diagonal().array() += law::basis_compliance * r.M.diagonal().maxCoeff();
  return r;
}

// The cell of rows D, M in the exact law's terms: Y = D S₀, H = M + D S₀ Dᵀ/|Ω|.
law::CondensedCell cell_of(const law::CondensedCell& cell, const Rows& r) {
  const Eigen::MatrixXd Y = r.D * cell.S0;
  return law::cell_of_rows(cell, Y, r.M + Y * r.D.transpose() / cell.volume);
}

struct Problem {
  const law::CondensedCell* cell;
  const law::CellSample* training;
  Layout layout;
  std::vector<std::size_t> points;  // the training points with a finite strain
  std::vector<double> weight;       // per point: its residuals count √weight times
  // Per point: the active set its last evaluation ended with. A Levenberg–Marquardt step moves
  // the rows a little, so a point's own set is nearly always right at once; the previous
  // point's (another direction) cost several factorisations per point.
  std::vector<law::CellHistory> history;
};

// Residuals (σ(ε_i) − σ_i)/|σ_i| and, when J is given, their Jacobian in closed form: on the
// active set F of point i, μ_F = M_FF⁻¹ D_F ε and σ = C₀ε + D_Fᵀ μ_F/|Ω|, so with
// w_k = M_FF⁻¹ D_F e_k: ∂σ_k/∂D = (μ e_kᵀ + w_k εᵀ)/|Ω|, ∂σ_k/∂M = −(w_k μᵀ + μ w_kᵀ)/(2|Ω|)
// symmetrised, and ∂/∂L = 2 (∂/∂M) L (lower triangle).
bool evaluate(const double* x, Problem& p, Eigen::VectorXd& f, Eigen::MatrixXd* J) {
  const Layout& lay = p.layout;
  const Rows rows = rows_of(lay, x);
  const law::CondensedCell small = cell_of(*p.cell, rows);
  law::CellEvaluator evaluator(small);
  if (p.history.size() != p.points.size()) p.history.assign(p.points.size(), evaluator.unloaded());
  const double volume = p.cell->volume;
  for (std::size_t q = 0; q < p.points.size(); ++q) {
    const std::size_t i = p.points[q];
    const Eigen::VectorXd e = p.training->strain[i].head(lay.nm);
    const Eigen::VectorXd target = p.training->stress[i].head(lay.nm);
    const double scale = p.training->stress[i].norm() / std::sqrt(p.weight[q]);
    const law::CellResponse r = evaluator.at_strain(p.training->strain[i], p.history[q], law::BondMode::held);
    if (!r.ok) return false;
    for (int k = 0; k < lay.nm; ++k) f(lay.nm * static_cast<Eigen::Index>(q) + k) = (r.stress(k) - target(k)) / scale;
    if (!J) continue;
    std::vector<int> F;
    for (int j = 0; j < lay.m; ++j)
      if (r.forces(j) > 0) F.push_back(j);
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(lay.m, lay.nm);  // w_k, zero off F
    if (!F.empty()) {
      const int nF = static_cast<int>(F.size());
      Eigen::MatrixXd MFF(nF, nF), DF(nF, lay.nm);
      for (int a = 0; a < nF; ++a) {
        DF.row(a) = rows.D.row(F[a]);
        for (int b = 0; b < nF; ++b) MFF(a, b) = rows.M(F[a], F[b]);
      }
      const Eigen::MatrixXd WF = MFF.llt().solve(DF);
      for (int a = 0; a < nF; ++a) W.row(F[a]) = WF.row(a);
    }
    const Eigen::VectorXd& mu = r.forces;
    // ∂/∂L = −(w μᵀ + μ wᵀ) L = −(w (Lᵀμ)ᵀ + μ (Lᵀw)ᵀ): two outer products, not an m³ product
    // per residual (that product was half the fit's time).
    const Eigen::VectorXd Lt_mu = rows.L.transpose() * mu;
    const Eigen::MatrixXd Lt_W = rows.L.transpose() * W;
    for (int k = 0; k < lay.nm; ++k) {
      const Eigen::Index row = lay.nm * static_cast<Eigen::Index>(q) + k;
      const double c = 1 / (volume * scale);
      // ∂/∂D(j, l) = (μ_j δ_lk + w_k,j ε_l)
      for (int l = 0; l < lay.nm; ++l)
        for (int j = 0; j < lay.m; ++j) (*J)(row, l * lay.m + j) = c * ((l == k ? mu(j) : 0.0) + W(j, k) * e(l));
      Eigen::Index col = lay.m * lay.nm;
      for (int jj = 0; jj < lay.m; ++jj)
        for (int ii = jj; ii < lay.m; ++ii) (*J)(row, col++) = -c * (W(ii, k) * Lt_mu(jj) + mu(ii) * Lt_W(jj, k));
    }
  }
  return true;
}

// The problem of an m-row cell over the training points with a finite strain, every weight 1.
Problem problem_of(const law::CondensedCell& cell, const law::CellSample& training, int m) {
  Problem p{&cell, &training, Layout{m, cell.n_macro}, {}, {}, {}};
  for (std::size_t i = 0; i < training.direction.size(); ++i)
    if (training.strain[i].allFinite()) p.points.push_back(i);
  p.weight.assign(p.points.size(), 1.0);
  return p;
}

// How much softer than the greedy's the rows a rung adds to the last rung's start (fit_small_cell).
constexpr double continuation_softening = 100;

// The parameters of the exact law on m of its own solutions (law::reduce_cell): D = Y C₀ and L
// the Cholesky factor of M = H − Y C₀ Yᵀ/|Ω|; empty where M is not positive definite.
Eigen::VectorXd starting_parameters(const law::CondensedCell& cell, const law::CondensedCell& basis) {
  const Layout layout{basis.n_rows(), cell.n_macro};
  const Eigen::MatrixXd C0 = cell.S0.inverse();
  const Eigen::MatrixXd M0 = basis.H - basis.Y * C0 * basis.Y.transpose() / cell.volume;
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (M0 + M0.transpose()));
  if (llt.info() != Eigen::Success) return {};
  const Eigen::MatrixXd L0 = llt.matrixL();
  Eigen::VectorXd x(layout.size());
  Eigen::Map<Eigen::MatrixXd>(x.data(), layout.m, layout.nm) = basis.Y * C0;
  Eigen::Index k = layout.m * layout.nm;
  for (int j = 0; j < layout.m; ++j)
    for (int i = j; i < layout.m; ++i) x(k++) = L0(i, j);
  return x;
}

}  // namespace

bool small_cell_residuals(const law::CondensedCell& cell, const law::CellSample& training, int m,
                          const Eigen::VectorXd& x, Eigen::VectorXd& f, Eigen::MatrixXd* J) {
  Problem problem = problem_of(cell, training, m);
  const Eigen::Index n = cell.n_macro * static_cast<Eigen::Index>(problem.points.size());
  f.resize(n);
  if (J) J->resize(n, problem.layout.size());
  return evaluate(x.data(), problem, f, J);
}

SmallCell fit_small_cell(const law::CondensedCell& cell, const law::CellSample& training,
                         const SmallCellOptions& options, const law::CellSample* start_sample,
                         const law::CondensedCell* previous) {
  const auto start = std::chrono::steady_clock::now();
  SmallCell out;
  const auto finish = [&](bool ok, std::string message) {
    out.ok = ok;
    out.message = std::move(message);
    out.seconds = seconds_since(start);
    return out;
  };
  law::ReduceOptions basis_options;
  basis_options.tolerance = 0;
  basis_options.max_rows = options.rows;
  basis_options.split_by_body = false;
  const law::ReducedCell basis = law::reduce_cell(cell, start_sample ? *start_sample : training, basis_options);
  if (basis.cell.n_rows() == 0) return finish(false, "no starting basis: " + basis.message);
  const law::ConeCheck start_check = law::check_reduced(basis.cell, training);
  out.start_max_error = start_check.max_error;
  out.start_rms_error = start_check.rms_error;
  Eigen::VectorXd x = starting_parameters(cell, basis.cell);
  if (x.size() == 0) return finish(false, "the starting basis' M is not positive definite");
  // The previous rung's fitted rows and the greedy's rows beyond them, uncoupled (M block
  // diagonal: the cross block of H is then Y_prev C₀ Y_newᵀ/|Ω|) and weak (their M
  // continuation_softening times the greedy's: their forces, and what they change, that much
  // smaller, while their derivatives are not zero), where that start misses the training points
  // by less than the greedy's own: a larger m then starts from what the smaller one reached.
  if (previous && previous->n_rows() < basis.cell.n_rows()) {
    const int mp = previous->n_rows(), mn = basis.cell.n_rows() - mp;
    const Eigen::MatrixXd C0 = cell.S0.inverse();
    const Eigen::MatrixXd Y_new = basis.cell.Y.bottomRows(mn);
    const Eigen::MatrixXd M_new = basis.cell.H.bottomRightCorner(mn, mn) - Y_new * C0 * Y_new.transpose() / cell.volume;
    Eigen::MatrixXd Y(mp + mn, cell.n_macro), H(mp + mn, mp + mn);
    Y << previous->Y, Y_new;
    const Eigen::MatrixXd cross = previous->Y * C0 * Y_new.transpose() / cell.volume;
    H << previous->H, cross, cross.transpose(),
        continuation_softening * M_new + Y_new * C0 * Y_new.transpose() / cell.volume;
    const law::CondensedCell continued = law::cell_of_rows(cell, Y, H);
    const Eigen::VectorXd xc = starting_parameters(cell, continued);
    if (xc.size() > 0) {
      const law::ConeCheck c = law::check_reduced(continued, training);
      if (c.max_error < out.start_max_error) {
        x = xc;
        out.start_max_error = c.max_error;
        out.start_rms_error = c.rms_error;
      }
    }
  }
  Problem problem = problem_of(cell, training, basis.cell.n_rows());
  if (problem.layout.nm * static_cast<Eigen::Index>(problem.points.size()) < problem.layout.size())
    return finish(false, "fewer residuals than parameters: sample more directions");
  // The largest error is what the law promises, so least squares is only the start: Lawson's
  // reweighting (each point's weight times its error, normalised) moves the weighted least-squares
  // solution toward the minimax one; the round with the smallest largest error is kept, or the
  // start where no round beats it (so a rung started from the last one never ends worse).
  Eigen::VectorXd best = x;
  double best_max = out.start_max_error;
  for (int round = 0; round < options.minimax_rounds; ++round) {
    const auto tell = [&](int step) {
      if (options.progress)
        options.progress->update([&] {
          return "small cell of " + std::to_string(options.rows) + " rows: round " + std::to_string(round + 1) +
                 " of " + std::to_string(options.minimax_rounds) + ", step " + std::to_string(step + 1) +
                 ", largest error so far " + formatted("%.2f", 100 * best_max) + " %, " +
                 seconds_text(options.progress->seconds());
        });
    };
    // The small cell's stop: three quiet steps in a row, each below 1e-6 of the cost.
    const LmEnd end =
        levenberg_marquardt([&](const Eigen::VectorXd& at, Eigen::VectorXd& f,
                                Eigen::MatrixXd* J) { return evaluate(at.data(), problem, f, J); },
                            problem.layout.nm * static_cast<Eigen::Index>(problem.points.size()), x,
                            {.max_iterations = options.max_iterations, .quiet_steps = 3, .quiet_fraction = 1e-6}, tell);
    out.iterations += end.iterations;
    if (!end.evaluated) return finish(false, "a fitted cell cannot be evaluated");
    const law::ConeCheck c = law::check_reduced(cell_of(cell, rows_of(problem.layout, x.data())), training);
    if (c.max_error < best_max) best_max = c.max_error, best = x;
    double mean = 0;
    for (std::size_t q = 0; q < problem.points.size(); ++q)
      mean += problem.weight[q] * c.error[problem.points[q]] / static_cast<double>(problem.points.size());
    if (!(mean > 0)) break;
    for (std::size_t q = 0; q < problem.points.size(); ++q) problem.weight[q] *= c.error[problem.points[q]] / mean;
  }
  out.cell = cell_of(cell, rows_of(problem.layout, best.data()));
  const law::ConeCheck fitted = law::check_reduced(out.cell, training);
  out.training_max_error = fitted.max_error;
  out.training_rms_error = fitted.rms_error;
  return finish(true, "");
}

}  // namespace dualcell::fit
