// The exact debond onset of the contact solver (docs/method.md §11): the bonded problem with its
// strengths lifted (law::bond::lifted), solved per direction for s* and the bonds that reach
// their strength there, and its three unit solves for the onset surface.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/error.hpp"
#include "core/text.hpp"
#include "feti/projected.hpp"
#include "feti/solver.hpp"
#include "law/bond.hpp"

namespace dualcell::feti {

namespace {

// The dual tolerance of the onset problems (bonds lifted: linear, or a cone of contact rows).
// The onset is the threshold a sweep steps to and a structure switches a cell at, so it is
// solved tighter than the scene's tolerance: at 1e-10 two solves of the same onset agree to
// only 4e-8 (cond(PFP) amplifies the projected gradient), at 1e-13 to 2e-10 (the onset tests); the problem has
// no active set to find, so the extra decades cost a few dozen CG steps.
constexpr double onset_qp_tolerance = 1e-13;

// The bonded problem with the interface rows' strengths lifted (law::bond::lifted): a normal row
// without normal strength keeps λ ≥ 0 (contact), which leaves a cone and keeps the response
// homogeneous, but not linear. Returns the lifted constraints; `lower`, `upper` get the intact
// bounds.
Constraints lifted_bonded(const mesh::Mesh& mesh, const Scene& scene, const BondState& intact, Eigen::VectorXd& lower,
                          Eigen::VectorXd& upper, bool& linear) {
  Constraints con = build_constraints(mesh, scene, intact);
  lower = con.lower, upper = con.upper;
  linear = true;
  for (int r = 0; r < con.n_rows(); ++r) {
    if (!is_interface(con.kind[r])) continue;
    const law::bond::Bounds lifted = law::bond::lifted({con.lower(r), con.upper(r)});
    con.lower(r) = lifted.lower;
    con.upper(r) = lifted.upper;
    linear = linear && lifted.lower == -std::numeric_limits<double>::infinity();
  }
  return con;
}

}  // namespace

ContactSolver::Lifted& ContactSolver::lifted() {
  if (!lifted_.dual) {
    Constraints con =
        lifted_bonded(setup_.mesh(), setup_.scene(), intact(), lifted_.lower, lifted_.upper, lifted_.linear);
    lifted_.dual = std::make_unique<DualProblem>(setup_, std::move(con));
    lifted_.norm_PFP = estimate_norm_PFP(*lifted_.dual);
    const double delta_T = setup_.scene().load.delta_T;
    if (delta_T != 0 && !lifted_.linear) {
      lifted_.thermal_message =
          "a temperature change with normal rows that have no normal strength (contact rows): the bonded forces are "
          "not affine in the load, so there is no onset by superposition";
    } else if (delta_T != 0) {
      // At the scene's tolerance, as the cool-down itself and bonded_expansion: p0 enters the
      // reach only through the room bound − p0, where its relative error is negligible, and the
      // onset's 1e-13 is below what a random RVE's cool-down attains (a six-fibre T300/BSL914C
      // RVE stagnated near 1e-11 and had no onset at all).
      const Solution s =
          solve_problem(*lifted_.dual, lifted_.norm_PFP,
                        MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::dT, delta_T), nullptr, nullptr);
      if (s.converged())
        lifted_.thermal = s.lambda.cwiseQuotient(lifted_.dual->constraints().weight);
      else
        lifted_.thermal_message = "the cool-down's bonded solve did not converge: " + s.qp.message;
    }
  }
  return lifted_;
}

