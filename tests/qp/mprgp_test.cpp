// MPRGP on seeded random dense problems against known solutions and the enumeration oracle,
// plus the failure statuses and a 1D obstacle problem of size 2000; then MPRGP preconditioned
// in face (exact inverse, Jacobi on badly scaled problems, arbitrary SPD and invalid ones).
#include "qp/mprgp.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "qp_test_utils.hpp"

namespace dualcell::qp {
namespace {

using testing::BoundKind;
using testing::Degeneracy;
using testing::DenseQp;
using testing::inf;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr BoundKind all_kinds[] = {BoundKind::lower, BoundKind::upper, BoundKind::box, BoundKind::mixed};

// A solve with every iterate observed: exact feasibility (no tolerance: the solver promises
// l ≤ x ≤ u bit for bit) and monotone decrease of f, which MPRGP guarantees for every step
// (up to the round-off of evaluating f).
struct ObservedSolve {
  Result result;
  Eigen::VectorXd x;
  long n_iterates = 0;
  long n_infeasible = 0;
  long n_increases = 0;
};

ObservedSolve observed_solve(const DenseQp& qp, MprgpOptions opts, Eigen::VectorXd x0 = {}) {
  ObservedSolve out;
  double f_previous = inf;
  opts.on_iterate = [&](const Eigen::VectorXd& x) {
    ++out.n_iterates;
    out.n_infeasible += testing::is_feasible(x, qp.l, qp.u) ? 0 : 1;
    const double f = testing::objective(qp.A, qp.b, x);
    out.n_increases += f > f_previous + 1e-12 * (1.0 + std::abs(f_previous)) ? 1 : 0;
    f_previous = f;
  };
  out.x = std::move(x0);
  out.result = mprgp(testing::dense_operator(qp.A), qp.b, qp.l, qp.u, out.x, opts);
  return out;
}

// Checks a converged solve against a reference solution x_ref with value f_ref.
// lambda_min > 0: A is SPD and the solution unique; then (Pang's error bound for strongly
// convex problems, with the natural residual bounded by ‖gᴾ‖)
//     ‖x − x*‖ ≤ (1 + ‖A‖)/λ_min · ‖gᴾ(x)‖.
// Always, by convexity and feasibility of x and x*:  0 ≤ f(x) − f* ≤ ‖gᴾ(x)‖ ‖x − x*‖.
// The slack 1e-11 covers the round-off of generating b and of the oracle's dense solves.
void expect_matches(const DenseQp& qp, const ObservedSolve& solve, const Eigen::VectorXd& x_ref, double f_ref,
                    double lambda_min, double norm_A) {
  const Result& result = solve.result;
  EXPECT_EQ(result.status, Status::converged) << result.message;
  EXPECT_EQ(solve.n_infeasible, 0);
  EXPECT_EQ(solve.n_increases, 0);
  ASSERT_TRUE(testing::is_feasible(solve.x, qp.l, qp.u));

  const Eigen::VectorXd g = qp.A * solve.x - qp.b;
  const double gP = testing::reference_projected_gradient(solve.x, g, qp.l, qp.u);
  const double slack = 1e-11 * (1.0 + qp.b.norm());
  // The reported residuals are those of the returned x, not of a drifted recursive gradient.
  EXPECT_NEAR(result.projected_gradient_norm, gP, slack);
  EXPECT_EQ(result.bound_violation, 0.0);
  EXPECT_LE(result.relative_projected_gradient, 1e-10 + 1e-14);

  const double error = (solve.x - x_ref).norm();
  if (lambda_min > 0.0) {
    EXPECT_LE(error, (1.0 + norm_A) / lambda_min * gP + slack);
  }
  const double f = testing::objective(qp.A, qp.b, solve.x);
  const double f_slack = 1e-11 * (1.0 + std::abs(f_ref));
  EXPECT_GE(f, f_ref - f_slack);
  EXPECT_LE(f, f_ref + gP * error + f_slack);
}

MprgpOptions tight_options() {
  MprgpOptions opts;
  opts.relative_tolerance = 1e-10;
  return opts;
}

TEST(EstimateNorm, IsWithinOnePercentAboveTheLargestEigenvalue) {
  std::mt19937 rng(11);
  Eigen::VectorXd d = testing::spectrum(rng, 30, 0.01, 0.5);
  d[0] = 3.0;  // gap 3 : 0.5 makes 20 power iterations exact to round-off
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, d);
  long applications = 0;
  const double estimate = estimate_norm(testing::dense_operator(A, &applications), 30);
  EXPECT_EQ(applications, 20);
  EXPECT_GE(estimate, 3.0);
  EXPECT_LE(estimate, 3.0 * 1.01 + 1e-12);
  EXPECT_EQ(estimate_norm(testing::dense_operator(Eigen::MatrixXd::Zero(4, 4)), 4), 0.0);
}

TEST(EnumerationOracle, RecoversGeneratedSolutions) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 3 + trial % 4;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
    const int n_eq = trial % 2;
    const Eigen::MatrixXd C = testing::random_orthonormal_rows(rng, n_eq, n);
    const DenseQp qp = testing::make_known_solution_problem(rng, A, C, all_kinds[trial % 4]);
    const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
    ASSERT_TRUE(oracle.found);
    EXPECT_LE((oracle.x - qp.x_star).norm(), 1e-9) << "trial " << trial;
  }
}

