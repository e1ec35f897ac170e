// The face solve (qp/face.hpp) on seeded problems with a known solution, in the FETI form
// A = PFP with Q = ĜᵀĜ: from a point on the solution's face it finds the solution and its
// multiplier; from a wrong face it moves to the right one or hands x and m back untouched; and
// SMALBE with it reaches the same solutions as without.
#include "qp/face.hpp"

#include <gtest/gtest.h>

#include "qp/smalbe.hpp"
#include "qp_test_utils.hpp"

namespace dualcell::qp {
namespace {

using testing::BoundKind;
using testing::DenseQp;

// The coarse algebra of a dense Ĝ: S⁺ of S = Ĝ_F Ĝ_Fᵀ by its eigenvalues, those below 1e-12 of the
// largest counted as zero (a row with no free entry, or rows the face cannot tell apart).
class DenseFaceProjector final : public FaceProjector {
 public:
  explicit DenseFaceProjector(const Eigen::MatrixXd& G) : G_(G) {}
  bool set_face(const Eigen::VectorXd& free) override {
    ++faces;
    G_F_ = G_ * free.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G_F_ * G_F_.transpose());
    const Eigen::VectorXd d = eig.eigenvalues();
    const double cut = 1e-12 * std::max(d.maxCoeff(), 1e-300);
    Eigen::VectorXd d_plus = Eigen::VectorXd::Zero(d.size());
    for (Eigen::Index i = 0; i < d.size(); ++i)
      if (d(i) > cut) d_plus(i) = 1 / d(i);
    S_plus_ = eig.eigenvectors() * d_plus.asDiagonal() * eig.eigenvectors().transpose();
    return true;
  }
  void solve_coarse(const Eigen::VectorXd& w, Eigen::VectorXd& c) override { c = S_plus_ * (G_ * w); }
  void apply_Gt(const Eigen::VectorXd& c, Eigen::VectorXd& v) override { v = G_.transpose() * c; }
  int faces = 0;

 private:
  Eigen::MatrixXd G_, G_F_, S_plus_;
};

struct Problem {
  DenseQp qp;
  Eigen::MatrixXd G, Q;
  Eigen::VectorXd m_star;  // Ĝᵀν: SMALBE's multiplier at the solution
};

// F with spectrum [0.1, 1], Ĝ with orthonormal rows, A = PFP; the solution x* with its active set
// and its multiplier from testing::make_known_solution_problem.
Problem make_problem(std::mt19937& rng, int n, int n_rows, BoundKind kind) {
  Problem p;
  const Eigen::MatrixXd F = testing::matrix_with_spectrum(rng, testing::spectrum(rng, n, 0.1, 1.0));
  p.G = testing::random_orthonormal_rows(rng, n_rows, n);
  p.Q = p.G.transpose() * p.G;
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n) - p.Q;
  p.qp = testing::make_known_solution_problem(rng, P * F * P, p.G, kind);
  p.m_star = p.G.transpose() * p.qp.nu;
  return p;
}

// One face solve of p from x (tolerance 1e-12·‖b‖, at most max_steps CG steps).
FaceResult face_solve(const Problem& p, Eigen::VectorXd& x, Eigen::VectorXd& m, Eigen::VectorXd& g, long max_steps) {
  DenseFaceProjector projector(p.G);
  FaceOptions opts;
  opts.tolerance = 1e-12 * p.qp.b.norm();
  opts.max_steps = max_steps;
  FaceWorkspace work;
  return solve_on_face(testing::dense_operator(p.qp.A), p.qp.b, p.qp.l, p.qp.u, projector, opts, x, m, g, work);
}

constexpr BoundKind all_kinds[] = {BoundKind::lower, BoundKind::upper, BoundKind::box, BoundKind::mixed};

// From x* moved along the face (free components shifted, staying inside the box, Ĝ x ≠ 0): one
// face, converged to x* within what its tolerance allows. The face has dim F − rank Ĝ_F ≤ n
// directions, so CG ends within n steps (plus round-off: 2n).
TEST(FaceSolve, FromTheSolutionsFaceItFindsTheSolutionAndItsMultiplier) {
  std::mt19937 rng(7301);
  std::uniform_real_distribution<double> shift(-0.05, 0.05);
  int converged = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 6 + trial % 20;
    const Problem p = make_problem(rng, n, 1 + trial % 3, all_kinds[trial % 4]);
    const DenseQp& qp = p.qp;
    Eigen::VectorXd x = qp.x_star;
    for (int i = 0; i < n; ++i)
      if (qp.l(i) < x(i) && x(i) < qp.u(i))
        x(i) = std::clamp(x(i) + shift(rng), 0.5 * (x(i) + qp.l(i)), 0.5 * (x(i) + qp.u(i)));
    Eigen::VectorXd m = Eigen::VectorXd::Zero(n), g;
    const FaceResult r = face_solve(p, x, m, g, 1000);
    ASSERT_EQ(r.outcome, FaceOutcome::converged);
    ++converged;
    EXPECT_EQ(r.rounds, 1);
    EXPECT_LE(r.counters.face_steps, 2 * n);
    // A = PFP ≥ 0.1 on ker Ĝ: ‖x − x*‖ ≤ ‖r‖/0.1 with ‖r‖ ≤ tolerance; 1e-9 leaves round-off room.
    EXPECT_LE((x - qp.x_star).norm(), 1e-9 * (1 + qp.x_star.norm()));
    EXPECT_LE((p.G * x).norm(), 1e-12 * (1 + x.norm()));
    EXPECT_TRUE(testing::is_feasible(x, qp.l, qp.u));
    // g is the fresh Lagrangian gradient, and m the multiplier of Ĝ x = 0 in Im Q.
    EXPECT_LE((g - (qp.A * x - qp.b + m)).norm(), 1e-12 * (1 + qp.b.norm()));
    EXPECT_LE(testing::reference_projected_gradient(x, g, qp.l, qp.u), 1e-11 * (1 + qp.b.norm()));
    EXPECT_LE((p.Q * m - m).norm(), 1e-12 * (1 + m.norm()));
  }
  EXPECT_EQ(converged, 40);
}

