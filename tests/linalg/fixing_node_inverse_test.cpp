// Tests for src/linalg/fixing_node_inverse.{hpp,cpp}: K K⁺ K = K on a floating truss, what
// the fixing must satisfy, sizes, moves. Tolerances: see pinv_tolerance() below and the file
// comment of sparse_cholesky_test.cpp.
#include "linalg/fixing_node_inverse.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "linalg/linalg_test_util.hpp"

namespace dualcell::linalg {
namespace {

using namespace test_matrices;

// x = K⁺ f.
VectorXd apply(const FixingNodeInverse& p, const VectorXd& f) {
  VectorXd x(p.n()), scratch(p.scratch_size());
  p.apply(f, x, scratch);
  return x;
}

// 2D truss on an m x m jittered grid, each square split by one diagonal:
// every bar e between nodes i and j contributes k_e g_e g_e^T with
// g_e = (-d, d) on (u_i, v_i, u_j, v_j), d the unit bar direction.  Thus
// K = G^T diag(k) G with every row of G orthogonal to the rigid body modes
// R = [translation x, translation y, rotation (-y, x)], and a triangulated
// grid is rigid: ker K = range(R), exactly 3-dimensional.
struct Truss {
  SpMat K;                   // full symmetric storage, n = 2 m^2
  MatrixXd R;                // n x 3 kernel basis
  std::vector<Index> fixed;  // u, v of node (0,0) and v of node (m-1,0)
  std::vector<Eigen::Vector2d> xy;
};

Truss make_truss(int m, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.2, 0.2), stiff(0.5, 2.0);
  Truss t;
  const int nodes = m * m;
  auto id = [m](int i, int j) { return j * m + i; };  // i: x index, j: y index
  t.xy.resize(static_cast<std::size_t>(nodes));
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i)
      t.xy[static_cast<std::size_t>(id(i, j))] =
          Eigen::Vector2d(i + (j > 0 ? jitter(rng) : 0.0), j + (j > 0 ? jitter(rng) : 0.0));
  // Row j = 0 is kept straight (y = 0) so that node (m-1, 0) lies on the x
  // axis through node (0, 0): fixing its v removes the rotation.
  std::vector<Eigen::Triplet<double>> trip;
  auto bar = [&](int a, int b) {
    const Eigen::Vector2d d = (t.xy[static_cast<std::size_t>(b)] - t.xy[static_cast<std::size_t>(a)]).normalized();
    const double k = stiff(rng);
    const int dofs[4] = {2 * a, 2 * a + 1, 2 * b, 2 * b + 1};
    const double g[4] = {-d.x(), -d.y(), d.x(), d.y()};
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) trip.emplace_back(dofs[r], dofs[c], k * g[r] * g[c]);
  };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      if (i + 1 < m) bar(id(i, j), id(i + 1, j));
      if (j + 1 < m) bar(id(i, j), id(i, j + 1));
      if (i + 1 < m && j + 1 < m) bar(id(i, j), id(i + 1, j + 1));
    }
  const int n = 2 * nodes;
  t.K.resize(n, n);
  t.K.setFromTriplets(trip.begin(), trip.end());
  t.R.setZero(n, 3);
  for (int a = 0; a < nodes; ++a) {
    const auto& p = t.xy[static_cast<std::size_t>(a)];
    t.R(2 * a, 0) = 1.0;
    t.R(2 * a + 1, 1) = 1.0;
    t.R(2 * a, 2) = -p.y();
    t.R(2 * a + 1, 2) = p.x();
  }
  t.fixed = {0, 1, 2 * id(m - 1, 0) + 1};
  return t;
}