TEST(Mprgp, SpdKnownSolutionsForEveryBoundKind) {
  std::mt19937 rng(101);
  for (BoundKind kind : all_kinds) {
    for (int trial = 0; trial < 15; ++trial) {
      SCOPED_TRACE(std::string(testing::to_string(kind)) + " trial " + std::to_string(trial));
      const int n = 3 + trial % 6;
      const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
      const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), kind);
      const ObservedSolve solve = observed_solve(qp, tight_options());
      expect_matches(qp, solve, qp.x_star, testing::objective(A, qp.b, qp.x_star), 0.1, 1.0);
      EXPECT_LE(solve.result.complementarity, 1e-8);
    }
  }
}

TEST(Mprgp, SpdRandomProblemsMatchTheEnumerationOracle) {
  std::mt19937 rng(202);
  for (BoundKind kind : all_kinds) {
    for (int trial = 0; trial < 10; ++trial) {
      SCOPED_TRACE(std::string(testing::to_string(kind)) + " trial " + std::to_string(trial));
      const int n = 3 + trial % 6;
      const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.05, 2.0));
      const DenseQp qp = testing::make_random_problem(rng, A, Eigen::MatrixXd(0, n), kind);
      const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
      ASSERT_TRUE(oracle.found);
      const ObservedSolve solve = observed_solve(qp, tight_options());
      expect_matches(qp, solve, oracle.x, oracle.value, 0.05, 2.0);
    }
  }
}

// Singular A, so x* need not be unique: only the optimal value is compared. Box bounds, or
// known-solution problems (which are bounded below by construction), keep the problem bounded.
TEST(Mprgp, SingularBoundedProblemsReachTheOptimalValue) {
  std::mt19937 rng(303);
  for (int trial = 0; trial < 24; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 3 + trial % 6;
    const int zeros = 1 + trial % 2;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0, zeros));
    const BoundKind kind = all_kinds[trial % 4];
    DenseQp qp = trial % 2 == 0 ? testing::make_random_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::box)
                                : testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), kind);
    const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
    ASSERT_TRUE(oracle.found);
    const ObservedSolve solve = observed_solve(qp, tight_options());
    expect_matches(qp, solve, oracle.x, oracle.value, 0.0, 1.0);
  }
}

// Weakly active components (at a bound with zero gradient) and solutions at a vertex of the box.
TEST(Mprgp, DegenerateSolutions) {
  std::mt19937 rng(404);
  for (Degeneracy degeneracy : {Degeneracy::weakly_active, Degeneracy::vertex}) {
    for (int trial = 0; trial < 16; ++trial) {
      SCOPED_TRACE("degeneracy " + std::to_string(static_cast<int>(degeneracy)) + " trial " + std::to_string(trial));
      const int n = 3 + trial % 6;
      const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
      const BoundKind kind = degeneracy == Degeneracy::vertex ? BoundKind::box : all_kinds[trial % 4];
      const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), kind, degeneracy);
      const ObservedSolve solve = observed_solve(qp, tight_options());
      expect_matches(qp, solve, qp.x_star, testing::objective(A, qp.b, qp.x_star), 0.1, 1.0);
      if (degeneracy == Degeneracy::vertex) {
        // Strict multipliers at a vertex: the active set is identified exactly.
        EXPECT_EQ(solve.x, qp.x_star);
      }
    }
  }
}

