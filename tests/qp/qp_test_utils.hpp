// Shared generators and the dense oracle for the QP tests. Everything is seeded and dense; the
// oracle is independent of the solvers (it never calls into src/qp beyond the operator type).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "qp/operator.hpp"

namespace dualcell::qp::testing {

inline constexpr double inf = std::numeric_limits<double>::infinity();

// y = A x for a dense matrix that outlives the operator; counts applications if asked.
inline LinearOperator dense_operator(const Eigen::MatrixXd& A, long* applications = nullptr) {
  return [&A, applications](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    y.noalias() = A * x;
    if (applications != nullptr) {
      ++*applications;
    }
  };
}

inline Eigen::MatrixXd gaussian_matrix(std::mt19937& rng, int rows, int cols) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd M(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      M(i, j) = normal(rng);
    }
  }
  return M;
}

// V diag(eigenvalues) Vᵀ with V a random orthogonal matrix (Q factor of a Gaussian matrix).
inline Eigen::MatrixXd matrix_with_spectrum(std::mt19937& rng, const Eigen::VectorXd& eigenvalues) {
  const int n = static_cast<int>(eigenvalues.size());
  const Eigen::MatrixXd V = Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian_matrix(rng, n, n)).householderQ() *
                            Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd A = V * eigenvalues.asDiagonal() * V.transpose();
  return 0.5 * (A + A.transpose());
}

// Eigenvalues uniform in [lo, hi] with both ends attained, then `zeros` of them set to 0.
inline Eigen::VectorXd spectrum(std::mt19937& rng, int n, double lo, double hi, int zeros = 0) {
  std::uniform_real_distribution<double> uniform(lo, hi);
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) {
    d[i] = uniform(rng);
  }
  d[0] = hi;
  d[n - 1] = lo;
  for (int i = 0; i < zeros; ++i) {
    d[n - 1 - i] = 0.0;
  }
  return d;
}

// m × n with orthonormal rows.
inline Eigen::MatrixXd random_orthonormal_rows(std::mt19937& rng, int m, int n) {
  const Eigen::MatrixXd Qfull = Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian_matrix(rng, n, m)).householderQ() *
                                Eigen::MatrixXd::Identity(n, m);
  return Qfull.transpose();
}

inline double objective(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  return 0.5 * x.dot(A * x) - b.dot(x);
}

// ‖gᴾ‖ written out again, independently of qp/bounds.cpp.
inline double reference_projected_gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                                           const Eigen::VectorXd& u) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    double gp = g[i];
    if (x[i] == l[i] && x[i] == u[i]) {
      gp = 0.0;
    } else if (x[i] == l[i]) {
      gp = std::min(g[i], 0.0);
    } else if (x[i] == u[i]) {
      gp = std::max(g[i], 0.0);
    }
    sum += gp * gp;
  }
  return std::sqrt(sum);
}

// gᴾ itself, componentwise as above.
inline Eigen::VectorXd reference_projected_gradient_vector(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                                           const Eigen::VectorXd& l, const Eigen::VectorXd& u) {
  Eigen::VectorXd gp = g;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (x[i] == l[i] && x[i] == u[i]) {
      gp[i] = 0.0;
    } else if (x[i] == l[i]) {
      gp[i] = std::min(g[i], 0.0);
    } else if (x[i] == u[i]) {
      gp[i] = std::max(g[i], 0.0);
    }
  }
  return gp;
}

// A badly scaled SPD matrix D^{1/2} A0 D^{1/2}, d_i = 10^{e_i} with e_i uniform in [-decades,
// decades] (both ends attained): κ grows by up to 10^{2·decades} over κ(A0), while the Jacobi
// preconditioner diag(A)⁻¹ undoes most of D. sqrt_d holds D^{1/2}.
struct BadlyScaled {
  Eigen::MatrixXd A;
  Eigen::VectorXd sqrt_d;
};

inline BadlyScaled badly_scaled(std::mt19937& rng, const Eigen::MatrixXd& A0, double decades) {
  const Eigen::Index n = A0.rows();
  std::uniform_real_distribution<double> exponent(-decades, decades);
  BadlyScaled out;
  out.sqrt_d.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    out.sqrt_d[i] = std::pow(10.0, 0.5 * exponent(rng));
  }
  out.sqrt_d[0] = std::pow(10.0, 0.5 * decades);
  out.sqrt_d[n - 1] = std::pow(10.0, -0.5 * decades);
  const Eigen::MatrixXd A = out.sqrt_d.asDiagonal() * A0 * out.sqrt_d.asDiagonal();
  out.A = 0.5 * (A + A.transpose());
  return out;
}