// Backward-error style bound for apply() (see the file comment): with
// K_rr x_r = f_r + delta, ||delta|| <= c_A u ||K_rr|| ||x_r||, the residual
// K x - f equals delta on the free rows and -R_f^{-T} R_r^T delta on the
// fixed rows (from K_rr R_r + K_rf R_f = 0).  Hence
//   ||K x - f|| <= (1 + ||R_f^{-T} R_r^T||_2) c_A u ||K|| ||x||.
// ||.||_2 of the 3 x n matrix is bounded by its Frobenius norm, ||K||_2 by
// ||K||_F.  The amplification is geometric (size of the rotation mode over
// sigma_min(R_f)), independent of kappa(K_rr) (~2.4e4 here, m = 20).
// Measured: 1e-17 against a bound of 3.5e-13 (||Kx - f|| / ||f|| ~ 4e-16).
double pinv_tolerance(const Truss& t) {
  MatrixXd Rf(3, 3);
  for (int r = 0; r < 3; ++r) Rf.row(r) = t.R.row(t.fixed[static_cast<std::size_t>(r)]);
  const MatrixXd amplification = Rf.transpose().fullPivLu().solve(t.R.transpose());
  return (1.0 + amplification.norm()) * kCA * kEps;
}

TEST(FixingNodeInverse, GeneralizedInverseOfTruss) {
  std::mt19937 rng(23);
  const Truss t = make_truss(20, rng);  // n = 800
  const Index n = t.K.rows();
  ASSERT_LE((t.K * t.R).norm(), 1e-12 * t.K.norm() * t.R.norm());  // construction check

  const FixingNodeInverse pinv(t.K, t.fixed);
  EXPECT_EQ(pinv.n(), n);
  const double tol = pinv_tolerance(t);
  const double normK = t.K.norm();

  VectorXd x;
  for (int k = 0; k < 10; ++k) {
    // K K^+ K v = K v: apply K^+ to f = K v in range(K).
    const VectorXd v = random_vector(n, rng);
    const VectorXd f = t.K * v;
    x = apply(pinv, f);
    for (Index i : t.fixed) EXPECT_EQ(x[i], 0.0);
    const VectorXd Kx = t.K * x;
    EXPECT_LE((Kx - f).norm() / (normK * x.norm()), tol) << "vector " << k;
  }

  // Aliasing f and x.
  const VectorXd f = t.K * random_vector(n, rng);
  VectorXd y = f, scratch(n - 3);
  pinv.apply(y, y, scratch);
  EXPECT_LE((t.K * y - f).norm() / (normK * y.norm()), tol);
  EXPECT_EQ((y - apply(pinv, f)).lpNorm<Eigen::Infinity>(), 0.0);

  // Lower-only storage of K gives the same operator.
  const FixingNodeInverse pinv_lower(lower_part(t.K), t.fixed);
  x = apply(pinv, f);
  EXPECT_LE((apply(pinv_lower, f) - x).norm(), 1e-12 * x.norm());
}

// The DOFs of a subdomain's boundary ordered last: K⁺(b, b) from the trailing block of the
// factor alone equals K⁺ applied to unit vectors on b, and the ordering leaves K⁺ itself as it
// was. The boundary here is the grid's outer ring, which holds one fixed DOF (zero row).
TEST(FixingNodeInverse, LastBlockInverseIsTheBoundaryBlockOfKPlus) {
  std::mt19937 rng(29);
  const int m = 12;
  const Truss t = make_truss(m, rng);
  std::vector<Index> ring;
  for (int a = 0; a < m * m; ++a) {
    const int i = a % m, j = a / m;
    if (i == 0 || j == 0 || i == m - 1 || j == m - 1) ring.insert(ring.end(), {2 * a + 1, 2 * a});  // any order
  }
  const FixingNodeInverse plain(t.K, t.fixed), ordered(t.K, t.fixed, {}, ring);
  const MatrixXd block = ordered.last_block_inverse();
  ASSERT_EQ(block.rows(), static_cast<Index>(ring.size()));
  MatrixXd expected(ring.size(), ring.size());
  for (std::size_t j = 0; j < ring.size(); ++j) {
    const VectorXd x = apply(plain, VectorXd::Unit(t.K.rows(), ring[j]));
    for (std::size_t i = 0; i < ring.size(); ++i) expected(i, j) = x(ring[i]);
  }
  // Two factorisations of one K_rr (κ ~ 1e4 for this grid) in two orders: they agree to
  // κ·ε, and the block is symmetric by construction (L⁻ᵀL⁻¹).
  EXPECT_LE((block - expected).norm(), 1e-10 * expected.norm());
  EXPECT_EQ((block - block.transpose()).norm(), 0.0);
  const auto fixed_in_ring = std::find(ring.begin(), ring.end(), t.fixed[2]) - ring.begin();
  EXPECT_EQ(block.row(fixed_in_ring).norm(), 0.0);
  const VectorXd f = t.K * random_vector(t.K.rows(), rng);
  EXPECT_LE((apply(ordered, f) - apply(plain, f)).norm(), 1e-10 * apply(plain, f).norm());
}

