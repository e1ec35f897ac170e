#include "law/condensed.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dualcell::law {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// A cell without shear (the symmetry boundary): its γxy and the tangent's shear entries are NaN.
void mark_no_shear(CellResponse& out) {
  out.strain(2) = nan;
  out.tangent.row(2).setConstant(nan);
  out.tangent.col(2).setConstant(nan);
}

}  // namespace

bool CondensedCell::adhesion() const {
  for (int r = 0; r < n_rows(); ++r)
    if (lower_bonded(r) != lower_broken(r) || upper_bonded(r) != upper_broken(r)) return true;
  return false;
}

Eigen::MatrixXd energy_matrix(const CondensedCell& cell) {
  const int n = cell.n_rows(), m = cell.n_macro;
  Eigen::MatrixXd energy(m + n, m + n);
  energy.topLeftCorner(m, m) = cell.volume * cell.S0;
  energy.topRightCorner(m, n) = -cell.Y.transpose();
  energy.bottomLeftCorner(n, m) = -cell.Y;
  energy.bottomRightCorner(n, n) = cell.H;
  return energy;
}

namespace {

// The fibres' rows G p = 0 on z = (σ̄, p): [0 G].
Eigen::MatrixXd strain_rows(const CondensedCell& cell) {
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(cell.G.rows(), cell.n_macro + cell.n_rows());
  C.rightCols(cell.n_rows()) = cell.G;
  return C;
}

}  // namespace

Eigen::Matrix<double, 6, 1> ply_stress(const CellResponse& r) {
  Eigen::Matrix<double, 6, 1> sigma;
  sigma << r.stress, r.stress_zz, r.shear_z;
  return sigma;
}

Eigen::Matrix<double, 6, 6> ply_tangent(const CellResponse& r) {
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>() = r.tangent;
  D.block<3, 1>(0, 3) = r.tangent_zz;
  D.block<1, 3>(3, 0) = r.tangent_zz.transpose();
  D(3, 3) = r.tangent_zz_zz;
  D.bottomRightCorner<2, 2>() = r.tangent_z;
  return D;
}

CellEvaluator::CellEvaluator(const CondensedCell& cell, qp::DenseActiveSet::Updates updates)
    : cell_(cell),
      energy_(energy_matrix(cell)),
      C_strain_(strain_rows(cell)),
      stress_qp_(cell.H, cell.G, updates),
      strain_qp_(energy_, C_strain_, updates),
      onset_qp_(cell.H, cell.G, updates),
      shear_qp_(cell.Hz, cell.Gz, updates) {}

CellHistory CellEvaluator::unloaded() const { return {cell_.bonded, {}, {}}; }

void CellEvaluator::set_bounds(const std::vector<std::uint8_t>& bonded, int offset, bool lifted) {
  const int n = cell_.n_rows();
  lower_.resize(offset + n);
  upper_.resize(offset + n);
  lower_.head(offset).setConstant(-inf);
  upper_.head(offset).setConstant(inf);
  for (int r = 0; r < n; ++r) {
    const bool b = bonded[cell_.pair[r]] != 0;
    // The strengths lifted (the bond rule): contact rows keep p_n ≥ 0, so the admissible set
    // stays a cone.
    const bond::Bounds bounds = !b       ? cell_.broken_bounds(r)
                                : lifted ? bond::lifted(cell_.bonded_bounds(r))
                                         : cell_.bonded_bounds(r);
    lower_(offset + r) = bounds.lower;
    upper_(offset + r) = bounds.upper;
  }
}

double CellEvaluator::strength_use(const Eigen::VectorXd& forces, const Eigen::VectorXd& forces_z,
                                   const std::vector<std::uint8_t>& bonded) const {
  double use = 0;
  for (int r = 0; r < cell_.n_rows(); ++r)
    if (bonded[cell_.pair[r]]) use = std::max(use, bond::strength_use(forces(r), cell_.bonded_bounds(r)));
  for (Eigen::Index r = 0; r < forces_z.size(); ++r)
    if (bonded[cell_.pair_z[r]]) use = std::max(use, bond::strength_use(forces_z(r), cell_.bonded_bounds_z(r)));
  return use;
}

