#include "law/ply_sample.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/error_tally.hpp"
#include "law/cone_check.hpp"

namespace dualcell::law {

namespace {

// A standard normal number from two raw draws of the generator (Box–Muller on uniforms built
// from its bits): the generator's output is fixed by the standard, std::normal_distribution's
// is not, and a sample must be the same on every machine.
double normal(std::mt19937_64& generator) {
  const auto uniform = [&] { return (static_cast<double>(generator() >> 11) + 0.5) * 0x1.0p-53; };
  const double u = uniform(), v = uniform();
  return std::sqrt(-2 * std::log(u)) * std::cos(2 * std::numbers::pi * v);
}

}  // namespace

Matrix6d open_ply_stiffness(const CondensedCell& cell) {
  // σ̄ = C₀(ε̄ − A33 ε33), σ33 = −A33·σ̄ + C33 ε33, τ = D0z Γ.
  const Eigen::Matrix3d C0 = cell.S0.inverse();
  const Eigen::Vector3d A33 = cell.A33.col(0);
  Matrix6d C = Matrix6d::Zero();
  C.topLeftCorner<3, 3>() = C0;
  C.block<3, 1>(0, 3) = -C0 * A33;
  C.block<1, 3>(3, 0) = -(C0 * A33).transpose();
  C(3, 3) = A33.dot(C0 * A33) + cell.C33(0, 0);
  C.bottomRightCorner<2, 2>() = cell.D0z;
  return C;
}

PlySample sample_ply(const CondensedCell& cell, int n, unsigned seed) {
  PlySample sample;
  const Matrix6d S_o = open_ply_stiffness(cell).inverse();
  CellEvaluator evaluator(cell);
  const bool adhesion = cell.adhesion();
  std::mt19937_64 generator(seed);
  for (int i = 0; i < n; ++i) {
    Vector6d nu;
    for (int k = 0; k < 6; ++k) nu(k) = normal(generator);
    nu.normalize();
    const Vector6d d = S_o * nu;
    std::vector<double> loads = {1};
    if (adhesion) {
      // The bonded cell is linear in the strain with its strengths lifted: t* = 1/(use at t = 1).
      CellHistory lifted = evaluator.unloaded();
      const CellResponse r = evaluator.at(MacroState::ply_strain(d), lifted, BondMode::lifted);
      if (!r.ok || !(r.strength_use > 0)) loads.clear();
      const double onset = r.ok ? 1 / r.strength_use : 0;
      if (!loads.empty()) {
        loads = {0.5 * onset};
        for (const double s : past_onset_factors(past_fuse_load_ratio)) loads.push_back(onset * s);
      }
    }
    std::vector<Vector6d> strain, stress;
    CellHistory history = evaluator.unloaded();
    const std::vector<CellResponse> path =
        walk_path(evaluator, history, loads, [&](double t) { return MacroState::ply_strain(t * d); });
    if (path.size() == loads.size() && (path.empty() || path.back().ok))
      for (std::size_t k = 0; k < path.size(); ++k) {
        strain.push_back(loads[k] * d);
        stress.push_back(ply_stress(path[k]));
      }
    sample.direction.push_back(nu);
    sample.strain.push_back(std::move(strain));
    sample.stress.push_back(std::move(stress));
    sample.bonded_points.push_back(adhesion && !sample.strain.back().empty() ? 1 : 0);
  }
  return sample;
}

PlyCheck check_ply(const CondensedCell& compact, const PlySample& sample) {
  CellEvaluator evaluator(compact);
  PlyCheck check;
  ErrorTally tally;
  for (std::size_t i = 0; i < sample.direction.size(); ++i) {
    if (sample.strain[i].empty()) continue;
    CellHistory history = evaluator.unloaded();
    double error = 0;
    for (std::size_t k = 0; k < sample.strain[i].size(); ++k) {
      const Vector6d& e = sample.strain[i][k];
      const CellResponse r = evaluator.at(MacroState::ply_strain(e), history);
      const double point = r.ok ? (ply_stress(r) - sample.stress[i][k]).norm() / sample.stress[i][k].norm()
                                : std::numeric_limits<double>::infinity();
      const double counted = std::isfinite(point) ? point : std::numeric_limits<double>::infinity();
      error = std::max(error, counted);
      if (static_cast<int>(k) < sample.bonded_points[i])
        check.bonded_max_error = std::max(check.bonded_max_error, counted);
      ++check.points;
    }
    if (tally.add(error)) check.worst = sample.direction[i];
  }
  check.directions = tally.count;
  check.max_error = tally.max_error();
  check.rms_error = tally.rms_error();
  return check;
}

}  // namespace dualcell::law
