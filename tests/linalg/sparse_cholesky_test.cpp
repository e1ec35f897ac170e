// Tests for src/linalg/sparse_cholesky.{hpp,cpp}.
//
// Tolerances.  u = DBL_EPSILON = 2.2e-16.
//  * Solves.  Cholesky is backward stable: the computed x solves
//    (A + dA) x = b with ||dA||_2 <= c_A u ||A||_2 (Higham, "Accuracy and
//    Stability of Numerical Algorithms", 2nd ed., Thm 10.4 / 10.5).  Hence
//      eta = ||A x - b|| / (||A|| ||x|| + ||b||) <= c_A u     (backward error)
//      ||A x - b|| / ||b||                      <= c_A u kappa(A)  (residual)
//      ||x - x_exact|| / ||x_exact||            <~ c_A u kappa(A)  (forward)
//    and two independently computed solutions differ by at most twice the
//    forward bound.  The worst-case c_A of the theorem grows with the length
//    of the inner products (the longest row of L, a few hundred entries
//    here), but that is attained only by adversarial rounding; random
//    rounding grows like its square root.  We use c_A = 50 together with a
//    rigorous upper bound for kappa(A) (Weyl, below).  Measured (m = 50):
//    eta ~ 1 u, residual / (u kappa) ~ 2e-3, i.e. the relative residual is
//    itself at rounding level (~5e-16) -- ample margin, but a wrong solve
//    (wrong permutation, stale factor, wrong column) fails by many orders.
//  * Test matrices: A = T + D, T the 5-point Dirichlet Laplacian on an m x m
//    grid, D >= 0 a random diagonal with entries in [0, s].  The eigenvalues
//    of T are 4 - 2cos(i pi/(m+1)) - 2cos(j pi/(m+1)) in
//    [4 - 4cos(pi/(m+1)), 8), so by Weyl
//      kappa(A) <= (8 + s) / (4 - 4cos(pi/(m+1))).
//    (m = 50, s = 1: kappa <= 1.19e3.)  ||A||_2 <= ||A||_inf (symmetric).
#include "linalg/sparse_cholesky.hpp"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#if __has_include(<cholmod.h>)
#include <cholmod.h>
#else
#include <suitesparse/cholmod.h>
#endif

#include "linalg/linalg_test_util.hpp"

namespace dualcell::linalg {
namespace {

using namespace test_matrices;

// Counts CHOLMOD's allocations (SuiteSparse 5.x routes every CHOLMOD
// allocation through SuiteSparse_config.{malloc,calloc,realloc}_func).
struct AllocCounter {
  static inline int count = 0;
  static void* m(std::size_t s) {
    ++count;
    return saved.malloc_func(s);
  }
  static void* c(std::size_t n, std::size_t s) {
    ++count;
    return saved.calloc_func(n, s);
  }
  static void* r(void* p, std::size_t s) {
    ++count;
    return saved.realloc_func(p, s);
  }
  static inline SuiteSparse_config_struct saved{};

  AllocCounter() {
    saved = SuiteSparse_config;
    count = 0;
    SuiteSparse_config.malloc_func = &m;
    SuiteSparse_config.calloc_func = &c;
    SuiteSparse_config.realloc_func = &r;
  }
  ~AllocCounter() {
    SuiteSparse_config.malloc_func = saved.malloc_func;
    SuiteSparse_config.calloc_func = saved.calloc_func;
    SuiteSparse_config.realloc_func = saved.realloc_func;
  }
  AllocCounter(const AllocCounter&) = delete;
  AllocCounter& operator=(const AllocCounter&) = delete;
};

// ------------------------------------------------------- status mapping

TEST(CholeskyStatusTest, EveryCholmodCodeIsMappedExplicitly) {
  EXPECT_EQ(status_from_cholmod(CHOLMOD_OK), CholeskyStatus::ok);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_NOT_POSDEF), CholeskyStatus::not_positive_definite);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_DSMALL), CholeskyStatus::numerical_warning);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_NOT_INSTALLED), CholeskyStatus::invalid_input);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_OUT_OF_MEMORY), CholeskyStatus::out_of_memory);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_TOO_LARGE), CholeskyStatus::too_large);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_INVALID), CholeskyStatus::invalid_input);
  EXPECT_EQ(status_from_cholmod(CHOLMOD_GPU_PROBLEM), CholeskyStatus::internal_error);
  EXPECT_EQ(status_from_cholmod(42), CholeskyStatus::numerical_warning);  // unknown warning
  EXPECT_EQ(status_from_cholmod(-42), CholeskyStatus::internal_error);    // unknown failure
}