void CellEvaluator::check_inputs(const MacroState& s, CellResponse& out) const {
  const Eigen::Vector3d v = s.in_plane();
  const double eps33 = s.eps33();
  const Eigen::Vector2d gamma = s.gamma();
  if (!v.allFinite() || !std::isfinite(eps33) || !gamma.allFinite() || !std::isfinite(s.delta_T()))
    out.message = "a non-finite input";
  if (cell_.n_macro == 2 && v(2) != 0)
    out.message = "the cell has the symmetry boundary: it carries no shear (the third component must be 0)";
  if (eps33 != 0 && cell_.longitudinal == 0)
    out.message = "the cell has no strain along the fibres (its scene's [load] macro is not \"full\"): eps33 must be 0";
  if (!gamma.isZero(0) && cell_.shear == 0)
    out.message =
        "the cell has no shear along the fibres (its scene's [load] macro is not \"full\"): gamma_xz and gamma_yz "
        "must be 0";
  if (!s.in_plane_stress() && !s.in_plane_strain())
    out.message = "an in-plane state part stress, part strain: the cell takes σ̄ or ε̄";
  if ((s.stress_driven & ~MacroState::in_plane_mask) != 0)
    out.message = "a stress along the fibres: the cell takes the strain ε33 and the shears Γ along them";
  if (s.delta_T() != 0 && cell_.thermal == 0)
    out.message = "the cell has no temperature change (its phases have no expansion coefficients): delta_T must be 0";
}

CellResponse CellEvaluator::at(const MacroState& s, CellHistory& h, BondMode bonds) {
  CellResponse out;
  check_inputs(s, out);
  if (!out.message.empty()) return out;
  if (s.in_plane_stress()) {
    if (bonds != BondMode::cascade) {
      out.message = "a stress-driven state runs the bonds' cascade (held or lifted bonds: strain-driven only)";
      return out;
    }
    return stress_driven(s.in_plane(), h, {s.eps33(), s.gamma(), s.delta_T()});
  }
  return strain_driven(s.in_plane(), h, bonds, {s.eps33(), s.gamma(), s.delta_T()});
}

bool CellEvaluator::solve_shear(const Eigen::Vector2d& gamma, CellHistory& h, bool lifted, CellResponse& r) {
  if (cell_.shear == 0) return true;
  const int n = cell_.shear_rows;
  r.forces_z = Eigen::VectorXd::Zero(n);
  if (n > 0) {
    // A row's force along z: within ±strength while its pair is bonded (no bound lifted), 0 once
    // the pair broke.
    lower_z_.resize(n), upper_z_.resize(n);
    for (int q = 0; q < n; ++q) {
      const bond::Bounds intact = cell_.bonded_bounds_z(q);
      const bond::Bounds b = !h.bonded[cell_.pair_z[q]]
                                 ? bond::bounds(bond::Kind::along_fibres, bond::State::broken, 0, 0, 0)
                             : lifted ? bond::lifted(intact)
                                      : intact;
      lower_z_(q) = b.lower, upper_z_(q) = b.upper;
    }
    b_z_ = cell_.Yz * gamma;
    if (h.active_z.size() != static_cast<std::size_t>(n)) h.active_z.clear();
    if (!solve_qp(shear_qp_, b_z_, lower_z_, upper_z_, h.active_z, r, r.forces_z)) return false;
  }
  r.shear_z = cell_.D0z * gamma;
  if (n > 0) r.shear_z += cell_.Yz.transpose() * r.forces_z / cell_.volume;
  // dτ/dΓ = D0z + Yzᵀ (dq/dΓ)/|Ω| on the final active set, dq/dΓ = the QP's sensitivity to Yz.
  if (n == 0) {
    shear_tangent_ = cell_.D0z;
  } else if (shear_tangent_of_ != shear_qp_.generation()) {
    const Eigen::Matrix2d T = cell_.D0z + cell_.Yz.transpose() * shear_qp_.sensitivity(cell_.Yz) / cell_.volume;
    shear_tangent_ = 0.5 * (T + T.transpose());
    shear_tangent_of_ = shear_qp_.generation();
  }
  r.tangent_z = shear_tangent_;
  return true;
}

