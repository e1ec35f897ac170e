// The exact active-set method for small dense QPs (qp/dense_qp.hpp), checked by the optimality
// conditions of a convex QP, which are sufficient: feasibility, stationarity with the signs of
// the bound multipliers, complementarity.
#include "qp/dense_qp.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>
#include <random>

namespace dualcell::qp {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

struct Problem {
  Eigen::MatrixXd A, C;
  Eigen::VectorXd b, l, u;
};

// A = LLᵀ of rank n − k (positive semidefinite) plus the rows C that make it definite on ker C:
// the structure of the cell law (fibres free to move unless their rows hold them).
Problem random_problem(int n, int n_c, unsigned seed, bool semidefinite) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> uniform(0, 1);
  Problem p;
  Eigen::MatrixXd L(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) L(i, j) = g(rng);
  p.C = Eigen::MatrixXd(n_c, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n_c; ++i) p.C(i, j) = g(rng);
  if (semidefinite && n_c > 0) {
    // Drop the directions that the rows of C see from A's range: A is singular there.
    const Eigen::MatrixXd Q = p.C.transpose().householderQr().householderQ() * Eigen::MatrixXd::Identity(n, n_c);
    L -= Q * (Q.transpose() * L);
  }
  p.A = L * L.transpose() + (semidefinite ? 0.0 : 0.1) * Eigen::MatrixXd::Identity(n, n);
  p.b.resize(n), p.l.resize(n), p.u.resize(n);
  for (int i = 0; i < n; ++i) {
    p.b(i) = 3 * g(rng);
    const double kind = uniform(rng);  // contact (0 ≤ x), bond (−s ≤ x), box, fixed, free
    p.l(i) = kind < 0.5 ? 0.0 : kind < 0.7 ? -uniform(rng) : kind < 0.85 ? -uniform(rng) : kind < 0.9 ? 0.0 : -inf;
    p.u(i) = kind < 0.7 ? inf : kind < 0.85 ? uniform(rng) : kind < 0.9 ? 0.0 : inf;
  }
  return p;
}

// The optimality conditions, to `tolerance` relative to the size of the terms.
void expect_optimal(const Problem& p, const DenseQpResult& r, const std::vector<Bound>& active, double tolerance) {
  ASSERT_TRUE(r.converged) << r.message;
  const Eigen::VectorXd& x = r.x;
  const double scale = (p.A.cwiseAbs() * x.cwiseAbs()).maxCoeff() + p.b.lpNorm<Eigen::Infinity>();
  if (p.C.rows() > 0) {
    EXPECT_LE((p.C * x).norm(), tolerance * p.C.norm() * x.norm());
  }
  const Eigen::VectorXd nu =
      p.A * x - p.b + (p.C.rows() > 0 ? (p.C.transpose() * r.mu).eval() : Eigen::VectorXd::Zero(x.size()).eval());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    EXPECT_GE(x(i), p.l(i) - tolerance * scale) << i;
    EXPECT_LE(x(i), p.u(i) + tolerance * scale) << i;
    switch (active[i]) {
      case Bound::free:
        EXPECT_NEAR(nu(i), 0, tolerance * scale) << i;
        break;
      case Bound::lower:
        EXPECT_EQ(x(i), p.l(i));
        // A fixed variable (l = u) is an equality: its multiplier has either sign.
        if (p.l(i) != p.u(i)) {
          EXPECT_GE(nu(i), -tolerance * scale) << i;
        }
        break;
      case Bound::upper:
        EXPECT_EQ(x(i), p.u(i));
        EXPECT_LE(nu(i), tolerance * scale) << i;
        break;
    }
  }
}

TEST(DenseActiveSet, SolvesRandomBoxQpsWithEqualityRowsExactly) {
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const int n = 5 + static_cast<int>(seed % 7) * 9, n_c = static_cast<int>(seed % 4);
    const Problem p = random_problem(n, n_c, seed, seed % 2 == 0);
    DenseActiveSet qp(p.A, p.C);
    std::vector<Bound> active;
    const DenseQpResult r = qp.solve(p.b, p.l, p.u, active);
    // Round-off of an LU of size ≤ 60 on matrices of condition ≲ 1e4: 1e-9 relative.
    expect_optimal(p, r, active, 1e-9);
  }
}

