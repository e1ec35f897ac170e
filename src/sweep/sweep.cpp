#include "sweep/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "core/directions.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/strain.hpp"

namespace dualcell::sweep {

namespace {

Step make_step(double load, const feti::Solution& s, int broken, double seconds) {
  Step step;
  step.load = load;
  step.stress = s.sigma;
  step.strain = s.strain;
  step.broken_bonds = broken;
  step.outer_iterations = s.counters.outer_iterations;
  step.operator_applications = s.counters.operator_applications;
  step.kkt_residual =
      std::max({s.kkt.relative_projected_gradient, s.kkt.relative_equality_residual, s.kkt.relative_equilibrium});
  step.seconds = seconds;
  step.converged = s.converged();
  if (s.eps33 != 0) step.stress_zz = s.average_stress_zz;
  if (!s.gamma.isZero(0)) step.shear_stress = s.shear_stress;
  return step;
}

// The jump of the strain along the load N:ε (tensor shear, the fuse's strains).
double jump_ratio(const PathSpec& spec, const Fuse& fuse) {
  const Eigen::Vector3d N = spec.state.in_plane();
  const double before = work_with_tensor_strain(N, fuse.strain_before);
  return before != 0 ? work_with_tensor_strain(N, fuse.strain_after) / before : std::numeric_limits<double>::infinity();
}

}  // namespace

int count_broken(const feti::BondState& intact, const feti::BondState& now) {
  int broken = 0;
  for (std::size_t p = 0; p < now.size(); ++p) broken += intact[p] && !now[p];
  return broken;
}

feti::Solution LoadWalk::solve(double load, const feti::BondState* from) {
  Eigen::VectorXd scaled, scaled_multiplier;
  if (lambda_.size() > 0 && load_ != 0) {
    scaled = lambda_ * (load / load_);
    if (multiplier_.size() == lambda_.size()) scaled_multiplier = multiplier_ * (load / load_);
  }
  return solver_.solve(direction_.at_factor(load), from ? *from : bonds_, scaled.size() ? &scaled : nullptr,
                       scaled_multiplier.size() ? &scaled_multiplier : nullptr);
}

void LoadWalk::accept(double load, const feti::Solution& s) {
  bonds_ = s.bonds;
  lambda_ = s.lambda;
  multiplier_ = s.multiplier;
  load_ = load;
}

std::vector<PathSpec> plan_paths(const Scene& scene) {
  std::vector<double> tension, compression;
  for (double m : scene.sweep.magnitudes) (m > 0 ? tension : compression).push_back(m);
  std::sort(tension.begin(), tension.end());
  std::sort(compression.begin(), compression.end(), std::greater<>());
  tension.erase(std::unique(tension.begin(), tension.end()), tension.end());
  compression.erase(std::unique(compression.begin(), compression.end()), compression.end());

  std::vector<PathSpec> paths;
  auto add = [&](double direction_deg, const Eigen::Vector3d& unit) {
    for (int sign : {1, -1}) {
      const auto& loads = sign > 0 ? tension : compression;
      if (loads.empty()) continue;
      PathSpec spec;
      spec.index = static_cast<int>(paths.size());
      spec.direction_deg = direction_deg;
      spec.sign = sign;
      spec.state = MacroState::stress(unit);
      spec.loads = loads;
      paths.push_back(spec);
    }
  };
  const bool symmetry = scene.load.boundary == Boundary::symmetry;
  for (double theta : scene.sweep.directions_deg) {
    Eigen::Vector3d unit = uniaxial_stress(theta * std::numbers::pi / 180);
    // Shear below round-off of cos·sin counts as none (θ a multiple of 90°).
    if (std::abs(unit(2)) < 1e-12) unit(2) = 0;
    if (std::abs(unit(0)) < 1e-12) unit(0) = 0;
    if (std::abs(unit(1)) < 1e-12) unit(1) = 0;
    if (symmetry && unit(2) != 0)
      throw InputError(scene.file.string() + ": [sweep] directions_deg contains " + std::to_string(theta) +
                       ": the symmetry boundary carries only shear-free directions (multiples of 90°); use "
                       "boundary = \"traction\" or \"periodic\"");
    add(theta, unit);  // n⊗n has unit Frobenius norm already
  }
  for (const auto& t : scene.sweep.stress_directions) {
    Eigen::Vector3d unit(t[0], t[1], t[2]);
    // Frobenius norm of the symmetric tensor: sqrt(σxx² + σyy² + 2σxy²).
    if (symmetry && unit(2) != 0)
      throw InputError(scene.file.string() +
                       ": [sweep] stress_directions has a tensor with sxy != 0: the symmetry "
                       "boundary carries only sxx and syy");
    unit /= std::sqrt(unit(0) * unit(0) + unit(1) * unit(1) + 2 * unit(2) * unit(2));
    add(std::numeric_limits<double>::quiet_NaN(), unit);
  }
  // The sphere: loads along +N only; without adhesion one load, the largest magnitude.
  std::vector<double> sphere_loads;
  for (double m : scene.sweep.magnitudes) sphere_loads.push_back(std::abs(m));
  std::sort(sphere_loads.begin(), sphere_loads.end());
  sphere_loads.erase(std::unique(sphere_loads.begin(), sphere_loads.end()), sphere_loads.end());
  // (Positively homogeneous only without a temperature change: ΔT is a fixed part of every load.)
  if (!scene.interface.has_adhesion() && scene.load.delta_T == 0 && !sphere_loads.empty())
    sphere_loads = {sphere_loads.back()};
  for (const Eigen::Vector3d& unit : sphere_directions(scene.sweep.sphere)) {
    PathSpec spec;
    spec.index = static_cast<int>(paths.size());
    spec.direction_deg = std::numeric_limits<double>::quiet_NaN();
    spec.sign = 1;
    spec.state = MacroState::stress(unit);
    spec.loads = sphere_loads;
    spec.sphere = true;
    paths.push_back(spec);
  }
  // The uniaxial paths again with each held strain along the fibres, after all the others.
  const std::size_t in_plane = paths.size();
  for (const double eps33 : scene.sweep.eps33)
    for (std::size_t i = 0; i < in_plane; ++i)
      if (!std::isnan(paths[i].direction_deg)) {
        PathSpec spec = paths[i];
        spec.index = static_cast<int>(paths.size());
        spec.state.hold(MacroState::zz, eps33);
        paths.push_back(spec);
      }
  // And with each held shear along the fibres.
  for (const auto& gamma : scene.sweep.gamma)
    for (std::size_t i = 0; i < in_plane; ++i)
      if (!std::isnan(paths[i].direction_deg)) {
        PathSpec spec = paths[i];
        spec.index = static_cast<int>(paths.size());
        spec.state.hold_shear(Eigen::Vector2d(gamma[0], gamma[1]));
        paths.push_back(spec);
      }
  // Every path holds the scene's temperature change: the cool-down is where each starts.
  if (scene.load.delta_T != 0)
    for (PathSpec& spec : paths) spec.state.hold(MacroState::dT, scene.load.delta_T);
  return paths;
}

std::vector<Eigen::Vector3d> sphere_directions(int n) {
  // (x, y, z) = (σxx, σyy, √2σxy) on the unit sphere is a tensor of unit Frobenius norm.
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : fibonacci_sphere(n)) out.emplace_back(p(0), p(1), p(2) / std::sqrt(2.0));
  return out;
}

