#include "sweep/checks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "feti/condense.hpp"
#include "feti/constraints.hpp"
#include "law/bond.hpp"
#include "primal/antiplane.hpp"

namespace dualcell::sweep {

using Clock = std::chrono::steady_clock;

// The cell on the interface forces of basis_solutions full solves along sphere directions, at the
// sphere paths' load (the law is homogeneous: any load gives the same columns); a direction in
// which every contact opens has no force and gives no column.
void build_basis(feti::ContactSolver& solver, const Scene& scene, SweepHeader& header, bool show) {
  const auto start = Clock::now();
  double load = 0;
  for (const double m : scene.sweep.magnitudes) load = std::max(load, std::abs(m));
  Progress progress("dualcell-sweep", show);
  std::vector<Eigen::VectorXd> lambdas;
  const std::vector<Eigen::Vector3d> directions = sphere_directions(basis_solutions);
  for (std::size_t j = 0; j < directions.size(); ++j) {
    const feti::Solution s = solver.solve(load * directions[j], solver.intact());
    progress.update([&] {
      return "basis solve " + std::to_string(j + 1) + "/" + std::to_string(directions.size()) + ", " +
             seconds_text(progress.seconds());
    });
    if (!s.converged()) {
      header.cell_basis_note = "the basis solve along sphere direction " + std::to_string(j) + " did not converge";
      return;
    }
    lambdas.push_back(s.lambda);
  }
  progress.finish();
  try {
    header.cell_basis = feti::condense_on_solutions(solver.setup(), lambdas);
    header.cell_basis->seconds = seconds_since(start);
  } catch (const InputError& e) {
    header.cell_basis_note = e.what();
  }
}

// The exact law's strain along the fibres against the full solve of generalised plane strain
// (docs/method.md §16a), at loads far below any bond's strength (the cell linear where it has
// bonds, positively homogeneous where it has contact only): σ̄ = 0 and s·n⊗n along each of the
// sweep's uniaxial paths (its directions in the signs its magnitudes have), each with ε33 = ±e; s a thousandth of the
// smallest |magnitude| and, with adhesion, at most a hundredth of the onset along every direction (the fit replays the
// checks with the cascade: no bond may come near its strength); e = s over the softer phase's E, so
// that both parts of the response count. A solve that does not converge is no check (the fit
// counts the points it has, and refuses a law with none).
std::vector<LongitudinalPoint> longitudinal_points(feti::ContactSolver& solver, const Scene& scene,
                                                   const std::vector<PathSpec>& specs, const law::OnsetSurface& onset) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const double m : scene.sweep.magnitudes) smallest = std::min(smallest, std::abs(m));
  // The uniaxial paths' directions with their signs, as the sweep planned them.
  std::vector<Eigen::Vector3d> units;
  for (const PathSpec& spec : specs)
    if (!std::isnan(spec.direction_deg) && spec.in_plane()) units.push_back(spec.sign * spec.state.in_plane());
  double s = 1e-3 * smallest;
  if (onset.linear)
    for (const Eigen::Vector3d& u : units)
      if (const double along = law::onset_along(onset, u); std::isfinite(along)) s = std::min(s, 1e-2 * along);
  const double e = s / std::min(scene.fibre.E, scene.matrix.E);
  std::vector<Eigen::Vector3d> stresses{Eigen::Vector3d::Zero()};
  for (const Eigen::Vector3d& u : units) stresses.push_back(s * u);
  std::vector<LongitudinalPoint> points;
  for (const Eigen::Vector3d& sigma : stresses)
    for (const double eps33 : {e, -e}) {
      const feti::Solution sol =
          solver.solve_fixed(MacroState::stress(sigma).hold(MacroState::zz, eps33), solver.intact());
      if (sol.converged()) points.push_back({sigma, eps33, sol.strain, sol.average_stress_zz, 0});
    }
  // Past the fuse: twice the onset along each uniaxial path, with ε33 = ±(that stress over the
  // softer phase's E), each from the intact cell through the solver's debond loop (the law's
  // cascade must break the same pairs).
  if (onset.linear)
    for (const Eigen::Vector3d& u : units)
      if (const double along = law::onset_along(onset, u); std::isfinite(along))
        for (const double sign : {1.0, -1.0}) {
          const double eps33 = sign * 2 * along / std::min(scene.fibre.E, scene.matrix.E);
          const feti::Solution sol =
              solver.solve(MacroState::stress(2 * along * u).hold(MacroState::zz, eps33), solver.intact());
          if (!sol.converged()) continue;
          long broken = 0;
          for (const auto b : sol.bonds) broken += b == 0;
          points.push_back({2 * along * u, eps33, sol.strain, sol.average_stress_zz, broken});
        }
  return points;
}

// The checks of the shear along the fibres (/shear_check): four paths of Γ, along 0°, 45°, 90° and
// 135° in the (γxz, γyz) plane, from the intact cell; with adhesion at 0.5, 1.2, 2 and 4 times the
// first break along the path (the intact cell is linear: the strength over the largest tie force
// at unit Γ), the one-body solve's debond cascade run at each (each tie holds to its strength
// along z, s_t L, and slips past it, as the law's shear rows are bounded; the ties at their
// strength break by the bond rule, and it is solved again until none is),
// so that the law meets it before, at and past its breaks; without adhesion one point per path
// (the fibres are holes along z whatever the load).
std::vector<ShearPoint> shear_points(const mesh::Mesh& mesh, const Scene& scene) {
  namespace bond = law::bond;
  const double st = scene.interface.tangential_strength;
  const std::size_t P = mesh.interface_pairs.size();
  const std::vector<double> strength = feti::shear_strengths(mesh, scene);
  std::vector<ShearPoint> points;
  for (int path = 0; path < 4; ++path) {
    const double angle = path * std::numbers::pi / 4;
    const Eigen::Vector2d unit(std::cos(angle), std::sin(angle));
    std::vector<char> bonded(P, st > 0 ? 1 : 0);
    std::vector<double> factors{1e-3};
    if (st > 0) {
      const primal::ShearResponse r = primal::longitudinal_shear_at(mesh, scene.fibre, scene.matrix, bonded, unit);
      double use = 0;
      for (std::size_t q = 0; q < P; ++q)
        use = std::max(use, bond::strength_use(r.pair_forces(static_cast<Eigen::Index>(q)),
                                               bond::intact_along_fibres(strength[q])));
      if (!(use > 0)) continue;
      factors = {0.5 / use, 1.2 / use, 2 / use, 4 / use};
    }
    for (const double factor : factors) {
      const Eigen::Vector2d gamma = factor * unit;
      const primal::ShearResponse r = feti::longitudinal_shear_cascade(mesh, scene, bonded, gamma, strength);
      int broken = 0;
      for (std::size_t q = 0; q < P; ++q) broken += st > 0 && !bonded[q];
      points.push_back({path, gamma, r.tau, broken});
    }
  }
  return points;
}

}  // namespace dualcell::sweep
