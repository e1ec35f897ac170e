// SMALBE-M on seeded random problems with equality constraints Ĝx = 0 given through the
// projector Q = ĜᵀĜ, mostly in the FETI form A = PFP (P = I − Q), against known solutions, the
// enumeration oracle and a direct KKT solve; plus the failure statuses; then SMALBE with a
// preconditioner P M⁻¹ P of A (the inner MPRGP preconditioned in face by P M⁻¹ P + Q/ρ).
#include "qp/smalbe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "qp_test_utils.hpp"

namespace dualcell::qp {
namespace {

using testing::BoundKind;
using testing::Degeneracy;
using testing::DenseQp;
using testing::inf;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr BoundKind all_kinds[] = {BoundKind::lower, BoundKind::upper, BoundKind::box, BoundKind::mixed};

// F with spectrum in [0.1, 1], Ĝ with orthonormal rows, Q = ĜᵀĜ and A = PFP.
struct FetiLikeProblem {
  Eigen::MatrixXd F, G, Q, A;
};

FetiLikeProblem make_feti_like(std::mt19937& rng, int n, int n_rows) {
  FetiLikeProblem p;
  p.F = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
  p.G = testing::random_orthonormal_rows(rng, n_rows, n);
  p.Q = p.G.transpose() * p.G;
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n) - p.Q;
  p.A = P * p.F * P;
  return p;
}

double norm_2(const Eigen::MatrixXd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().cwiseAbs().maxCoeff();
}

SmalbeOptions tight_options() {
  SmalbeOptions opts;
  opts.relative_tolerance = 1e-10;
  opts.equality_tolerance = 1e-10;
  return opts;
}

// No bounds, only G x = 0: the solution from the KKT system [A Gᵀ; G 0] [x; ν] = [b; 0].
DenseQp equality_only_problem(std::mt19937& rng, const FetiLikeProblem& p) {
  const auto n = p.A.rows(), n_rows = p.G.rows();
  DenseQp qp = testing::make_random_problem(rng, p.A, p.G, BoundKind::box);
  qp.l.setConstant(-std::numeric_limits<double>::infinity());
  qp.u.setConstant(std::numeric_limits<double>::infinity());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + n_rows, n + n_rows);
  K.topLeftCorner(n, n) = p.A;
  K.topRightCorner(n, n_rows) = p.G.transpose();
  K.bottomLeftCorner(n_rows, n) = p.G;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + n_rows);
  rhs.head(n) = qp.b;
  const Eigen::VectorXd z = K.fullPivLu().solve(rhs);
  qp.x_star = z.head(n);
  qp.nu = z.tail(n_rows);
  return qp;
}

struct ObservedSolve {
  Result result;
  Eigen::VectorXd x, m;
  long n_iterates = 0;
  long n_infeasible = 0;
};

ObservedSolve observed_solve(const DenseQp& qp, const Eigen::MatrixXd& Q, SmalbeOptions opts, Eigen::VectorXd x0 = {}) {
  ObservedSolve out;
  opts.inner.on_iterate = [&](const Eigen::VectorXd& x) {
    ++out.n_iterates;
    out.n_infeasible += testing::is_feasible(x, qp.l, qp.u) ? 0 : 1;
  };
  out.x = std::move(x0);
  out.result = smalbe(testing::dense_operator(qp.A), testing::dense_operator(Q), qp.b, qp.l, qp.u, out.x, out.m, opts);
  return out;
}

// Error bound for the SMALBE output x with multiplier m against a KKT pair (x*, m*), with
// a = ‖gᴾ‖ of the Lagrangian gradient A x − b + m, q = ‖Q x‖, e = x − x*, p = ‖P e‖ and λ > 0
// with eᵀAe ≥ λ‖Pe‖² for all e (λ_min(F) for A = PFP, λ_min(A) for an SPD A):
//   λp² ≤ eᵀAe = (∇L(x) − ∇L*(x*))ᵀe − (m − m*)ᵀQe ≤ a‖e‖ + 0 + ‖m − m*‖ q,  ‖e‖ ≤ p + q,
// (∇L(x)ᵀe ≤ a‖e‖ and −∇L*(x*)ᵀe ≤ 0 because x, x* lie in the box and x* is a KKT point), so
//   ‖e‖ ≤ q + (a + √(a² + 4λ(a q + ‖m − m*‖ q))) / (2λ).
double error_bound(double a, double q, double multiplier_gap, double lambda) {
  return q + (a + std::sqrt(a * a + 4.0 * lambda * (a * q + multiplier_gap * q))) / (2.0 * lambda);
}