// Narrow boxes entered from the lower corner with a large load: the first steps release many
// components at once, and an uncapped proportioning step (ω_cg ≈ ‖b‖/λ ≫ width) would carry
// them far past the upper bound. Every iterate is observed.
TEST(Mprgp, EveryIterateStaysInANarrowBox) {
  std::mt19937 rng(505);
  long proportioning = 0;
  long expansions = 0;
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 4 + trial % 5;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.2, 1.0));
    DenseQp qp = testing::make_random_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::box);
    qp.u = qp.l.array() + 0.01;
    qp.b *= 50.0;
    const ObservedSolve solve = observed_solve(qp, tight_options(), qp.l);
    EXPECT_EQ(solve.result.status, Status::converged) << solve.result.message;
    EXPECT_GT(solve.n_iterates, 1);
    EXPECT_EQ(solve.n_infeasible, 0);
    EXPECT_EQ(solve.n_increases, 0);
    proportioning += solve.result.counters.proportioning_steps;
    expansions += solve.result.counters.expansion_steps;
    const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
    EXPECT_NEAR(testing::objective(A, qp.b, solve.x), oracle.value, 1e-8 * std::abs(oracle.value));
  }
  // Otherwise this test would not exercise the steps it is about.
  EXPECT_GT(proportioning, 0);
  EXPECT_GT(expansions, 0);
}

TEST(Mprgp, InfeasibleInitialGuessIsProjected) {
  std::mt19937 rng(606);
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, 5, 0.1, 1.0));
  const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, 5), BoundKind::box);
  Eigen::VectorXd first;
  MprgpOptions opts = tight_options();
  opts.on_iterate = [&](const Eigen::VectorXd& x) {
    if (first.size() == 0) {
      first = x;
    }
  };
  Eigen::VectorXd x = Eigen::VectorXd::Constant(5, 100.0);
  const Result result = mprgp(testing::dense_operator(A), qp.b, qp.l, qp.u, x, opts);
  EXPECT_EQ(result.status, Status::converged);
  EXPECT_EQ(first, qp.u);
  EXPECT_LE((x - qp.x_star).norm(), 1e-8);
}

TEST(Mprgp, InvalidInputIsRejectedAndLeavesXUnchanged) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(3);
  const Eigen::VectorXd l = Eigen::VectorXd::Zero(3);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(3, 2.0);
  const auto run = [&](Eigen::VectorXd bb, Eigen::VectorXd ll, Eigen::VectorXd uu, Eigen::VectorXd x,
                       const MprgpOptions& opts = {}) {
    const Eigen::VectorXd x_before = x;
    const Result result = mprgp(testing::dense_operator(A), bb, ll, uu, x, opts);
    EXPECT_EQ(result.status, Status::invalid_input);
    EXPECT_FALSE(result.message.empty());
    EXPECT_TRUE(std::isnan(result.projected_gradient_norm));
    EXPECT_EQ(x.size(), x_before.size());
    if (x.size() == x_before.size()) {
      EXPECT_TRUE(x.cwiseEqual(x_before).all() || x.hasNaN());
    }
    return result.message;
  };
  Eigen::VectorXd bad = l;
  bad[1] = 3.0;
  EXPECT_NE(run(b, bad, u, l).find("l[1]"), std::string::npos);  // l > u
  run(b, l.head(2), u, l);                                       // size mismatch
  run(b, l, u, Eigen::VectorXd::Zero(4));                        // x size mismatch
  bad = b;
  bad[0] = nan;
  run(bad, l, u, l);  // NaN in b
  bad = l;
  bad[2] = nan;
  run(b, bad, u, l);  // NaN in l
  bad = u;
  bad[2] = -inf;
  run(b, l.cwiseMin(-1.0), bad, l);  // empty feasible set
  bad = l;
  bad[0] = nan;
  run(b, l, u, bad);  // NaN in the initial guess
  MprgpOptions opts;
  opts.Gamma = 0.0;
  run(b, l, u, l, opts);
  opts = {};
  opts.omega_bar_factor = 2.5;
  run(b, l, u, l, opts);
}

TEST(Mprgp, NanFromTheOperatorIsReported) {
  std::mt19937 rng(707);
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, 6, 0.1, 1.0));
  const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, 6), BoundKind::mixed);
  for (long fail_at : {1L, 3L, 6L}) {
    long applications = 0;
    const LinearOperator broken = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      y.noalias() = A * v;
      if (++applications == fail_at) {
        y[2] = nan;
      }
    };
    Eigen::VectorXd x;
    MprgpOptions opts;
    opts.norm_A = 1.0;
    const Result result = mprgp(broken, qp.b, qp.l, qp.u, x, opts);
    EXPECT_EQ(result.status, Status::non_finite) << "fail_at " << fail_at;
    EXPECT_FALSE(result.message.empty());
    EXPECT_TRUE(x.allFinite());
    EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
  }
}

