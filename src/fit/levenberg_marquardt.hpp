#pragma once
// Levenberg–Marquardt with Marquardt's scaling of the normal equations (docs/theory/exact-law.md,
// the small cell): the one least-squares loop of the compact laws, for the small cell's rows in
// three components (fit/small_cell.cpp) and for its strain along the fibres in six
// (fit/small_ply.cpp).
//
// From x, each step solves (JᵀJ + λ diag JᵀJ) δ = −Jᵀf, diag JᵀJ floored at 1e-12 of its largest
// entry; a step that lowers the cost ‖f‖² is accepted and λ divided by 3 (floor 1e-12), a refused
// one (or a matrix that is not positive definite) multiplies λ by 4, at most 20 tries per step,
// λ = 1e-3 at the start. It stops after `quiet_steps` accepted steps in a row that each lowered
// the cost by less than `quiet_fraction` of it, after max_iterations steps, or when no try is
// accepted. JᵀJ is formed by one symmetric rank update (a general least-squares library's
// unblocked BLAS made that the whole cost at the small cell's 2 272 unknowns), and the matrices
// are allocated once per call, not per step.
#include <Eigen/Core>
#include <functional>

namespace dualcell::fit {

// f(x) (n residuals) and, where J is given, its Jacobian (n × x.size()); false where x cannot be
// evaluated (a trial there is refused; at the start the loop gives up).
using Residuals = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& f, Eigen::MatrixXd* J)>;

struct LmStop {
  int max_iterations = 100;
  int quiet_steps = 1;
  double quiet_fraction = 1e-12;
};

struct LmEnd {
  bool evaluated = false;  // false: the residuals at the start could not be evaluated
  int iterations = 0;      // accepted steps
};

// `step` (may be empty) is told each step's index before it (a fit's progress line).
LmEnd levenberg_marquardt(const Residuals& residuals, Eigen::Index n, Eigen::VectorXd& x, const LmStop& stop,
                          const std::function<void(int)>& step = {});

}  // namespace dualcell::fit