void expect_converged_to(const DenseQp& qp, const Eigen::MatrixXd& Q, const ObservedSolve& solve,
                         const SmalbeOptions& opts, double lambda, double norm_A) {
  const Result& result = solve.result;
  EXPECT_EQ(result.status, Status::converged) << result.message;
  EXPECT_GT(solve.n_iterates, 0);
  EXPECT_EQ(solve.n_infeasible, 0);
  ASSERT_TRUE(testing::is_feasible(solve.x, qp.l, qp.u));
  EXPECT_EQ(result.bound_violation, 0.0);

  const double b_norm = qp.b.norm();
  const Eigen::VectorXd g = qp.A * solve.x - qp.b + solve.m;
  const double gP = testing::reference_projected_gradient(solve.x, g, qp.l, qp.u);
  const double Qx_norm = (qp.C * solve.x).norm();
  // Round-off of the dense products, far below the tolerances.
  const double slack = 1e-13 * (1.0 + b_norm);
  EXPECT_NEAR(result.projected_gradient_norm, gP, slack);
  EXPECT_NEAR(result.equality_residual, Qx_norm, slack);
  EXPECT_LE(gP, opts.relative_tolerance * b_norm + slack);
  // The solver scales the equality test by its power-iteration estimate of ‖A‖, which is
  // ×1.01 over a lower bound; 0.95 allows for an estimate up to 6% short.
  EXPECT_LE(Qx_norm, opts.equality_tolerance * b_norm / (0.95 * norm_A) + slack);
  // m stays in Im Q.
  EXPECT_LE((Q * solve.m - solve.m).norm(), 1e-12 * (1.0 + solve.m.norm()));

  const Eigen::VectorXd m_star = qp.C.transpose() * qp.nu;
  const double bound = error_bound(gP, Qx_norm, (solve.m - m_star).norm(), lambda);
  EXPECT_LE((solve.x - qp.x_star).norm(), bound + 1e-12) << "bound " << bound;
}

TEST(Smalbe, PfpFormReachesKnownSolutionsAndTheOracle) {
  std::mt19937 rng(2101);
  long max_outer = 0;
  for (BoundKind kind : all_kinds) {
    for (int trial = 0; trial < 12; ++trial) {
      SCOPED_TRACE(std::string(testing::to_string(kind)) + " trial " + std::to_string(trial));
      const int n = 3 + trial % 6;
      const int n_rows = 1 + trial % std::min(3, n - 1);
      const FetiLikeProblem p = make_feti_like(rng, n, n_rows);
      const Degeneracy degeneracy = trial % 4 == 3 ? Degeneracy::weakly_active : Degeneracy::none;
      const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, kind, degeneracy);
      const ObservedSolve solve = observed_solve(qp, p.Q, tight_options());
      expect_converged_to(qp, p.Q, solve, tight_options(), 0.1, norm_2(p.A));
      max_outer = std::max(max_outer, solve.result.counters.outer_iterations);
      if (n <= 7) {
        const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
        ASSERT_TRUE(oracle.found);
        EXPECT_LE((oracle.x - qp.x_star).norm(), 1e-9);
      }
    }
  }
  // Measured at most 41 (g++ 12, -O2); plain SMALBE-M (rho_growth = 1) exceeds 100 on some.
  EXPECT_LE(max_outer, 60);
}

// Without the projection A need not be PFP: any SPD A works, only the outer count differs.
TEST(Smalbe, GeneralSpdOperator) {
  std::mt19937 rng(2202);
  for (int trial = 0; trial < 16; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 3 + trial % 6;
    const int n_rows = 1 + trial % std::min(3, n - 1);
    const FetiLikeProblem p = make_feti_like(rng, n, n_rows);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.F, p.G, all_kinds[trial % 4]);
    const ObservedSolve solve = observed_solve(qp, p.Q, tight_options());
    expect_converged_to(qp, p.Q, solve, tight_options(), 0.1, norm_2(p.F));
  }
}