double ContactSolver::debond_onset(const Eigen::Vector3d& sigma, std::vector<int>* critical) {
  if (critical) critical->clear();
  if (!setup_.scene().interface.has_adhesion()) return std::numeric_limits<double>::infinity();
  Lifted& lifted = this->lifted();
  const Eigen::VectorXd &lower = lifted.lower, &upper = lifted.upper;
  const bool thermal = setup_.scene().load.delta_T != 0;
  onset_note_.clear();
  if (thermal && lifted.thermal.size() == 0) {
    if (!lifted.linear) throw InputError(setup_.scene().file.string() + ": [load] delta_T: " + lifted.thermal_message);
    onset_note_ = lifted.thermal_message;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const Solution s = solve_problem(*lifted.dual, lifted.norm_PFP, MacroState::stress(sigma), nullptr, nullptr,
                                   std::min(onset_qp_tolerance, setup_.scene().solver.tolerance));
  if (!s.converged()) {
    onset_note_ = "the bonded solve with the strengths lifted did not converge: " + s.qp.message;
    return std::numeric_limits<double>::quiet_NaN();
  }
  // The load factor at which row r reaches its bound (+inf where it never does along σ̄).
  const Constraints& c = lifted.dual->constraints();
  const auto reach = [&](int r) {
    return law::bond::reach(s.lambda(r) / c.weight(r), {lower(r), upper(r)}, thermal ? lifted.thermal(r) : 0.0);
  };
  double onset = std::numeric_limits<double>::infinity();
  for (int r = 0; r < c.n_rows(); ++r)
    if (is_interface(c.kind[r])) onset = std::min(onset, reach(r));
  if (critical && std::isfinite(onset)) {
    for (int r = 0; r < c.n_rows(); ++r)
      if (is_interface(c.kind[r]) && law::bond::reaches_at_onset(reach(r), onset)) critical->push_back(c.pair[r]);
    std::sort(critical->begin(), critical->end());
    critical->erase(std::unique(critical->begin(), critical->end()), critical->end());
  }
  return onset;
}

law::OnsetSurface ContactSolver::onset_surface() {
  law::OnsetSurface out;
  if (!setup_.scene().interface.has_adhesion()) {
    out.message = "no adhesion: nothing to break";
    return out;
  }
  if (setup_.scene().load.boundary == Boundary::edges) {
    out.message = "the edges boundary has one load pattern, not a macro stress: its onset is debond_onset";
    return out;
  }
  Lifted& lifted = this->lifted();
  const Eigen::VectorXd &lower = lifted.lower, &upper = lifted.upper;
  if (!lifted.linear) {
    out.message =
        "normal rows without normal strength stay contact rows: the bonded response is not linear, "
        "so the onset set is no polytope (use the onset per direction)";
    return out;
  }
  const bool thermal = setup_.scene().load.delta_T != 0;
  if (thermal && lifted.thermal.size() == 0) {
    out.message = lifted.thermal_message;
    return out;
  }
  const Constraints& c = lifted.dual->constraints();
  // Row forces per unit stress: column j = λ(e_j) in force units.
  const int n_unit = setup_.scene().load.boundary == Boundary::symmetry ? 2 : 3;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(c.n_rows(), 3);
  for (int j = 0; j < n_unit; ++j) {
    const Solution s = solve_problem(*lifted.dual, lifted.norm_PFP, MacroState::stress(Eigen::Vector3d::Unit(j)),
                                     nullptr, nullptr, std::min(onset_qp_tolerance, setup_.scene().solver.tolerance));
    if (!s.converged()) {
      out.message = "the unit solve " + std::to_string(j) + " did not converge: " + s.qp.message;
      return out;
    }
    a.col(j) = s.lambda.cwiseQuotient(c.weight);
  }
  std::vector<Eigen::Vector3d> rows;
  for (int r = 0; r < c.n_rows(); ++r) {
    if (!is_interface(c.kind[r])) continue;
    for (const double bound : {lower(r), upper(r)}) {
      if (!std::isfinite(bound) || bound == 0) continue;
      // With the cool-down's force p0 the facet a·σ̄ ≤ υ − p0 (a·σ̄ ≥ ℓ − p0): g = a/(bound − p0), the
      // polytope shifted and contracted, still g·σ̄ ≤ 1 while the cool-down leaves the row below
      // its strength.
      const double room = thermal ? bound - lifted.thermal(r) : bound;
      if (room == 0 || (room > 0) != (bound > 0)) {
        out.message = "the cool-down alone (delta_T " + shortest(setup_.scene().load.delta_T) + ") brings pair " +
                      std::to_string(c.pair[r]) + " to its strength: no onset surface around 0";
        out.pair.clear();
        out.tangential.clear();
        return out;
      }
      rows.push_back(a.row(r).transpose() / room);  // a·σ̄ ≥ ℓ (ℓ < 0) and a·σ̄ ≤ υ (υ > 0) alike: g·σ̄ ≤ 1
      out.pair.push_back(c.pair[r]);
      out.tangential.push_back(c.kind[r] == RowKind::tangential ? 1 : 0);
    }
  }
  out.facets.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) out.facets.row(static_cast<Eigen::Index>(k)) = rows[k].transpose();
  out.linear = true;
  return out;
}

law::PlyExpansion ContactSolver::bonded_expansion() {
  law::PlyExpansion out;
  const Scene& scene = setup_.scene();
  if (!scene.fibre.expands || !scene.matrix.expands) return out;
  if (!scene.interface.has_adhesion()) {
    out.note = "no adhesion: the cell has no bonded state (a contact cell's expansion depends on the sign of delta_T)";
    return out;
  }
  Lifted& lifted = this->lifted();
  if (!lifted.linear) {
    out.note = "normal rows without normal strength stay contact rows: the bonded cell is not linear";
    return out;
  }
  // The scene's tolerance: no threshold is stepped onto here (the onset's reason for 1e-13), and an
  // RVE's problem may not reach 1e-13 at all (measured: 1.5e-13 attainable on a two-fibre RVE).
  const double tolerance = scene.solver.tolerance;
  const MacroState none = MacroState::stress(Eigen::Vector3d::Zero());
  const Solution heated = solve_problem(*lifted.dual, lifted.norm_PFP, MacroState(none).hold(MacroState::dT, 1),
                                        nullptr, nullptr, tolerance);
  const Solution axial = solve_problem(*lifted.dual, lifted.norm_PFP, MacroState(none).hold(MacroState::zz, 1), nullptr,
                                       nullptr, tolerance);
  if (!heated.converged() || !axial.converged()) {
    out.note = "a bonded solve did not converge: " + (heated.converged() ? axial : heated).qp.message;
    return out;
  }
  // ⟨σ33⟩ = 0 by superposition: ε33 = −⟨σ33⟩(ΔT = 1)/⟨σ33⟩(ε33 = 1); the in-plane strain follows
  // (engineering shear γxy = 2εxy).
  const double e33 = -heated.average_stress_zz / axial.average_stress_zz;
  const Eigen::Vector3d e = heated.strain + e33 * axial.strain;
  out.alpha1 = e33;
  out.alpha2 = e(0);
  out.alpha3 = e(1);
  out.alpha23 = 2 * e(2);
  out.ok = 1;
  return out;
}

}  // namespace dualcell::feti