// Along a path (b moving a little) the active set stays: the warm start solves one subproblem
// with the factorisation it kept.
TEST(DenseActiveSet, AWarmStartAtTheSameActiveSetIsOneSolveWithoutFactorisation) {
  const Problem p = random_problem(40, 2, 5, false);
  DenseQpResult r;
  DenseActiveSet qp(p.A, p.C);
  std::vector<Bound> active;
  r = qp.solve(p.b, p.l, p.u, active);
  ASSERT_TRUE(r.converged);
  EXPECT_GE(r.factorisations, 1);
  const std::vector<Bound> first = active;
  Problem q = p;
  q.b *= 1.0 + 1e-9;  // scaled: x scales, the active set of a cone stays (bounds at 0 stay)
  for (Eigen::Index i = 0; i < q.l.size(); ++i)
    if (q.l(i) != 0 || q.u(i) != 0) q.l(i) = q.l(i) == 0 ? 0.0 : -inf, q.u(i) = q.u(i) == 0 ? 0.0 : inf;
  DenseActiveSet cone(q.A, q.C);
  std::vector<Bound> cone_active;
  ASSERT_TRUE(cone.solve(p.b, q.l, q.u, cone_active).converged);
  const DenseQpResult again = cone.solve(q.b, q.l, q.u, cone_active);
  expect_optimal(q, again, cone_active, 1e-9);
  EXPECT_EQ(again.iterations, 1);
  EXPECT_EQ(again.factorisations, 0);
}

// Two material points sharing one solver, each warm-started from its own last active set: the
// second visit of each finds its factorisation among the kept ones (no new factorisation), and
// the answers are bit for bit those of a solver for that point alone, tangent and generation
// included (a restored factorisation is the one a caller's tangent came from).
TEST(DenseActiveSet, ReturningToAKeptFreeSetReusesItsFactorisation) {
  const Problem p = random_problem(30, 2, 9, false);
  Problem q = p;
  q.b = -p.b;  // another active set
  DenseActiveSet shared(p.A, p.C), alone_p(p.A, p.C), alone_q(q.A, q.C);
  std::vector<Bound> ap, aq, bp, bq;
  const DenseQpResult rp = shared.solve(p.b, p.l, p.u, ap);
  const long generation_p = shared.generation();
  const Eigen::MatrixXd tangent_p = shared.sensitivity(Eigen::MatrixXd::Identity(30, 30));
  const DenseQpResult rq = shared.solve(q.b, q.l, q.u, aq);
  ASSERT_TRUE(rp.converged && rq.converged);
  ASSERT_NE(ap, aq);
  const DenseQpResult again_p = shared.solve(p.b, p.l, p.u, ap);
  EXPECT_EQ(again_p.factorisations, 0);
  EXPECT_EQ(shared.generation(), generation_p);
  EXPECT_EQ(shared.sensitivity(Eigen::MatrixXd::Identity(30, 30)), tangent_p);
  const DenseQpResult again_q = shared.solve(q.b, q.l, q.u, aq);
  EXPECT_EQ(again_q.factorisations, 0);
  alone_p.solve(p.b, p.l, p.u, bp);
  alone_q.solve(q.b, q.l, q.u, bq);
  EXPECT_EQ(again_p.x, alone_p.solve(p.b, p.l, p.u, bp).x);
  EXPECT_EQ(again_q.x, alone_q.solve(q.b, q.l, q.u, bq).x);
  EXPECT_EQ(ap, bp);
  EXPECT_EQ(aq, bq);
}