TEST(Mprgp, MaxIterationsIsReportedWithHonestResiduals) {
  std::mt19937 rng(808);
  const int n = 8;
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.01, 1.0));
  const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::box);
  Eigen::VectorXd x;
  MprgpOptions opts = tight_options();
  opts.max_iterations = 2;
  const Result result = mprgp(testing::dense_operator(A), qp.b, qp.l, qp.u, x, opts);
  EXPECT_EQ(result.status, Status::max_iterations);
  EXPECT_FALSE(result.message.empty());
  const Counters& c = result.counters;
  EXPECT_EQ(c.cg_steps + c.expansion_steps + c.proportioning_steps, 2);
  const double gP = testing::reference_projected_gradient(x, A * x - qp.b, qp.l, qp.u);
  EXPECT_NEAR(result.projected_gradient_norm, gP, 1e-12);
  EXPECT_GT(result.relative_projected_gradient, opts.relative_tolerance);
}

TEST(Mprgp, UnboundedProblemIsReported) {
  // A = diag(1, 0), b = (0, 1), x₂ ≥ 0 only: f → −∞ as x₂ → ∞.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2);
  A(0, 0) = 1.0;
  const Eigen::VectorXd b = Eigen::Vector2d(0.0, 1.0);
  const Eigen::VectorXd l = Eigen::Vector2d(-inf, 0.0);
  const Eigen::VectorXd u = Eigen::Vector2d(inf, inf);
  Eigen::VectorXd x;
  const Result result = mprgp(testing::dense_operator(A), b, l, u, x);
  EXPECT_EQ(result.status, Status::unbounded) << result.message;
  EXPECT_TRUE(x.allFinite());

  // Bounded from above, the same direction is stopped by the bound.
  x.resize(0);
  const Eigen::VectorXd u_box = Eigen::Vector2d(inf, 5.0);
  const Result boxed = mprgp(testing::dense_operator(A), b, l, u_box, x);
  EXPECT_EQ(boxed.status, Status::converged) << boxed.message;
  EXPECT_EQ(x[1], 5.0);
}

TEST(Mprgp, ZeroRightSideUsesTheToleranceAsAbsolute) {
  const Eigen::MatrixXd A = Eigen::Matrix2d{{2.0, -1.0}, {-1.0, 2.0}};
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd x = Eigen::Vector2d(3.0, -4.0);
  Result result = mprgp(testing::dense_operator(A), b, Eigen::Vector2d(-inf, -inf), Eigen::Vector2d(inf, inf), x);
  EXPECT_EQ(result.status, Status::converged);
  EXPECT_LE(x.norm(), 1e-8);
  // Bounds that exclude 0: the solution (1, 1/2) has gradient (3/2, 0) ≥ 0 at x₁ = l₁.
  x.resize(0);
  result = mprgp(testing::dense_operator(A), b, Eigen::Vector2d(1.0, -inf), Eigen::Vector2d(inf, inf), x);
  EXPECT_EQ(result.status, Status::converged);
  EXPECT_LE((x - Eigen::Vector2d(1.0, 0.5)).norm(), 1e-8);
}

TEST(Mprgp, CustomStoppingTestSeesFreshGradientAtTheEnd) {
  std::mt19937 rng(909);
  const int n = 7;
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
  const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::mixed);
  long calls = 0;
  double last_gP = inf;
  const StoppingTest stop = [&](const Eigen::VectorXd&, const Eigen::VectorXd&, double gP) {
    ++calls;
    last_gP = gP;
    return gP <= 1e-6;
  };
  MprgpWorkspace work;
  Eigen::VectorXd x;
  long applications = 0;
  const Result result =
      mprgp(testing::dense_operator(A, &applications), qp.b, qp.l, qp.u, x, MprgpOptions{}, stop, work);
  EXPECT_EQ(result.status, Status::converged);
  EXPECT_GT(calls, 1);
  EXPECT_LE(last_gP, 1e-6);
  // work.g is the gradient of the returned x, bit for bit the product the test would form.
  EXPECT_LE((work.g - (A * x - qp.b)).norm(), 1e-14);
  EXPECT_EQ(result.counters.operator_applications, applications);
}

TEST(Mprgp, UnattainableToleranceStagnatesInsteadOfSpinning) {
  std::mt19937 rng(1010);
  const int n = 8;
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 1e-3, 1.0));
  DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::mixed);
  qp.b *= 1e6;
  Eigen::VectorXd x;
  MprgpOptions opts;
  opts.relative_tolerance = 1e-30;
  opts.max_iterations = 100000;
  const Result result = mprgp(testing::dense_operator(A), qp.b, qp.l, qp.u, x, opts);
  EXPECT_EQ(result.status, Status::stagnated) << result.message;
  const Counters& c = result.counters;
  EXPECT_LT(c.cg_steps + c.expansion_steps + c.proportioning_steps, 5000);
  // The point is still a good solution; only the tolerance was unattainable.
  EXPECT_LE(result.relative_projected_gradient, 1e-10);
}