// No bounds: the solution is that of the KKT system [A Ĝᵀ; Ĝ 0][x; ν] = [b; 0].
TEST(Smalbe, EqualityOnlyMatchesTheKktSolve) {
  std::mt19937 rng(2303);
  for (int trial = 0; trial < 8; ++trial) {
    const int n = 4 + trial;
    const int n_rows = 1 + trial % 3;
    const FetiLikeProblem p = make_feti_like(rng, n, n_rows);
    const DenseQp qp = equality_only_problem(rng, p);
    const ObservedSolve solve = observed_solve(qp, p.Q, tight_options());
    expect_converged_to(qp, p.Q, solve, tight_options(), 0.1, norm_2(p.A));
    // Without bounds the multiplier is unique: m = Ĝᵀν.
    EXPECT_LE((solve.m - p.G.transpose() * qp.nu).norm(), 1e-8 * (1.0 + qp.nu.norm()));
  }
}

// Narrow boxes around 0 entered from a corner: the first steps release many components at once
// and an uncapped proportioning step would overshoot the other bound. Every inner iterate of
// every outer iteration is observed. (The load is moderate: with a box of width w pinning x,
// SMALBE needs about ‖m*‖/(ρ w) outer iterations, since each adds at most ρ‖Qx‖ ≲ ρ w to m.)
TEST(Smalbe, EveryInnerIterateStaysInANarrowBox) {
  std::mt19937 rng(2404);
  long proportioning = 0;
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 4 + trial % 5;
    const FetiLikeProblem p = make_feti_like(rng, n, 1 + trial % 2);
    DenseQp qp = testing::make_random_problem(rng, p.A, p.G, BoundKind::box);
    const double width = 0.05 + 0.05 * (trial % 3);
    qp.l.setConstant(-0.5 * width);
    qp.u.setConstant(0.5 * width);
    const ObservedSolve solve = observed_solve(qp, p.Q, tight_options(), qp.l);
    EXPECT_EQ(solve.result.status, Status::converged) << solve.result.message;
    EXPECT_EQ(solve.n_infeasible, 0);
    EXPECT_GT(solve.n_iterates, 1);
    proportioning += solve.result.counters.proportioning_steps;
  }
  // Otherwise this test would not exercise the step it is about.
  EXPECT_GT(proportioning, 0);
}

TEST(Smalbe, InvalidInputIsRejectedAndLeavesXUnchanged) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(3, 3);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(3);
  const Eigen::VectorXd l = Eigen::VectorXd::Zero(3);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(3, 2.0);
  const auto run = [&](const Eigen::VectorXd& bb, const Eigen::VectorXd& ll, const Eigen::VectorXd& uu,
                       Eigen::VectorXd m, const SmalbeOptions& opts) {
    Eigen::VectorXd x = Eigen::VectorXd::Constant(3, 0.5);
    const Result result = smalbe(testing::dense_operator(A), testing::dense_operator(Q), bb, ll, uu, x, m, opts);
    EXPECT_EQ(result.status, Status::invalid_input);
    EXPECT_FALSE(result.message.empty());
    EXPECT_TRUE(std::isnan(result.projected_gradient_norm));
    EXPECT_EQ(x, Eigen::VectorXd::Constant(3, 0.5));
  };
  const SmalbeOptions defaults;
  Eigen::VectorXd bad = l;
  bad[0] = 5.0;
  run(b, bad, u, {}, defaults);        // l > u
  run(b.head(2), l, u, {}, defaults);  // size mismatch
  bad = b;
  bad[1] = nan;
  run(bad, l, u, {}, defaults);                      // NaN in b
  run(b, l, u, Eigen::VectorXd::Ones(2), defaults);  // multiplier of the wrong size
  SmalbeOptions opts;
  opts.xi_reduction = 1.0;
  run(b, l, u, {}, opts);
  opts = {};
  opts.inner.Gamma = -1.0;
  run(b, l, u, {}, opts);
}

TEST(Smalbe, MaxOuterIterationsAndBudgetAreReportedWithHonestResiduals) {
  std::mt19937 rng(2505);
  const int n = 8;
  const FetiLikeProblem p = make_feti_like(rng, n, 3);
  const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
  for (const bool by_budget : {false, true}) {
    SmalbeOptions opts = tight_options();
    if (by_budget) {
      opts.max_operator_applications = 60;
    } else {
      opts.max_outer_iterations = 1;
    }
    Eigen::VectorXd x, m;
    const Result result =
        smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x, m, opts);
    EXPECT_EQ(result.status, Status::max_iterations) << result.message;
    EXPECT_FALSE(result.message.empty());
    const Eigen::VectorXd g = p.A * x - qp.b + m;
    EXPECT_NEAR(result.projected_gradient_norm, testing::reference_projected_gradient(x, g, qp.l, qp.u), 1e-12);
    EXPECT_NEAR(result.equality_residual, (p.G * x).norm(), 1e-12);
    EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
    if (by_budget) {
      // The budget is checked between inner solves and caps each of them.
      EXPECT_LE(result.counters.operator_applications, 60 + 3);
    } else {
      EXPECT_EQ(result.counters.outer_iterations, 1);
    }
  }
}