inline bool is_feasible(const Eigen::VectorXd& x, const Eigen::VectorXd& l, const Eigen::VectorXd& u) {
  return (x.array() >= l.array()).all() && (x.array() <= u.array()).all();
}

// A small QP  min ½xᵀAx − bᵀx  s.t.  C x = 0, l ≤ x ≤ u  (C may have no rows).
struct DenseQp {
  Eigen::MatrixXd A;
  Eigen::VectorXd b, l, u;
  Eigen::MatrixXd C;
  Eigen::VectorXd x_star;  // a known solution, when generated with one
  Eigen::VectorXd nu;      // and the multiplier of C x = 0 that goes with it
};

struct OracleSolution {
  bool found = false;
  Eigen::VectorXd x;
  double value = inf;
};

// Dense active-set enumeration for n ≤ 8: each component is free, at its lower or at its upper
// bound (3ⁿ assignments). For one assignment, with F the free and B the fixed components,
//   [A_FF  C_Fᵀ] [x_F]   [b_F − A_FB x_B]
//   [C_F   0   ] [ ν ] = [   − C_B x_B  ]
// gives a minimiser of f on the affine set {x_B fixed, C x = 0} (complete orthogonal
// decomposition: the minimum-norm solution when singular; inconsistent systems are skipped).
// The oracle returns the feasible candidate of least f. That is the optimum: every feasible
// candidate is ≥ it, and the assignment of an optimal x* (moved along zero-curvature directions
// until bounds stop it, for singular A) reproduces x*. Unlike "first candidate with correctly
// signed multipliers", this needs no multiplier, which is not unique in degenerate cases.
inline OracleSolution solve_by_enumeration(const DenseQp& qp) {
  const int n = static_cast<int>(qp.b.size());
  const int n_eq = static_cast<int>(qp.C.rows());
  double bound_scale = 1.0;
  for (int i = 0; i < n; ++i) {
    for (double v : {qp.l[i], qp.u[i]}) {
      if (std::isfinite(v)) {
        bound_scale = std::max(bound_scale, std::abs(v));
      }
    }
  }
  // Round-off of the small dense solves, relative to the data.
  const double feasibility_tolerance = 1e-10 * bound_scale;

  OracleSolution best;
  std::vector<int> state(n, 0);  // 0 free, 1 lower, 2 upper
  long n_assignments = 1;
  for (int i = 0; i < n; ++i) {
    n_assignments *= 3;
  }
  for (long code = 0; code < n_assignments; ++code) {
    long rest = code;
    bool valid = true;
    std::vector<int> free_index;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) {
      state[i] = static_cast<int>(rest % 3);
      rest /= 3;
      if (state[i] == 0) {
        free_index.push_back(i);
      } else {
        const double bound = state[i] == 1 ? qp.l[i] : qp.u[i];
        valid = valid && std::isfinite(bound);
        x[i] = bound;
      }
    }
    if (!valid) {
      continue;
    }
    const int n_free = static_cast<int>(free_index.size());
    const int size = n_free + n_eq;
    if (size > 0) {
      Eigen::MatrixXd K = Eigen::MatrixXd::Zero(size, size);
      Eigen::VectorXd rhs(size);
      const Eigen::VectorXd Ax_fixed = qp.A * x;
      const Eigen::VectorXd Cx_fixed = qp.C * x;
      for (int a = 0; a < n_free; ++a) {
        for (int c = 0; c < n_free; ++c) {
          K(a, c) = qp.A(free_index[a], free_index[c]);
        }
        for (int r = 0; r < n_eq; ++r) {
          K(a, n_free + r) = qp.C(r, free_index[a]);
          K(n_free + r, a) = qp.C(r, free_index[a]);
        }
        rhs[a] = qp.b[free_index[a]] - Ax_fixed[free_index[a]];
      }
      for (int r = 0; r < n_eq; ++r) {
        rhs[n_free + r] = -Cx_fixed[r];
      }
      const Eigen::VectorXd z = K.completeOrthogonalDecomposition().solve(rhs);
      if ((K * z - rhs).norm() > 1e-9 * (1.0 + rhs.norm())) {
        continue;
      }
      for (int a = 0; a < n_free; ++a) {
        x[free_index[a]] = z[a];
      }
    }
    const bool feasible = ((x - qp.l).minCoeff() >= -feasibility_tolerance || n == 0) &&
                          ((qp.u - x).minCoeff() >= -feasibility_tolerance || n == 0) &&
                          (n_eq == 0 || (qp.C * x).norm() <= feasibility_tolerance);
    if (!feasible) {
      continue;
    }
    const double value = objective(qp.A, qp.b, x);
    if (value < best.value) {
      best = {true, x.cwiseMax(qp.l).cwiseMin(qp.u), value};
    }
  }
  return best;
}