TEST(CholeskyStatusTest, ToStringIsDistinctAndNonEmpty) {
  const CholeskyStatus all[] = {CholeskyStatus::ok,
                                CholeskyStatus::not_positive_definite,
                                CholeskyStatus::out_of_memory,
                                CholeskyStatus::too_large,
                                CholeskyStatus::invalid_input,
                                CholeskyStatus::numerical_warning,
                                CholeskyStatus::internal_error};
  std::vector<std::string> names;
  for (auto s : all) names.emplace_back(to_string(s));
  for (const auto& s : names) EXPECT_FALSE(s.empty());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::unique(names.begin(), names.end()), names.end());
  EXPECT_EQ(to_string(CholeskyStatus::not_positive_definite), "not_positive_definite");
  EXPECT_EQ(to_string(CholeskyPhase::factorize), "factorize");
}

// ------------------------------------------------ SPD solves, per config

struct Config {
  FactorKind kind;
  Ordering ordering;
  const char* name;
};

class SparseCholeskySpd : public ::testing::TestWithParam<Config> {
 protected:
  CholmodOptions options() const {
    CholmodOptions o;
    o.factor_kind = GetParam().kind;
    o.ordering = GetParam().ordering;
    return o;
  }
};

TEST_P(SparseCholeskySpd, FactorOnceSolveManyMatchesFreshAndReference) {
  std::mt19937 rng(20240601);
  const auto [A, kappa] = make_laplacian(50, 1.0, rng);  // n = 2500
  const Index n = A.rows();
  const double res_tol = kCA * kEps * kappa;         // residual bound
  const double diff_tol = 2.0 * kCA * kEps * kappa;  // two forward errors

  SparseCholesky chol(options());
  EXPECT_EQ(chol.compute(A), CholeskyStatus::ok);
  EXPECT_EQ(chol.n(), n);
  EXPECT_TRUE(chol.is_factorized());

  const VectorXd b0 = random_vector(n, rng);
  VectorXd x0;
  chol.solve(b0, x0);
  EXPECT_LE(rel_residual(A, x0, b0), res_tol);
  EXPECT_LE(backward_error(A, x0, b0), kCA * kEps);

  // Many solves with the same factor.
  VectorXd x;
  for (int k = 0; k < 50; ++k) {
    const VectorXd b = random_vector(n, rng);
    chol.solve(b, x);
    ASSERT_LE(rel_residual(A, x, b), res_tol) << "rhs " << k;
    ASSERT_LE(backward_error(A, x, b), kCA * kEps) << "rhs " << k;
  }
  // The factor is unchanged by solves: b0 again gives the same x0.
  chol.solve(b0, x);
  EXPECT_LE((x - x0).norm() / x0.norm(), diff_tol);

  // A fresh factorization (same wrapper) and an independent one (Eigen).
  SparseCholesky fresh(options());
  fresh.compute(A);
  VectorXd xf;
  fresh.solve(b0, xf);
  EXPECT_LE((xf - x0).norm() / x0.norm(), diff_tol);

  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ref(A);
  ASSERT_EQ(ref.info(), Eigen::Success);
  const VectorXd xr = ref.solve(b0);
  EXPECT_LE((xr - x0).norm() / x0.norm(), diff_tol);
}