// apply() checks the sizes of f, x and scratch (FETI's threads pass their own scratch).
TEST(FixingNodeInverse, ApplyChecksItsSizes) {
  std::mt19937 rng(31);
  const Truss t = make_truss(8, rng);
  const Index n = t.K.rows();
  const FixingNodeInverse pinv(t.K, t.fixed);
  const VectorXd f = t.K * random_vector(n, rng);
  VectorXd x(n), scratch(n - static_cast<Index>(t.fixed.size()));
  VectorXd wrong_scratch(3), wrong_x(n + 1);
  EXPECT_EQ(expect_cholesky_error([&] { pinv.apply(f, x, wrong_scratch); }).status(), CholeskyStatus::invalid_input);
  EXPECT_EQ(expect_cholesky_error([&] { pinv.apply(f, wrong_x, scratch); }).status(), CholeskyStatus::invalid_input);
  const auto e = expect_cholesky_error([&] { pinv.apply(VectorXd(n - 1), x, scratch); });
  EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
  EXPECT_EQ(e.phase(), CholeskyPhase::solve);
}

TEST(FixingNodeInverse, WhatTheFixingMustDo) {
  std::mt19937 rng(31);
  const Truss t = make_truss(10, rng);
  const Index n = t.K.rows();

  // Exactly dim ker K fixed DOFs: with a fourth, K_rr is regular but K K⁺ K != K (why
  // FetiSetup fixes exactly three DOFs per subdomain).
  std::vector<Index> four = t.fixed;
  four.push_back(n - 1);
  {
    const FixingNodeInverse p(t.K, four);
    const VectorXd f = t.K * random_vector(n, rng);
    EXPECT_GT((t.K * apply(p, f) - f).norm() / f.norm(), 1e-6);  // not a generalised inverse
  }

  // DOF list errors.
  for (const std::vector<Index>& bad :
       {std::vector<Index>{0, 1, n}, std::vector<Index>{0, 1, 1}, std::vector<Index>{-1}}) {
    const auto e = expect_cholesky_error([&] { FixingNodeInverse p(t.K, bad); });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::setup);
  }
}

TEST(FixingNodeInverse, RegularMatrixAndMoves) {
  // No fixed DOFs on an SPD matrix: K^+ = K^{-1}.
  std::mt19937 rng(37);
  const auto [A, kappa] = make_laplacian(12, 1.0, rng);
  FixingNodeInverse inv(A, std::vector<Index>{});
  const VectorXd b = random_vector(A.rows(), rng);
  EXPECT_LE(rel_residual(A, apply(inv, b), b), kCA * kEps * kappa);

  FixingNodeInverse moved(std::move(inv));
  EXPECT_LE(rel_residual(A, apply(moved, b), b), kCA * kEps * kappa);
  EXPECT_THROW(apply(inv, b), CholeskyError);  // NOLINT(bugprone-use-after-move)

  // All DOFs fixed: K^+ = 0.
  std::vector<Index> all(static_cast<std::size_t>(A.rows()));
  for (Index i = 0; i < A.rows(); ++i) all[static_cast<std::size_t>(i)] = i;
  const FixingNodeInverse zero(A, all);
  EXPECT_EQ(apply(zero, b).norm(), 0.0);
}

}  // namespace
}  // namespace dualcell::linalg