TEST(Smalbe, NanFromEitherOperatorIsReported) {
  std::mt19937 rng(2606);
  const int n = 6;
  const FetiLikeProblem p = make_feti_like(rng, n, 2);
  const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::box);
  for (int which = 0; which < 2; ++which) {
    // A clean run counts the applications, so that NaN can be injected at the first, a
    // middle and the last one.
    long clean_count = 0;
    const long* counter = &clean_count;
    {
      Eigen::VectorXd x;
      const Result clean = smalbe(testing::dense_operator(p.A, which == 0 ? &clean_count : nullptr),
                                  testing::dense_operator(p.Q, which == 1 ? &clean_count : nullptr), qp.b, qp.l, qp.u,
                                  x, tight_options());
      ASSERT_EQ(clean.status, Status::converged);
    }
    for (long fail_at : {1L, (*counter + 1) / 2, *counter}) {
      long applications = 0;
      const auto broken = [&](const Eigen::MatrixXd& M) {
        return LinearOperator([&M, &applications, fail_at](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
          y.noalias() = M * v;
          if (++applications == fail_at) {
            y[1] = nan;
          }
        });
      };
      const LinearOperator A = which == 0 ? broken(p.A) : testing::dense_operator(p.A);
      const LinearOperator Q = which == 1 ? broken(p.Q) : testing::dense_operator(p.Q);
      Eigen::VectorXd x;
      const Result result = smalbe(A, Q, qp.b, qp.l, qp.u, x, tight_options());
      EXPECT_EQ(result.status, Status::non_finite)
          << "operator " << which << " fail_at " << fail_at << ": " << result.message;
      EXPECT_TRUE(x.allFinite());
      EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
    }
  }
}

TEST(Smalbe, CountsEveryApplicationOfA) {
  std::mt19937 rng(2707);
  const FetiLikeProblem p = make_feti_like(rng, 8, 2);
  const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::box);
  long applications = 0;
  Eigen::VectorXd x;
  const Result result = smalbe(testing::dense_operator(p.A, &applications), testing::dense_operator(p.Q), qp.b, qp.l,
                               qp.u, x, tight_options());
  EXPECT_EQ(result.status, Status::converged);
  EXPECT_EQ(result.counters.operator_applications, applications);
  // Two norm estimates of 20 applications each, then at least one per step.
  const Counters& c = result.counters;
  EXPECT_GE(applications, 40 + c.cg_steps + c.proportioning_steps + 2 * c.expansion_steps);
}

// Re-solving from the solution and its multiplier: the first inner solve already satisfies the
// final test, so one outer iteration and very few steps suffice.
TEST(Smalbe, WarmStartFromSolutionAndMultiplierTakesOneOuterIteration) {
  std::mt19937 rng(2808);
  const FetiLikeProblem p = make_feti_like(rng, 8, 3);
  const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
  SmalbeOptions opts = tight_options();
  Eigen::VectorXd x, m;
  const Result cold = smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x, m, opts);
  ASSERT_EQ(cold.status, Status::converged);
  opts.inner.norm_A = 1.0;
  const Result warm = smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x, m, opts);
  EXPECT_EQ(warm.status, Status::converged);
  EXPECT_EQ(warm.counters.outer_iterations, 1);
  EXPECT_LT(warm.counters.operator_applications, cold.counters.operator_applications);
}

// Plain SMALBE-M (fixed ρ, no growth safeguard) on problems where it behaves: it converges and
// keeps ρ = ρ₀.
TEST(Smalbe, PlainSmalbeMKeepsRhoFixed) {
  std::mt19937 rng(3030);
  for (int n : {40, 160}) {
    SCOPED_TRACE("n " + std::to_string(n));
    const FetiLikeProblem p = make_feti_like(rng, n, 6);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
    SmalbeOptions opts = tight_options();
    opts.rho_growth = 1.0;
    opts.inner.norm_A = norm_2(p.A);
    const ObservedSolve solve = observed_solve(qp, p.Q, opts);
    expect_converged_to(qp, p.Q, solve, opts, 0.1, norm_2(p.A));
    EXPECT_EQ(solve.result.rho_final, opts.inner.norm_A);
  }
}

