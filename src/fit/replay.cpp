// The exact law replayed through what the sweep recorded (docs/method.md §16a): its paths, its
// checks of the strain along the fibres and of the shear along them, each a tally of relative
// errors against the sweep's solves and of points whose broken pairs differ.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/error_tally.hpp"
#include "core/strain.hpp"
#include "fit/fit.hpp"

namespace dualcell::fit {

namespace {

// A step at load 0 is the unloaded cell, except on a path with shears along the fibres (the shear
// alone, its first step).
bool replayed(const sweep::Step& step) {
  return step.converged && (step.load != 0 || std::isfinite(step.shear_stress(0)));
}

// A replay's tally: its limit (1e3 × the sweep's QP tolerance), and per point its error, where it
// is and whether its breaks differ from the reference's.
// (A point the law has no answer at counts as +inf: the worst.)
class ReplayTally {
 public:
  explicit ReplayTally(double qp_tolerance) { replay_.limit = 1e3 * qp_tolerance; }
  void add(double error, int path, int step, bool breaks_differ) {
    if (errors_.add(error)) replay_.worst_path = path, replay_.worst_step = step;
    replay_.break_mismatches += breaks_differ ? 1 : 0;
  }
  law::CellReplay result() {
    replay_.points = errors_.count;
    replay_.max_error = errors_.count > 0 ? errors_.max : 0;
    replay_.rms_error = errors_.rms_error();
    return replay_;
  }

 private:
  law::CellReplay replay_;
  ErrorTally errors_;
};
}  // namespace

int replay_stride(const std::vector<sweep::PathResult>& paths, int rows, int checked_rows) {
  if (rows <= checked_rows) return 1;
  long points = 0;
  for (const auto& p : paths) points += std::count_if(p.steps.begin(), p.steps.end(), replayed);
  return static_cast<int>(std::max(1L, (points + max_replayed_points - 1) / max_replayed_points));
}

law::CellReplay replay_longitudinal(const law::CondensedCell& cell, const std::vector<sweep::LongitudinalPoint>& points,
                                    double qp_tolerance) {
  ReplayTally tally(qp_tolerance);
  law::CellEvaluator evaluator(cell);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const sweep::LongitudinalPoint& p = points[i];
    law::CellHistory history = evaluator.unloaded();
    const law::CellResponse r = evaluator.at(MacroState::stress(p.stress).hold(MacroState::zz, p.eps33), history);
    if (!r.ok)
      throw ExactLawFailed("not kept: its QP failed at the check of the strain along the fibres: " + r.message);
    Eigen::Vector3d expected = engineering_from_tensor(p.strain), strain = r.strain;
    if (cell.n_macro == 2) expected(2) = strain(2) = 0;
    const double error = std::max((strain - expected).norm() / (expected.norm() + std::abs(p.eps33)),
                                  std::abs(r.stress_zz - p.stress_zz) / (std::abs(p.stress_zz) + p.stress.norm()));
    tally.add(error, static_cast<int>(i), -1, r.broken != p.broken);
  }
  return tally.result();
}

law::CellReplay replay_shear(const law::CondensedCell& cell, const std::vector<sweep::ShearPoint>& points,
                             double qp_tolerance) {
  ReplayTally tally(qp_tolerance);
  law::CellEvaluator evaluator(cell);
  std::map<int, law::CellHistory> histories;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const sweep::ShearPoint& p = points[i];
    law::CellHistory& history = histories.try_emplace(p.path, evaluator.unloaded()).first->second;
    const law::CellResponse r = evaluator.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(p.gamma), history);
    if (!r.ok) throw ExactLawFailed("not kept: its QP failed at the check of the shear along the fibres: " + r.message);
    const double error = (r.shear_z - p.tau).norm() / p.tau.norm();
    tally.add(error, p.path, static_cast<int>(i), r.broken != p.broken);
  }
  return tally.result();
}

law::CellReplay replay_cell(const law::CondensedCell& cell, const std::vector<sweep::PathResult>& paths,
                            double qp_tolerance, int path_stride) {
  ReplayTally tally(qp_tolerance);
  law::CellEvaluator evaluator(cell);
  law::CellHistory history = evaluator.unloaded();
  for (std::size_t i = 0; i < paths.size(); i += static_cast<std::size_t>(std::max(1, path_stride))) {
    // Each path from the intact cell; the last active set stays as the warm start (the sweep's
    // neighbouring directions share most of it: the answer is the same, found in fewer steps).
    history.bonded = cell.bonded;
    for (std::size_t k = 0; k < paths[i].steps.size(); ++k) {
      const sweep::Step& step = paths[i].steps[k];
      const double eps33 = paths[i].spec.state.eps33();
      const Eigen::Vector2d gamma = paths[i].spec.state.gamma();
      const law::CellResponse r =
          evaluator.at(MacroState::stress(step.stress).hold(MacroState::zz, eps33).hold_shear(gamma), history);
      if (!r.ok)
        throw ExactLawFailed("not kept: its QP failed on the sweep's stress of path " + std::to_string(i) + ": " +
                             r.message);
      if (!replayed(step)) continue;
      Eigen::Vector3d expected = engineering_from_tensor(step.strain), strain = r.strain;
      if (cell.n_macro == 2) expected(2) = strain(2) = 0;  // no shear with the symmetry boundary
      // A path with a strain along the fibres: ε̄ against ε̄ and ε33 together, and σ33 too; with
      // shears along them ε̄ against ε̄ and Γ together, and ⟨τ⟩ against ⟨τ⟩ and σ̄ together.
      double error = (strain - expected).norm() / (expected.norm() + std::abs(eps33) + gamma.norm());
      if (eps33 != 0)
        error =
            std::max(error, std::abs(r.stress_zz - step.stress_zz) / (std::abs(step.stress_zz) + step.stress.norm()));
      if (!gamma.isZero(0))
        error =
            std::max(error, (r.shear_z - step.shear_stress).norm() / (step.shear_stress.norm() + step.stress.norm()));
      tally.add(error, static_cast<int>(i), static_cast<int>(k), r.broken != step.broken_bonds);
    }
  }
  return tally.result();
}

}  // namespace dualcell::fit
