#include "law/ply.hpp"

#include <cmath>
#include <stdexcept>

namespace dualcell::law {

const char* to_string(PlyState s) {
  switch (s) {
    case PlyState::bonded:
      return "bonded";
    case PlyState::after_fuse:
      return "after fuse";
    case PlyState::contact:
      return "contact";
  }
  return "";
}

namespace {

// The secant steps' goal: |σ33| within this fraction of the load s (the law is exact to
// round-off, so the steps stop on the piece where σ33 = 0, within a few of them).
constexpr double sigma33_tolerance = 1e-9;

// Probes of one bond state: every evaluation from a copy of the state's history, which must
// come back with no new break.
class StateProbes {
 public:
  StateProbes(CellEvaluator& law, const CellHistory& h) : law_(law), h_(h) {}

  // The response at the in-plane stress σ̄ with ε33 found so that σ33 = 0 (s: the load's size,
  // C33: the open cell's σ33 per unit ε33, the first step's slope); left: |σ33|/s at the end.
  CellResponse uniaxial(const Eigen::Vector3d& sigma, double s, double C33, double& left) {
    double x0 = 0, f0 = at_stress(sigma, x0).stress_zz;
    double x1 = -f0 / C33;
    CellResponse r = at_stress(sigma, x1);
    for (int step = 0; step < 60 && std::abs(r.stress_zz) > sigma33_tolerance * s; ++step) {
      const double slope = (r.stress_zz - f0) / (x1 - x0);
      if (!(slope > 0)) throw std::runtime_error("σ33 does not increase with ε33 at this state");
      x0 = x1, f0 = r.stress_zz;
      x1 -= r.stress_zz / slope;
      r = at_stress(sigma, x1);
    }
    left = std::abs(r.stress_zz) / s;
    if (left > sigma33_tolerance) throw std::runtime_error("the secant steps on ε33 did not reach σ33 = 0");
    return r;
  }

  CellResponse at_stress(const Eigen::Vector3d& sigma, double eps33) {
    CellHistory h = h_;
    CellResponse r = law_.at(MacroState::stress(sigma).hold(MacroState::zz, eps33), h);
    check(r);
    return r;
  }

  // dτ/dΓ of the state (bonds held: the probe's shear is far below any strength).
  Eigen::Matrix2d shear_moduli(double e) {
    CellHistory h = h_;
    CellResponse r =
        law_.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(Eigen::Vector2d(e, e)), h, BondMode::held);
    check(r);
    return r.tangent_z;
  }

 private:
  void check(const CellResponse& r) const {
    if (!r.ok) throw std::runtime_error(r.message);
    if (r.newly_broken > 0) throw std::runtime_error("a probe broke a bond (the state is at its strength)");
  }
  CellEvaluator& law_;
  const CellHistory& h_;
};

PlyConstants constants_of(CellEvaluator& law, const CellHistory& h, PlyState state, int sign) {
  const CondensedCell& cell = law.cell();
  const double e = 1e-8, s = e / cell.S0(0, 0), C33 = cell.C33(0, 0);
  StateProbes probe(law, h);
  PlyConstants c;
  c.state = state, c.sign = sign;
  for (int p = 0; p < cell.n_pairs; ++p) c.broken += cell.bonded[p] && !h.bonded[p];
  const CellResponse axial = probe.at_stress(Eigen::Vector3d::Zero(), sign * e);
  c.E1 = axial.stress_zz / (sign * e);
  c.nu12 = -axial.strain(0) / (sign * e);
  c.nu13 = -axial.strain(1) / (sign * e);
  double left = 0;
  const CellResponse x = probe.uniaxial(Eigen::Vector3d(sign * s, 0, 0), s, C33, left);
  c.sigma33_left = left;
  c.E2 = sign * s / x.strain(0);
  c.nu23 = -x.strain(1) / x.strain(0);
  const CellResponse y = probe.uniaxial(Eigen::Vector3d(0, sign * s, 0), s, C33, left);
  c.sigma33_left = std::max(c.sigma33_left, left);
  c.E3 = sign * s / y.strain(1);
  if (cell.n_macro == 3) {
    const CellResponse xy = probe.uniaxial(Eigen::Vector3d(0, 0, sign * s), s, C33, left);
    c.sigma33_left = std::max(c.sigma33_left, left);
    c.G23 = sign * s / xy.strain(2);
  }
  // Secants as the others: τxz alone (τyz = 0) gives γxz = (G⁻¹)₀₀ τxz, so G12 = det G / G₁₁.
  const Eigen::Matrix2d G = probe.shear_moduli(e);
  c.G12 = G.determinant() / G(1, 1), c.G13 = G.determinant() / G(0, 0);
  return c;
}

}  // namespace

PlyTable ply_constants(const CondensedCell& cell) {
  PlyTable table;
  if (cell.longitudinal != 1 || cell.shear != 2) {
    table.note =
        "the cell does not carry the strain and the shears along the fibres ([load] macro = \"full\", "
        "periodic)";
    return table;
  }
  CellEvaluator law(cell);
  const auto add_state = [&](const CellHistory& h, PlyState state) {
    for (const int sign : {1, -1}) table.rows.push_back(constants_of(law, h, state, sign));
  };
  try {
    if (!cell.adhesion()) {
      add_state(law.unloaded(), PlyState::contact);
      return table;
    }
    add_state(law.unloaded(), PlyState::bonded);
    const double onset = law.onset(Eigen::Vector3d(1, 0, 0));
    if (!std::isfinite(onset)) {
      table.note = "no bond breaks under σxx: no state after the fuse";
      return table;
    }
    table.fuse_stress = 4 * onset;
    CellHistory h = law.unloaded();
    const CellResponse fused = law.at_stress(Eigen::Vector3d(table.fuse_stress, 0, 0), h);
    if (!fused.ok) throw std::runtime_error(fused.message);
    add_state(h, PlyState::after_fuse);
  } catch (const std::runtime_error& e) {
    table.note = std::string("stopped: ") + e.what();
  }
  return table;
}

}  // namespace dualcell::law