// dx/db at the active set against the difference of two solves that keep it.
TEST(DenseActiveSet, SensitivityIsTheDerivativeAtTheActiveSet) {
  const Problem p = random_problem(30, 3, 9, false);
  DenseActiveSet qp(p.A, p.C);
  std::vector<Bound> active;
  const DenseQpResult r = qp.solve(p.b, p.l, p.u, active);
  ASSERT_TRUE(r.converged);
  Eigen::VectorXd db = Eigen::VectorXd::Zero(p.b.size());
  db(3) = 1e-7, db(7) = -2e-7;
  const Eigen::MatrixXd dx = qp.sensitivity(db);
  DenseActiveSet other(p.A, p.C);
  std::vector<Bound> same = active;
  const Eigen::VectorXd b2 = p.b + db;
  const DenseQpResult r2 = other.solve(b2, p.l, p.u, same);
  ASSERT_TRUE(r2.converged);
  ASSERT_EQ(same, active) << "the step must keep the active set";
  // A linear map: exact to round-off.
  EXPECT_LE((r2.x - r.x - dx.col(0)).norm(), 1e-12 * r.x.norm());
}

// A change of the variables' units, x = D x' with D diagonal (a cell's macro stresses beside its
// interface forces, in any length unit), is the same problem: A' = DAD, b' = Db, l' = D⁻¹l,
// C' = CD, and its solution is D⁻¹x with the same active set. Half the variables in units 10¹²
// larger puts A's blocks 10²⁴ apart, which an unequilibrated pivot test reads as singular.
TEST(DenseActiveSet, TheUnitsOfTheVariablesDoNotMatter) {
  for (const double unit : {1e-12, 1e12}) {
    const Problem p = random_problem(30, 2, 11, true);
    Eigen::VectorXd d = Eigen::VectorXd::Ones(30);
    d.head(15).setConstant(unit);
    Problem q = p;
    q.A = d.asDiagonal() * p.A * d.asDiagonal();
    q.C = p.C * d.asDiagonal();
    q.b = d.asDiagonal() * p.b;
    q.l = p.l.cwiseQuotient(d);
    q.u = p.u.cwiseQuotient(d);
    DenseActiveSet qp(p.A, p.C), scaled(q.A, q.C);
    std::vector<Bound> active, scaled_active;
    const DenseQpResult r = qp.solve(p.b, p.l, p.u, active);
    const DenseQpResult rs = scaled.solve(q.b, q.l, q.u, scaled_active);
    ASSERT_TRUE(r.converged) << r.message;
    ASSERT_TRUE(rs.converged) << unit << ": " << rs.message;
    EXPECT_EQ(scaled_active, active) << unit;
    // Both exact to round-off of an LU of size 30 on a matrix of condition ≲ 1e4 once equilibrated.
    EXPECT_LE((d.asDiagonal() * rs.x - r.x).norm(), 1e-9 * r.x.norm()) << unit;
    const Eigen::MatrixXd dx = qp.sensitivity(Eigen::MatrixXd::Identity(30, 3));
    const Eigen::MatrixXd dx_scaled = scaled.sensitivity(d.asDiagonal() * Eigen::MatrixXd::Identity(30, 3));
    EXPECT_LE((d.asDiagonal() * dx_scaled - dx).norm(), 1e-9 * dx.norm()) << unit;
  }
}

