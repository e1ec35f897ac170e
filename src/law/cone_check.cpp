#include "law/cone_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/directions.hpp"
#include "core/error_tally.hpp"

namespace dualcell::law {

namespace {

// Directions along rings of constant (√2σxy) on the unit sphere, each ring walked in the
// direction opposite to the last, so that consecutive directions are neighbours.
std::vector<Eigen::Vector3d> ordered_sphere(int n) {
  std::vector<Eigen::Vector3d> out;
  const int rings = std::max(2, static_cast<int>(std::round(std::sqrt(n * std::numbers::pi / 4))));
  for (int i = 0; i < rings; ++i) {
    const double polar = std::numbers::pi * (i + 0.5) / rings, z = std::cos(polar), r = std::sin(polar);
    const int m = std::max(1, static_cast<int>(std::round(2 * rings * r)));
    for (int j = 0; j < m; ++j) {
      const int k = i % 2 == 0 ? j : m - 1 - j;
      const double azimuth = 2 * std::numbers::pi * (k + 0.5) / m;
      out.emplace_back(r * std::cos(azimuth), r * std::sin(azimuth), z / std::sqrt(2.0));
    }
  }
  return out;
}

std::vector<Eigen::Vector3d> ordered_circle(int n) {
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * std::numbers::pi * (k + 0.5) / n;
    out.emplace_back(std::cos(t), std::sin(t), 0.0);
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector3d> sample_directions(int n_macro, int n) {
  return n_macro == 3 ? ordered_sphere(n) : ordered_circle(std::max(180, n / 2));
}

namespace {

// "sampling the exact law (what): direction i of n" on `progress`, when a line is due.
void tell(Progress* progress, const char* what, std::size_t i, std::size_t n) {
  if (progress)
    progress->update([&] {
      return std::string("sampling the exact law ") + what + ": direction " + std::to_string(i + 1) + " of " +
             std::to_string(n) + ", " + seconds_text(progress->seconds());
    });
}

}  // namespace

CellSample sample_cell(const CondensedCell& cell, int n, Progress* progress) {
  CellSample sample;
  CellEvaluator evaluator(cell);
  CellHistory history = evaluator.unloaded();
  sample.direction = sample_directions(cell.n_macro, n);
  for (const Eigen::Vector3d& N : sample.direction) {
    tell(progress, "below the onset", sample.stress.size(), sample.direction.size());
    const double s = evaluator.bonded_load(N);
    history.bonded = cell.bonded;  // each point from the intact cell; the active set stays as the warm start
    const CellResponse r = evaluator.at_stress(s * N, history);
    Eigen::Vector3d e = r.strain;
    if (cell.n_macro == 2) e(2) = 0;
    const bool failed = !r.ok || r.broken > 0;
    if (failed) e.setConstant(std::numeric_limits<double>::quiet_NaN());
    sample.strain.push_back(e);
    sample.stress.push_back(s * N);
    sample.forces.push_back(failed ? Eigen::VectorXd() : r.forces);
  }
  return sample;
}

CellSample sample_cell_past_fuse(const CondensedCell& cell, int n, double factor, Progress* progress) {
  CellSample sample;
  CellEvaluator evaluator(cell);
  CellHistory history = evaluator.unloaded();
  sample.direction = sample_directions(cell.n_macro, n);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector3d& N : sample.direction) {
    tell(progress, "past the fuse", sample.stress.size(), sample.direction.size());
    const double onset = evaluator.onset(N);
    Eigen::Vector3d e = Eigen::Vector3d::Constant(nan);
    if (std::isfinite(onset)) {
      history.bonded = cell.bonded;
      // Just past the onset the first bond breaks and the cascade runs; then on to factor·s* in
      // steps, as a path goes (a bond can pass its strength on the way and not at the end).
      const std::vector<double> loads = past_onset_factors(factor);
      const std::vector<CellResponse> path =
          walk_path(evaluator, history, loads, [&](double s) { return MacroState::stress(s * onset * N); });
      if (path.size() == loads.size() && path.back().ok) {
        std::vector<Eigen::Vector3d> path_strain, path_stress;
        for (std::size_t k = 0; k < path.size(); ++k) {
          path_strain.push_back(path[k].strain);
          if (cell.n_macro == 2) path_strain.back()(2) = 0;
          path_stress.push_back(loads[k] * onset * N);
        }
        e = path_strain.back();
        sample.forces.push_back(path.back().forces);
        path_strain.pop_back();
        path_stress.pop_back();
        sample.path_strain.push_back(std::move(path_strain));
        sample.path_stress.push_back(std::move(path_stress));
      }
    }
    if (sample.forces.size() < sample.strain.size() + 1) sample.forces.emplace_back();
    if (sample.path_strain.size() < sample.strain.size() + 1) {
      sample.path_strain.emplace_back();
      sample.path_stress.emplace_back();
    }
    sample.strain.push_back(e);
    sample.stress.push_back((std::isfinite(onset) ? factor * onset : 1.0) * N);
  }
  return sample;
}

std::vector<CellResponse> walk_path(CellEvaluator& evaluator, CellHistory& history, const std::vector<double>& loads,
                                    const std::function<MacroState(double)>& state_at) {
  std::vector<CellResponse> path;
  for (const double t : loads) {
    path.push_back(evaluator.at(state_at(t), history));
    if (!path.back().ok) break;
  }
  return path;
}

std::vector<double> past_onset_factors(double factor) {
  std::vector<double> loads{1 + 1e-6};
  for (int step = 1; step <= past_fuse_steps; ++step) loads.push_back(1 + (factor - 1) * step / past_fuse_steps);
  return loads;
}

const char* checked_against_text(CheckedAgainst against) {
  switch (against) {
    case CheckedAgainst::exact_law:
      return "the exact law";
    case CheckedAgainst::held_out_directions:
      return "held-out sweep directions";
    case CheckedAgainst::held_out_solves:
      return "held-out full solves";
    case CheckedAgainst::exact_law_past_fuse:
      return "the exact law past the fuse";
  }
  return "";
}

CheckedAgainst checked_against_from(const std::string& text) {
  for (CheckedAgainst a : {CheckedAgainst::exact_law, CheckedAgainst::held_out_directions,
                           CheckedAgainst::held_out_solves, CheckedAgainst::exact_law_past_fuse})
    if (text == checked_against_text(a)) return a;
  throw std::invalid_argument("not a cone check's reference: '" + text + "'");
}

ConeCheck check_cone(const ConeLaw& cone, const CellSample& sample) {
  return check_law([&](const Eigen::Vector3d& e) { return evaluate(cone, e).stress; }, sample);
}

ConeCheck check_law(const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& stress_at, const CellSample& sample) {
  return check_over(sample, [&](std::size_t i) {
    return (stress_at(sample.strain[i]) - sample.stress[i]).norm() / sample.stress[i].norm();
  });
}

ConeCheck check_over(const CellSample& sample, const std::function<double(std::size_t)>& error_at) {
  ConeCheck check;
  check.directions = sample.direction;
  ErrorTally tally;
  for (std::size_t i = 0; i < sample.direction.size(); ++i) {
    if (!sample.strain[i].allFinite()) {  // the exact law has no point here: not counted
      check.error.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    double error = error_at(i);
    if (!std::isfinite(error)) error = std::numeric_limits<double>::infinity();  // the law has none: the worst
    check.error.push_back(error);
    if (tally.add(error)) check.worst = sample.direction[i];
  }
  check.max_error = tally.max_error();
  check.rms_error = tally.rms_error();
  return check;
}

PolarModuli exact_polar(const CondensedCell& cell) {
  CellEvaluator evaluator(cell);
  CellHistory history = evaluator.unloaded();
  return polar_moduli([&](double theta_deg, double sign) {
    const Eigen::Vector3d n = uniaxial_stress(theta_deg * std::numbers::pi / 180);
    const Eigen::Vector3d N = sign * n;
    const double s = evaluator.bonded_load(N);
    history.bonded = cell.bonded;
    const CellResponse r = evaluator.at_stress(s * N, history);
    if (!r.ok || r.broken != 0) return std::numeric_limits<double>::quiet_NaN();
    Eigen::Vector3d e = r.strain;
    if (cell.n_macro == 2) e(2) = 0;
    return sign * s / (n(0) * e(0) + n(1) * e(1) + n(2) * e(2));
  });
}

}  // namespace dualcell::law