// The exported factor: L Lᵀ = A(perm, perm) with L lower triangular, whatever CHOLMOD kept
// (supernodal or simplicial, any ordering); the kept factor still solves afterwards.
// Tolerance: a backward-stable Cholesky gives ‖LLᵀ − PAPᵀ‖ ≤ c·n_row·eps·‖A‖, n_row ≤ 5 here.
TEST_P(SparseCholeskySpd, TriangularFactorReproducesThePermutedMatrix) {
  std::mt19937 rng(20241122);
  const auto [A, kappa] = make_laplacian(12, 1.0, rng);  // n = 144
  const Index n = A.rows();
  SparseCholesky chol(options());
  chol.compute(A);
  const SparseCholesky::TriangularFactor factor = chol.triangular_factor();
  ASSERT_EQ(factor.L.rows(), n);
  ASSERT_EQ(factor.perm.size(), static_cast<std::size_t>(n));
  const MatrixXd L = MatrixXd(factor.L);
  EXPECT_EQ(MatrixXd(L.triangularView<Eigen::StrictlyUpper>()).norm(), 0.0);
  const MatrixXd Ad = MatrixXd(A);
  MatrixXd PAPt(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) PAPt(i, j) = Ad(factor.perm[i], factor.perm[j]);
  EXPECT_LE((L * L.transpose() - PAPt).norm(), 64 * kEps * Ad.norm());
  const VectorXd b = random_vector(n, rng);
  VectorXd x;
  chol.solve(b, x);
  EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
}

TEST_P(SparseCholeskySpd, RefactorizeSamePattern) {
  std::mt19937 rng(11);
  const auto [A1, kappa1] = make_laplacian(40, 1.0, rng);
  const auto [A2, kappa2] = make_laplacian(40, 3.0, rng, 0.7);  // same pattern
  const Index n = A1.rows();
  SparseCholesky chol(options());
  chol.analyze(A1);
  EXPECT_TRUE(chol.is_analyzed());
  EXPECT_FALSE(chol.is_factorized());
  chol.factorize(A1);

  const VectorXd b = random_vector(n, rng);
  VectorXd x1, x2;
  chol.solve(b, x1);
  EXPECT_LE(rel_residual(A1, x1, b), kCA * kEps * kappa1);

  EXPECT_EQ(chol.factorize(A2), CholeskyStatus::ok);
  chol.solve(b, x2);
  EXPECT_LE(rel_residual(A2, x2, b), kCA * kEps * kappa2);

  SparseCholesky fresh(options());
  fresh.compute(A2);
  VectorXd xf;
  fresh.solve(b, xf);
  EXPECT_LE((xf - x2).norm() / xf.norm(), 2.0 * kCA * kEps * kappa2);

  // Lower-only storage of the same matrix is accepted and equivalent.
  EXPECT_EQ(chol.factorize(lower_part(A2)), CholeskyStatus::ok);
  VectorXd x3;
  chol.solve(b, x3);
  EXPECT_LE((x3 - x2).norm() / x2.norm(), 2.0 * kCA * kEps * kappa2);
}

INSTANTIATE_TEST_SUITE_P(Configs, SparseCholeskySpd,
                         ::testing::Values(Config{FactorKind::supernodal, Ordering::automatic, "SupernodalAuto"},
                                           Config{FactorKind::simplicial, Ordering::amd, "SimplicialAmd"},
                                           Config{FactorKind::supernodal, Ordering::metis, "SupernodalMetis"},
                                           Config{FactorKind::automatic, Ordering::natural, "AutoNatural"}),
                         [](const ::testing::TestParamInfo<Config>& i) { return std::string(i.param.name); });

// ------------------------------------------------------------ specifics