// 1D obstacle problem with A = tridiag(−1, 2 + mass, −1): load, an obstacle from below and a
// ceiling 0.01 above it over a stretch, so lower-only and box bounds mix and both are touched.
// mass = 0 is the Dirichlet Laplacian (‖A‖ < 4, κ ≈ 4n²/π², 1.6e6 for n = 2000); mass = 1 gives
// κ < 5 whatever n. Every iterate is checked for feasibility, and the result for KKT with an
// independently computed gradient.
struct ObstacleSolve {
  Result result;
  long steps = 0;
  long at_lower = 0;
  long at_upper = 0;
};

ObstacleSolve solve_obstacle(Eigen::Index n, double mass) {
  const double h = 1.0 / static_cast<double>(n + 1);
  long applications = 0;
  const LinearOperator A = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    for (Eigen::Index i = 0; i < n; ++i) {
      y[i] = (2.0 + mass) * v[i] - (i > 0 ? v[i - 1] : 0.0) - (i + 1 < n ? v[i + 1] : 0.0);
    }
    ++applications;
  };
  const Eigen::VectorXd b = Eigen::VectorXd::Constant(n, mass > 0.0 ? -0.1 : -h * h);
  Eigen::VectorXd l(n);
  Eigen::VectorXd u = Eigen::VectorXd::Constant(n, inf);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = static_cast<double>(i + 1) * h;
    l[i] = -0.09 + 0.03 * std::sin(6.0 * M_PI * s);
    if (s > 0.15 && s < 0.3) {
      u[i] = l[i] + 0.01;
    }
  }
  Eigen::VectorXd x;
  MprgpOptions opts;
  opts.max_iterations = 50000;
  long n_infeasible = 0;
  opts.on_iterate = [&](const Eigen::VectorXd& xi) { n_infeasible += testing::is_feasible(xi, l, u) ? 0 : 1; };
  ObstacleSolve out;
  out.result = mprgp(A, b, l, u, x, opts);
  EXPECT_EQ(out.result.status, Status::converged) << out.result.message;
  EXPECT_EQ(n_infeasible, 0);
  EXPECT_EQ(out.result.counters.operator_applications, applications);
  const Counters& c = out.result.counters;
  out.steps = c.cg_steps + c.expansion_steps + c.proportioning_steps;
  out.at_lower = (x.array() == l.array()).count();
  out.at_upper = (x.array() == u.array()).count();

  Eigen::VectorXd g(n);
  A(x, g);
  g -= b;
  EXPECT_LE(testing::reference_projected_gradient(x, g, l, u), 1e-8 * b.norm());
  return out;
}

TEST(Mprgp, LaplacianObstacleOfSize2000Converges) {
  const ObstacleSolve solve = solve_obstacle(2000, 0.0);
  // Both kinds of contact occur: the test is about bounds, not a plain CG solve.
  EXPECT_GT(solve.at_lower, 10);
  EXPECT_GT(solve.at_upper, 10);
  // Measured 13069 steps (g++ 12, -O2). CG alone needs O(√κ) = O(n) steps and MPRGP restarts
  // it at every expansion; the bound leaves room for round-off-dependent paths, not for a
  // change in the algorithm.
  EXPECT_LE(solve.steps, 20000);
}

// The MPRGP rate depends on the spectrum only: with κ < 5 the step count must not grow with n.
TEST(Mprgp, WellConditionedObstacleStepsDoNotGrowWithSize) {
  const ObstacleSolve small = solve_obstacle(500, 1.0);
  const ObstacleSolve large = solve_obstacle(4000, 1.0);
  EXPECT_GT(large.at_lower, 100);
  EXPECT_GT(large.at_upper, 10);
  // Measured 23 and 28 steps.
  EXPECT_LE(small.steps, 40);
  EXPECT_LE(large.steps, 40);
}

// ---- Preconditioning in face ----

