// SMALBE-M: min ½ xᵀA x - bᵀx  s.t.  Q x = 0, l ≤ x ≤ u, with Q the orthogonal projector onto
// Im Ĝᵀ (Q = Ĝᵀ Ĝ, Ĝ with orthonormal rows) given as an operator (docs/method.md §7).
// See smalbe.cpp for the method.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "qp/face.hpp"
#include "qp/mprgp.hpp"
#include "qp/operator.hpp"
#include "qp/result.hpp"

namespace dualcell::qp {

// The state after one outer iteration, for a monitor (progress on a terminal): the two
// stopping quantities relative to ‖b‖ as the tolerances are, and the work so far.
struct OuterReport {
  long outer_iterations = 0;       // done so far
  double projected_gradient = 0;   // ‖gᴾ‖/‖b‖, against relative_tolerance
  double equality_residual = 0;    // ‖A‖‖Qx‖/‖b‖, against equality_tolerance
  long operator_applications = 0;  // so far, all included
  double rho = 0;                  // the penalty now
};

struct SmalbeOptions {
  // Stop when ‖gᴾ‖ ≤ relative_tolerance·‖b‖ and ‖A‖‖Q x‖ ≤ equality_tolerance·‖b‖ (‖b‖ → 1 if
  // b = 0). ‖A‖‖Qx‖ is the gradient a residual Qx can cause, so both tests are in units of b
  // and invariant under scaling of A; for ‖A‖ = 1 it is the plain ‖Qx‖ ≤ tol·‖b‖.
  double relative_tolerance = 1e-8;
  double equality_tolerance = 1e-8;
  long max_outer_iterations = 100;
  // Budget of applications of A, all included (norm estimates, inner steps); checked between
  // inner solves and passed down as the inner step budget.
  long max_operator_applications = 100000;
  double rho0_factor = 1.0;  // ρ₀ = rho0_factor·‖A‖
  double eta_factor = 0.1;   // η = eta_factor·‖b‖
  double xi0 = 1.0;          // ξ₀ = xi0·‖A‖ (relative to ‖A‖ like ρ)
  double xi_reduction = 10;  // ξ ← ξ/xi_reduction when the augmented Lagrangian grows too little
  // Safeguard beyond SMALBE-M (penalty growth, docs/method.md §7): ρ ← c_ρ ρ,
  // c_ρ = rho_growth, when an inner solve converged but ‖Qx‖ fell by less than the factor
  // feasibility_reduction (r_Q), up to rho_max_factor·‖A‖. rho_growth = 1 gives plain SMALBE-M.
  double rho_growth = 10;
  double feasibility_reduction = 0.1;
  // ρ_max = 1e4·‖A‖: when most components are pinned by boxes of width w, x can move Q x by no
  // more than about w per outer iteration, so m ← m + ρQx needs about ‖m*‖/(ρ w) iterations to
  // reach its solution value m*. Measured on the stability matrix (bonds of strength 1e-6 under
  // unit loads, boxes 2e-6·L wide): at ρ_max = 100‖A‖, 100 of 9 960 cases stopped at 200 outer
  // iterations; at 1e4‖A‖ none, the worst needing 75, and the F applications over the cases that
  // converged before fell by 2 % (ρ grows only where feasibility is slow, so no other case moved).
  double rho_max_factor = 1e4;
  // ρ grows only after this many consecutive outer iterations of too little feasibility gain
  // (1: at the first). One slow iteration is no evidence of slow contraction: in the FETI
  // contact problems the first outer iterations change the active set, and growing ρ there
  // shrinks every later expansion step (ω̄ = 1.95/max(‖A‖, ρ)) for nothing.
  long rho_patience = 1;
  // The caller asserts A Q = Q A = 0 (A = PFP with P = I − Q, as in FETI): then the spectra of A
  // and ρQ live on orthogonal subspaces and ‖A + ρQ‖ = max(‖A‖, ρ) exactly, so no power
  // iterations are spent on it.
  bool projected_operator = false;
  // Preconditioner y = M⁻¹x for A on Im(I − Q); empty (the default) → none. It must be symmetric
  // positive semidefinite, positive definite on Im(I − Q) and, when projected_operator is true,
  // vanish on Im Q: in FETI, P M⁻¹ P with P = I − Q and M⁻¹ a lumped or Dirichlet preconditioner
  // of F. The inner MPRGP is preconditioned in face by M⁻¹ + Q/ρ, a preconditioner of A + ρQ
  // (see smalbe.cpp). Applications are counted in Counters::preconditioner_applications.
  LinearOperator preconditioner;
  // Optional fused forms y = A v + s·Q v and y = M⁻¹ v + s·Q v, for a caller that forms Q v
  // anyway inside A and M⁻¹ (FETI: A = PFP and P M⁻¹ P need P v = v − Q v), so that the inner
  // solver's A + ρQ and M⁻¹ + Q/ρ cost two applications of Q, not three. They must equal the
  // composed forms (A, Q and preconditioner are still used elsewhere); empty → composed.
  std::function<void(const Eigen::VectorXd&v, double s, Eigen::VectorXd&y)> A_plus_shifted_Q,
      preconditioner_plus_shifted_Q;
  // Inner MPRGP: Gamma, omega_bar_factor, max_iterations (per inner solve), stagnation_window,
  // on_iterate are used; norm_A is ‖A‖ of the caller's A (0 → estimated); its tolerances are
  // replaced by SMALBE's inner stopping test. inner.preconditioner must be empty (it is built
  // from preconditioner, for the current ρ).
  MprgpOptions inner;
  // The face solve (qp/face.hpp): given the caller's coarse algebra of Ĝ, SMALBE finishes on the
  // face once an inner solve converged and ended with at most face_changes components changed
  // between free, at a lower and at an upper bound since the previous outer iteration (null:
  // never). A face that did not settle is not tried again until the active set has changed.
  // face_changes = 2, measured on the contact ladder (docs/method.md §7b): 0 waited one outer
  // iteration longer on half of the RVEs (the 64-fibre one 1 823 → 1 997 F applications).
  FaceProjector* face_projector = nullptr;
  long face_changes = 2;
  // Called after every outer iteration (empty: not called); must not change anything.
  std::function<void(const OuterReport&)> on_outer;
};

// Empty when the options are valid, else a one-line description of the first invalid one.
std::string check_options(const SmalbeOptions& opts);

// x: in, initial guess (empty → 0; projected onto the box); out, the solution (feasible for the
// bounds, Q x ≈ 0). On invalid_input x is unchanged.
Result smalbe(const LinearOperator& A, const LinearOperator& Q, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
              const Eigen::VectorXd& u, Eigen::VectorXd& x, const SmalbeOptions& opts = {});

// As above with the multiplier m = Ĝᵀμ of Q x = 0, kept in x-space: in, initial value (empty →
// 0; replaced by Q m), out, the final value, so that A x - b + m is the Lagrangian gradient at the
// solution. Pass the previous m to warm-start a sequence of related solves.
Result smalbe(const LinearOperator& A, const LinearOperator& Q, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
              const Eigen::VectorXd& u, Eigen::VectorXd& x, Eigen::VectorXd& m, const SmalbeOptions& opts);

}  // namespace dualcell::qp