void CellEvaluator::set_stress_zz(const Held& held, CellResponse& out) const {
  if (cell_.longitudinal == 0) return;
  const int m = cell_.n_macro;
  out.stress_zz = -cell_.A33.col(0).dot(out.stress.head(m)) + cell_.C33(0, 0) * held.eps33 +
                  cell_.y33.col(0).dot(out.forces) / cell_.volume;
  if (held.delta_T != 0) out.stress_zz += cell_.CT(0, 0) * held.delta_T;
}

// Solve, break the bonded rows that end at their strength, solve again: the debond cascade
// (with BondMode::cascade; otherwise one solve). `solve` runs one QP with the bounds of h.bonded
// and returns the forces p; the shear rows are solved beside it at gamma, with the same bonds,
// and a pair that ends at its strength in either breaks.
template <class Solve>
CellResponse CellEvaluator::cascade(CellHistory& h, BondMode bonds, const Eigen::Vector2d& gamma, Solve&& solve) {
  CellResponse out;
  if (static_cast<int>(h.bonded.size()) != cell_.n_pairs) h = unloaded();
  // Each round breaks at least one bonded pair: n_pairs + 1 solves end every cascade.
  const bond::CascadeEnd end = bond::cascade(
      h.bonded, bonds == BondMode::cascade ? cell_.n_pairs + 1 : 1,
      [&] { return solve(out) && solve_shear(gamma, h, bonds == BondMode::lifted, out); },
      [&](std::vector<int>& breaking) {
        if (bonds != BondMode::cascade) return;
        for (int r = 0; r < cell_.n_rows(); ++r)
          if (h.bonded[cell_.pair[r]] && bond::at_strength(out.forces(r), cell_.bonded_bounds(r)))
            breaking.push_back(cell_.pair[r]);
        for (Eigen::Index q = 0; q < out.forces_z.size(); ++q)
          if (h.bonded[cell_.pair_z[q]] && bond::at_strength(out.forces_z(q), cell_.bonded_bounds_z(q)))
            breaking.push_back(cell_.pair_z[q]);
      },
      [](const std::vector<int>&) {});
  if (!end.solved) return out;
  out.newly_broken = end.newly_broken;
  for (int p = 0; p < cell_.n_pairs; ++p) out.broken += cell_.bonded[p] && !h.bonded[p];
  out.strength_use = strength_use(out.forces, out.forces_z, h.bonded);
  out.ok = true;
  return out;
}

bool CellEvaluator::solve_qp(qp::DenseActiveSet& qp, const Eigen::VectorXd& b, const Eigen::VectorXd& lower,
                             const Eigen::VectorXd& upper, std::vector<qp::Bound>& active, CellResponse& r,
                             Eigen::VectorXd& x) {
  const qp::DenseQpResult result = qp.solve(b, lower, upper, active);
  r.iterations += result.iterations;
  r.factorisations += result.factorisations;
  r.updates += result.updates;
  if (!result.converged) {
    r.message = "the cell's QP: " + result.message;
    return false;
  }
  x = result.x;
  return true;
}

