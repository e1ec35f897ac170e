// Tests for src/linalg/cholmod.{hpp,cpp}.
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
#include "linalg/cholmod.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#if __has_include(<cholmod.h>)
#include <cholmod.h>
#else
#include <suitesparse/cholmod.h>
#endif

namespace dualcell::linalg {
namespace {

using SpMat = SparseCholesky::SparseMatrix;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kCA = 50.0;  // backward-error constant, see file comment

// ---------------------------------------------------------------- helpers

struct Laplacian {
    SpMat A;           // full symmetric storage
    double kappa_max;  // rigorous upper bound of the 2-norm condition number
};

// A = T + D on an m x m grid; diag shift D uniform in [0, shift_max];
// off-diagonal entries scaled by offdiag (|offdiag| <= 1 keeps the bound).
Laplacian make_laplacian(int m, double shift_max, std::mt19937& rng, double offdiag = 1.0) {
    std::uniform_real_distribution<double> shift(0.0, shift_max);
    const int n = m * m;
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<std::size_t>(5 * n));
    auto id = [m](int i, int j) { return i * m + j; };
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            const int k = id(i, j);
            t.emplace_back(k, k, 4.0 + shift(rng));
            if (i > 0) t.emplace_back(k, id(i - 1, j), -offdiag);
            if (i + 1 < m) t.emplace_back(k, id(i + 1, j), -offdiag);
            if (j > 0) t.emplace_back(k, id(i, j - 1), -offdiag);
            if (j + 1 < m) t.emplace_back(k, id(i, j + 1), -offdiag);
        }
    SpMat A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    const double pi = std::acos(-1.0);
    // With off-diagonals scaled by |o| <= 1 the spectrum of T shrinks towards
    // 4: lambda in [4 - 4|o|cos, 4 + 4|o|cos]; |o| = 1 is the worst case.
    const double c = std::abs(offdiag) * std::cos(pi / (m + 1));
    return {A, (4.0 + 4.0 * c + shift_max) / (4.0 - 4.0 * c)};
}

VectorXd random_vector(Index n, std::mt19937& rng) {
    std::normal_distribution<double> d;
    VectorXd v(n);
    for (Index i = 0; i < n; ++i) v[i] = d(rng);
    return v;
}

MatrixXd random_matrix(Index r, Index c, std::mt19937& rng) {
    std::normal_distribution<double> d;
    MatrixXd M(r, c);
    for (Index j = 0; j < c; ++j)
        for (Index i = 0; i < r; ++i) M(i, j) = d(rng);
    return M;
}

double rel_residual(const SpMat& A, const VectorXd& x, const VectorXd& b) {
    const VectorXd r = A * x - b;
    return r.norm() / b.norm();
}

// Normwise backward error with ||A||_inf >= ||A||_2 (A symmetric); using an
// upper bound of ||A||_2 can only make eta smaller, and for these matrices
// ||A||_inf <= 8 + s is within ~10% of ||A||_2.
double backward_error(const SpMat& A, const VectorXd& x, const VectorXd& b) {
    VectorXd rowsum = VectorXd::Zero(A.rows());
    for (Index j = 0; j < A.outerSize(); ++j)
        for (SpMat::InnerIterator it(A, j); it; ++it) rowsum[it.row()] += std::abs(it.value());
    const VectorXd r = A * x - b;
    return r.norm() / (rowsum.maxCoeff() * x.norm() + b.norm());
}

SpMat lower_part(const SpMat& A) {
    return SpMat(A.triangularView<Eigen::Lower>());
}

template <class F>
CholeskyError expect_cholesky_error(F&& f) {
    try {
        f();
    } catch (const CholeskyError& e) {
        return e;
    }
    ADD_FAILURE() << "expected CholeskyError";
    return CholeskyError(CholeskyStatus::ok, CholeskyPhase::setup, -1, "none");
}

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
    if (GetParam().kind == FactorKind::supernodal) {
        EXPECT_TRUE(chol.is_supernodal());
    }
    if (GetParam().kind == FactorKind::simplicial) {
        EXPECT_FALSE(chol.is_supernodal());
    }
    // L has at least the lower triangle of A (no cancellation in the pattern).
    EXPECT_GE(chol.nnz_factor(), lower_part(A).nonZeros());
    EXPECT_GE(chol.bytes(), static_cast<std::size_t>(chol.nnz_factor()) * sizeof(double));
    EXPECT_GE(chol.common().peak_memory(), chol.bytes());
    // cholmod_rcond = (min diag L / max diag L)^2 >= 1/kappa_2(A), because
    // every squared diagonal entry of L is a Schur-complement pivot lying in
    // [lambda_min(A), lambda_max(A)].  Factor 0.5 absorbs rounding.
    EXPECT_GE(chol.rcond(), 0.5 / kappa);
    EXPECT_LE(chol.rcond(), 1.0);

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