// A free set near the kept one is solved through the kept LU bordered by the variables that
// differ (qp/dense_qp.hpp): it must give what a factorisation of its own gives, to round-off,
// along paths whose active sets change a few variables at a time. The problems are large enough
// to be bordered (≥ 64 unknowns), with dense rows of C and with rows that each see a block of
// contact variables only (as a fibre's rows see its own pairs), one with a dependent row.
TEST(DenseActiveSet, BorderedSolvesAreTheFactorisedOnes) {
  int updates = 0, factorisations = 0, reference_factorisations = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const int n = 150 + 20 * static_cast<int>(seed % 4), n_c = static_cast<int>(seed % 3) + 1;
    Problem p = random_problem(n, n_c, seed, seed % 2 == 0);
    if (seed > 5) {  // rows over blocks of 8 contact variables
      p.C.setZero();
      for (int q = 0; q < n_c; ++q)
        for (int j = 8 * q; j < 8 * q + 8; ++j) p.C(q, j) = 1 + 0.1 * j, p.l(j) = 0, p.u(j) = inf;
    }
    // Dependent rows (a 16-fibre RVE's are): the QR may pick other independent rows from one free
    // set to the next, and the border must carry on with the base's where they span the same.
    if (seed == 5) p.C.row(2) = p.C.row(0) + p.C.row(1);
    DenseActiveSet bordered(p.A, p.C), reference(p.A, p.C, DenseActiveSet::Updates::factorise_each);
    std::vector<Bound> active, reference_active;
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    Eigen::VectorXd b = p.b;
    for (int step = 0; step < 30; ++step) {
      for (Eigen::Index i = 0; i < n; ++i) b(i) += 0.05 * g(rng);  // a step along a path
      const DenseQpResult r = bordered.solve(b, p.l, p.u, active);
      const DenseQpResult ref = reference.solve(b, p.l, p.u, reference_active);
      Problem at = p;
      at.b = b;
      // Round-off of an LU of size ≤ 200 and of a Schur complement of ≤ 32 on matrices of
      // condition ≲ 1e5: 1e-9 relative.
      expect_optimal(at, r, active, 1e-9);
      ASSERT_TRUE(ref.converged) << ref.message;
      EXPECT_EQ(active, reference_active) << seed << " " << step;
      EXPECT_LE((r.x - ref.x).norm(), 1e-9 * ref.x.norm()) << seed << " " << step;
      const Eigen::MatrixXd db = Eigen::MatrixXd::Random(n, 3);
      EXPECT_LE((bordered.sensitivity(db) - reference.sensitivity(db)).norm(), 1e-9 * reference.sensitivity(db).norm());
      updates += r.updates, factorisations += r.factorisations;
      reference_factorisations += ref.factorisations;
      EXPECT_EQ(ref.updates, 0);
    }
  }
  // The test must see the bordered solves, and they must save most of the factorisations.
  EXPECT_GT(updates, 200);
  EXPECT_LT(4 * factorisations, reference_factorisations) << updates << " " << factorisations;
}

// A freed variable that A cannot hold (its row and column those of a free variable w, so A_FF is
// singular once both are free, and b leans along e_v − e_w: the problem is unbounded) leaves a
// Schur complement of round-off: the border must read that as singular, as a factorisation does,
// not take a step of 1e16.
TEST(DenseActiveSet, ABorderThatMakesTheSystemSingularIsRefusedAsAFactorisationIs) {
  Problem p = random_problem(100, 0, 21, false);
  const int v = 40, w = 41;
  p.A.row(v) = p.A.row(w);
  p.A.col(v) = p.A.col(w);
  p.l.setConstant(-inf);
  p.u.setConstant(inf);
  p.l(v) = 0;
  p.b(v) = p.b(w) + 1;
  for (const auto updates : {DenseActiveSet::Updates::bordered, DenseActiveSet::Updates::factorise_each}) {
    DenseActiveSet qp(p.A, p.C, updates);
    std::vector<Bound> active(100, Bound::free);
    active[v] = Bound::lower;
    const DenseQpResult r = qp.solve(p.b, p.l, p.u, active);
    EXPECT_FALSE(r.converged) << r.x.lpNorm<Eigen::Infinity>();
    EXPECT_EQ(r.message, "the KKT system of the free set is singular (A not positive definite on ker C)");
  }
}

TEST(DenseActiveSet, RefusesWhatItCannotSolve) {
  Problem p = random_problem(6, 1, 3, false);
  DenseActiveSet qp(p.A, p.C);
  std::vector<Bound> active;
  p.l(2) = 0.5;  // x = 0 infeasible
  const DenseQpResult r = qp.solve(p.b, p.l, p.u, active);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.message, "x = 0 is not within the bounds");
  p.l(2) = 0;
  Eigen::VectorXd short_b = p.b.head(5);
  EXPECT_EQ(qp.solve(short_b, p.l, p.u, active).message, "sizes do not match");
}

}  // namespace
}  // namespace dualcell::qp