TEST(SparseCholesky, SolveAllocatesNothingInCholmodAfterWarmUp) {
  for (auto kind : {FactorKind::supernodal, FactorKind::simplicial}) {
    SCOPED_TRACE(kind == FactorKind::supernodal ? "supernodal" : "simplicial");
    std::mt19937 rng(3);
    const auto [A, kappa] = make_laplacian(40, 1.0, rng);
    const Index n = A.rows();
    CholmodOptions o;
    o.factor_kind = kind;
    SparseCholesky chol(o);
    chol.compute(A);
    const VectorXd b = random_vector(n, rng);
    VectorXd x;
    chol.solve(b, x);  // warm-up: allocates X/Y/E (one column: not a multiple of
                       // CHOLMOD's simplicial chunk width 4, the case of the
                       // workspace-shape workaround in solve_impl())
    const double* xdata = x.data();
    {
      AllocCounter counter;
      for (int k = 0; k < 20; ++k) chol.solve(b, x);
      EXPECT_EQ(AllocCounter::count, 0);
    }
    EXPECT_EQ(x.data(), xdata);  // output storage reused, not reallocated
    EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
  }
}

TEST(SparseCholesky, AliasedRhsAndSolution) {
  std::mt19937 rng(5);
  const auto [A, kappa] = make_laplacian(20, 1.0, rng);
  SparseCholesky chol;
  chol.compute(A);
  const VectorXd b = random_vector(A.rows(), rng);
  VectorXd x = b;
  chol.solve(x, x);
  EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
}

TEST(SparseCholesky, SubsetPatternAcceptedSupersetRejected) {
  std::mt19937 rng(9);
  const auto [A, kappa] = make_laplacian(20, 1.0, rng);
  SparseCholesky chol;
  chol.analyze(A);

  // Remove the coupling (1,0)/(0,1): still SPD (strictly diagonally
  // dominant rows 0 and 1, irreducible otherwise), pattern is a subset.
  SpMat S = A;
  S.coeffRef(1, 0) = 0.0;
  S.coeffRef(0, 1) = 0.0;
  S.prune(0.0);
  EXPECT_EQ(chol.factorize(S), CholeskyStatus::ok);
  const VectorXd b = random_vector(A.rows(), rng);
  VectorXd x;
  chol.solve(b, x);
  EXPECT_LE(rel_residual(S, x, b), kCA * kEps * kappa);

  // Add an entry far outside the analyzed pattern.
  SpMat T = A;
  T.coeffRef(A.rows() - 1, 0) = 1e-3;
  T.coeffRef(0, A.rows() - 1) = 1e-3;
  const auto e = expect_cholesky_error([&] { chol.factorize(T); });
  EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
  EXPECT_EQ(e.phase(), CholeskyPhase::factorize);
  EXPECT_NE(std::string(e.what()).find("not in the lower pattern"), std::string::npos) << e.what();
  EXPECT_EQ(chol.last_status(), CholeskyStatus::invalid_input);
  EXPECT_TRUE(chol.is_factorized());  // the factor of S is kept
  chol.solve(b, x);
  EXPECT_LE(rel_residual(S, x, b), kCA * kEps * kappa);
}

TEST(SparseCholesky, IllConditionedGivesWarningNotThrow) {
  // diag(1, 1e-20): SPD, so CHOLMOD succeeds, but rcond = 1e-20 < 1e-14.
  SpMat A(2, 2);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = 1e-20;
  SparseCholesky chol;
  EXPECT_EQ(chol.compute(A), CholeskyStatus::numerical_warning);
  EXPECT_EQ(chol.last_status(), CholeskyStatus::numerical_warning);
  EXPECT_NE(chol.last_message().find("rcond"), std::string::npos) << chol.last_message();
  VectorXd x;
  chol.solve(VectorXd::Ones(2), x);
  EXPECT_DOUBLE_EQ(x[0], 1.0);
  EXPECT_DOUBLE_EQ(x[1], 1e20);

  // Threshold disabled: ok.
  CholmodOptions o;
  o.rcond_warning_threshold = 0.0;
  SparseCholesky quiet(o);
  EXPECT_EQ(quiet.compute(A), CholeskyStatus::ok);
}