// From x* with a component that is on its bound at x* moved off it (a wrong face), the face solve
// either moves to the solution's face (then x = x*) or, unsettled, returns x and m bit for bit
// as they came.
TEST(FaceSolve, FromAWrongFaceItFindsTheRightOneOrLeavesEverythingAsItWas) {
  std::mt19937 rng(7302);
  int moved = 0, restored = 0;
  for (int trial = 0; trial < 60; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 8 + trial % 16;
    const Problem p = make_problem(rng, n, 1 + trial % 3, all_kinds[trial % 4]);
    const DenseQp& qp = p.qp;
    Eigen::VectorXd x = qp.x_star;
    int released = 0;
    for (int i = 0; i < n && released < 2; ++i) {
      if (x(i) == qp.l(i) && qp.u(i) > x(i) + 0.1) {
        x(i) += 0.1;
        ++released;
      } else if (x(i) == qp.u(i) && qp.l(i) < x(i) - 0.1) {
        x(i) -= 0.1;
        ++released;
      }
    }
    if (released == 0) continue;
    const Eigen::VectorXd x_in = x;
    const Eigen::VectorXd m_in = Eigen::VectorXd::Constant(n, 0.25).eval();
    Eigen::VectorXd m = p.Q * m_in, g;
    const Eigen::VectorXd m_before = m;
    const FaceResult r = face_solve(p, x, m, g, 1000);
    ASSERT_NE(r.outcome, FaceOutcome::refused);
    if (r.outcome == FaceOutcome::converged) {
      ++moved;
      EXPECT_GE(r.rounds, 2);  // the released components had to go back to their bounds
      EXPECT_LE((x - qp.x_star).norm(), 1e-9 * (1 + qp.x_star.norm()));
      EXPECT_LE((m - p.m_star).norm(), 1e-8 * (1 + p.m_star.norm()));
    } else {
      ++restored;
      EXPECT_EQ(x, x_in);
      EXPECT_EQ(m, m_before);
    }
  }
  // Measured: every wrong face here is mended (leaving components go back to their bounds).
  EXPECT_GT(moved, 0);
  EXPECT_GE(moved, 4 * restored);
}

// No budget: nothing can settle, and x and m come back as they were.
TEST(FaceSolve, WithoutABudgetXAndMComeBackUnchanged) {
  std::mt19937 rng(7303);
  const Problem p = make_problem(rng, 12, 2, BoundKind::box);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(12).cwiseMax(p.qp.l).cwiseMin(p.qp.u);
  const Eigen::VectorXd x_in = x;
  Eigen::VectorXd m = Eigen::VectorXd::Zero(12), g;
  const FaceResult r = face_solve(p, x, m, g, 0);
  EXPECT_EQ(r.outcome, FaceOutcome::unsettled);
  EXPECT_EQ(r.counters.face_steps, 0);
  EXPECT_EQ(x, x_in);
  EXPECT_EQ(m, Eigen::VectorXd::Zero(12));
}

// SMALBE with the face solve reaches the known solutions at the same tolerance as without, and
// the face solve runs in some of them.
TEST(FaceSolve, SmalbeWithFacesReachesTheSameSolutions) {
  std::mt19937 rng(7304);
  long with_a_face = 0;
  for (int trial = 0; trial < 48; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 8 + trial % 24;
    const Problem p = make_problem(rng, n, 1 + trial % 3, all_kinds[trial % 4]);
    const DenseQp& qp = p.qp;
    SmalbeOptions opts;
    opts.relative_tolerance = 1e-10;
    opts.equality_tolerance = 1e-10;
    opts.projected_operator = true;
    DenseFaceProjector projector(p.G);
    opts.face_projector = &projector;
    Eigen::VectorXd x, m;
    const Result r = smalbe(testing::dense_operator(qp.A), testing::dense_operator(p.Q), qp.b, qp.l, qp.u, x, m, opts);
    ASSERT_EQ(r.status, Status::converged) << r.message;
    with_a_face += r.counters.face_solves > 0 && projector.faces > 0;
    const Eigen::VectorXd g = qp.A * x - qp.b + m;
    EXPECT_LE(testing::reference_projected_gradient(x, g, qp.l, qp.u), 1e-10 * qp.b.norm() + 1e-13);
    EXPECT_LE((p.G * x).norm(), 1e-10 * qp.b.norm() + 1e-13);
    // ‖x − x*‖ from gP and Qx through λ_min = 0.1 of F on ker Ĝ, with room for the multiplier term.
    EXPECT_LE((x - qp.x_star).norm(), 1e-7 * (1 + qp.x_star.norm()));
  }
  EXPECT_GT(with_a_face, 0);
}

}  // namespace
}  // namespace dualcell::qp
