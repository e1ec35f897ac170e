#include "feti/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "feti/projected.hpp"
#include "law/bond.hpp"
#include "primal/antiplane.hpp"
#include "qp/operator.hpp"
#include "qp/smalbe.hpp"

namespace dualcell::feti {

namespace {

using Clock = std::chrono::steady_clock;

// The tightest dual tolerance the primal check may ask for: a relative projected gradient of
// 1e-14 is a few hundred ulps of its terms, below which SMALBE stagnates instead of converging.
constexpr double min_qp_tolerance = 1e-14;
// A QP whose forces are all below this (a load some 1e-100 of the moduli or less) is solved
// scaled by a power of two: its CG's squares would underflow (docs/theory/solver.md §7, "Tiny loads").
constexpr double smallest_unscaled_qp = 1e-100;

// SMALBE's options from the scene's solver settings, at the dual tolerance `tolerance`, for A = PFP
// of norm norm_PFP.
qp::SmalbeOptions smalbe_options(const SolverSettings& settings, double tolerance, double norm_PFP) {
  qp::SmalbeOptions options;
  options.relative_tolerance = tolerance;
  options.equality_tolerance = tolerance;
  options.max_outer_iterations = settings.max_outer_iterations;
  options.max_operator_applications = settings.max_operator_applications;
  options.rho0_factor = settings.rho_factor;
  options.rho_growth = settings.rho_growth;
  options.rho_patience = settings.rho_patience;
  options.inner.Gamma = settings.Gamma;
  options.inner.norm_A = norm_PFP;
  options.inner.max_iterations = settings.max_operator_applications;
  options.projected_operator = true;  // A = PFP: ‖A + ρQ‖ = max(‖A‖, ρ)
  return options;
}

// The QP's progress line: the last outer iteration's stopping quantities against their
// tolerance, F applications so far, and what is left at the rate their distance to convergence,
// max(‖gᴾ‖, ‖Gλ−e‖)/tol, has fallen per outer iteration (GeometricEta).
class QpProgressLine {
 public:
  QpProgressLine(Progress& progress, int rows, double tolerance)
      : progress_(progress), rows_(rows), tolerance_(tolerance) {}
  // One application of F: one clock read, a line when one is due.
  void applied() {
    ++applications_;
    progress_.update([&] { return text(); });
  }
  void outer(const qp::OuterReport& r) {
    last_ = r;
    eta_.observe(r.outer_iterations, std::max(r.projected_gradient, r.equality_residual) / tolerance_,
                 progress_.seconds());
  }

 private:
  std::string text() const {
    char line[320];
    const double now = progress_.seconds();
    if (last_.outer_iterations == 0)
      std::snprintf(line, sizeof line, "QP (%d rows): %ld F applications, %s", rows_, applications_,
                    seconds_text(now).c_str());
    else
      std::snprintf(line, sizeof line,
                    "QP (%d rows): outer %ld, |gP| %.1e, |G l - e| %.1e (tol %.0e), %ld F applications, %s%s", rows_,
                    last_.outer_iterations, last_.projected_gradient, last_.equality_residual, tolerance_,
                    applications_, seconds_text(now).c_str(), eta_.left(now).c_str());
    return line;
  }