PathResult run_path(feti::ContactSolver& solver, const PathSpec& spec, double fuse_tolerance,
                    const StepObserver& on_step) {
  using Clock = std::chrono::steady_clock;
  PathResult result;
  result.spec = spec;
  const feti::BondState intact = solver.intact();
  const bool adhesion = solver.setup().scene().interface.has_adhesion();

  // The schedule, with the exact onset inserted where it falls inside it (plane strain only).
  std::vector<double> loads = spec.loads;
  double onset = std::numeric_limits<double>::infinity();
  std::vector<int> critical;  // the bonds at their strength at the onset
  if (adhesion && spec.in_plane()) {
    onset = spec.sign * solver.debond_onset(spec.sign * spec.state.in_plane(), &critical);
    // (0: the cool-down broke bonds by itself, before any load.)
    if (std::isfinite(onset) && onset != 0 && std::abs(onset) <= std::abs(loads.back()) &&
        std::find(loads.begin(), loads.end(), onset) == loads.end()) {
      loads.push_back(onset);
      std::sort(loads.begin(), loads.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    }
  }

  LoadWalk walk(solver, spec.state, intact);
  Eigen::Vector3d previous_strain = Eigen::Vector3d::Zero();
  auto record = [&](double load, const feti::Solution& s, double seconds) {
    result.steps.push_back(make_step(load, s, count_broken(intact, s.bonds), seconds));
    if (on_step) on_step(spec, static_cast<int>(result.steps.size()) - 1, result.steps.back());
  };

  // Each scheduled load is reached from the last recorded state. Whenever the solve there
  // breaks new bonds, the jump is bracketed by bisection from that state, both sides are
  // recorded, and the walk continues from the state after the jump (at most
  // max_events_per_step brackets per scheduled load; a progressive debonding beyond that is
  // recorded at the scheduled loads only).
  constexpr int max_events_per_step = 20;
  if (!spec.state.gamma().isZero(0) || spec.state.delta_T() != 0) {
    // The shear alone, or the cure's cool-down, first: the bonds it breaks by itself are broken
    // before any in-plane load, as a bisection from load 0 could not bracket.
    const auto t0 = Clock::now();
    feti::Solution s = walk.solve(0.0);
    record(0.0, s, seconds_since(t0));
    walk.accept(0.0, s);
    previous_strain = s.strain;
  }
  for (double load : loads) {
    for (int event = 0;; ++event) {
      const auto t0 = Clock::now();
      // Onto the onset from the intact state: the critical bonds are at their strength, which
      // the onset solve knows exactly and the QP's multipliers only to its tolerance. They
      // break here, as the rule says, and the solve goes on from there (the cascade).
      feti::BondState from = walk.bonds();
      long broken_at_onset = 0;
      if (load == onset && count_broken(intact, walk.bonds()) == 0)
        for (int p : critical) broken_at_onset += std::exchange(from[p], std::uint8_t{0}) ? 1 : 0;
      feti::Solution s = walk.solve(load, &from);
      s.newly_broken += broken_at_onset;
      if (!(adhesion && s.newly_broken > 0) || event >= max_events_per_step) {
        record(load, s, seconds_since(t0));
        walk.accept(load, s);
        previous_strain = s.strain;
        break;
      }
      double lo = walk.load(), hi = load;
      std::optional<feti::Solution> at_lo;
      feti::Solution at_hi = std::move(s);
      while (std::abs(hi - lo) > fuse_tolerance * std::abs(hi)) {
        const double mid = 0.5 * (lo + hi);
        feti::Solution m = walk.solve(mid);
        if (m.newly_broken > 0) {
          hi = mid;
          at_hi = std::move(m);
        } else {
          lo = mid;
          at_lo = std::move(m);
        }
      }
      const double seconds = seconds_since(t0);
      // The fuse is the jump with the largest growth of the strain along the load, N:ε.
      const Fuse jump{onset, lo, hi, at_lo ? at_lo->strain : previous_strain, at_hi.strain};
      if (!result.fuse || jump_ratio(spec, jump) > jump_ratio(spec, *result.fuse)) result.fuse = jump;
      if (at_lo) record(lo, *at_lo, seconds / 2);
      record(hi, at_hi, at_lo ? seconds / 2 : seconds);
      walk.accept(hi, at_hi);
      previous_strain = at_hi.strain;
      if (hi == load) break;
    }
  }
  return result;
}

}  // namespace dualcell::sweep