// The fused forms y = A v + s·Q v and M⁻¹ v + s·Q v (what FETI supplies, reusing the Q v of
// P v) replace SMALBE's composition with the right shift (ρ for A, 1/ρ for M⁻¹): the same
// solve up to round-off (1e-12 relative: both stop at a relative gradient of 1e-10 on a
// problem with κ ≤ 10, and differ only in the rounding of the shift's products).
TEST(Smalbe, FusedShiftedFormsGiveTheSameSolve) {
  std::mt19937 rng(3232);
  for (const bool preconditioned : {false, true}) {
    SCOPED_TRACE(preconditioned ? "preconditioned" : "plain");
    const FetiLikeProblem p = make_feti_like(rng, 60, 5);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
    const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(60, 60) - p.Q;
    const Eigen::MatrixXd M = P * Eigen::MatrixXd(p.F.diagonal().cwiseInverse().asDiagonal()) * P;
    SmalbeOptions opts = tight_options();
    opts.inner.norm_A = norm_2(p.A);
    opts.projected_operator = true;
    if (preconditioned) opts.preconditioner = testing::dense_operator(M);
    long composed_Q = 0, fused_Q = 0;
    Eigen::VectorXd x1, m1, x2, m2;
    const Result composed =
        smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q, &composed_Q), qp.b, qp.l, qp.u, x1, m1, opts);
    // The fused forms as FETI builds them: P v = v − Q v once, reused for the shift.
    Eigen::VectorXd Qv;
    const LinearOperator Q_counted = testing::dense_operator(p.Q, &fused_Q);
    opts.A_plus_shifted_Q = [&](const Eigen::VectorXd& v, double shift, Eigen::VectorXd& y) {
      Qv.resize(v.size());
      Q_counted(v, Qv);
      y.noalias() = p.A * v;  // PA₀P v, as the composed A computes it
      y += shift * Qv;
    };
    if (preconditioned)
      opts.preconditioner_plus_shifted_Q = [&](const Eigen::VectorXd& v, double shift, Eigen::VectorXd& y) {
        Qv.resize(v.size());
        Q_counted(v, Qv);
        y.noalias() = M * v;
        y += shift * Qv;
      };
    // Q itself uncounted: fused_Q counts only the hooks' applications.
    const Result fused =
        smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x2, m2, opts);
    ASSERT_EQ(composed.status, Status::converged);
    EXPECT_EQ(fused.status, Status::converged);
    EXPECT_LE((x1 - x2).norm(), 1e-12 * x1.norm());
    EXPECT_LE((m1 - m2).norm(), 1e-12 * m1.norm());
    EXPECT_GE(fused_Q, fused.counters.cg_steps);  // the fused forms were used for A + ρQ
  }
}

// The safeguard's patience: ρ grows only after rho_patience consecutive slow outer iterations.
// Patience beyond the outer iterations used keeps ρ = ρ₀ exactly (plain SMALBE-M); any patience
// reaches the same solution.
TEST(Smalbe, RhoGrowsOnlyAfterItsPatience) {
  std::mt19937 rng(3131);
  int grew_at_patience_1 = 0;
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const FetiLikeProblem p = make_feti_like(rng, 80, 6);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
    SmalbeOptions opts = tight_options();
    opts.inner.norm_A = norm_2(p.A);
    const ObservedSolve eager = observed_solve(qp, p.Q, opts);
    expect_converged_to(qp, p.Q, eager, opts, 0.1, norm_2(p.A));
    grew_at_patience_1 += eager.result.rho_final > opts.inner.norm_A;
    opts.rho_patience = 1000;
    const ObservedSolve patient = observed_solve(qp, p.Q, opts);
    expect_converged_to(qp, p.Q, patient, opts, 0.1, norm_2(p.A));
    EXPECT_EQ(patient.result.rho_final, opts.inner.norm_A);
  }
  EXPECT_GT(grew_at_patience_1, 0);  // the trials do exercise the safeguard
}

