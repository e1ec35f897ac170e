// SMALBE-M — SemiMonotonic Augmented Lagrangian for Bound and Equality constraints, variant with
// adaptive precision ξ (M in the book of docs/method.md §18; here M⁻¹ is the preconditioner), plus a bounded
// penalty growth safeguard.
//
// Solves   min f(x) = ½ xᵀA x - bᵀx   s.t.   Q x = 0,   l ≤ x ≤ u,
// with Q = Ĝᵀ Ĝ (Ĝ orthonormal rows) the orthogonal projector onto Im Ĝᵀ, so Qx = 0 ⇔ Ĝx = 0
// and ‖Q x‖ = ‖Ĝ x‖. In FETI: A = PFP, P = I - Q, which makes the spectrum of A + ρQ on Im Q
// equal to ρ, so ρ up to ‖A‖ costs the inner solver nothing.
//
// The method: docs/method.md §7 (SMALBE, its source in §18; SMALBE-M
// keeps ρ and adapts ξ). The multiplier μ of Ĝx = 0 is kept as m = Ĝᵀμ ∈ Im Q, so
//   L(x, m, ρ) = ½ xᵀA x - bᵀx + mᵀx + ρ/2 xᵀQ x = ½ xᵀ(A + ρQ) x - (b - m)ᵀx,
//   ∇ₓL = A x - b + m + ρ Q x.
// Outer iteration k:
//   1. inner MPRGP on A + ρQ, right side b - m, from the previous x, until
//        ‖gᴾ‖ ≤ min(ξ ‖Qx‖, η)   or ‖gᴾ‖ ≤ ε_g (the outer gradient tolerance);
//   2. m ← m + ρ Q x   (then A x - b + m is the gradient the inner solver just reduced);
//   3. stop if ‖gᴾ‖ ≤ ε_g and ‖A‖‖Qx‖ ≤ ε_e;
//   4. if k > 0 and L(x_k, m_k, ρ) < L(x_{k-1}, m_{k-1}, ρ) + ρ/2 ‖Q x_k‖² (beyond round-off),
//      then ξ ← ξ/c_ξ;
//   5. safeguard: if the inner solve converged and ‖Q x_k‖ > r_Q ‖Q x_{k-1}‖ in rho_patience
//      consecutive outer iterations, then ρ ← min(c_ρ ρ, ρ_max), and the bound ‖A + ρQ‖ grows
//      by the same amount.
// Why step 5: with ρ fixed the multiplier iteration contracts like 1/(1 + ρτ), τ the smallest
// eigenvalue of the dual Schur complement on the free set; when the active set leaves Ĝ little
// room on the free components, τ is small. On the seeded test problems plain SMALBE-M needed
// more than 100 outer iterations on 4–8 of 67 problems (tolerances 1e-6 to 1e-10); with the
// safeguard none needed more than 41, with fewer operator applications in total. ρ_max caps
// the price, κ(A + ρQ) ≤ (ρ_max/‖A‖)·κ(A on ker Ĝ).
//
// Preconditioning (optional). Given M⁻¹, a preconditioner of A on Im(I - Q) (in FETI
// P M⁻¹_F P with P = I - Q and M⁻¹_F a preconditioner of F, so zero on Im Q), the inner MPRGP is
// preconditioned in face (mprgp.cpp) by the preconditioner of A + ρQ
//   M⁻¹_ρ = M⁻¹ + Q/ρ,   z = M⁻¹_ρ v = M⁻¹v + (Q v)/ρ,
// with the current ρ (captured by reference: the safeguard of step 5 changes it). Why: with
// A Q = Q A = 0 and P Q = Q P = 0,
//   (P M⁻¹_F P + Q/ρ)(A + ρQ) = P M⁻¹_F P A + P M⁻¹_F P Q ρ + Q A/ρ + Q² = P M⁻¹_F P A + Q,
// so the Im Q part is preconditioned exactly, whatever ρ, and only P M⁻¹_F P A on Im P is left
// to the quality of M⁻¹_F. M⁻¹_ρ is symmetric positive definite when M⁻¹ is positive
// semidefinite and definite on Im(I - Q). In the face F the inner solver uses (M⁻¹_ρ)_FF, which
// is then positive definite as well.
//
// Symbol → variable
//   A, Q, b, l, u, x    A, Q, b, l, u, x
//   m = Ĝᵀμ             m
//   ρ, ξ, η, c_ξ        rho, xi, eta, opts.xi_reduction
//   c_ρ, r_Q, ρ_max     opts.rho_growth, opts.feasibility_reduction, rho_max
//   b - m               b_minus_m
//   Q x, ‖Q x‖          Qx, Qx_norm (Qx_norm_previous for k - 1)
//   L(x_k, m_k, ρ)      lagrangian, lagrangian_previous
//   ε_g, ε_e            tolerance_g, tolerance_e
//   M⁻¹, M⁻¹_ρ          opts.preconditioner, inner.preconditioner
#include "qp/smalbe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "qp/bounds.hpp"