TEST(SparseCholesky, EmptyMatrix) {
  SparseCholesky chol;
  EXPECT_EQ(chol.compute(SpMat(0, 0)), CholeskyStatus::ok);
  VectorXd x(3);
  chol.solve(VectorXd(0), x);
  EXPECT_EQ(x.size(), 0);
}

// ----------------------------------------------- not positive definite

class NotPositiveDefinite : public ::testing::TestWithParam<Config> {};

TEST_P(NotPositiveDefinite, ReportsFailingColumn) {
  std::mt19937 rng(13);
  auto [A, kappa] = make_laplacian(30, 1.0, rng);
  (void)kappa;
  // Make diagonal entry c negative.  Every leading principal submatrix of
  // P A P^T that does not contain c is a principal submatrix of the SPD
  // Laplacian, and the Schur complement pivot of c is <= A(c,c) < 0, so the
  // factorization fails exactly at the pivot of column c: the reported
  // original column must be c.
  const Index c = 417;
  SpMat bad = A;
  bad.coeffRef(c, c) = -1.0;

  CholmodOptions o;
  o.factor_kind = GetParam().kind;
  o.ordering = GetParam().ordering;
  SparseCholesky chol(o);
  chol.analyze(bad);
  const auto e = expect_cholesky_error([&] { chol.factorize(bad); });
  EXPECT_EQ(e.status(), CholeskyStatus::not_positive_definite);
  EXPECT_EQ(e.phase(), CholeskyPhase::factorize);
  EXPECT_EQ(e.matrix_size(), A.rows());
  EXPECT_EQ(e.original_column(), c);
  ASSERT_GE(e.column(), 0);
  EXPECT_LT(e.column(), A.rows());
  if (GetParam().ordering == Ordering::natural) {
    EXPECT_EQ(e.column(), c);
  }
  const std::string what = e.what();
  EXPECT_NE(what.find("factorize"), std::string::npos) << what;
  EXPECT_NE(what.find("n=900"), std::string::npos) << what;
  EXPECT_NE(what.find("failing column " + std::to_string(e.column())), std::string::npos) << what;
  EXPECT_NE(what.find("column " + std::to_string(c) + " of the input"), std::string::npos) << what;
  EXPECT_EQ(chol.last_status(), CholeskyStatus::not_positive_definite);
  EXPECT_FALSE(chol.is_factorized());
  EXPECT_THROW(
      {
        VectorXd x;
        chol.solve(VectorXd::Ones(A.rows()), x);
      },
      CholeskyError);

  // Recovery: the symbolic analysis survives, a good matrix with the same
  // pattern factorizes.
  EXPECT_EQ(chol.factorize(A), CholeskyStatus::ok);
  const VectorXd b = random_vector(A.rows(), rng);
  VectorXd x;
  chol.solve(b, x);
  EXPECT_LE(rel_residual(A, x, b), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Configs, NotPositiveDefinite,
                         ::testing::Values(Config{FactorKind::supernodal, Ordering::automatic, "SupernodalAuto"},
                                           Config{FactorKind::simplicial, Ordering::amd, "SimplicialAmd"},
                                           Config{FactorKind::supernodal, Ordering::natural, "SupernodalNatural"},
                                           Config{FactorKind::simplicial, Ordering::natural, "SimplicialNatural"}),
                         [](const ::testing::TestParamInfo<Config>& i) { return std::string(i.param.name); });

TEST(SparseCholesky, IndefiniteWithPositiveDiagonalIsRejected) {
  // [[1, 2], [2, 1]]: positive diagonal, eigenvalues 3 and -1.  A simplicial
  // LDL^T without pivoting would "succeed" (D = diag(1, -3)); we use LL^T.
  SpMat A(2, 2);
  A.insert(0, 0) = 1.0;
  A.insert(1, 0) = 2.0;
  A.insert(0, 1) = 2.0;
  A.insert(1, 1) = 1.0;
  for (auto kind : {FactorKind::supernodal, FactorKind::simplicial}) {
    CholmodOptions o;
    o.factor_kind = kind;
    o.ordering = Ordering::natural;
    SparseCholesky chol(o);
    const auto e = expect_cholesky_error([&] { chol.compute(A); });
    EXPECT_EQ(e.status(), CholeskyStatus::not_positive_definite);
    EXPECT_EQ(e.column(), 1);
  }
}

// ---------------------------------------------------------- invalid input

TEST(SparseCholesky, InvalidInputIsCheckedBeforeCholmod) {
  SparseCholesky chol;
  {
    SpMat R(3, 4);
    R.insert(0, 0) = 1.0;
    const auto e = expect_cholesky_error([&] { chol.analyze(R); });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::analyze);
    EXPECT_NE(std::string(e.what()).find("3x4"), std::string::npos) << e.what();
  }
  {
    const auto e = expect_cholesky_error([&] {
      VectorXd x;
      chol.solve(VectorXd::Ones(3), x);
    });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::solve);
  }
  {
    SpMat A(3, 3);
    A.insert(0, 0) = 1.0;
    const auto e = expect_cholesky_error([&] { chol.factorize(A); });  // no analyze
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
  }

  std::mt19937 rng(17);
  const auto [A, kappa] = make_laplacian(10, 1.0, rng);  // n = 100
  (void)kappa;
  chol.compute(A);
  {
    const auto e = expect_cholesky_error([&] {
      VectorXd x;
      chol.solve(VectorXd::Ones(99), x);
    });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::solve);
    EXPECT_EQ(e.matrix_size(), 100);
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
  }
  {
    const auto [A2, k2] = make_laplacian(11, 1.0, rng);
    (void)k2;
    const auto e = expect_cholesky_error([&] { chol.factorize(A2); });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::factorize);
  }
  // Rejected arguments leave the existing factor usable.
  EXPECT_TRUE(chol.is_factorized());
  {
    VectorXd x;
    const VectorXd b = VectorXd::Ones(100);
    chol.solve(b, x);
    EXPECT_LE(rel_residual(A, x, b), 1e-12);
  }
  {
    SpMat U = SpMat(A.triangularView<Eigen::Upper>());
    SparseCholesky other;
    const auto e = expect_cholesky_error([&] { other.compute(U); });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_NE(std::string(e.what()).find("upper"), std::string::npos) << e.what();
  }
}

