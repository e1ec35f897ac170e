// MPRGP — Modified Proportioning with Reduced Gradient Projections.
//
// Solves   min f(x) = ½ xᵀA x - bᵀx   s.t.   l ≤ x ≤ u,   A symmetric positive semidefinite.
//
// The method: docs/method.md §7 (MPRGP, from the works of §18), with lower and upper bounds
// and the reduced free gradient φ̃.
//
// Definitions of φ, ψ (β in the papers), φ̃, gᴾ:
// qp/bounds.hpp. Step lengths are ω here (α in the papers; α is the rigid-body amplitude in
// this project, docs/method.md glossary).
//
// Every step is one of
//   x proportional, ‖ψ‖² ≤ Γ² φ̃ᵀφ (φ̃, not φ, on the right: the paper's test for ω̄-steps):
//     CG step          x ← x - ω_cg p, ω_cg = gᵀp / pᵀAp, if feasible (ω_cg ≤ ω_f);
//                      p ← z - ζ p, ζ = zᵀAp / pᵀAp
//     expansion step   x½ ← x - ω_f p (half step to the boundary),
//                      x ← P_Ω(x½ - ω̄ φ(x½)), g ← A x - b, p ← z
//   otherwise:
//     proportioning    x ← x - ω ψ, ω = min(ω_cg, ω_f), ω_cg = ‖ψ‖² / ψᵀAψ, p ← z
// with z = φ without a preconditioner. The proportioning step is capped by the feasible step
// ω_f along -ψ: with a box, releasing a component from one bound can carry it past the other,
// and the paper's lower-bound-only ω_cg would leave Ω. f is convex along -ψ with minimiser
// ω_cg, so any ω ≤ ω_cg still decreases f. All moves go through step_within_box, so every
// iterate is feasible up to the last bit.
//
// Preconditioning in face (optional; docs/method.md §7). With a preconditioner M⁻¹ ≈ A⁻¹
// (symmetric, positive definite on the free components) the CG directions are built from the
// preconditioned free gradient
//   z = χ_F ⊙ M⁻¹(χ_F ⊙ g) = χ_F ⊙ M⁻¹φ,   χ_F the indicator of the free set F,
// i.e. the restriction (M⁻¹)_FF of one fixed M⁻¹ to the face instead of the book's (M_FF)⁻¹,
// which would have to be rebuilt whenever F changes (approximate variants of this kind are
// studied in a work listed in docs/method.md §18).
// z, p and the steps vanish off F, so within a face this is PCG on
// min f(x - d), d_i = 0 off F, i.e. on A_FF d_F = g_F, with preconditioner (M⁻¹)_FF:
//   ζ = zᵀAp / pᵀAp makes the new p A-conjugate to the old one;
//   ω_cg = gᵀp / pᵀAp is the exact minimiser of f along -p. After an exact line search the new
//   gradient is orthogonal to the old p, so gᵀp = gᵀz - ζ gᵀp_old = gᵀz = φᵀz, and
//   ω_cg = φᵀz / pᵀAp is the textbook PCG step rᵀz_r / p_rᵀAp_r for the residual r = -φ
//   (z_r = -z, p_r = -p, x ← x + ω p_r). gᵀp is kept as the computed form: it stays the exact
//   minimiser when round-off erodes the orthogonality, and it is what the unpreconditioned
//   code computes.
// Without bounds and with M⁻¹ = A⁻¹: z = A⁻¹g, ω_cg = gᵀA⁻¹g / gᵀA⁻¹g = 1 and x - z = A⁻¹b,
// one step. The expansion step (fixed ω̄ along φ, projected), the proportioning step along ψ,
// the proportioning test and the stopping test on ‖gᴾ‖ stay unpreconditioned, as in the book,
// so the feasibility and monotonicity arguments are unchanged; the direction restarts (p ← z)
// whenever the free set may have changed (after expansion and proportioning steps and on a
// fresh gradient). Should z fail to be a descent direction (M⁻¹ not positive definite on the
// face), that step uses φ.
// The direction for the next CG-branch step is formed at its start (next_direction says whether
// to conjugate or restart), so a step that turns out to be proportioning, or the end of the
// solve, costs no application of M⁻¹: exactly one per CG or expansion step. Without a
// preconditioner this is the same arithmetic, bit for bit, as forming p right after each step.
//
// Symbol → variable
//   A, b, l, u, x       A, b, l, u, x
//   g = A x - b         work.g
//   φ, ψ                work.phi, work.psi
//   M⁻¹, z              opts.preconditioner, work.z (z is work.phi without M⁻¹)
//   φ̃ᵀφ, ‖gᴾ‖           split.phi_tilde_dot_phi, gP_norm
//   p, A p, pᵀAp        work.p, work.Ap, pAp (of the last CG step: pAp_last)
//   ω_cg, ω_f, ω̄        omega_cg, omega_f (FeasibleStep), omega_bar
//   ζ, Γ                zeta, opts.Gamma
//   ‖A‖, ε              norm_A, tolerance
#include "qp/mprgp.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "qp/bounds.hpp"