// With A = PFP the outer iteration count is bounded independently of the size (Dostál 2009):
// same spectrum of F, n from 40 to 640.
TEST(Smalbe, OuterIterationsDoNotGrowWithSize) {
  std::mt19937 rng(2909);
  for (int n : {40, 160, 640}) {
    SCOPED_TRACE("n " + std::to_string(n));
    const FetiLikeProblem p = make_feti_like(rng, n, 6);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
    const ObservedSolve solve = observed_solve(qp, p.Q, tight_options());
    expect_converged_to(qp, p.Q, solve, tight_options(), 0.1, norm_2(p.A));
    // Measured 9, 8, 8 outer iterations and 121, 121, 120 applications of A.
    EXPECT_LE(solve.result.counters.outer_iterations, 15);
    EXPECT_LE(solve.result.counters.operator_applications, 200);
  }
}

// ---- Preconditioning ----

// P M P for P = I - Q: a preconditioner of A = PFP that vanishes on Im Q, as FETI supplies it.
Eigen::MatrixXd projected(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& M) {
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(Q.rows(), Q.cols()) - Q;
  return P * M * P;
}

TEST(SmalbePreconditioning, EmptyPreconditionerLeavesTheMethodUnchanged) {
  std::mt19937 rng(4101);
  for (int trial = 0; trial < 8; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const FetiLikeProblem p = make_feti_like(rng, 6 + 4 * trial, 1 + trial % 3);
    const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, all_kinds[trial % 4]);
    SmalbeOptions opts = tight_options();
    opts.projected_operator = trial % 2 == 0;
    const ObservedSolve first = observed_solve(qp, p.Q, opts);
    const ObservedSolve second = observed_solve(qp, p.Q, opts);
    EXPECT_EQ(first.result.status, Status::converged) << first.result.message;
    EXPECT_EQ(first.x, second.x);
    EXPECT_EQ(first.m, second.m);
    EXPECT_EQ(first.n_iterates, second.n_iterates);
    EXPECT_EQ(first.result.counters.operator_applications, second.result.counters.operator_applications);
    EXPECT_EQ(first.result.counters.preconditioner_applications, 0);
  }
}

// The FETI form with projected Jacobi P diag(F)⁻¹ P, every bound kind, weakly active components
// included: the same checks as without a preconditioner (known solution through the error bound,
// Q x ≈ 0, m ∈ Im Q, every inner iterate feasible), and one application of the caller's
// preconditioner per inner CG or expansion step. The outer budget is raised: one instance (lower
// bounds, trial 2: n = 7, 3 rows, 4 components at a bound) needed 176 outer iterations with or
// without the preconditioner when ρ stopped at 100‖A‖ (the multiplier iteration contracting by
// only 0.91 per step); ρ_max is now 1e4‖A‖.
TEST(SmalbePreconditioning, ProjectedJacobiReachesKnownSolutions) {
  std::mt19937 rng(4202);
  for (BoundKind kind : all_kinds) {
    for (int trial = 0; trial < 8; ++trial) {
      SCOPED_TRACE(std::string(testing::to_string(kind)) + " trial " + std::to_string(trial));
      const int n = trial < 4 ? 3 + 2 * trial : 20 * trial;
      const int n_rows = 1 + trial % std::min(3, n - 1);
      const FetiLikeProblem p = make_feti_like(rng, n, n_rows);
      const Degeneracy degeneracy = trial % 4 == 3 ? Degeneracy::weakly_active : Degeneracy::none;
      const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, kind, degeneracy);
      const Eigen::MatrixXd M_inverse = projected(p.Q, p.F.diagonal().cwiseInverse().asDiagonal());
      SmalbeOptions opts = tight_options();
      opts.projected_operator = true;
      opts.max_outer_iterations = 400;
      long applications = 0;
      opts.preconditioner = testing::dense_operator(M_inverse, &applications);
      const ObservedSolve solve = observed_solve(qp, p.Q, opts);
      expect_converged_to(qp, p.Q, solve, opts, 0.1, norm_2(p.A));
      const Counters& c = solve.result.counters;
      EXPECT_EQ(c.preconditioner_applications, applications);
      EXPECT_EQ(c.preconditioner_applications, c.cg_steps + c.expansion_steps);
    }
  }
}

