#include "fit/small_ply.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "core/error_tally.hpp"
#include "fit/levenberg_marquardt.hpp"

namespace dualcell::fit {

bool small_ply_residuals(const law::CondensedCell& small, const Eigen::VectorXd& y,
                         const std::vector<law::Vector6d>& strain, const std::vector<law::Vector6d>& stress,
                         Eigen::VectorXd& f, Eigen::MatrixXd* J) {
  law::CondensedCell cell = small;
  cell.y33 = y;
  const int m = cell.n_rows(), n = cell.n_macro;
  const Eigen::MatrixXd C0 = cell.S0.inverse();
  const Eigen::MatrixXd D = cell.Y * C0;                                              // D = Y C₀
  const Eigen::MatrixXd M = cell.H - cell.Y * C0 * cell.Y.transpose() / cell.volume;  // M = H − Y C₀ Yᵀ/|Ω|
  const Eigen::VectorXd A33 = cell.A33.col(0);
  law::CellEvaluator evaluator(cell);
  law::CellHistory history = evaluator.unloaded();
  const int points = static_cast<int>(strain.size());
  f.resize(4 * points);
  if (J) J->setZero(4 * points, m);
  for (int i = 0; i < points; ++i) {
    const law::Vector6d& e = strain[static_cast<std::size_t>(i)];
    const law::CellResponse r = evaluator.at(MacroState::strain(e.head<3>()).hold(MacroState::zz, e(3)), history);
    if (!r.ok) return false;
    const double scale = stress[static_cast<std::size_t>(i)].norm();
    f.segment<3>(4 * i) = (r.stress - stress[static_cast<std::size_t>(i)].head<3>()) / scale;
    f(4 * i + 3) = (r.stress_zz - stress[static_cast<std::size_t>(i)](3)) / scale;
    if (!J) continue;
    std::vector<int> free;
    for (int j = 0; j < m; ++j)
      if (r.forces(j) > 0) free.push_back(j);
    const int k = static_cast<int>(free.size());
    if (k == 0) continue;
    Eigen::MatrixXd M_FF(k, k), D_F(k, n);
    Eigen::VectorXd mu_F(k), y_F(k);
    for (int a = 0; a < k; ++a) {
      D_F.row(a) = D.row(free[a]);
      mu_F(a) = r.forces(free[a]);
      y_F(a) = y(free[a]);
      for (int b = 0; b < k; ++b) M_FF(a, b) = M(free[a], free[b]);
    }
    const Eigen::MatrixXd W = e(3) * M_FF.llt().solve(Eigen::MatrixXd::Identity(k, k));
    const Eigen::MatrixXd dsigma = D_F.transpose() * W / cell.volume;  // n × k
    const Eigen::RowVectorXd dzz =
        -A33.transpose() * dsigma + (mu_F + W * y_F).transpose() / cell.volume;  // W symmetric
    for (int a = 0; a < k; ++a) {
      J->block(4 * i, free[a], n, 1) = dsigma.col(a) / scale;
      (*J)(4 * i + 3, free[a]) = dzz(a) / scale;
    }
  }
  return true;
}

SmallPlyFit fit_small_ply(law::CondensedCell& small, const law::CondensedCell& cell,
                          const std::vector<law::Vector6d>& strain, const std::vector<law::Vector6d>& stress) {
  SmallPlyFit out;
  out.points = static_cast<int>(strain.size());
  if (cell.longitudinal != 1 || cell.shear != 2 || small.G.rows() != 0 || small.adhesion()) {
    out.message = "the cell does not carry the whole ply, or the small cell is not one of contact rows";
    return out;
  }
  const int m = small.n_rows();
  small.shear = 2;
  small.D0z = cell.D0z;
  small.longitudinal = 1;
  small.A33 = cell.A33;
  small.C33 = cell.C33;
  small.y33 = Eigen::MatrixXd::Zero(m, 1);
  if (out.points == 0) {
    out.message = "no points of the exact law to fit the strain along the fibres to";
    return out;
  }
  // The one Levenberg–Marquardt (fit/levenberg_marquardt.hpp), from y33 = 0, until a step lowers
  // the cost by less than 1e-12 of it.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(m);
  const LmEnd end =
      levenberg_marquardt([&](const Eigen::VectorXd& at, Eigen::VectorXd& f,
                              Eigen::MatrixXd* J) { return small_ply_residuals(small, at, strain, stress, f, J); },
                          4 * static_cast<Eigen::Index>(strain.size()), y,
                          {.max_iterations = 100, .quiet_steps = 1, .quiet_fraction = 1e-12});
  if (!end.evaluated) {
    out.message = "the small cell could not be evaluated at the exact law's points";
    return out;
  }
  out.iterations = end.iterations;
  small.y33 = y;
  // The six stresses' error at each point (the shears along the fibres are D0z Γ, not fitted).
  law::CellEvaluator evaluator(small);
  law::CellHistory history = evaluator.unloaded();
  ErrorTally tally;
  for (int i = 0; i < out.points; ++i) {
    const law::Vector6d& e = strain[static_cast<std::size_t>(i)];
    const law::CellResponse r = evaluator.at(MacroState::ply_strain(e), history);
    const law::Vector6d& target = stress[static_cast<std::size_t>(i)];
    tally.add(r.ok ? (law::ply_stress(r) - target).norm() / target.norm() : std::numeric_limits<double>::infinity());
  }
  out.training_max_error = tally.max_error();
  out.training_rms_error = tally.rms_error();
  out.ok = true;
  return out;
}

}  // namespace dualcell::fit