namespace dualcell::qp {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double epsilon = std::numeric_limits<double>::epsilon();
constexpr int power_iterations = 20;

// Stagnation test: a step makes progress when f drops by more than the round-off in computing
// it, or ‖gᴾ‖ reaches a new minimum. f = ½ xᵀ(g - b) reuses the gradient, so it costs two dots.
class ProgressMonitor {
 public:
  // Returns the number of consecutive steps without progress.
  long update(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& b, double gP_norm) {
    const double xg = x.dot(g);
    const double xb = x.dot(b);
    const double f = 0.5 * (xg - xb);
    const double noise = 16.0 * epsilon * (std::abs(xg) + std::abs(xb));
    if (f < best_f_ - noise || gP_norm < best_gP_) {
      steps_without_progress_ = 0;
    } else {
      ++steps_without_progress_;
    }
    best_f_ = std::min(best_f_, f);
    best_gP_ = std::min(best_gP_, gP_norm);
    return steps_without_progress_;
  }

 private:
  double best_f_ = infinity;
  double best_gP_ = infinity;
  long steps_without_progress_ = 0;
};

}  // namespace

std::string check_options(const MprgpOptions& opts) {
  if (!(opts.relative_tolerance >= 0.0) || !(opts.absolute_tolerance >= 0.0)) {
    return "tolerances must be non-negative";
  }
  if (opts.max_iterations < 0 || opts.stagnation_window < 0) {
    return "max_iterations and stagnation_window must be non-negative";
  }
  if (!(opts.Gamma > 0.0) || !std::isfinite(opts.Gamma)) {
    return "Gamma must be positive and finite";
  }
  if (!(opts.omega_bar_factor > 0.0 && opts.omega_bar_factor <= 2.0)) {
    return "omega_bar_factor must lie in (0, 2]";
  }
  if (!(opts.norm_A >= 0.0) || !std::isfinite(opts.norm_A)) {
    return "norm_A must be finite and non-negative (0 = estimate)";
  }
  return {};
}

Result mprgp(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
             Eigen::VectorXd& x, const MprgpOptions& opts) {
  MprgpWorkspace work;
  return mprgp(A, b, l, u, x, opts, StoppingTest{}, work);
}