// No bounds and the exact preconditioner on Im P, (PFP)⁺: then (PFP)⁺ + Q/ρ is the exact inverse
// of A + ρQ, so every inner solve is at most one PCG step (mprgp's exactness argument), and
// SMALBE itself needs two outer iterations: the first multiplier update gives m = Q b exactly.
// Measured: 2 outer iterations and 2 CG steps on trials 1–5. Trial 0 takes 4 and 3: with
// M₀ = ρ₀ = ‖A‖ (the defaults) the inner test after the first update compares ρ‖Qx‖ ≤ M‖Qx‖, a
// tie that round-off resolves as "stop" with no step; the safeguard then grows ρ twice, and
// the later inner solves, for the new ρ, are still one step each. A Q part scaled wrongly (ρQ
// instead of Q/ρ) leaves eigenvalues 1 and ρ², two steps for the first inner solve; a missing
// one never moves Q x.
TEST(SmalbePreconditioning, ExactPreconditionerSolvesEachInnerProblemInOnePcgStep) {
  std::mt19937 rng(4303);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 8 + 8 * trial;
    const int n_rows = 1 + trial % 4;
    const FetiLikeProblem p = make_feti_like(rng, n, n_rows);
    const DenseQp qp = equality_only_problem(rng, p);
    // (PFP)⁺ = P (PFP + Q)⁻¹ P: PFP + Q is SPD and maps Im P to itself.
    const Eigen::MatrixXd M_inverse = projected(p.Q, (p.A + p.Q).inverse());
    SmalbeOptions opts = tight_options();
    opts.projected_operator = true;
    opts.preconditioner = testing::dense_operator(M_inverse);
    const ObservedSolve solve = observed_solve(qp, p.Q, opts);
    expect_converged_to(qp, p.Q, solve, opts, 0.1, norm_2(p.A));
    const Counters& c = solve.result.counters;
    EXPECT_LE(c.outer_iterations, 4);
    EXPECT_LE(c.cg_steps, c.outer_iterations);
    EXPECT_EQ(c.expansion_steps + c.proportioning_steps, 0);
  }
}

// A badly scaled FETI-like problem: F = D^{1/2} F0 D^{1/2}, D spanning 1e-3…1e3, λ(F0) in
// [0.5, 1], A = PFP, bounds active; solved without and with P diag(F)⁻¹ P.
//
// Same solution, in the norm ‖D^{1/2}·‖ where the problem is well conditioned (the plain bound
// of expect_converged_to would carry λ_min(F) ≈ 5e-4). As for error_bound, with e = x - x*,
// a = gᴾ of A x - b + m, q = ‖Q x‖ = ‖Q e‖, and s = max D^{1/2}:
//   λ_min(F0)‖D^{1/2}Pe‖² ≤ (Pe)ᵀF(Pe) = eᵀAe ≤ aᵀe + ‖m - m*‖ q
//                                      ≤ ‖D^{-1/2}a‖ ‖D^{1/2}e‖ + (‖m - m*‖/s)·(s q),
//   ‖D^{1/2}e‖ ≤ ‖D^{1/2}Pe‖ + s q,
// which is error_bound(‖D^{-1/2}a‖, s q, ‖m - m*‖/s, λ_min(F0)) as a bound of ‖D^{1/2}e‖.
//
// Fewer applications: measured over the three seeds (g++ 12, -O3) 1585/1774/1466 applications
// of A without, 255/269/250 with (plus 195/212/191 applications of the preconditioner), 5–6
// outer iterations either way, ρ grown to 10‖A‖ by the safeguard on the way (so the inner
// preconditioner is used with more than one ρ); ≥ 3× is required, the measured factor is ≥ 5.8.
TEST(SmalbePreconditioning, BadlyScaledProjectedJacobiGivesTheSameSolutionWithFewerApplications) {
  const int n = 100;
  const int n_rows = 4;
  const double lambda_min_F0 = 0.5;
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    const Eigen::MatrixXd F0 = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, lambda_min_F0, 1.0));
    const testing::BadlyScaled scaled = testing::badly_scaled(rng, F0, 3.0);
    const Eigen::MatrixXd G = testing::random_orthonormal_rows(rng, n_rows, n);
    const Eigen::MatrixXd Q = G.transpose() * G;
    const Eigen::MatrixXd A = projected(Q, scaled.A);
    const DenseQp qp = testing::make_known_solution_problem(rng, A, G, BoundKind::mixed);
    const Eigen::MatrixXd M_inverse = projected(Q, scaled.A.diagonal().cwiseInverse().asDiagonal());

    SmalbeOptions opts = tight_options();
    opts.projected_operator = true;
    opts.max_operator_applications = 1000000;
    const ObservedSolve plain = observed_solve(qp, Q, opts);
    long applications = 0;
    opts.preconditioner = testing::dense_operator(M_inverse, &applications);
    const ObservedSolve preconditioned = observed_solve(qp, Q, opts);

    const double norm_A = norm_2(A);
    const double s = scaled.sqrt_d.maxCoeff();
    const Eigen::VectorXd m_star = G.transpose() * qp.nu;
    double bound_sum = 0.0;
    for (const ObservedSolve* solve : {&plain, &preconditioned}) {
      EXPECT_EQ(solve->result.status, Status::converged) << solve->result.message;
      EXPECT_EQ(solve->n_infeasible, 0);
      const Eigen::VectorXd g = A * solve->x - qp.b + solve->m;
      const Eigen::VectorXd gP = testing::reference_projected_gradient_vector(solve->x, g, qp.l, qp.u);
      const double Qx_norm = (G * solve->x).norm();
      const double slack = 1e-13 * (1.0 + qp.b.norm());
      EXPECT_LE(gP.norm(), opts.relative_tolerance * qp.b.norm() + slack);
      EXPECT_LE(Qx_norm, opts.equality_tolerance * qp.b.norm() / (0.95 * norm_A) + slack);
      const double bound = error_bound(gP.cwiseQuotient(scaled.sqrt_d).norm(), s * Qx_norm,
                                       (solve->m - m_star).norm() / s, lambda_min_F0);
      EXPECT_LE(scaled.sqrt_d.cwiseProduct(solve->x - qp.x_star).norm(), bound);
      bound_sum += bound;
    }
    EXPECT_LE(scaled.sqrt_d.cwiseProduct(preconditioned.x - plain.x).norm(), bound_sum);
    EXPECT_GT((preconditioned.x.array() == qp.l.array()).count() + (preconditioned.x.array() == qp.u.array()).count(),
              n / 10);

    const Counters& with = preconditioned.result.counters;
    const Counters& without = plain.result.counters;
    EXPECT_EQ(with.preconditioner_applications, applications);
    EXPECT_LE(3 * with.operator_applications, without.operator_applications)
        << "with " << with.operator_applications << ", without " << without.operator_applications;
  }
}

