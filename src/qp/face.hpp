// The face solve: SMALBE's finish once the active set has settled (docs/method.md §7b).
//
// On the face of the box that an active set fixes, with Q x = 0 imposed exactly, the bound and
// equality constrained QP is a linear problem:
//   min f(x) = ½ xᵀA x − bᵀx   s.t.   x_i fixed off F,   Ĝ x = 0,
// F the free set, Ĝ any matrix whose rows span Im Q. With Ĝ_F = Ĝ χ_F (the columns off F set to
// zero) and S = Ĝ_F Ĝ_Fᵀ, the projector onto {v : v = 0 off F, Ĝ v = 0} is
//   P_F = χ_F − Ĝ_Fᵀ S⁺ Ĝ_F,
// and the face solve is a primal–dual active-set iteration on faces:
//   1. x ← x − Ĝ_Fᵀ S⁺ Ĝ x: the nearest point of the face with Ĝ x = 0 (it may leave the box, as
//      CG's iterates may: only the face's minimiser must stay inside);
//   2. CG on f along the face: r = P_F g, g = A x − b, optionally preconditioned by
//      P_F M⁻¹ P_F, to ‖r‖ ≤ forcing·‖r₀‖ first (the face may still change);
//   3. free components that ended outside the box are fixed on their bound; otherwise the
//      multiplier of Ĝ x = 0 that makes the Lagrangian gradient g + Ĝᵀμ smallest on F,
//      μ = −S⁺ Ĝ_F g (SMALBE's m = Ĝᵀμ), tells which components on a bound should be free (the
//      chopped gradient ψ of g + m, when ‖ψ‖ is above the tolerance); a changed face goes back
//      to 1, an unchanged one is finished to the tolerance.
// It ends converged (a face whose minimiser lies in the box with ‖r‖ and ‖ψ‖ within the
// tolerance) or, after max_rounds faces or max_steps CG steps, unsettled, with x and m as they
// came. SMALBE tests a converged face with its own stopping test.
//
// Why (measured on the contact ladder, docs/method.md §7b): once the active set stops changing,
// SMALBE still needs outer iterations to make Q x small, each an inner solve, and the penalty
// growth that speeds them shortens MPRGP's expansion steps. On the face the equality is one
// projection, and CG converges as on a bonded problem.
//
// Symbol → variable
//   F (indicator χ_F)    work.free (1 on F, 0 off)
//   Ĝ, S⁺                FaceProjector::apply_Gt, FaceProjector::solve_coarse
//   r, z, p, A p, ψ      work.r, work.z, work.p, work.Ap, work.z (after CG)
//   g, m                 g, m
#pragma once

#include <Eigen/Core>

#include "qp/operator.hpp"
#include "qp/result.hpp"

namespace dualcell::qp {

// The caller's coarse algebra of Ĝ on a face (in FETI: the rows of G, and a sparse Cholesky
// factor of S + δI with δ at the round-off of S; docs/method.md §7b).
class FaceProjector {
 public:
  virtual ~FaceProjector() = default;
  // Prepares S for the free set (free_i = 1 on F, 0 off). False when it cannot (nothing is
  // changed and no face solve is run).
  virtual bool set_face(const Eigen::VectorXd& free) = 0;
  // c = S⁺ Ĝ w: the coarse solve of the face, for w on any support.
  virtual void solve_coarse(const Eigen::VectorXd& w, Eigen::VectorXd& c) = 0;
  // v = Ĝᵀ c, on every component.
  virtual void apply_Gt(const Eigen::VectorXd& c, Eigen::VectorXd& v) = 0;
};

enum class FaceOutcome {
  refused,    // the projector could not be built: x, m unchanged, nothing applied
  converged,  // a face whose minimiser lies in the box, with multipliers of the right sign
  unsettled,  // no such face within max_rounds or max_steps: x, m restored
};

struct FaceOptions {
  double tolerance = 0;  // on ‖r‖, absolute
  long max_steps = 0;    // CG steps over all rounds
  // Faces tried (primal–dual active-set rounds). Measured on the contact ladder (docs/method.md
  // §7b): a face that needs more than two corrections rarely settles, the signs of the
  // multipliers near zero flipping from round to round; at 8 rounds the H = 8 beam paid 420 F
  // applications for two such faces (1 912 against 1 592 at 3), at 2 and 3 rounds the ladder's
  // counts agree within 2 %.
  int max_rounds = 3;
  // A round's CG stops at ‖r‖ ≤ forcing·‖r₀‖ (or the tolerance) while the face may still change,
  // and goes on to the tolerance once it holds. Forcing 0 (every face solved to the tolerance)
  // cost up to 1 400 CG steps in eight rounds on a 64-fibre RVE; 0.1 left the multipliers' signs
  // too rough to judge (that RVE's stagnation came back); 0.01 kept both.
  double forcing = 0.01;
  LinearOperator preconditioner;  // M⁻¹ (optional), as SMALBE's: symmetric, PSD
};

struct FaceWorkspace {
  Eigen::VectorXd free, r, z, p, Ap, c, v, x_start, m_start;
};

struct FaceResult {
  FaceOutcome outcome = FaceOutcome::refused;
  int rounds = 0;  // faces solved
  // face_solves 1 unless refused, face_steps the CG steps, operator_applications every
  // application of A (the CG steps and the fresh gradients), preconditioner_applications.
  Counters counters;
  bool non_finite = false;  // A or M⁻¹ produced NaN/Inf (x and m as they came)
};

// x feasible for l ≤ x ≤ u; A symmetric positive semidefinite. Converged: x feasible with
// Ĝ x = 0 to round-off, m = Ĝᵀμ and g = A x − b + m (a fresh gradient: the Lagrangian's).
// Otherwise x and m are as they came and g is scratch.
FaceResult solve_on_face(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
                         const Eigen::VectorXd& u, FaceProjector& projector, const FaceOptions& opts,
                         Eigen::VectorXd& x, Eigen::VectorXd& m, Eigen::VectorXd& g, FaceWorkspace& work);

}  // namespace dualcell::qp
