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

law::CellReplay replay_expansion(const law::CondensedCell& cell, const law::PlyExpansion& solved, double qp_tolerance) {
  ReplayTally tally(qp_tolerance);
  law::CellEvaluator evaluator(cell);
  law::CellHistory history = evaluator.unloaded();
  const law::CellResponse r =
      evaluator.at(MacroState::ply_strain(Eigen::Matrix<double, 6, 1>::Zero()).hold(MacroState::dT, 1.0), history,
                   law::BondMode::lifted);
  if (!r.ok) throw ExactLawFailed("not kept: its QP failed at the check of the temperature change: " + r.message);
  // The components the cell has, in (εxx, εyy, γxy, ε33): γxy not on the symmetry boundary.
  std::vector<int> k = {0, 1, 3};
  if (cell.n_macro == 3) k = {0, 1, 2, 3};
  const Eigen::Matrix<double, 6, 6> D = law::ply_tangent(r);
  const Eigen::Matrix<double, 6, 1> sigma = law::ply_stress(r);
  const Eigen::Vector4d all_solved(solved.alpha2, solved.alpha3, solved.alpha23, solved.alpha1);
  const auto n = static_cast<Eigen::Index>(k.size());
  Eigen::MatrixXd C(n, n);
  Eigen::VectorXd s(n), expected(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    s(i) = sigma(k[i]);
    expected(i) = all_solved(k[i]);
    for (Eigen::Index j = 0; j < n; ++j) C(i, j) = D(k[i], k[j]);
  }
  const Eigen::VectorXd alpha = -C.fullPivLu().solve(s);
  tally.add((alpha - expected).norm() / expected.norm(), 0, -1, false);
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