namespace dualcell::qp {

namespace {
constexpr int power_iterations = 20;
constexpr double epsilon = std::numeric_limits<double>::epsilon();

// SMALBE's side of the face solve (qp/face.hpp): when a face is due, and what is kept of it.
class FaceFinish {
 public:
  struct Outcome {
    bool non_finite = false;
    bool converged_face = false;  // the face solve converged (gP_norm, Qx_norm are its)
    bool passed = false;          // and its point passes SMALBE's stopping test: the solve ends
    double gP_norm = 0, Qx_norm = 0;
  };
  FaceFinish(const SmalbeOptions& opts, Eigen::Index n, double tolerance_g)
      : projector_(*opts.face_projector),
        max_changes_(opts.face_changes),
        max_applications_(opts.max_operator_applications),
        where_(n, -1) {
    options_.tolerance = 0.5 * tolerance_g;
    options_.preconditioner = opts.preconditioner;
  }
  // After outer iteration k: a face is due when the inner solve converged with at most
  // face_changes components changed between free, at l and at u since the previous outer
  // iteration, no face ran on this active set yet, and fewer than max_failures faces failed.
  bool due(long k, Status inner, const Eigen::VectorXd& x, const Eigen::VectorXd& l, const Eigen::VectorXd& u) {
    long changes = 0;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      const signed char w = x(i) <= l(i) ? 1 : x(i) >= u(i) ? 2 : 0;
      changes += w != where_[i];
      where_[i] = w;
    }
    if (changes > 0) tried_ = false;
    return k > 0 && changes <= max_changes_ && !tried_ && failures_ < max_failures && inner == Status::converged;
  }
  // One face solve from x, m. A face that converges but misses SMALBE's test (its S is
  // regularised, so Q x is only as small as S's conditioning allows) gives x and m back as
  // they were; Qx holds Q x of the face's point when it converged.
  Outcome attempt(const LinearOperator& A, const LinearOperator& Q, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
                  const Eigen::VectorXd& u, Eigen::VectorXd& x, Eigen::VectorXd& m, Eigen::VectorXd& Qx,
                  double tolerance_g, double tolerance_e, Counters& counters) {
    tried_ = true;
    // A face solve may cost at most half of what the solve has cost so far: one that does not
    // settle is paid for and forgotten (x and m come back unchanged).
    options_.max_steps =
        std::min(counters.operator_applications / 2, max_applications_ - counters.operator_applications);
    const FaceResult face = solve_on_face(A, b, l, u, projector_, options_, x, m, g_, work_);
    counters += face.counters;
    Outcome out;
    out.non_finite = face.non_finite;
    if (face.non_finite) return out;
    if (face.outcome == FaceOutcome::converged) {
      Q(x, Qx);
      out.converged_face = true;
      out.Qx_norm = Qx.norm();
      out.gP_norm = projected_gradient_norm(x, g_, l, u);
      out.passed = out.gP_norm <= tolerance_g && out.Qx_norm <= tolerance_e;
      if (!out.passed) {
        x = work_.x_start;
        m = work_.m_start;
      }
    }
    if (!out.passed && face.outcome != FaceOutcome::refused) ++failures_;
    return out;
  }
  // The Lagrangian gradient at the face's point, after an attempt that passed.
  const Eigen::VectorXd& gradient() const { return g_; }

 private:
  // After this many faces that did not end the solve none is tried again. On the stability
  // matrix a stiff cell (E_f/E_m = 1e6, bonds of strength 1e-6) met its face's test but not
  // SMALBE's every other outer iteration, 200 of them, where without faces it converged in 39;
  // the ladder's solves need at most one failed face before the one that ends it.
  static constexpr int max_failures = 2;
  FaceProjector& projector_;
  long max_changes_, max_applications_;
  std::vector<signed char> where_;  // per component after the previous outer iteration: 0 free, 1 at l, 2 at u
  bool tried_ = false;              // a face already ran on this active set
  int failures_ = 0;
  FaceOptions options_;
  FaceWorkspace work_;
  Eigen::VectorXd g_;
};

}  // namespace