CellResponse CellEvaluator::stress_driven(const Eigen::Vector3d& sigma, CellHistory& h, const Held& held) {
  CellResponse out;
  const int m = cell_.n_macro, n = cell_.n_rows();
  if (h.active.size() != static_cast<std::size_t>(n)) h.active.clear();
  Eigen::Matrix3d compliance = Eigen::Matrix3d::Zero();
  out = cascade(h, BondMode::cascade, held.gamma, [&](CellResponse& r) {
    set_bounds(h.bonded, 0);
    b_ = cell_.Y * sigma.head(m);
    if (held.eps33 != 0) b_ += cell_.y33.col(0) * held.eps33;
    if (held.delta_T != 0) b_ += cell_.yT.col(0) * held.delta_T;
    return solve_qp(stress_qp_, b_, lower_, upper_, h.active, r, r.forces);
  });
  if (!out.ok) return out;
  out.stress.head(m) = sigma.head(m);
  out.strain.head(m) = cell_.S0 * sigma.head(m) - cell_.Y.transpose() * out.forces / cell_.volume;
  if (held.eps33 != 0) out.strain.head(m) += cell_.A33.col(0) * held.eps33;
  if (held.delta_T != 0) out.strain.head(m) += cell_.AT.col(0) * held.delta_T;
  set_stress_zz(held, out);
  // Compliance tangent dε̄/dσ̄ = S₀ − Yᵀ (dp/dσ̄)/|Ω| on the final active set; the stiffness
  // tangent is its inverse.
  if (stress_tangent_of_ != stress_qp_.generation()) {
    const Eigen::MatrixXd dp = stress_qp_.sensitivity(cell_.Y);
    compliance.topLeftCorner(m, m) = cell_.S0 - cell_.Y.transpose() * dp / cell_.volume;
    const Eigen::MatrixXd C = compliance.topLeftCorner(m, m).inverse();
    stress_tangent_.setZero();
    stress_tangent_.topLeftCorner(m, m) = 0.5 * (C + C.transpose());
    stress_tangent_of_ = stress_qp_.generation();
  }
  out.tangent = stress_tangent_;
  if (m == 2) mark_no_shear(out);
  return out;
}