Result mprgp(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
             Eigen::VectorXd& x, const MprgpOptions& opts, const StoppingTest& stop, MprgpWorkspace& work) {
  Result result;
  std::string problem = check_bound_problem(b, l, u, x);
  if (problem.empty()) {
    problem = check_options(opts);
  }
  if (!problem.empty()) {
    result.status = Status::invalid_input;
    result.message = "mprgp: " + problem;
    clear_residuals(result);
    return result;
  }

  const Eigen::Index n = b.size();
  const auto observe = [&](const Eigen::VectorXd& iterate) {
    if (opts.on_iterate) {
      opts.on_iterate(iterate);
    }
  };
  const auto fail_non_finite = [&](const char* where) {
    result.status = Status::non_finite;
    result.message = std::string("mprgp: the operator produced NaN/Inf in ") + where;
    clear_residuals(result);
    return result;
  };
  const auto fail_preconditioner = [&]() {
    result.status = Status::non_finite;
    result.message = "mprgp: the preconditioner produced NaN/Inf in M^-1 phi";
    clear_residuals(result);
    return result;
  };

  if (x.size() == 0) {
    x = Eigen::VectorXd::Zero(n);
  }
  project_onto_box(l, u, x);
  observe(x);
  work.g.resize(n);
  work.p.resize(n);
  work.Ap.resize(n);
  work.phi.resize(n);
  work.psi.resize(n);
  const bool preconditioned = static_cast<bool>(opts.preconditioner);
  if (preconditioned) {
    work.z.resize(n);
  }

  Counters& counters = result.counters;
  double norm_A = opts.norm_A;
  if (norm_A == 0.0) {
    norm_A = estimate_norm(A, n, power_iterations);
    counters.operator_applications += power_iterations;
    if (!std::isfinite(norm_A)) {
      return fail_non_finite("the norm estimate");
    }
  }
  // A = 0 leaves ω̄ free (2/‖A‖ = ∞); take ‖A‖ = 1 for it.
  const double omega_bar = opts.omega_bar_factor / (norm_A > 0.0 ? norm_A : 1.0);
  const double b_norm = b.norm();
  const double scale = b_norm > 0.0 ? b_norm : 1.0;
  const double tolerance = std::max(opts.absolute_tolerance, opts.relative_tolerance * scale);
  // Curvature dᵀA d at the round-off level of ‖A‖ ‖d‖² is treated as zero.
  const auto negligible_curvature = [&](double dAd, double d_norm2) {
    return dAd <= 64.0 * epsilon * norm_A * d_norm2;
  };
  // A d into work.Ap and the steps along d: to the first bound (ω_f) and to the minimum of f
  // along d, ω_cg = gᵀd / dᵀAd (+∞ where the curvature is negligible against ‖d‖² = d_norm2);
  // `finite` false when dᵀAd is not. The CG and the proportioning steps both take it.
  struct AlongDirection {
    bool finite = false;
    double curvature = 0;
    FeasibleStep omega_f{0, -1};
    double omega_cg = 0;
  };
  const auto along_direction = [&](const Eigen::VectorXd& d, double g_dot_d, double d_norm2) {
    AlongDirection out;
    A(d, work.Ap);
    ++counters.operator_applications;
    out.curvature = d.dot(work.Ap);
    if (!std::isfinite(out.curvature)) return out;
    out.finite = true;
    out.omega_f = max_feasible_step(x, d, l, u);
    out.omega_cg = negligible_curvature(out.curvature, d_norm2) ? infinity : g_dot_d / out.curvature;
    return out;
  };

  // g ← A x - b through work.Ap, so a failed application leaves g as it was.
  const auto recompute_gradient = [&]() {
    A(x, work.Ap);
    ++counters.operator_applications;
    if (!work.Ap.allFinite()) {
      return false;
    }
    work.g = work.Ap - b;
    return true;
  };

  // z ← χ_F ⊙ M⁻¹φ (φ = χ_F ⊙ g already); false if M⁻¹ produced NaN/Inf anywhere.
  const auto precondition_free_gradient = [&]() {
    opts.preconditioner(work.phi, work.z);
    ++counters.preconditioner_applications;
    if (!work.z.allFinite()) {
      return false;
    }
    restrict_to_free_set(x, l, u, work.z);
    return true;
  };

  if (!recompute_gradient()) {
    return fail_non_finite("A x at the initial guess");
  }
  bool gradient_is_fresh = true;
  GradientSplit split = split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
  double gP_norm = split.projected_norm();
  // How the next CG-branch step forms p: p ← z, or p ← z - ζ p after a CG step, whose
  // pᵀAp is kept in pAp_last and A p in work.Ap (untouched until that step's A p).
  enum class Direction { restart, conjugate };
  Direction next_direction = Direction::restart;
  double pAp_last = 0.0;

  ProgressMonitor progress;
  long steps_without_progress = 0;
  long steps = 0;
  // Why the loop ended, when not converged; formatted after the loop.
  const char* reason = "";
  while (true) {
    // gᴾ = 0 is an exact KKT point: no test can ask for more.
    const bool done = gP_norm == 0.0 || (stop ? stop(x, work.g, gP_norm) : gP_norm <= tolerance);
    const bool out_of_budget = steps >= opts.max_iterations;
    const bool stalled = opts.stagnation_window > 0 && steps_without_progress >= opts.stagnation_window;
    if ((done || out_of_budget || stalled) && !gradient_is_fresh) {
      // Decide on the true gradient, not the recursively updated one.
      if (!recompute_gradient()) {
        return fail_non_finite("A x");
      }
      gradient_is_fresh = true;
      split = split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
      gP_norm = split.projected_norm();
      next_direction = Direction::restart;
      continue;
    }
    if (done) {
      result.status = Status::converged;
      break;
    }
    if (out_of_budget) {
      result.status = Status::max_iterations;
      reason = "max_iterations reached";
      break;
    }
    if (stalled) {
      result.status = Status::stagnated;
      reason =
          "no progress in stagnation_window steps; the tolerance is below the "
          "attainable accuracy";
      break;
    }
    ++steps;

    if (split.psi_norm2 <= opts.Gamma * opts.Gamma * split.phi_tilde_dot_phi) {
      // Proportional: φ ≠ 0 here (φ = 0 would force ψ = 0, i.e. gᴾ = 0).
      const Eigen::VectorXd* z = &work.phi;
      if (preconditioned) {
        if (!precondition_free_gradient()) {
          return fail_preconditioner();
        }
        z = &work.z;
      }
      if (next_direction == Direction::conjugate) {
        const double zeta = z->dot(work.Ap) / pAp_last;
        work.p = *z - zeta * work.p;
      } else {
        work.p = *z;
      }
      double g_dot_p = work.g.dot(work.p);
      if (!(g_dot_p > 0.0) && preconditioned && next_direction == Direction::conjugate) {
        // Round-off made p a non-descent direction: restart PCG.
        work.p = work.z;
        g_dot_p = work.g.dot(work.p);
      }
      if (!(g_dot_p > 0.0)) {
        // Without M⁻¹: round-off made p a non-descent direction, restart CG. With M⁻¹: z is no
        // descent direction, M⁻¹ is not positive definite on this face; step along φ.
        work.p = work.phi;
        g_dot_p = split.phi_norm2;
      }
      const AlongDirection along = along_direction(work.p, g_dot_p, work.p.squaredNorm());
      if (!along.finite) return fail_non_finite("A p");
      const double pAp = along.curvature;
      const FeasibleStep omega_f = along.omega_f;
      const double omega_cg = along.omega_cg;

      if (omega_cg <= omega_f.omega) {
        step_within_box(omega_cg, work.p, omega_f, l, u, x);
        work.g -= omega_cg * work.Ap;
        gradient_is_fresh = false;
        split = split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
        pAp_last = pAp;
        next_direction = Direction::conjugate;
        ++counters.cg_steps;
      } else if (omega_f.omega == infinity) {
        result.status = Status::unbounded;
        reason =
            "f decreases without bound along a direction of zero curvature that no "
            "bound blocks";
        break;
      } else {
        step_within_box(omega_f.omega, work.p, omega_f, l, u, x);
        work.g -= omega_f.omega * work.Ap;
        observe(x);
        split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
        x -= omega_bar * work.phi;
        project_onto_box(l, u, x);
        if (!recompute_gradient()) {
          return fail_non_finite("A x after an expansion step");
        }
        gradient_is_fresh = true;
        split = split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
        next_direction = Direction::restart;
        ++counters.expansion_steps;
      }
    } else {
      // Proportioning along the chopped gradient ψ releases active components.
      const AlongDirection along = along_direction(work.psi, split.psi_norm2, split.psi_norm2);
      if (!along.finite) return fail_non_finite("A psi");
      const FeasibleStep omega_f = along.omega_f;
      const double omega_cg = along.omega_cg;
      const double omega = std::min(omega_cg, omega_f.omega);
      if (omega == infinity) {
        result.status = Status::unbounded;
        reason = "f decreases without bound along a released component";
        break;
      }
      step_within_box(omega, work.psi, omega_f, l, u, x);
      work.g -= omega * work.Ap;
      gradient_is_fresh = false;
      split = split_gradient(x, work.g, l, u, omega_bar, work.phi, work.psi);
      next_direction = Direction::restart;
      ++counters.proportioning_steps;
    }
    observe(x);
    gP_norm = split.projected_norm();
    steps_without_progress = progress.update(x, work.g, b, gP_norm);
  }

  if (!gradient_is_fresh && !recompute_gradient()) {
    return fail_non_finite("A x at the returned point");
  }
  fill_bound_residuals(x, work.g, l, u, scale, result);
  result.equality_residual = 0.0;
  if (result.status != Status::converged) {
    std::ostringstream message;
    message << "mprgp: " << reason << " after " << steps << " steps; ||gP|| = " << result.projected_gradient_norm
            << ", tolerance = " << tolerance;
    result.message = message.str();
  }
  return result;
}

}  // namespace dualcell::qp