// ----------------------------------------------------------------- moves

TEST(SparseCholesky, MovesLeaveSafeMovedFromObjects) {
  std::mt19937 rng(19);
  const auto [A, kappa] = make_laplacian(15, 1.0, rng);
  const VectorXd b = random_vector(A.rows(), rng);

  {
    CholmodCommon c1;
    ASSERT_TRUE(c1.valid());
    cholmod_common* raw = c1.get();
    CholmodCommon c2(std::move(c1));
    EXPECT_FALSE(c1.valid());  // NOLINT(bugprone-use-after-move): documented state
    EXPECT_EQ(c1.get(), nullptr);
    EXPECT_EQ(c2.get(), raw);  // address stable across moves
    CholmodCommon c3;
    c3 = std::move(c2);
    EXPECT_EQ(c3.get(), raw);
  }  // all three destroyed: moved-from ones do nothing

  SparseCholesky a;
  a.compute(A);
  SparseCholesky b2(std::move(a));
  VectorXd x;
  b2.solve(b, x);
  EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
  // Moved-from: no factor, every operation throws invalid_input.
  EXPECT_FALSE(a.is_analyzed());  // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(a.n(), 0);
  const auto e = expect_cholesky_error([&] { a.solve(b, x); });
  EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
  EXPECT_THROW(a.analyze(A), CholeskyError);

  // Move-assign onto a factorized object frees its old factor (ASan/LSan).
  SparseCholesky c;
  c.compute(A);
  c = std::move(b2);
  c.solve(b, x);
  EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
  // Assigning a live object into a moved-from one revives it.
  a = std::move(c);
  a.solve(b, x);
  EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
}

}  // namespace
}  // namespace dualcell::linalg
