// Recovery of the primal solution from the dual one and its checks (docs/method.md §9, §10):
// u and α from λ and SMALBE's multiplier, the undetermined rigid motions of fibres, the KKT
// report and the primal check of every solve.
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "feti/macro.hpp"
#include "feti/solver.hpp"

namespace dualcell::feti {

namespace {

// A multiplier strictly inside its bounds: the constraint holds as an equality (active).
bool is_active(const Constraints& con, const Eigen::VectorXd& lambda_scaled, int r) {
  return lambda_scaled(r) > con.lower(r) && lambda_scaled(r) < con.upper(r);
}

// Recovery of a fibre's rigid motion: a direction is seen by the active rows when its singular
// value is above this fraction of what all the fibre's rows could give (rank-revealing), and a
// row's rate along a direction below this fraction of |row|·|step| is round-off (a spin seen by
// normal rows), which limits nothing.
constexpr double active_rank_tolerance = 1e-8;
constexpr double round_off_rate = 1e-10;

// The primal check never asks for better than this relative accuracy, which still flags any
// recovery error (those err by O(‖u‖)).
constexpr double primal_check_floor = 1e-6;

}  // namespace

// u = K⁺(f − Bᵀλ) + Rα (docs/method.md §9). The KKT amplitudes come from the equality multiplier of
// SMALBE: with g = Fλ − d and m its multiplier, B u − c = −(P g + m) vanishes on active rows
// and is ≤ 0 on open ones when α = (GGᵀ)⁻¹G(g − m). They are unique where the active
// constraints determine the motion. Where they do not (a fibre touching at one point or at
// none, or spinning freely without adhesion), the undetermined part of the fibre's motion
// follows the surrounding matrix (the rigid motion that best fits the matrix at the rim),
// moved there along a straight line only as far as the open gaps allow, so that no gap closes
// into a penetration.
void ContactSolver::recover(const DualProblem& dual, const Eigen::VectorXd& f, const Eigen::VectorXd& d,
                            const Eigen::VectorXd& lambda_scaled, const Eigen::VectorXd& multiplier,
                            Solution& out) const {
  const Constraints& con = dual.constraints();
  const auto& subs = setup_.subdomains();
  const auto& locals = dual.locals();
  const int n_subdomains = static_cast<int>(subs.size());
  Eigen::VectorXd u = dual.K_plus_residual(f, lambda_scaled);
  Eigen::VectorXd g(con.n_rows());
  dual.apply_F(lambda_scaled, g);
  g -= d + multiplier;
  // α̂: amplitudes of the modes R̂ that B sees; α = V α̂ per subdomain (R̂_i = R_i V_i).
  const Eigen::VectorXd alpha_hat = dual.coarse_solve(g);
  out.alpha = Eigen::VectorXd::Zero(3 * n_subdomains);
  for (int s = 0; s < n_subdomains; ++s) {
    const auto& local = locals[s];
    const Eigen::Vector3d alpha = local.V * alpha_hat.segment(local.G_offset, local.V.cols());
    out.alpha.segment<3>(3 * s) = alpha;
    u.segment(subs[s].dof_begin, subs[s].n_dofs) += subs[s].R * alpha;
  }

  const mesh::Mesh& mesh = setup_.mesh();
  std::vector<int> subdomain_of_fibre(mesh.n_fibres(), -1);
  for (int s = 0; s < static_cast<int>(mesh.subdomains.size()); ++s)
    if (mesh.subdomains[s].is_fibre) subdomain_of_fibre[mesh.subdomains[s].fibre] = s;
  std::vector<std::vector<int>> pairs_of_fibre(n_subdomains);
  for (int p = 0; p < static_cast<int>(mesh.interface_pairs.size()); ++p)
    pairs_of_fibre[subdomain_of_fibre[mesh.interface_fibre[p]]].push_back(p);
  const Eigen::VectorXd Bu = con.B * u;
  for (int s = 0; s < n_subdomains; ++s) {
    if (!subs[s].is_fibre) continue;
    const FloatingSubdomain& sub = subs[s];
    const auto& local = locals[s];
    // Target: the rigid motion that best fits u_matrix − u_fibre at the rim.
    Eigen::MatrixXd fit(2 * pairs_of_fibre[s].size(), 3);
    Eigen::VectorXd mismatch(2 * pairs_of_fibre[s].size());
    for (std::size_t i = 0; i < pairs_of_fibre[s].size(); ++i) {
      const auto [fn, mn] = mesh.interface_pairs[pairs_of_fibre[s][i]];
      fit.middleRows<2>(2 * i) = sub.R.middleRows<2>(2 * fn - sub.dof_begin);
      mismatch.segment<2>(2 * i) = u.segment<2>(2 * mn) - u.segment<2>(2 * fn);
    }
    const Eigen::Vector3d shift_target = (fit.transpose() * fit).ldlt().solve(fit.transpose() * mismatch);
    // Directions the active rows do not see: right singular vectors of B_A R with singular
    // values below active_rank_tolerance of what all rows of this fibre could give.
    const Eigen::MatrixXd BR = local.B * sub.R;
    std::vector<int> active, open;
    for (std::size_t k = 0; k < local.rows.size(); ++k)
      (is_active(con, lambda_scaled, local.rows[k]) ? active : open).push_back(static_cast<int>(k));
    const double reference = Eigen::JacobiSVD<Eigen::MatrixXd>(BR).singularValues()(0);
    // Undetermined directions: an orthonormal basis of the null space of the active rows.
    Eigen::MatrixXd undetermined = Eigen::Matrix3d::Identity();
    if (!active.empty()) {
      Eigen::MatrixXd Ma(active.size(), 3);
      for (std::size_t i = 0; i < active.size(); ++i) Ma.row(i) = BR.row(active[i]);
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ma, Eigen::ComputeFullV);
      int rank = 0;
      for (int j = 0; j < svd.singularValues().size(); ++j)
        rank += svd.singularValues()(j) > active_rank_tolerance * reference;
      undetermined = svd.matrixV().rightCols(3 - rank);
    }
    // Move along each undetermined direction separately, as far as the rows at a bound allow:
    // at a lower bound (open contact, a bond at its tensile or negative shear strength)
    // gap + t·rate ≤ 0; at an upper bound (shear at +strength) gap + t·rate ≥ 0. A rate at
    // round-off level (a spin seen by normal rows) limits nothing: dividing a gap of ~0 by it
    // would pick an arbitrary step.
    Eigen::VectorXd gap(local.rows.size());
    for (std::size_t k = 0; k < local.rows.size(); ++k)
      gap(k) = Bu(local.rows[k]) - setup_.load_factor(out.sigma) * con.c(local.rows[k]);
    for (int j = 0; j < undetermined.cols(); ++j) {
      const Eigen::Vector3d direction = undetermined.col(j);
      const double amount = direction.dot(shift_target);
      if (amount == 0) continue;
      const Eigen::Vector3d step = amount * direction;
      double t = 1;
      for (int k : open) {
        const double rate = BR.row(k).dot(step);
        if (std::abs(rate) <= round_off_rate * BR.row(k).norm() * step.norm()) continue;
        const bool at_upper = lambda_scaled(local.rows[k]) >= con.upper(local.rows[k]);
        if (!at_upper && rate > 0) t = std::min(t, std::max(0.0, -gap(k) / rate));
        if (at_upper && rate < 0) t = std::min(t, std::max(0.0, gap(k) / -rate));
      }
      out.alpha.segment<3>(3 * s) += t * step;
      u.segment(sub.dof_begin, sub.n_dofs) += sub.R * (t * step);
      gap += t * (BR * step);
    }
  }
  out.u = std::move(u);
}