CellResponse CellEvaluator::strain_driven(const Eigen::Vector3d& strain, CellHistory& h, BondMode bonds,
                                          const Held& held) {
  CellResponse out;
  const int m = cell_.n_macro, n = cell_.n_rows();
  if (h.active.size() != static_cast<std::size_t>(m + n)) h.active.clear();
  Eigen::VectorXd z;
  const double eps33 = held.eps33, dT = held.delta_T;
  const Eigen::Vector2d& gamma = held.gamma;
  out = cascade(h, bonds, gamma, [&](CellResponse& r) {
    set_bounds(h.bonded, m, bonds == BondMode::lifted);
    // With ε33 the mixed energy gains ε33 (|Ω| A33·σ̄ − y33·p) − ½ |Ω| C33 ε33² (docs/method.md
    // §16a), and ΔT the same with AT, yT: the linear term moves, 𝓗 stays.
    b_ = Eigen::VectorXd::Zero(m + n);
    b_.head(m) = cell_.volume * strain.head(m);
    if (eps33 != 0) {
      b_.head(m) -= cell_.volume * cell_.A33.col(0) * eps33;
      b_.tail(n) = cell_.y33.col(0) * eps33;
    }
    if (dT != 0) {
      b_.head(m) -= cell_.volume * cell_.AT.col(0) * dT;
      b_.tail(n) += cell_.yT.col(0) * dT;
    }
    if (!solve_qp(strain_qp_, b_, lower_, upper_, h.active, r, z)) return false;
    r.forces = z.tail(n);
    return true;
  });
  if (!out.ok) return out;
  out.stress.head(m) = z.head(m);
  out.strain.head(m) = strain.head(m);
  out.energy = strain.head(m).dot(z.head(m)) - 0.5 * z.dot(energy_ * z) / cell_.volume;
  if (eps33 != 0)
    out.energy -= eps33 * (cell_.A33.col(0).dot(z.head(m)) - cell_.y33.col(0).dot(z.tail(n)) / cell_.volume) -
                  0.5 * cell_.C33(0, 0) * eps33 * eps33;
  // ΔT's part likewise, and CT ε33 ΔT, so that ∂W/∂ε33 = σ33 (a function of ΔT alone, the heat's,
  // is left out).
  if (dT != 0) {
    out.energy -= dT * (cell_.AT.col(0).dot(z.head(m)) - cell_.yT.col(0).dot(z.tail(n)) / cell_.volume);
    if (eps33 != 0) out.energy += cell_.CT(0, 0) * eps33 * dT;
  }
  // The shear along the fibres adds ½ ΓᵀD0zΓ + (qᵀYzΓ − ½ qᵀHz q)/|Ω| (docs/method.md §16a).
  if (cell_.shear == 2) {
    out.energy += 0.5 * gamma.dot(cell_.D0z * gamma);
    if (cell_.shear_rows > 0)
      out.energy +=
          (out.forces_z.dot(cell_.Yz * gamma) - 0.5 * out.forces_z.dot(cell_.Hz * out.forces_z)) / cell_.volume;
  }
  set_stress_zz(held, out);
  // dσ̄/dε̄: the σ̄ rows of dz/db for db = (|Ω| I, 0), symmetric as the KKT system is.
  if (strain_tangent_of_ != strain_qp_.generation()) {
    Eigen::MatrixXd db = Eigen::MatrixXd::Zero(m + n, m);
    db.topRows(m) = cell_.volume * Eigen::MatrixXd::Identity(m, m);
    const Eigen::MatrixXd dz = strain_qp_.sensitivity(db);
    strain_tangent_.setZero();
    strain_tangent_.topLeftCorner(m, m) = 0.5 * (dz.topRows(m) + dz.topRows(m).transpose());
    if (cell_.longitudinal == 1) {
      // dz/dε33 for db = (−|Ω| A33, y33); dσ33/dε33 = −A33·dσ̄/dε33 + C33 + y33·dp/dε33/|Ω|, and
      // dσ̄/dε33 is the row dσ33/dε̄ (the mixed energy's symmetry).
      Eigen::VectorXd d33(m + n);
      d33 << -cell_.volume * cell_.A33.col(0), cell_.y33.col(0);
      const Eigen::VectorXd dz33 = strain_qp_.sensitivity(d33);
      strain_tangent_zz_.setConstant(nan);
      strain_tangent_zz_.head(m) = dz33.head(m);
      strain_tangent_zz_zz_ =
          -cell_.A33.col(0).dot(dz33.head(m)) + cell_.C33(0, 0) + cell_.y33.col(0).dot(dz33.tail(n)) / cell_.volume;
    }
    strain_tangent_of_ = strain_qp_.generation();
  }
  out.tangent = strain_tangent_;
  if (cell_.longitudinal == 1) {
    out.tangent_zz = strain_tangent_zz_;
    out.tangent_zz_zz = strain_tangent_zz_zz_;
  }
  if (m == 2) mark_no_shear(out);
  return out;
}

double CellEvaluator::onset(const Eigen::Vector3d& sigma) {
  const int m = cell_.n_macro;
  if (!cell_.adhesion()) return inf;
  // The intact cell with the strengths lifted: p(sσ̄) = s p(σ̄) for s ≥ 0.
  set_bounds(cell_.bonded, 0, true);
  b_ = cell_.Y * sigma.head(m);
  const qp::DenseQpResult qp = onset_qp_.solve(b_, lower_, upper_, onset_active_);
  if (!qp.converged) return nan;
  // The first row to reach its strength: s* = 1/(largest strength use), the bond rule's reach.
  const double use = strength_use(qp.x, Eigen::VectorXd(), cell_.bonded);
  return use > 0 ? 1 / use : inf;
}

double CellEvaluator::bonded_load(const Eigen::Vector3d& sigma) {
  const double s = onset(sigma);
  return std::isfinite(s) ? 0.5 * s : 1.0;
}

}  // namespace dualcell::law
