// Linear operators for the QP solvers: the solvers see A only through y = A x, so a dense
// matrix, a sparse matrix or a FETI dual operator F = B K⁺ Bᵀ all fit.
#pragma once

#include <Eigen/Core>
#include <functional>

namespace dualcell::qp {

// y = A x. The solver pre-sizes y to x.size(); the operator must only write into it.
using LinearOperator = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& y)>;

// Estimate of ‖A‖₂ for a symmetric positive semidefinite A of size n by power iteration from a
// seeded random start vector; applies A exactly `iterations` times (iterations ≥ 1).
// Power iteration approaches ‖A‖ from below, so the last ‖A v‖ (‖v‖ = 1) is multiplied by 1.01
// to make the estimate a safe upper-ish bound for step lengths such as ω̄ ≤ 2/‖A‖.
// Returns 0 for A = 0 (on the start vector) and a non-finite value if A produced NaN/Inf.
double estimate_norm(const LinearOperator& A, Eigen::Index n, int iterations = 20, unsigned seed = 1);

}  // namespace dualcell::qp
