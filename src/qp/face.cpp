// The face solve (qp/face.hpp; docs/method.md §7b).
#include "qp/face.hpp"

#include <algorithm>
#include <cmath>

#include "qp/bounds.hpp"

namespace dualcell::qp {

namespace {
// CG restarts from a fresh gradient when the recursively updated residual met the tolerance but
// the fresh one does not (round-off drift); beyond this many the face's CG ends at its budget.
constexpr int max_restarts = 3;
}  // namespace

FaceResult solve_on_face(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
                         const Eigen::VectorXd& u, FaceProjector& projector, const FaceOptions& opts,
                         Eigen::VectorXd& x, Eigen::VectorXd& m, Eigen::VectorXd& g, FaceWorkspace& work) {
  FaceResult result;
  const Eigen::Index n = b.size();
  Counters& counters = result.counters;
  const bool preconditioned = static_cast<bool>(opts.preconditioner);
  work.free.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) work.free(i) = l(i) < x(i) && x(i) < u(i) ? 1.0 : 0.0;
  work.x_start = x;
  work.m_start = m;

  // P_F v for v on F (zero off F): v − χ_F Ĝᵀ S⁺ Ĝ v.
  const auto project = [&](Eigen::VectorXd& v) {
    projector.solve_coarse(v, work.c);
    projector.apply_Gt(work.c, work.v);
    v -= work.free.cwiseProduct(work.v);
  };
  const auto fresh_gradient = [&]() {
    A(x, work.Ap);
    ++counters.operator_applications;
    g = work.Ap - b;
    return g.allFinite();
  };
  // r ← P_F χ_F g, z ← P_F χ_F M⁻¹ r (or r); returns rᵀz.
  const auto residuals = [&]() {
    work.r = work.free.cwiseProduct(g);
    project(work.r);
    if (!preconditioned) {
      work.z = work.r;
    } else {
      opts.preconditioner(work.r, work.z);
      ++counters.preconditioner_applications;
      work.z = work.free.cwiseProduct(work.z);
      project(work.z);
    }
    return work.r.dot(work.z);
  };
  // CG on the face from x until ‖r‖ ≤ max(tolerance, forcing·‖r₀‖) (r₀: the first residual);
  // true when that was met on a fresh gradient, and `tight` says whether it was the tolerance.
  bool tight = false;
  const auto minimise_on_face = [&](bool loose) {
    double target = opts.tolerance;
    for (int restart = 0; restart <= max_restarts; ++restart) {
      if (!fresh_gradient()) return false;
      double rz = residuals();
      if (restart == 0 && loose) target = std::max(opts.tolerance, opts.forcing * work.r.norm());
      tight = target == opts.tolerance;
      if (work.r.norm() <= target) return true;
      work.p = work.z;
      while (true) {
        if (counters.face_steps >= opts.max_steps) return false;
        A(work.p, work.Ap);
        ++counters.operator_applications;
        ++counters.face_steps;
        const double pAp = work.p.dot(work.Ap);
        // No curvature, or M⁻¹ not positive on the face: not a face CG can finish.
        if (!(pAp > 0.0) || !(rz > 0.0)) return false;
        // Along −p, as MPRGP steps: x ← x − ω p, g ← g − ω A p.
        const double omega = rz / pAp;
        x -= omega * work.p;
        g -= omega * work.Ap;
        const double rz_new = residuals();
        if (work.r.norm() <= 0.5 * target) break;  // confirmed on a fresh gradient
        work.p = work.z + (rz_new / rz) * work.p;
        rz = rz_new;
      }
    }
    return false;
  };

  // Primal–dual active-set rounds: minimise on the face (loosely while the face may still change);
  // components that leave the box are fixed on their bound, components on a bound whose
  // multiplier has the wrong sign are freed, and the face is solved again from there, until
  // neither happens and the face's minimum meets the tolerance.
  for (int round = 0; round < opts.max_rounds; ++round) {
    if (!projector.set_face(work.free)) {
      if (round == 0) return result;  // refused: nothing changed
      break;
    }
    // The nearest point of the face with Ĝ x = 0; it may leave the box, as CG's iterates may:
    // only the face's minimiser must stay inside.
    projector.solve_coarse(x, work.c);
    projector.apply_Gt(work.c, work.v);
    x -= work.free.cwiseProduct(work.v);
    counters.face_solves = 1;
    bool loose = true;
    long leaving = 0, entering = 0;
    bool converged = false;
    while (true) {
      converged = minimise_on_face(loose);
      if (!x.allFinite() || !g.allFinite()) {
        result.non_finite = true;
        x = work.x_start;
        m = work.m_start;
        return result;
      }
      leaving = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (work.free(i) == 0.0 || (l(i) < x(i) && x(i) < u(i))) continue;
        x(i) = std::clamp(x(i), l(i), u(i));
        work.free(i) = 0.0;
        ++leaving;
      }
      // μ = −S⁺ Ĝ_F g, m = Ĝᵀμ (of the face just solved; g is its gradient).
      work.r = -work.free.cwiseProduct(g);
      projector.solve_coarse(work.r, work.c);
      projector.apply_Gt(work.c, m);
      // Components on a bound whose multiplier has the wrong sign (the chopped gradient ψ of
      // g + m) enter F, when ψ is what keeps the face from meeting the tolerance.
      entering = 0;
      if (leaving == 0 && converged) {
        work.v = g + m;
        double psi_norm2 = 0;
        for (Eigen::Index i = 0; i < n; ++i) {
          work.z(i) = 0.0;
          if (work.free(i) != 0.0 || l(i) == u(i)) continue;
          work.z(i) = x(i) <= l(i) ? std::min(work.v(i), 0.0) : std::max(work.v(i), 0.0);
          psi_norm2 += work.z(i) * work.z(i);
        }
        if (psi_norm2 > opts.tolerance * opts.tolerance) {
          for (Eigen::Index i = 0; i < n; ++i) {
            if (work.z(i) == 0.0) continue;
            work.free(i) = 1.0;
            ++entering;
          }
        }
      }
      if (leaving > 0 || entering > 0 || !converged || tight) break;
      loose = false;  // the face holds: finish it
    }
    result.rounds = round + 1;
    if (converged && tight && leaving == 0 && entering == 0) {
      result.outcome = FaceOutcome::converged;
      g += m;
      return result;
    }
    if (!converged && leaving == 0) break;
  }
  // Not settled: x and m as they came, for SMALBE to go on from as if no face solve had run.
  x = work.x_start;
  m = work.m_start;
  result.outcome = FaceOutcome::unsettled;
  return result;
}

}  // namespace dualcell::qp