// The same problem solved twice with an empty preconditioner gives the same bits, and M⁻¹ = I
// (z = χ_F ⊙ φ = φ) takes the same path: same steps, x to round-off. (That the empty
// preconditioner reproduces the code before preconditioning bit for bit was checked out of
// tree on 602 problems; here the existing tests above guard it.)
TEST(MprgpPreconditioning, EmptyPreconditionerLeavesTheMethodUnchanged) {
  std::mt19937 rng(3101);
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 5 + 3 * trial;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.01, 1.0));
    const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), all_kinds[trial % 4]);
    const ObservedSolve first = observed_solve(qp, tight_options());
    const ObservedSolve second = observed_solve(qp, tight_options());
    EXPECT_EQ(first.result.status, Status::converged);
    EXPECT_EQ(first.x, second.x);
    EXPECT_EQ(first.n_iterates, second.n_iterates);
    EXPECT_EQ(first.result.counters.operator_applications, second.result.counters.operator_applications);
    EXPECT_EQ(first.result.counters.preconditioner_applications, 0);

    MprgpOptions opts = tight_options();
    long applications = 0;
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
    opts.preconditioner = testing::dense_operator(identity, &applications);
    const ObservedSolve with_identity = observed_solve(qp, opts);
    const Counters& c = with_identity.result.counters;
    EXPECT_EQ(c.cg_steps, first.result.counters.cg_steps);
    EXPECT_EQ(c.expansion_steps, first.result.counters.expansion_steps);
    EXPECT_EQ(c.proportioning_steps, first.result.counters.proportioning_steps);
    EXPECT_EQ(c.operator_applications, first.result.counters.operator_applications);
    EXPECT_EQ(c.preconditioner_applications, applications);
    EXPECT_LE((with_identity.x - first.x).norm(), 1e-13 * (1.0 + first.x.norm()));
  }
}

// No active bounds and M⁻¹ = A⁻¹: z = A⁻¹g, ω_cg = gᵀA⁻¹g / gᵀA⁻¹g = 1 and x - z = A⁻¹b, so
// one PCG step solves the problem whatever κ(A) (here 1e3). The step is exact up to round-off of
// order κ(A)·ε·‖x*‖ ≈ 1e-13‖x*‖; 1e-10 leaves room and is still far below the error
// ‖gᴾ‖/λ_min ≤ 1e-10‖b‖/1e-3 = 1e-7‖b‖ that the stopping test alone would allow. Bounds that
// are infinite and bounds that stay inactive (ω_cg ≤ ω_f) are both covered.
TEST(MprgpPreconditioning, ExactInverseWithoutActiveBoundsIsOnePcgStep) {
  std::mt19937 rng(3202);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 10 + 10 * trial;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 1e-3, 1.0));
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
    const Eigen::VectorXd b = testing::gaussian_matrix(rng, n, 1).col(0);
    const Eigen::VectorXd x_star = ldlt.solve(b);
    const bool box = trial % 2 == 1;
    const double reach = x_star.cwiseAbs().maxCoeff() + 10.0;
    const Eigen::VectorXd l = Eigen::VectorXd::Constant(n, box ? -reach : -inf);
    const Eigen::VectorXd u = Eigen::VectorXd::Constant(n, box ? reach : inf);
    long applications = 0;
    MprgpOptions opts = tight_options();
    opts.preconditioner = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      y = ldlt.solve(v);
      ++applications;
    };
    Eigen::VectorXd x = testing::gaussian_matrix(rng, n, 1).col(0);
    const Result result = mprgp(testing::dense_operator(A), b, l, u, x, opts);
    EXPECT_EQ(result.status, Status::converged) << result.message;
    // Measured: 1 CG step and 1 application of M⁻¹ on every trial, error ≤ 5e-14‖x*‖.
    EXPECT_GE(result.counters.cg_steps, 1);
    EXPECT_LE(result.counters.cg_steps, 2);
    EXPECT_EQ(result.counters.expansion_steps, 0);
    EXPECT_EQ(result.counters.proportioning_steps, 0);
    EXPECT_EQ(result.counters.preconditioner_applications, applications);
    EXPECT_EQ(result.counters.preconditioner_applications, result.counters.cg_steps);
    EXPECT_LE((x - x_star).norm(), 1e-10 * x_star.norm());
  }
}