enum class BoundKind { lower, upper, box, mixed };

inline const char* to_string(BoundKind kind) {
  switch (kind) {
    case BoundKind::lower:
      return "lower";
    case BoundKind::upper:
      return "upper";
    case BoundKind::box:
      return "box";
    case BoundKind::mixed:
      return "mixed";
  }
  return "?";
}

enum class Degeneracy { none, weakly_active, vertex };

// A problem with a known solution x*: pick x* with C x* = 0, an active pattern allowed by `kind`,
// bounds that make x* feasible with that pattern, KKT multipliers g* (≥ 0 at lower, ≤ 0 at upper,
// 0 on free and, for weakly_active, on some active components), and b = A x* − g* + Cᵀν.
// x* is then a solution; it is the only one when A is positive definite on ker C.
inline DenseQp make_known_solution_problem(std::mt19937& rng, const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                                           BoundKind kind, Degeneracy degeneracy = Degeneracy::none) {
  const int n = static_cast<int>(A.rows());
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> gap(0.2, 1.0);
  std::uniform_int_distribution<int> pick(0, 3);

  DenseQp qp;
  qp.A = A;
  qp.C = C;
  Eigen::VectorXd z(n);
  for (int i = 0; i < n; ++i) {
    z[i] = unit(rng);
  }
  qp.x_star = z - C.transpose() * (C * z);
  qp.l = Eigen::VectorXd::Constant(n, -inf);
  qp.u = Eigen::VectorXd::Constant(n, inf);
  Eigen::VectorXd g_star = Eigen::VectorXd::Zero(n);
  bool forced_weak = false;
  for (int i = 0; i < n; ++i) {
    bool has_lower = kind == BoundKind::lower || kind == BoundKind::box;
    bool has_upper = kind == BoundKind::upper || kind == BoundKind::box;
    if (kind == BoundKind::mixed) {
      const int type = pick(rng);  // none, lower, upper, both
      has_lower = type == 1 || type == 3;
      has_upper = type == 2 || type == 3;
    }
    // 0 free, 1 at lower, 2 at upper
    int status = 0;
    const int choice = pick(rng) % 3;
    if (degeneracy == Degeneracy::vertex) {
      status = has_lower && (choice != 2 || !has_upper) ? 1 : (has_upper ? 2 : 0);
    } else if (choice == 1 && has_lower) {
      status = 1;
    } else if (choice == 2 && has_upper) {
      status = 2;
    }
    const double x = qp.x_star[i];
    if (has_lower) {
      qp.l[i] = status == 1 ? x : x - gap(rng);
    }
    if (has_upper) {
      qp.u[i] = status == 2 ? x : x + gap(rng);
    }
    if (status != 0) {
      const bool weak = degeneracy == Degeneracy::weakly_active && (!forced_weak || pick(rng) % 2 == 0);
      forced_weak = forced_weak || weak;
      g_star[i] = weak ? 0.0 : (status == 1 ? gap(rng) : -gap(rng));
    }
  }
  qp.nu.resize(C.rows());
  for (Eigen::Index r = 0; r < C.rows(); ++r) {
    qp.nu[r] = unit(rng);
  }
  qp.b = A * qp.x_star - g_star + C.transpose() * qp.nu;
  return qp;
}

// Random bounds of the given kind around a random feasible point (C p = 0) and a random b.
inline DenseQp make_random_problem(std::mt19937& rng, const Eigen::MatrixXd& A, const Eigen::MatrixXd& C,
                                   BoundKind kind) {
  const int n = static_cast<int>(A.rows());
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> width(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 3);
  DenseQp qp;
  qp.A = A;
  qp.C = C;
  Eigen::VectorXd p(n);
  qp.b.resize(n);
  for (int i = 0; i < n; ++i) {
    p[i] = unit(rng);
    qp.b[i] = 2.0 * unit(rng);
  }
  p -= C.transpose() * (C * p);
  qp.l = Eigen::VectorXd::Constant(n, -inf);
  qp.u = Eigen::VectorXd::Constant(n, inf);
  for (int i = 0; i < n; ++i) {
    const int type = kind == BoundKind::mixed   ? pick(rng)
                     : kind == BoundKind::lower ? 1
                     : kind == BoundKind::upper ? 2
                                                : 3;
    if (type == 1 || type == 3) {
      qp.l[i] = p[i] - width(rng);
    }
    if (type == 2 || type == 3) {
      qp.u[i] = p[i] + width(rng);
    }
  }
  return qp;
}

}  // namespace dualcell::qp::testing