  Progress& progress_;
  int rows_;
  double tolerance_;
  long applications_ = 0;
  qp::OuterReport last_{};
  GeometricEta eta_;
};

}  // namespace

// ‖PFP‖ by qp::estimate_norm (20 applications from a fixed start vector): part of building a
// problem, so that it is a function of the problem alone and no QP's count depends on which
// came first.
double estimate_norm_PFP(const DualProblem& dual) {
  const int m = dual.constraints().n_rows();
  ProjectedPlusShiftedQ PFP(dual, &DualProblem::apply_F, m);
  return qp::estimate_norm([&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { PFP(x, 0.0, y); }, m);
}

bool FaceCoarse::set_face(const Eigen::VectorXd& free) {
  using ColMajor = linalg::SparseCholesky::SparseMatrix;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> DG_F = DG_ * free.asDiagonal();
  ColMajor S = ColMajor(DG_F * DG_F.transpose());
  const Eigen::Index n = S.rows();
  const Eigen::VectorXd diagonal = S.diagonal();
  const double delta = 1e-13 * (diagonal.size() ? diagonal.maxCoeff() : 0.0);
  if (!(delta > 0)) return false;
  ColMajor shift(n, n);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(n);
  for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(i, i, diagonal(i) > 0 ? delta : 1.0);
  shift.setFromTriplets(t.begin(), t.end());
  S += shift;
  try {
    S_.compute(S);
  } catch (const linalg::CholeskyError&) {
    return false;
  }
  return true;
}

void FaceCoarse::solve_coarse(const Eigen::VectorXd& w, Eigen::VectorXd& c) {
  Gw_.noalias() = DG_ * w;
  S_.solve(Gw_, c);
}

void FaceCoarse::apply_Gt(const Eigen::VectorXd& c, Eigen::VectorXd& v) { v.noalias() = DG_.transpose() * c; }

ContactSolver::ContactSolver(const mesh::Mesh& mesh, const Scene& scene, int threads, int min_dofs_per_thread,
                             par::Group group, Progress* progress, double expected_qps)
    : setup_(mesh, scene, threads, min_dofs_per_thread, std::move(group), progress, expected_qps),
      progress_(progress) {}

ContactSolver::Cached& ContactSolver::cached(const BondState& bonds) {
  Cached& c = bonds == intact() ? intact_ : other_;
  if (!c.dual || bonds != c.bonds) {
    c.dual = std::make_unique<DualProblem>(setup_, build_constraints(setup_.mesh(), setup_.scene(), bonds));
    c.bonds = bonds;
    c.norm_PFP = estimate_norm_PFP(*c.dual);
  }
  return c;
}

const DualProblem& ContactSolver::problem(const BondState& bonds) { return *cached(bonds).dual; }

Solution ContactSolver::solve_fixed(const MacroState& state, const BondState& bonds, const Eigen::VectorXd* warm_lambda,
                                    const Eigen::VectorXd* warm_multiplier) {
  if (!state.in_plane_stress())
    throw std::invalid_argument("the full solver takes the in-plane macro stress, ε33, Γ and ΔT");
  if (state.delta_T() != 0 && !(setup_.scene().fibre.expands && setup_.scene().matrix.expands))
    throw std::invalid_argument("a temperature change on a scene whose phases have no expansion coefficients");
  const Eigen::Vector3d sigma = state.in_plane();
  if (setup_.scene().load.boundary == Boundary::symmetry && sigma(2) != 0)
    throw InputError("the symmetry boundary carries only sxx and syy (sxy must be 0)");
  if (setup_.scene().load.boundary == Boundary::edges && (sigma(1) != 0 || sigma(2) != 0))
    throw InputError("the edges boundary has one load coordinate, the load factor (t, 0, 0)");
  if (bonds.size() != setup_.mesh().interface_pairs.size())
    throw InputError("bond state has " + std::to_string(bonds.size()) + " entries, the mesh " +
                     std::to_string(setup_.mesh().interface_pairs.size()) + " interface pairs");
  const auto t0 = Clock::now();
  const Cached& before = bonds == intact() ? intact_ : other_;
  const bool rebuilt = !before.dual || bonds != before.bonds;
  if (rebuilt && progress_)
    progress_->update([&] { return "dual setup (B, G, GGᵀ), " + seconds_text(progress_->seconds()); });
  Cached& c = cached(bonds);
  const DualProblem& dual = *c.dual;
  const double dual_setup = rebuilt ? seconds_since(t0) : 0.0;
  Solution out = solve_problem(dual, c.norm_PFP, state, warm_lambda, warm_multiplier);
  // A well-posed problem must not end in "failed": when the QP converged but the recovered
  // primal solution misses its check (a stiffness contrast amplifies the dual residual in u),
  // the dual tolerance does not give the accuracy this problem needs. Tighten it a decade at a
  // time and go on from the multipliers reached, down to min_qp_tolerance.
  // (A non-finite answer is not a matter of tolerance: no tightening mends it.)
  while (out.qp_converged() && !out.primal_ok && out.u.allFinite() && out.qp_tolerance > min_qp_tolerance) {
    const double tighter = std::max(out.qp_tolerance / 10, min_qp_tolerance);
    Solution next = solve_problem(dual, c.norm_PFP, state, &out.lambda, &out.multiplier, tighter);
    next.add_work(out);
    ++next.tightenings;
    out = std::move(next);
  }
  out.bonds = bonds;
  out.seconds.dual_setup = dual_setup;
  return out;
}

Solution ContactSolver::solve_problem(const DualProblem& dual, double norm_PFP, const MacroState& state,
                                      const Eigen::VectorXd* warm_lambda, const Eigen::VectorXd* warm_multiplier,
                                      double qp_tolerance) {
  Solution out;
  out.qp_tolerance = qp_tolerance > 0 ? qp_tolerance : setup_.scene().solver.tolerance;
  const Eigen::Vector3d sigma = state.in_plane();
  out.sigma = sigma;
  out.eps33 = state.eps33();
  out.delta_T = state.delta_T();
  out.seconds.assembly = setup_.seconds_assembly;
  out.seconds.factorisation = setup_.seconds_factorisation;
  out.seconds.explicit_operators = setup_.seconds_explicit;
  out.subdomains = setup_.n_stiff_subdomains();
  out.explicit_subdomains = setup_.explicit_subdomains();
  const Constraints& con = dual.constraints();
  const int m = con.n_rows();
  out.n_rows = m;

  const auto t_qp = Clock::now();
  const DualProblem::Profile profile_before = dual.profile();
  const Eigen::VectorXd f = setup_.load(sigma, {out.eps33, out.delta_T});
  const Eigen::VectorXd e = dual.e(f);
  const Eigen::VectorXd lambda0 = dual.lambda_0(e);
  const Eigen::VectorXd d = dual.d(f, setup_.load_factor(sigma));
  Eigen::VectorXd b(m), tmp(m);
  dual.apply_F(lambda0, tmp);
  b = d - tmp;
  dual.apply_Q(b, tmp);
  b -= tmp;  // b = P(d − Fλ₀)

  // A = PFP, fused with SMALBE's shift: A + ρQ.
  ProjectedPlusShiftedQ A_plus_shifted_Q(dual, &DualProblem::apply_F, m);
  const qp::LinearOperator A = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { A_plus_shifted_Q(x, 0.0, y); };
  const qp::LinearOperator Q = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { dual.apply_Q(x, y); };
  const long extra_applications = 1;  // Fλ₀

  Eigen::VectorXd lower = con.lower - lambda0, upper = con.upper - lambda0;
  // The QP's unknown: λ − λ₀ (scaled rows), zero or the caller's warm start.
  Eigen::VectorXd lambda_shift = Eigen::VectorXd::Zero(m);
  if (warm_lambda && warm_lambda->size() == m) lambda_shift = warm_lambda->cwiseQuotient(con.weight) - lambda0;

  const SolverSettings& settings = setup_.scene().solver;
  qp::SmalbeOptions options = smalbe_options(settings, out.qp_tolerance, norm_PFP);
  // Progress: per application of F one clock read; the line is formed only when one is due.
  std::optional<QpProgressLine> line;
  if (progress_) line.emplace(*progress_, m, out.qp_tolerance);
  options.A_plus_shifted_Q = [&](const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
    A_plus_shifted_Q(x, shift, y);
    if (line) line->applied();
  };
  if (line) options.on_outer = [&](const qp::OuterReport& r) { line->outer(r); };
  // The preconditioner of PFP on Im P: P M⁻¹ P, fused with SMALBE's Q/ρ like A + ρQ.
  std::optional<ProjectedPlusShiftedQ> M_plus_shifted_Q;
  if (settings.preconditioner != Preconditioner::none) {
    M_plus_shifted_Q.emplace(dual, &DualProblem::apply_preconditioner, m);
    options.preconditioner = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { (*M_plus_shifted_Q)(x, 0.0, y); };
    options.preconditioner_plus_shifted_Q = [&](const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
      (*M_plus_shifted_Q)(x, shift, y);
    };
  }
  // SMALBE's m = Ĝᵀμ, in λ-space; warm-started with the caller's when it fits this problem.
  Eigen::VectorXd multiplier = Eigen::VectorXd::Zero(m);
  if (warm_multiplier && warm_multiplier->size() == m) multiplier = *warm_multiplier;
  FaceCoarse face(dual);
  options.face_projector = &face;
  // The problem is positively homogeneous in the load and the strengths together: a tiny one is
  // solved as the same problem times s = 2^k, exactly (a power of two), and scaled back. Every
  // other load has s = 1 and the same bits.
  const double size = std::max(b.lpNorm<Eigen::Infinity>(), lambda0.lpNorm<Eigen::Infinity>());
  const double s = size > 0 && size < smallest_unscaled_qp ? std::ldexp(1.0, -std::ilogb(size)) : 1.0;
  if (s != 1) {
    b *= s;
    for (Eigen::VectorXd* v : {&lower, &upper, &lambda_shift, &multiplier}) *v *= s;
  }
  out.qp = qp::smalbe(A, Q, b, lower, upper, lambda_shift, multiplier, options);
  if (s != 1) {
    lambda_shift /= s;
    multiplier /= s;
  }
  out.seconds.qp = seconds_since(t_qp);
  out.seconds.in_qp = dual.profile() - profile_before;
  out.counters = out.qp.counters;
  out.counters.operator_applications += extra_applications;

  const Eigen::VectorXd lambda_scaled = lambda0 + lambda_shift;
  out.lambda = lambda_scaled.cwiseProduct(con.weight);
  out.multiplier = multiplier;
  const auto t_rec = Clock::now();
  if (progress_) progress_->update([&] { return "recovery of u, " + seconds_text(progress_->seconds()); });
  recover(dual, f, d, lambda_scaled, multiplier, out);
  out.seconds.recovery = seconds_since(t_rec);
  report(dual, f, lambda_scaled, out);
  return out;
}

Solution ContactSolver::solve(const MacroState& state, const BondState& bonds, const Eigen::VectorXd* warm_lambda,
                              const Eigen::VectorXd* warm_multiplier) {
  const Scene& scene = setup_.scene();
  const Eigen::Vector2d gamma = state.gamma();
  if (!gamma.isZero(0)) {
    if (scene.load.macro != Macro::full || scene.load.boundary != Boundary::periodic)
      throw std::invalid_argument(
          "a shear along the fibres needs a periodic cell with [load] macro = \"full\" (the antiplane problem)");
    if (shear_strength_.empty()) shear_strength_ = shear_strengths(setup_.mesh(), scene);
  }
  BondState current = bonds;
  Solution s;         // the current round's
  Solution previous;  // the work of the rounds before the current one
  Eigen::VectorXd warm;
  if (warm_lambda) warm = *warm_lambda;
  const bool adhesion = scene.interface.has_adhesion();
  // No loop at all without adhesion: one round, nothing can break.
  const int max_rounds = adhesion ? scene.solver.max_debond_rounds : 1;
  bool first = true;
  const law::bond::CascadeEnd end = law::bond::cascade(
      current, max_rounds,
      [&] {
        // The caller's multiplier belongs to the first problem only: after breaks the rows change.
        s = solve_fixed(state, current, warm.size() ? &warm : nullptr, first ? warm_multiplier : nullptr);
        first = false;
        return true;
      },
      [&](std::vector<int>& breaking) {
        // Bonds at their strength break, normal and tangential together (docs/method.md §11).
        if (!s.qp_converged()) return;
        if (adhesion) {
          const Constraints& con = problem(current).constraints();
          for (int r = 0; r < con.n_rows(); ++r)
            if (is_interface(con.kind[r]) && current[con.pair[r]] &&
                law::bond::at_strength(s.lambda(r) / con.weight(r), {con.lower(r), con.upper(r)}))
              breaking.push_back(con.pair[r]);
        }
        if (!gamma.isZero(0)) {
          // The shear along the fibres with the same bonds: ties only where bonds carry shear (s_t > 0;
          // otherwise the fibres slip along z, as the exact law's cell without shear rows).
          const bool ties = scene.interface.tangential_strength > 0;
          std::vector<char> bonded(current.size(), 0);
          for (std::size_t p = 0; p < current.size(); ++p) bonded[p] = ties && current[p] ? 1 : 0;
          const primal::ShearResponse z =
              primal::longitudinal_shear_at(setup_.mesh(), scene.fibre, scene.matrix, bonded, gamma, shear_strength_);
          s.gamma = gamma;
          s.shear_stress = z.tau;
          for (const int p : ties_at_strength(z.pair_forces, bonded, shear_strength_)) breaking.push_back(p);
        }
      },
      [&](const std::vector<int>&) {
        // Carry the multipliers of the rows that stay over to the next problem as a warm start.
        // Structural rows keep their order; interface rows are found by (kind, pair).
        const Constraints& old = problem(s.bonds).constraints();
        const Constraints next = build_constraints(setup_.mesh(), scene, current);
        warm.resize(next.n_rows());
        std::map<std::pair<int, int>, double> by_key;
        for (int r = 0; r < old.n_rows(); ++r)
          by_key[{static_cast<int>(old.kind[r]), !is_interface(old.kind[r]) ? r : old.pair[r]}] = s.lambda(r);
        for (int r = 0; r < next.n_rows(); ++r) {
          const auto it = by_key.find({static_cast<int>(next.kind[r]), !is_interface(next.kind[r]) ? r : next.pair[r]});
          warm(r) = it == by_key.end()
                        ? 0.0
                        : std::clamp(it->second, next.lower(r) * next.weight(r), next.upper(r) * next.weight(r));
        }
        previous.add_work(s);
      });
  s.add_work(previous);
  Solution total = std::move(s);
  total.debond_rounds = end.rounds;
  if (!end.settled) {
    total.qp.message = "debonding did not settle within max_debond_rounds = " + std::to_string(max_rounds);
    total.qp.status = qp::Status::max_iterations;
  }
  total.newly_broken = end.newly_broken;
  return total;
}

}  // namespace dualcell::feti