// Badly scaled problems A = D^{1/2} A0 D^{1/2}, D spanning 1e-4…1e4 (κ(A) up to ≈ 2e8), with
// bounds active at the solution, solved with and without the Jacobi preconditioner diag(A)⁻¹.
//
// Same solution: both runs are compared with the known x* and with each other in the norm
// ‖D^{1/2}·‖ in which the problem is well conditioned. For e = x - x*, x and x* feasible and x*
// a KKT point, gᵀe ≤ gᴾᵀe and g*ᵀe ≥ 0 (as in expect_matches), so
//   λ_min(A0)‖D^{1/2}e‖² ≤ eᵀAe = (g - g*)ᵀe ≤ gᴾᵀe ≤ ‖D^{-1/2}gᴾ‖ ‖D^{1/2}e‖,
//   ‖D^{1/2}(x - x*)‖ ≤ ‖D^{-1/2}gᴾ‖ / λ_min(A0),
// a tolerance from the stopping residual and κ(A0) = 2 only. (The unweighted bound ‖gᴾ‖/λ_min(A)
// would carry κ(D) = 1e8 and allow errors of order 1.)
//
// Fewer applications: the unpreconditioned run needs CG steps of order the number of distinct
// scales (≈ n), the preconditioned one a few per face. Measured over the three seeds (g++ 12,
// -O3): 1502/910/1049 applications of A without, 78/89/95 with (plus 33/37/42 applications of
// M⁻¹), 30–35 of 100 components at a bound; ≥ 3× is required, the measured factor is ≥ 10.
TEST(MprgpPreconditioning, JacobiOnABadlyScaledProblemGivesTheSameSolutionWithFewerApplications) {
  const int n = 100;
  const double lambda_min_A0 = 0.5;
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    const Eigen::MatrixXd A0 = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, lambda_min_A0, 1.0));
    const testing::BadlyScaled scaled = testing::badly_scaled(rng, A0, 4.0);
    const DenseQp qp = testing::make_known_solution_problem(rng, scaled.A, Eigen::MatrixXd(0, n), BoundKind::mixed);
    const Eigen::MatrixXd jacobi = scaled.A.diagonal().cwiseInverse().asDiagonal();

    MprgpOptions opts = tight_options();
    opts.max_iterations = 100000;
    const ObservedSolve plain = observed_solve(qp, opts);
    long applications = 0;
    opts.preconditioner = testing::dense_operator(jacobi, &applications);
    const ObservedSolve preconditioned = observed_solve(qp, opts);

    double bound_sum = 0.0;
    for (const ObservedSolve* solve : {&plain, &preconditioned}) {
      EXPECT_EQ(solve->result.status, Status::converged) << solve->result.message;
      EXPECT_EQ(solve->n_infeasible, 0);
      EXPECT_EQ(solve->n_increases, 0);
      const Eigen::VectorXd g = qp.A * solve->x - qp.b;
      const Eigen::VectorXd gP = testing::reference_projected_gradient_vector(solve->x, g, qp.l, qp.u);
      EXPECT_LE(gP.norm(), 1e-10 * qp.b.norm() + 1e-14);
      const double bound = gP.cwiseQuotient(scaled.sqrt_d).norm() / lambda_min_A0;
      EXPECT_LE(scaled.sqrt_d.cwiseProduct(solve->x - qp.x_star).norm(), bound);
      bound_sum += bound;
    }
    EXPECT_LE(scaled.sqrt_d.cwiseProduct(preconditioned.x - plain.x).norm(), bound_sum);
    // Some bounds are active, so the faces matter.
    EXPECT_GT((preconditioned.x.array() == qp.l.array()).count() + (preconditioned.x.array() == qp.u.array()).count(),
              n / 10);

    const Counters& with = preconditioned.result.counters;
    const Counters& without = plain.result.counters;
    EXPECT_EQ(without.preconditioner_applications, 0);
    EXPECT_EQ(with.preconditioner_applications, applications);
    EXPECT_LE(3 * with.operator_applications, without.operator_applications)
        << "with " << with.operator_applications << ", without " << without.operator_applications;
  }
}

