#pragma once
// Test matrices and checks shared by the linalg tests (tolerances: sparse_cholesky_test.cpp).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "linalg/sparse_cholesky.hpp"

namespace dualcell::linalg::test_matrices {

using SpMat = SparseCholesky::SparseMatrix;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

inline constexpr double kEps = std::numeric_limits<double>::epsilon();
inline constexpr double kCA = 50.0;  // backward-error constant, see sparse_cholesky_test.cpp

struct Laplacian {
  SpMat A;           // full symmetric storage
  double kappa_max;  // rigorous upper bound of the 2-norm condition number
};

// A = T + D on an m x m grid; diag shift D uniform in [0, shift_max];
// off-diagonal entries scaled by offdiag (|offdiag| <= 1 keeps the bound).
inline Laplacian make_laplacian(int m, double shift_max, std::mt19937& rng, double offdiag = 1.0) {
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

inline VectorXd random_vector(Index n, std::mt19937& rng) {
  std::normal_distribution<double> d;
  VectorXd v(n);
  for (Index i = 0; i < n; ++i) v[i] = d(rng);
  return v;
}

inline MatrixXd random_matrix(Index r, Index c, std::mt19937& rng) {
  std::normal_distribution<double> d;
  MatrixXd M(r, c);
  for (Index j = 0; j < c; ++j)
    for (Index i = 0; i < r; ++i) M(i, j) = d(rng);
  return M;
}

inline double rel_residual(const SpMat& A, const VectorXd& x, const VectorXd& b) {
  const VectorXd r = A * x - b;
  return r.norm() / b.norm();
}

// Normwise backward error with ||A||_inf >= ||A||_2 (A symmetric); using an
// upper bound of ||A||_2 can only make eta smaller, and for these matrices
// ||A||_inf <= 8 + s is within ~10% of ||A||_2.
inline double backward_error(const SpMat& A, const VectorXd& x, const VectorXd& b) {
  VectorXd rowsum = VectorXd::Zero(A.rows());
  for (Index j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) rowsum[it.row()] += std::abs(it.value());
  const VectorXd r = A * x - b;
  return r.norm() / (rowsum.maxCoeff() * x.norm() + b.norm());
}

inline SpMat lower_part(const SpMat& A) { return SpMat(A.triangularView<Eigen::Lower>()); }

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

}  // namespace dualcell::linalg::test_matrices
