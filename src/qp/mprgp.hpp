// MPRGP: min ½ xᵀA x - bᵀx  s.t.  l ≤ x ≤ u, for symmetric positive semidefinite A given as an
// operator, in box form (docs/method.md §7, its sources in §18),
// optionally preconditioned in
// face (docs/method.md §7). See mprgp.cpp for the method.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "qp/operator.hpp"
#include "qp/result.hpp"

namespace dualcell::qp {

struct MprgpOptions {
  // Stop when ‖gᴾ‖ ≤ max(absolute_tolerance, relative_tolerance·‖b‖); if b = 0 the relative
  // tolerance is taken against 1 (it becomes absolute).
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 0;
  // Budget of steps (CG + expansion + proportioning).
  long max_iterations = 10000;
  // Proportioning parameter Γ > 0 in ‖ψ‖² ≤ Γ² φ̃ᵀφ.
  double Gamma = 1.0;
  // Expansion steplength ω̄ = omega_bar_factor/‖A‖, factor in (0, 2].
  double omega_bar_factor = 1.95;
  // ‖A‖; 0 → estimated by 20 power iterations (counted as operator applications).
  double norm_A = 0;
  // Status stagnated after this many consecutive steps in which neither the objective decreased
  // by more than round-off nor ‖gᴾ‖ reached a new minimum; 0 disables the test.
  long stagnation_window = 200;
  // Preconditioner y = M⁻¹x ≈ A⁻¹x, symmetric and positive definite (on the free components of
  // the iterates, at least), applied as the restriction to the free set F: the CG directions are
  // built from z = χ_F ⊙ M⁻¹(χ_F ⊙ g) instead of φ; expansion and proportioning steps and all
  // tests stay unpreconditioned. Empty (the default) → no preconditioning, the plain method bit
  // for bit. Applications are counted in Counters::preconditioner_applications. If M⁻¹ turns
  // out not to give a descent direction on some face, that step falls back to φ.
  LinearOperator preconditioner;
  // Observer called with every iterate (the projected initial guess, each half step and each
  // step); empty by default. Meant for tests and monitors.
  std::function<void(const Eigen::VectorXd& x)> on_iterate;
};

// Custom stopping test, replacing the tolerance test: called with the iterate, its gradient
// g = A x - b and ‖gᴾ‖; returning true stops with status converged once it also holds on a freshly
// computed gradient (the solver recomputes g and asks again).
using StoppingTest = std::function<bool(const Eigen::VectorXd& x, const Eigen::VectorXd& g, double gP_norm)>;

// Work vectors, so that repeated solves (SMALBE's inner loop) do not allocate. On return, g holds
// A x - b at the returned x (unless the status is invalid_input or non_finite).
struct MprgpWorkspace {
  Eigen::VectorXd g;    // gradient A x - b
  Eigen::VectorXd p;    // conjugate direction
  Eigen::VectorXd Ap;   // A p, A ψ, or A x on recomputation
  Eigen::VectorXd phi;  // free gradient φ
  Eigen::VectorXd psi;  // chopped gradient ψ
  Eigen::VectorXd z;    // preconditioned free gradient χ_F ⊙ M⁻¹φ (with a preconditioner only)
};

// Empty when the options are valid, else a one-line description of the first invalid one.
std::string check_options(const MprgpOptions& opts);

// x: in, initial guess (empty → 0; projected onto the box if infeasible); out, the solution, always
// feasible. On invalid_input x is unchanged.
Result mprgp(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
             Eigen::VectorXd& x, const MprgpOptions& opts = {});

// As above with a custom stopping test (empty → tolerance test) and caller-owned work vectors.
Result mprgp(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
             Eigen::VectorXd& x, const MprgpOptions& opts, const StoppingTest& stop, MprgpWorkspace& work);

}  // namespace dualcell::qp