// KKT with a preconditioner on, for many seeds: the enumeration oracle on small problems and
// known solutions on larger ones, every iterate feasible and f monotone (observed_solve), the
// residuals of expect_matches, and complementarity: a component off its lower bound carries
// g_i⁺ (x_i - l_i) ≤ |gᴾ_i| (x_i - l_i), so max_i ≤ ‖gᴾ‖∞ · the largest finite distance to a
// bound (and the same for upper bounds). M⁻¹ is either Jacobi or a random SPD matrix unrelated
// to A, with spectrum in [0.1, 10] (a poor preconditioner must still be a correct one). Each CG
// or expansion step applies M⁻¹ exactly once; nothing else does.
TEST(MprgpPreconditioning, KktHoldsWithAPreconditionerForManySeeds) {
  for (unsigned seed = 3301; seed < 3309; ++seed) {
    std::mt19937 rng(seed);
    for (int trial = 0; trial < 8; ++trial) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " trial " + std::to_string(trial));
      const bool small = trial % 2 == 0;
      const int n = small ? 3 + trial % 6 : 20 + 5 * trial;
      const BoundKind kind = all_kinds[(seed + trial) % 4];
      const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.05, 2.0));
      const DenseQp qp = small ? testing::make_random_problem(rng, A, Eigen::MatrixXd(0, n), kind)
                               : testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), kind);
      const Eigen::MatrixXd M_inverse = trial % 4 < 2
                                            ? Eigen::MatrixXd(A.diagonal().cwiseInverse().asDiagonal())
                                            : testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 10.0));
      MprgpOptions opts = tight_options();
      long applications = 0;
      opts.preconditioner = testing::dense_operator(M_inverse, &applications);
      const ObservedSolve solve = observed_solve(qp, opts);
      if (small) {
        const testing::OracleSolution oracle = testing::solve_by_enumeration(qp);
        ASSERT_TRUE(oracle.found);
        expect_matches(qp, solve, oracle.x, oracle.value, 0.05, 2.0);
      } else {
        expect_matches(qp, solve, qp.x_star, testing::objective(A, qp.b, qp.x_star), 0.05, 2.0);
      }

      const Eigen::VectorXd g = A * solve.x - qp.b;
      const Eigen::VectorXd gP = testing::reference_projected_gradient_vector(solve.x, g, qp.l, qp.u);
      double complementarity = 0.0;
      double distance = 0.0;
      for (int i = 0; i < n; ++i) {
        if (std::isfinite(qp.l[i])) {
          complementarity = std::max(complementarity, std::max(g[i], 0.0) * (solve.x[i] - qp.l[i]));
          distance = std::max(distance, solve.x[i] - qp.l[i]);
        }
        if (std::isfinite(qp.u[i])) {
          complementarity = std::max(complementarity, std::max(-g[i], 0.0) * (qp.u[i] - solve.x[i]));
          distance = std::max(distance, qp.u[i] - solve.x[i]);
        }
      }
      EXPECT_LE(complementarity, gP.lpNorm<Eigen::Infinity>() * distance);
      EXPECT_NEAR(solve.result.complementarity, complementarity, 1e-11 * (1.0 + qp.b.norm()) * (1.0 + distance));

      const Counters& c = solve.result.counters;
      EXPECT_EQ(c.preconditioner_applications, applications);
      EXPECT_EQ(c.preconditioner_applications, c.cg_steps + c.expansion_steps);
    }
  }
}

// M⁻¹ = -I is no preconditioner at all (z = -φ points uphill): every step falls back to φ, and
// the solve is still correct, only unpreconditioned and without conjugation.
TEST(MprgpPreconditioning, ANonPositivePreconditionerFallsBackToTheFreeGradient) {
  std::mt19937 rng(3404);
  for (int trial = 0; trial < 8; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 3 + trial % 6;
    const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
    const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), all_kinds[trial % 4]);
    const Eigen::MatrixXd minus_identity = -Eigen::MatrixXd::Identity(n, n);
    MprgpOptions opts = tight_options();
    opts.preconditioner = testing::dense_operator(minus_identity);
    const ObservedSolve solve = observed_solve(qp, opts);
    expect_matches(qp, solve, qp.x_star, testing::objective(A, qp.b, qp.x_star), 0.1, 1.0);
  }
}

TEST(MprgpPreconditioning, NanFromThePreconditionerIsReported) {
  std::mt19937 rng(3505);
  const int n = 12;
  const Eigen::MatrixXd A = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.01, 1.0));
  const DenseQp qp = testing::make_known_solution_problem(rng, A, Eigen::MatrixXd(0, n), BoundKind::mixed);
  for (long fail_at : {1L, 3L, 6L}) {
    SCOPED_TRACE("fail_at " + std::to_string(fail_at));
    long applications = 0;
    long operator_applications = 0;
    MprgpOptions opts = tight_options();
    opts.preconditioner = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      y = v.cwiseQuotient(A.diagonal());
      if (++applications == fail_at) {
        y[n - 1] = nan;  // wherever it lands, free or not
      }
    };
    Eigen::VectorXd x;
    const Result result = mprgp(testing::dense_operator(A, &operator_applications), qp.b, qp.l, qp.u, x, opts);
    EXPECT_EQ(result.status, Status::non_finite) << result.message;
    EXPECT_NE(result.message.find("preconditioner"), std::string::npos) << result.message;
    EXPECT_EQ(result.counters.preconditioner_applications, fail_at);
    EXPECT_EQ(result.counters.operator_applications, operator_applications);
    EXPECT_TRUE(std::isnan(result.projected_gradient_norm));
    EXPECT_TRUE(x.allFinite());
    EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
  }
}

}  // namespace
}  // namespace dualcell::qp
