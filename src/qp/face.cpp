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

// Free components that lie on or outside their bound are put on it and leave F; their count.
long fix_leaving(const Eigen::VectorXd& l, const Eigen::VectorXd& u, Eigen::VectorXd& x, Eigen::VectorXd& free) {
  long leaving = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (free(i) == 0.0 || (l(i) < x(i) && x(i) < u(i))) continue;
    x(i) = std::clamp(x(i), l(i), u(i));
    free(i) = 0.0;
    ++leaving;
  }
  return leaving;
}

// The chopped gradient ψ of the Lagrangian gradient g_L into psi; when ‖ψ‖ > tolerance, the
// components it pulls off their bound enter F. Their count.
long free_entering(const Eigen::VectorXd& x, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                   const Eigen::VectorXd& g_L, double tolerance, Eigen::VectorXd& psi, Eigen::VectorXd& free) {
  double psi_norm2 = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    psi(i) = 0.0;
    if (free(i) != 0.0 || l(i) == u(i)) continue;
    psi(i) = x(i) <= l(i) ? std::min(g_L(i), 0.0) : std::max(g_L(i), 0.0);
    psi_norm2 += psi(i) * psi(i);
  }
  if (psi_norm2 <= tolerance * tolerance) return 0;
  long entering = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (psi(i) == 0.0) continue;
    free(i) = 1.0;
    ++entering;
  }
  return entering;
}

// CG on the face F (work.free) with the projector P_F, counting into `counters`.
class FaceCg {
 public:
  FaceCg(const LinearOperator& A, const Eigen::VectorXd& b, FaceProjector& projector, const FaceOptions& opts,
         FaceWorkspace& work, Counters& counters)
      : A_(A), b_(b), projector_(projector), opts_(opts), work_(work), counters_(counters) {}

  // v ← v − χ_F Ĝᵀ S⁺ Ĝ v: P_F v for v on F; for any v, the nearest vector to it (off F
  // unchanged) with Ĝ v = 0.
  void project(Eigen::VectorXd& v) {
    projector_.solve_coarse(v, work_.c);
    projector_.apply_Gt(work_.c, work_.v);
    v -= work_.free.cwiseProduct(work_.v);
  }

  // From x until ‖r‖ ≤ max(tolerance, forcing·‖r₀‖) when loose (r₀ the first residual), else the
  // tolerance; true when that was met on a fresh gradient g, and `tight` says whether the target
  // was the tolerance.
  bool minimise(bool loose, Eigen::VectorXd& x, Eigen::VectorXd& g, bool& tight) {
    double target = opts_.tolerance;
    for (int restart = 0; restart <= max_restarts; ++restart) {
      A_(x, work_.Ap);
      ++counters_.operator_applications;
      g = work_.Ap - b_;
      if (!g.allFinite()) return false;
      double rz = residuals(g);
      if (restart == 0 && loose) target = std::max(opts_.tolerance, opts_.forcing * work_.r.norm());
      tight = target == opts_.tolerance;
      if (work_.r.norm() <= target) return true;
      work_.p = work_.z;
      while (true) {
        if (counters_.face_steps >= opts_.max_steps) return false;
        A_(work_.p, work_.Ap);
        ++counters_.operator_applications;
        ++counters_.face_steps;
        const double pAp = work_.p.dot(work_.Ap);
        // No curvature, or M⁻¹ not positive on the face: not a face CG can finish.
        if (!(pAp > 0.0) || !(rz > 0.0)) return false;
        // Along −p, as MPRGP steps: x ← x − ω p, g ← g − ω A p.
        const double omega = rz / pAp;
        x -= omega * work_.p;
        g -= omega * work_.Ap;
        const double rz_new = residuals(g);
        if (work_.r.norm() <= 0.5 * target) break;  // confirmed on a fresh gradient
        work_.p = work_.z + (rz_new / rz) * work_.p;
        rz = rz_new;
      }
    }
    return false;
  }

 private:
  // r ← P_F χ_F g, z ← P_F χ_F M⁻¹ r (or r); returns rᵀz.
  double residuals(const Eigen::VectorXd& g) {
    work_.r = work_.free.cwiseProduct(g);
    project(work_.r);
    if (!opts_.preconditioner) {
      work_.z = work_.r;
    } else {
      opts_.preconditioner(work_.r, work_.z);
      ++counters_.preconditioner_applications;
      work_.z = work_.free.cwiseProduct(work_.z);
      project(work_.z);
    }
    return work_.r.dot(work_.z);
  }

  const LinearOperator& A_;
  const Eigen::VectorXd& b_;
  FaceProjector& projector_;
  const FaceOptions& opts_;
  FaceWorkspace& work_;
  Counters& counters_;
};
}  // namespace

FaceResult solve_on_face(const LinearOperator& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
                         const Eigen::VectorXd& u, FaceProjector& projector, const FaceOptions& opts,
                         Eigen::VectorXd& x, Eigen::VectorXd& m, Eigen::VectorXd& g, FaceWorkspace& work) {
  FaceResult result;
  const Eigen::Index n = b.size();
  Counters& counters = result.counters;
  work.free.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) work.free(i) = l(i) < x(i) && x(i) < u(i) ? 1.0 : 0.0;
  work.x_start = x;
  work.m_start = m;

  FaceCg cg{A, b, projector, opts, work, counters};
  bool tight = false;

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
    cg.project(x);
    counters.face_solves = 1;
    bool loose = true;
    long leaving = 0, entering = 0;
    bool converged = false;
    while (true) {
      converged = cg.minimise(loose, x, g, tight);
      if (!x.allFinite() || !g.allFinite()) {
        result.non_finite = true;
        x = work.x_start;
        m = work.m_start;
        return result;
      }
      leaving = fix_leaving(l, u, x, work.free);
      // μ = −S⁺ Ĝ_F g, m = Ĝᵀμ (of the face just solved; g is its gradient).
      work.r = -work.free.cwiseProduct(g);
      projector.solve_coarse(work.r, work.c);
      projector.apply_Gt(work.c, m);
      work.v = g + m;
      entering = leaving == 0 && converged ? free_entering(x, l, u, work.v, opts.tolerance, work.z, work.free) : 0;
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