std::string check_options(const SmalbeOptions& opts) {
  if (!(opts.relative_tolerance >= 0.0) || !(opts.equality_tolerance >= 0.0)) {
    return "tolerances must be non-negative";
  }
  if (opts.max_outer_iterations < 0 || opts.max_operator_applications < 0) {
    return "max_outer_iterations and max_operator_applications must be non-negative";
  }
  if (!(opts.rho0_factor > 0.0) || !std::isfinite(opts.rho0_factor)) {
    return "rho0_factor must be positive and finite";
  }
  if (!(opts.eta_factor > 0.0) || !std::isfinite(opts.eta_factor)) {
    return "eta_factor must be positive and finite";
  }
  if (!(opts.xi0 > 0.0) || !std::isfinite(opts.xi0)) {
    return "xi0 must be positive and finite";
  }
  if (!(opts.xi_reduction > 1.0) || !std::isfinite(opts.xi_reduction)) {
    return "xi_reduction must be finite and greater than 1";
  }
  if (opts.rho_patience < 1) {
    return "rho_patience must be at least 1";
  }
  if (!(opts.rho_growth >= 1.0) || !std::isfinite(opts.rho_growth) || !(opts.feasibility_reduction > 0.0) ||
      !(opts.rho_max_factor > 0.0) || !std::isfinite(opts.rho_max_factor)) {
    return "rho_growth must be finite and ≥ 1, feasibility_reduction and rho_max_factor "
           "positive";
  }
  if (opts.inner.preconditioner) {
    return "inner.preconditioner must be empty: smalbe builds it from preconditioner";
  }
  const std::string inner = check_options(opts.inner);
  return inner.empty() ? inner : "inner: " + inner;
}

Result smalbe(const LinearOperator& A, const LinearOperator& Q, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
              const Eigen::VectorXd& u, Eigen::VectorXd& x, const SmalbeOptions& opts) {
  Eigen::VectorXd m;
  return smalbe(A, Q, b, l, u, x, m, opts);
}