TEST_P(SparseCholeskySpd, MultiRhsEqualsColumnwise) {
    std::mt19937 rng(7);
    const auto [A, kappa] = make_laplacian(30, 2.0, rng);  // n = 900
    const Index n = A.rows();
    SparseCholesky chol(options());
    chol.compute(A);

    const MatrixXd B = random_matrix(n, 7, rng);
    MatrixXd X;
    chol.solve(B, X);
    ASSERT_EQ(X.rows(), n);
    ASSERT_EQ(X.cols(), 7);
    for (Index j = 0; j < B.cols(); ++j) {
        VectorXd xj;
        chol.solve(VectorXd(B.col(j)), xj);
        EXPECT_LE(rel_residual(A, VectorXd(X.col(j)), VectorXd(B.col(j))), kCA * kEps * kappa);
        EXPECT_LE((xj - X.col(j)).norm() / xj.norm(), 2.0 * kCA * kEps * kappa);
    }
    // A block with one column and an empty block.
    MatrixXd X1;
    chol.solve(MatrixXd(B.col(0)), X1);
    EXPECT_LE(rel_residual(A, VectorXd(X1.col(0)), VectorXd(B.col(0))), kCA * kEps * kappa);
    MatrixXd X0;
    chol.solve(MatrixXd(n, 0), X0);
    EXPECT_EQ(X0.rows(), n);
    EXPECT_EQ(X0.cols(), 0);
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
    const std::size_t bytes_symbolic = chol.bytes();
    const auto nnz_symbolic = chol.nnz_factor();
    chol.factorize(A1);
    if (chol.is_supernodal()) {
        // The supernodal projection made after analyze() is exact.
        EXPECT_EQ(chol.bytes(), bytes_symbolic);
        EXPECT_EQ(chol.nnz_factor(), nnz_symbolic);
    }

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

INSTANTIATE_TEST_SUITE_P(
    Configs, SparseCholeskySpd,
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
        // 5 columns: not a multiple of CHOLMOD's simplicial chunk width 4,
        // which exercises the workspace-shape workaround in solve_impl().
        const MatrixXd B = random_matrix(n, 5, rng);
        VectorXd x;
        MatrixXd X;
        chol.solve(b, x);  // warm-up: allocates X/Y/E for 1 and for 5 columns
        chol.solve(B, X);
        const double* xdata = x.data();
        const double* Xdata = X.data();
        {
            AllocCounter counter;
            for (int k = 0; k < 20; ++k) {
                chol.solve(b, x);
                chol.solve(B, X);  // alternating does not thrash the workspaces
            }
            EXPECT_EQ(AllocCounter::count, 0);
        }
        EXPECT_EQ(x.data(), xdata);  // output storage reused, not reallocated
        EXPECT_EQ(X.data(), Xdata);
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
    const MatrixXd B = random_matrix(A.rows(), 3, rng);
    MatrixXd X = B;
    chol.solve(X, X);
    EXPECT_LE(rel_residual(A, VectorXd(X.col(2)), VectorXd(B.col(2))), kCA * kEps * kappa);
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
    EXPECT_NE(std::string(e.what()).find("not in the lower pattern"), std::string::npos)
        << e.what();
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
    EXPECT_NEAR(chol.rcond(), 1e-20, 1e-30);  // (min diag L / max diag L)^2
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
    EXPECT_EQ(chol.nnz_factor(), 0);
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
    EXPECT_NE(what.find("column " + std::to_string(c) + " of the input"), std::string::npos)
        << what;
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

INSTANTIATE_TEST_SUITE_P(
    Configs, NotPositiveDefinite,
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
        const auto e = expect_cholesky_error([&] {
            MatrixXd X;
            chol.solve(MatrixXd::Ones(101, 2), X);
        });
        EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
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
    EXPECT_EQ(a.bytes(), 0u);
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

// ========================================================================
// FixedDofPseudoInverse
// ========================================================================

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
        const Eigen::Vector2d d =
            (t.xy[static_cast<std::size_t>(b)] - t.xy[static_cast<std::size_t>(a)]).normalized();
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

TEST(FixedDofPseudoInverse, GeneralizedInverseOfTruss) {
    std::mt19937 rng(23);
    const Truss t = make_truss(20, rng);  // n = 800
    const Index n = t.K.rows();
    ASSERT_LE((t.K * t.R).norm(), 1e-12 * t.K.norm() * t.R.norm());  // construction check

    FixedDofPseudoInverse pinv(t.K, t.fixed, t.R);
    EXPECT_EQ(pinv.n(), n);
    EXPECT_GE(pinv.nnz_factor(), n - 3);  // at least the diagonal of L for K_rr
    EXPECT_EQ(pinv.free_dofs().size(), static_cast<std::size_t>(n - 3));
    const double tol = pinv_tolerance(t);
    const double normK = t.K.norm();

    VectorXd x;
    for (int k = 0; k < 10; ++k) {
        // K K^+ K v = K v: apply K^+ to f = K v in range(K).
        const VectorXd v = random_vector(n, rng);
        const VectorXd f = t.K * v;
        pinv.apply(f, x);
        for (Index i : t.fixed) EXPECT_EQ(x[i], 0.0);
        const VectorXd Kx = t.K * x;
        EXPECT_LE((Kx - f).norm() / (normK * x.norm()), tol) << "vector " << k;
    }

    // Block apply equals column-wise apply.
    const MatrixXd F = t.K * random_matrix(n, 5, rng);
    MatrixXd X;
    pinv.apply(F, X);
    for (Index j = 0; j < F.cols(); ++j) {
        VectorXd xj;
        pinv.apply(VectorXd(F.col(j)), xj);
        EXPECT_LE((xj - X.col(j)).norm(), 1e-12 * xj.norm());
        for (Index i : t.fixed) EXPECT_EQ(X(i, j), 0.0);
    }

    // Aliasing f and x.
    const VectorXd f = t.K * random_vector(n, rng);
    VectorXd y = f;
    pinv.apply(y, y);
    EXPECT_LE((t.K * y - f).norm() / (normK * y.norm()), tol);

    // Lower-only storage of K gives the same operator.
    FixedDofPseudoInverse pinv_lower(lower_part(t.K), t.fixed);
    VectorXd z;
    pinv_lower.apply(f, z);
    pinv.apply(f, x);
    EXPECT_LE((z - x).norm(), 1e-12 * x.norm());
}

// apply() keeps its output buffer (it no longer calls CHOLMOD at all: the factor is a plain
// exported L, see ConstApplyWithScratchEqualsApply).
TEST(FixedDofPseudoInverse, ApplyKeepsItsOutputBuffer) {
    std::mt19937 rng(29);
    const Truss t = make_truss(8, rng);
    FixedDofPseudoInverse pinv(t.K, t.fixed);
    const VectorXd f = t.K * random_vector(t.K.rows(), rng);
    VectorXd x;
    pinv.apply(f, x);
    const double* data = x.data();
    for (int k = 0; k < 20; ++k) pinv.apply(f, x);
    EXPECT_EQ(x.data(), data);
}

// The const apply with caller-owned scratch (what FETI's threads use): bitwise the same as the
// member-scratch apply, aliasing allowed, sizes checked.
TEST(FixedDofPseudoInverse, ConstApplyWithScratchEqualsApply) {
    std::mt19937 rng(31);
    const Truss t = make_truss(8, rng);
    const Index n = t.K.rows();
    const FixedDofPseudoInverse pinv(t.K, t.fixed);
    FixedDofPseudoInverse reference(t.K, t.fixed);
    const VectorXd f = t.K * random_vector(n, rng);
    VectorXd x(n), y, scratch(n - static_cast<Index>(t.fixed.size()));
    pinv.apply(f, x, scratch);
    reference.apply(f, y);
    EXPECT_EQ((x - y).lpNorm<Eigen::Infinity>(), 0.0);
    VectorXd z = f;
    pinv.apply(z, z, scratch);
    EXPECT_EQ((z - y).lpNorm<Eigen::Infinity>(), 0.0);
    VectorXd wrong_scratch(3), wrong_x(n + 1);
    EXPECT_EQ(expect_cholesky_error([&] { pinv.apply(f, x, wrong_scratch); }).status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(expect_cholesky_error([&] { pinv.apply(f, wrong_x, scratch); }).status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(expect_cholesky_error([&] { pinv.apply(VectorXd(n - 1), x, scratch); }).status(),
              CholeskyStatus::invalid_input);
}

TEST(FixedDofPseudoInverse, BadFixingIsDetected) {
    std::mt19937 rng(31);
    const Truss t = make_truss(10, rng);
    const Index n = t.K.rows();
    const int m = 10;

    // u of node (m-1, 0) instead of v: the rotation about node 0 moves that
    // node only vertically, so the rotation is not fixed; R(fixed,:) singular.
    const std::vector<Index> rotation_free = {0, 1, 2 * (m - 1)};
    {
        const auto e =
            expect_cholesky_error([&] { FixedDofPseudoInverse p(t.K, rotation_free, t.R); });
        EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
        EXPECT_EQ(e.phase(), CholeskyPhase::setup);
        EXPECT_NE(std::string(e.what()).find("sigma_min"), std::string::npos) << e.what();
    }
    // Without the kernel check, K_rr is singular: CHOLMOD either hits a
    // non-positive pivot (throws) or a rounding-level positive one, caught by
    // the rcond warning (measured rcond ~ 1e-15 < 1e-14 default threshold;
    // the regular fixing gives ~ 4e-2).
    try {
        FixedDofPseudoInverse p(t.K, rotation_free);
        EXPECT_EQ(p.status(), CholeskyStatus::numerical_warning);
    } catch (const CholeskyError& e) {
        EXPECT_EQ(e.status(), CholeskyStatus::not_positive_definite);
    }

    // Too many fixed DOFs: K_rr is regular but K K^+ K != K.  Only the
    // kernel check (count mismatch) catches it.
    std::vector<Index> four = t.fixed;
    four.push_back(n - 1);
    {
        const auto e = expect_cholesky_error([&] { FixedDofPseudoInverse p(t.K, four, t.R); });
        EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    }
    {
        FixedDofPseudoInverse p(t.K, four);
        const VectorXd f = t.K * random_vector(n, rng);
        VectorXd x;
        p.apply(f, x);
        EXPECT_GT((t.K * x - f).norm() / f.norm(), 1e-6);  // not a generalized inverse
    }

    // A basis that is not in ker K, and dependent columns.
    {
        MatrixXd Rbad = t.R;
        Rbad.col(2) += random_vector(n, rng);
        const auto e = expect_cholesky_error([&] { FixedDofPseudoInverse p(t.K, t.fixed, Rbad); });
        EXPECT_NE(std::string(e.what()).find("not in ker K"), std::string::npos) << e.what();
    }
    {
        MatrixXd Rdep = t.R;
        Rdep.col(2) = 2.0 * Rdep.col(0);
        const auto e = expect_cholesky_error([&] { FixedDofPseudoInverse p(t.K, t.fixed, Rdep); });
        EXPECT_NE(std::string(e.what()).find("dependent"), std::string::npos) << e.what();
    }
    // DOF list errors.
    for (const std::vector<Index>& bad :
         {std::vector<Index>{0, 1, n}, std::vector<Index>{0, 1, 1}, std::vector<Index>{-1}}) {
        const auto e = expect_cholesky_error([&] { FixedDofPseudoInverse p(t.K, bad); });
        EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
        EXPECT_EQ(e.phase(), CholeskyPhase::setup);
    }
    // Size errors in apply.
    FixedDofPseudoInverse p(t.K, t.fixed);
    const auto e = expect_cholesky_error([&] {
        VectorXd x;
        p.apply(VectorXd::Ones(n + 1), x);
    });
    EXPECT_EQ(e.status(), CholeskyStatus::invalid_input);
    EXPECT_EQ(e.phase(), CholeskyPhase::solve);
}

TEST(FixedDofPseudoInverse, RegularMatrixAndMoves) {
    // No fixed DOFs on an SPD matrix: K^+ = K^{-1}.
    std::mt19937 rng(37);
    const auto [A, kappa] = make_laplacian(12, 1.0, rng);
    FixedDofPseudoInverse inv(A, std::vector<Index>{});
    const VectorXd b = random_vector(A.rows(), rng);
    VectorXd x;
    inv.apply(b, x);
    EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);

    FixedDofPseudoInverse moved(std::move(inv));
    moved.apply(b, x);
    EXPECT_LE(rel_residual(A, x, b), kCA * kEps * kappa);
    EXPECT_THROW(inv.apply(b, x), CholeskyError);  // NOLINT(bugprone-use-after-move)

    // All DOFs fixed: K^+ = 0.
    std::vector<Index> all(static_cast<std::size_t>(A.rows()));
    for (Index i = 0; i < A.rows(); ++i) all[static_cast<std::size_t>(i)] = i;
    FixedDofPseudoInverse zero(A, all);
    zero.apply(b, x);
    EXPECT_EQ(x.size(), A.rows());
    EXPECT_EQ(x.norm(), 0.0);
}

}  // namespace
}  // namespace dualcell::linalg