TEST(SmalbePreconditioning, NanFromThePreconditionerIsReported) {
  std::mt19937 rng(4404);
  const int n = 10;
  const FetiLikeProblem p = make_feti_like(rng, n, 2);
  const DenseQp qp = testing::make_known_solution_problem(rng, p.A, p.G, BoundKind::mixed);
  const Eigen::MatrixXd M_inverse = projected(p.Q, p.F.diagonal().cwiseInverse().asDiagonal());
  for (long fail_at : {1L, 4L, 12L}) {
    SCOPED_TRACE("fail_at " + std::to_string(fail_at));
    long applications = 0;
    SmalbeOptions opts = tight_options();
    opts.projected_operator = true;
    opts.preconditioner = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      y.noalias() = M_inverse * v;
      if (++applications == fail_at) {
        y[0] = nan;
      }
    };
    Eigen::VectorXd x, m;
    const Result result =
        smalbe(testing::dense_operator(p.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x, m, opts);
    EXPECT_EQ(result.status, Status::non_finite) << result.message;
    EXPECT_NE(result.message.find("preconditioner"), std::string::npos) << result.message;
    EXPECT_EQ(result.counters.preconditioner_applications, fail_at);
    EXPECT_TRUE(std::isnan(result.projected_gradient_norm));
    EXPECT_TRUE(x.allFinite());
    EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
  }
}

// SMALBE builds the inner preconditioner for the current ρ; one set by the caller in
// inner.preconditioner would be ignored or stale, so it is refused.
TEST(SmalbePreconditioning, InnerPreconditionerIsRejected) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(3, 3);
  SmalbeOptions opts;
  opts.inner.preconditioner = testing::dense_operator(A);
  EXPECT_NE(check_options(opts).find("inner.preconditioner"), std::string::npos);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(3, 0.5);
  const Result result = smalbe(testing::dense_operator(A), testing::dense_operator(Q), Eigen::VectorXd::Ones(3),
                               Eigen::VectorXd::Zero(3), Eigen::VectorXd::Constant(3, 2.0), x, opts);
  EXPECT_EQ(result.status, Status::invalid_input);
  EXPECT_EQ(x, Eigen::VectorXd::Constant(3, 0.5));
}

}  // namespace
}  // namespace dualcell::qp