Result smalbe(const LinearOperator& A, const LinearOperator& Q, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
              const Eigen::VectorXd& u, Eigen::VectorXd& x, Eigen::VectorXd& m, const SmalbeOptions& opts) {
  Result result;
  const Eigen::Index n = b.size();
  std::string problem = check_bound_problem(b, l, u, x);
  if (problem.empty() && m.size() != 0 && (m.size() != n || !m.allFinite())) {
    problem = "the initial multiplier m must be empty or finite with b's size";
  }
  if (problem.empty()) {
    problem = check_options(opts);
  }
  if (!problem.empty()) {
    result.status = Status::invalid_input;
    result.message = "smalbe: " + problem;
    clear_residuals(result);
    return result;
  }
  const auto fail_non_finite = [&](const std::string& where) {
    result.status = Status::non_finite;
    result.message = "smalbe: NaN/Inf in " + where;
    clear_residuals(result);
    return result;
  };

  if (x.size() == 0) {
    x = Eigen::VectorXd::Zero(n);
  }
  project_onto_box(l, u, x);
  if (m.size() == 0) {
    m = Eigen::VectorXd::Zero(n);
  }
  Eigen::VectorXd Qx(n);
  Eigen::VectorXd Qv(n);
  Eigen::VectorXd b_minus_m(n);
  MprgpWorkspace work;

  Counters& counters = result.counters;
  double norm_A = opts.inner.norm_A;
  if (norm_A == 0.0) {
    norm_A = estimate_norm(A, n, power_iterations);
    counters.operator_applications += power_iterations;
    if (!std::isfinite(norm_A)) {
      return fail_non_finite("the estimate of ||A||");
    }
  }
  // A = 0 gives no scale; take 1.
  const double scale_A = norm_A > 0.0 ? norm_A : 1.0;
  double rho = opts.rho0_factor * scale_A;
  const double rho_max = std::max(rho, opts.rho_max_factor * scale_A);

  // The inner operator A + ρQ; each application is one application of the caller's A.
  const LinearOperator A_plus_rho_Q = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    if (opts.A_plus_shifted_Q) {
      opts.A_plus_shifted_Q(v, rho, y);
      return;
    }
    A(v, y);
    Q(v, Qv);
    y += rho * Qv;
  };
  MprgpOptions inner = opts.inner;
  if (opts.preconditioner) {
    // M⁻¹_ρ = M⁻¹ + Q/ρ with the current ρ (by reference). Qv is shared with A_plus_rho_Q: the
    // two are never applied at the same time.
    inner.preconditioner = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      if (opts.preconditioner_plus_shifted_Q) {
        opts.preconditioner_plus_shifted_Q(v, 1 / rho, y);
        return;
      }
      opts.preconditioner(v, y);
      Q(v, Qv);
      y += Qv / rho;
    };
  }
  if (opts.projected_operator) {
    inner.norm_A = std::max(norm_A, rho);
  } else {
    inner.norm_A = estimate_norm(A_plus_rho_Q, n, power_iterations);
    counters.operator_applications += power_iterations;
  }
  if (!std::isfinite(inner.norm_A)) {
    return fail_non_finite("the estimate of ||A + rho Q||");
  }
  Q(m, Qv);
  if (!Qv.allFinite()) {
    return fail_non_finite("Q m");
  }
  m = Qv;

  const double b_norm = b.norm();
  const double scale = b_norm > 0.0 ? b_norm : 1.0;
  const double tolerance_g = opts.relative_tolerance * scale;
  const double tolerance_e = opts.equality_tolerance * scale / scale_A;
  const double eta = opts.eta_factor * scale;
  double xi = opts.xi0 * scale_A;

  // Inner test: ‖gᴾ‖ ≤ min(ξ‖Qx‖, η), or ‖gᴾ‖ ≤ ε_g. The second ends an inner solve that has
  // reached the gradient accuracy the outer test asks for: what is left is feasibility, which
  // only the update of m improves (if ‖A‖‖Qx‖ ≤ ε_e too, the outer test holds). Without it, a
  // nearly feasible x (‖Qx‖ just above ε_e) asked for ‖gᴾ‖ ≤ ξ‖Qx‖, orders of magnitude below
  // ε_g and below the attainable accuracy: on the contact ladder's 64-fibre RVE the inner
  // solver stagnated there (exit 4), on the 36-fibre one it spent 13 % of its F applications
  // (tools/bench_contact.py; docs/method.md §7). Q x is formed only when ε_g < ‖gᴾ‖ ≤ η.
  bool non_finite_in_stop = false;
  const StoppingTest inner_stop = [&](const Eigen::VectorXd& x_inner, const Eigen::VectorXd&, double gP_norm) {
    if (gP_norm <= tolerance_g) {
      return true;
    }
    if (gP_norm > eta) {
      return false;
    }
    Q(x_inner, Qx);
    const double Qx_norm = Qx.norm();
    if (!std::isfinite(Qx_norm)) {
      // Ends the inner solve; reported after it, as NaN/Inf anywhere else is.
      non_finite_in_stop = true;
      return true;
    }
    return gP_norm <= xi * Qx_norm;
  };

  std::optional<FaceFinish> face;
  if (opts.face_projector) face.emplace(opts, n, tolerance_g);

  double lagrangian_previous = 0.0;
  double Qx_norm_previous = 0.0;
  long slow_iterations = 0;  // consecutive outer iterations with too little feasibility gain
  double Qx_norm = 0.0;
  std::ostringstream message;
  for (long k = 0;; ++k) {
    const long budget = opts.max_operator_applications - counters.operator_applications;
    if (k >= opts.max_outer_iterations || budget <= 0) {
      result.status = Status::max_iterations;
      message << "smalbe: " << (budget <= 0 ? "max_operator_applications = " : "max_outer_iterations = ")
              << (budget <= 0 ? opts.max_operator_applications : opts.max_outer_iterations) << " reached";
      break;
    }
    inner.max_iterations = std::min(opts.inner.max_iterations, budget);
    b_minus_m = b - m;
    const Result inner_result = mprgp(A_plus_rho_Q, b_minus_m, l, u, x, inner, inner_stop, work);
    counters += inner_result.counters;  // MPRGP counts no outer iterations
    counters.outer_iterations = k + 1;
    if (non_finite_in_stop) {
      return fail_non_finite("Q x in the inner stopping test");
    }
    if (inner_result.status == Status::non_finite || inner_result.status == Status::invalid_input) {
      result.status = inner_result.status;
      result.message = "smalbe: outer iteration " + std::to_string(k) + ": " + inner_result.message;
      result.rho_final = rho;
      clear_residuals(result);
      return result;
    }

    Q(x, Qx);
    Qx_norm = Qx.norm();
    if (!std::isfinite(Qx_norm)) {
      return fail_non_finite("Q x");
    }
    const double gP_norm = inner_result.projected_gradient_norm;
    // L = ½ xᵀ(A + ρQ)x - (b - m)ᵀx = ½ xᵀ(g - (b - m)) with the fresh inner gradient g.
    const double lagrangian = 0.5 * x.dot(work.g - b_minus_m);
    m += rho * Qx;
    if (opts.on_outer)
      opts.on_outer(
          {counters.outer_iterations, gP_norm / scale, Qx_norm * scale_A / scale, counters.operator_applications, rho});

    if (gP_norm <= tolerance_g && Qx_norm <= tolerance_e) {
      result.status = Status::converged;
      break;
    }
    if (inner_result.status == Status::stagnated || inner_result.status == Status::unbounded) {
      result.status = inner_result.status;
      message << "smalbe: outer iteration " << k << ": " << inner_result.message;
      break;
    }
    if (face && face->due(k, inner_result.status, x, l, u)) {
      const FaceFinish::Outcome f = face->attempt(A, Q, b, l, u, x, m, Qx, tolerance_g, tolerance_e, counters);
      if (f.non_finite) return fail_non_finite("the face solve");
      if (f.converged_face && opts.on_outer)
        opts.on_outer({counters.outer_iterations, f.gP_norm / scale, f.Qx_norm * scale_A / scale,
                       counters.operator_applications, rho});
      if (f.passed) {
        Qx_norm = f.Qx_norm;
        work.g = face->gradient();
        result.status = Status::converged;
        break;
      }
    }
    // A shortfall within the round-off of L is no evidence: ξ is not decreased for it.
    const double shortfall = lagrangian_previous + 0.5 * rho * Qx_norm * Qx_norm - lagrangian;
    const double noise = 16.0 * epsilon * (std::abs(lagrangian) + std::abs(lagrangian_previous));
    if (k > 0 && shortfall > noise) {
      xi /= opts.xi_reduction;
    }
    lagrangian_previous = lagrangian;
    const bool slow =
        inner_result.status == Status::converged && k > 0 && Qx_norm > opts.feasibility_reduction * Qx_norm_previous;
    slow_iterations = slow ? slow_iterations + 1 : 0;
    if (slow && rho < rho_max && slow_iterations >= opts.rho_patience) {
      const double rho_new = std::min(opts.rho_growth * rho, rho_max);
      // ‖A + ρ'Q‖ ≤ ‖A + ρQ‖ + (ρ' - ρ) since ‖Q‖ = 1; exactly max(‖A‖, ρ') when A Q = 0.
      inner.norm_A = opts.projected_operator ? std::max(norm_A, rho_new) : inner.norm_A + rho_new - rho;
      rho = rho_new;
      slow_iterations = 0;  // the next growth waits for its own rho_patience slow iterations
    }
    Qx_norm_previous = Qx_norm;
  }

  // After the update of m, work.g = A x - b + m_old + ρQx = A x - b + m: the Lagrangian gradient.
  if (counters.outer_iterations == 0) {
    // No inner solve ran (zero budget): evaluate the residuals once.
    work.g.resize(n);
    A(x, work.g);
    ++counters.operator_applications;
    work.g += m - b;
    Q(x, Qx);
    Qx_norm = Qx.norm();
    if (!work.g.allFinite() || !std::isfinite(Qx_norm)) {
      return fail_non_finite("A x at the initial guess");
    }
  }
  fill_bound_residuals(x, work.g, l, u, scale, result);
  result.equality_residual = Qx_norm;
  result.rho_final = rho;
  if (result.status != Status::converged) {
    message << "; ||gP|| = " << result.projected_gradient_norm << " (tolerance " << tolerance_g
            << "), ||Qx|| = " << Qx_norm << " (tolerance " << tolerance_e << ")";
    result.message = message.str();
  }
  return result;
}

}  // namespace dualcell::qp