void ContactSolver::report(const DualProblem& dual, const Eigen::VectorXd& f, const Eigen::VectorXd& lambda_scaled,
                           Solution& out) const {
  const Constraints& con = dual.constraints();
  const mesh::Mesh& mesh = setup_.mesh();
  const Scene& scene = setup_.scene();
  KktReport& kkt = out.kkt;
  kkt.relative_projected_gradient = out.qp.relative_projected_gradient;

  // Gλ = e, relative to the size of the terms that cancel.
  const Eigen::VectorXd e = dual.e(f);
  const Eigen::VectorXd Glambda = dual.G() * lambda_scaled;
  const double scale = std::max(e.norm(), (dual.G().cwiseAbs() * lambda_scaled.cwiseAbs()).norm());
  kkt.relative_equality_residual = scale > 0 ? (Glambda - e).norm() / scale : 0.0;

  // Complementarity of a bounded row: its gap times its distance to the nearest bound, the
  // distance capped at ‖λ‖∞ so that a row far inside huge (or infinite) bounds, which must hold
  // as an equality, counts its gap at the scale of the interface forces.
  const double lambda_cap = std::max(out.lambda.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  auto complementarity = [&](double lambda, double lower, double upper, double gap) {
    return std::min({lambda - lower, upper - lambda, lambda_cap}) * std::abs(gap);
  };
  const Eigen::VectorXd Bu = con.B * out.u;
  out.normal_force.assign(mesh.interface_pairs.size(), 0.0);
  out.tangential_force.assign(mesh.interface_pairs.size(), 0.0);
  for (int r = 0; r < con.n_rows(); ++r) {
    const double w = con.weight(r);
    const double gap =
        (Bu(r) - setup_.load_factor(out.sigma) * con.c(r)) / w;  // length units: rows of B have unit coefficients
    const double lambda = out.lambda(r), lower = con.lower(r) * w, upper = con.upper(r) * w;
    kkt.bound_violation = std::max({kkt.bound_violation, lower - lambda, lambda - upper});
    switch (con.kind[r]) {
      case RowKind::normal:
        kkt.max_penetration = std::max(kkt.max_penetration, gap);
        kkt.complementarity = std::max(kkt.complementarity, complementarity(lambda, lower, upper, gap));
        out.normal_force[con.pair[r]] = lambda;
        break;
      case RowKind::tangential:
        kkt.complementarity = std::max(kkt.complementarity, complementarity(lambda, lower, upper, gap));
        out.tangential_force[con.pair[r]] = lambda;
        break;
      default:
        kkt.max_glue_jump = std::max(kkt.max_glue_jump, std::abs(gap));
    }
  }

  // Equilibrium of every subdomain: K_i u_i − f_i + B_iᵀλ = 0 (the macro subdomain: K = 0),
  // each checked by the rank that holds its K.
  const auto& subs = setup_.subdomains();
  const double f_scale = std::max(f.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  double worst = 0;
  for (int s = setup_.owned_begin(); s < setup_.owned_end(); ++s) {
    const auto& local = dual.locals()[s];
    Eigen::VectorXd residual = -f.segment(subs[s].dof_begin, subs[s].n_dofs);
    if (!subs[s].is_macro) residual += subs[s].K * out.u.segment(subs[s].dof_begin, subs[s].n_dofs);
    Eigen::VectorXd lambda_local(local.rows.size());
    for (std::size_t k = 0; k < local.rows.size(); ++k) lambda_local(k) = lambda_scaled(local.rows[k]);
    if (!local.rows.empty()) residual += local.B.transpose() * lambda_local;
    worst = std::max(worst, residual.lpNorm<Eigen::Infinity>());
  }
  kkt.relative_equilibrium = setup_.group().max(worst) / f_scale;

  // Check the recovered primal solution. A wrong recovery (a wrong α, a fibre pushed through
  // its hole) errs by O(‖u‖). A right one has gaps and jumps of the dual residual amplified by
  // the conditioning of F: ≤ 1 × tolerance × ‖u‖∞ on the thesis cases, but 2.5e-8 at a
  // tolerance of 1e-10 for bonded near-voids (compliance contrast 1e6). Hence 100 × tolerance,
  // and never below primal_check_floor relative.
  const double tolerance = std::max(100 * scene.solver.tolerance, primal_check_floor);
  const double u_scale = out.u.lpNorm<Eigen::Infinity>();
  const double lambda_scale = out.lambda.lpNorm<Eigen::Infinity>();
  out.primal_ok = true;
  out.primal_message.clear();
  auto check = [&](double value, double limit, const char* what) {
    if (!(value <= limit)) {  // NaN fails too
      out.primal_ok = false;
      if (out.primal_message.empty()) {
        char text[160];
        std::snprintf(text, sizeof text, "recovered solution fails its check: %s %.3g > %.3g", what, value, limit);
        out.primal_message = text;
      }
    }
  };
  check(kkt.max_penetration, tolerance * u_scale, "max penetration");
  check(kkt.max_glue_jump, tolerance * u_scale, "max glue jump");
  check(kkt.complementarity, tolerance * u_scale * lambda_scale, "complementarity");

  out.strain = boundary_strain(mesh, out.u);
  out.average_stress =
      average_stress(mesh, scene.fibre, scene.matrix, out.u, {out.eps33, out.delta_T}, &out.average_stress_zz);
  // No answer with a non-finite number passes (a load beyond what doubles carry).
  if (!out.u.allFinite() || !out.lambda.allFinite() || !out.strain.allFinite() || !out.average_stress.allFinite() ||
      !std::isfinite(out.average_stress_zz)) {
    out.primal_ok = false;
    out.primal_message = "recovered solution is not finite (the load is beyond what doubles carry)";
  }
}

}  // namespace dualcell::feti
