#include "feti/solver.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "core/error.hpp"
#include "feti/macro.hpp"
#include "law/bond.hpp"
#include "qp/operator.hpp"
#include "qp/smalbe.hpp"

namespace dualcell::feti {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// A multiplier strictly inside its bounds: the constraint holds as an equality (active).
bool is_active(const Constraints& con, const Eigen::VectorXd& lambda_scaled, int r) {
  return lambda_scaled(r) > con.lower(r) && lambda_scaled(r) < con.upper(r);
}

// y = P T P x + s·Q x with P = I − Q and T = F or M⁻¹ (SMALBE's A + ρQ and M⁻¹ + Q/ρ),
// reusing the Q x that P x needs: two applications of Q. Work vectors allocated once per solve.
class ProjectedPlusShiftedQ {
 public:
  using Apply = void (DualProblem::*)(const Eigen::VectorXd&, Eigen::VectorXd&) const;
  ProjectedPlusShiftedQ(const DualProblem& dual, Apply T, int m)
      : dual_(dual), T_(T), Qx_(m), Px_(m), TPx_(m), QTPx_(m) {}
  void operator()(const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
    dual_.apply_Q(x, Qx_);
    Px_ = x - Qx_;
    (dual_.*T_)(Px_, TPx_);
    dual_.apply_Q(TPx_, QTPx_);
    y = TPx_ - QTPx_;
    if (shift != 0) y += shift * Qx_;
  }

 private:
  const DualProblem& dual_;
  Apply T_;
  Eigen::VectorXd Qx_, Px_, TPx_, QTPx_;
};

// ‖PFP‖ by qp::estimate_norm (20 applications from a fixed start vector): part of building a
// problem, so that it is a function of the problem alone and no QP's count depends on which
// came first.
double estimate_norm_PFP(const DualProblem& dual) {
  const int m = dual.constraints().n_rows();
  ProjectedPlusShiftedQ PFP(dual, &DualProblem::apply_F, m);
  return qp::estimate_norm([&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { PFP(x, 0.0, y); }, m);
}

// The tightest dual tolerance the primal check may ask for: a relative projected gradient of
// 1e-14 is a few hundred ulps of its terms, below which SMALBE stagnates instead of converging.
constexpr double min_qp_tolerance = 1e-14;

// The dual tolerance of the onset problems (bonds lifted: linear, or a cone of contact rows).
// The onset is the threshold a sweep steps to and a structure switches a cell at, so it is
// solved tighter than the scene's tolerance: at 1e-10 two solves of the same onset agree to
// only 4e-8 (cond(PFP) amplifies the projected gradient), at 1e-13 to 2e-10 (the onset tests); the problem has
// no active set to find, so the extra decades cost a few dozen CG steps.
constexpr double onset_qp_tolerance = 1e-13;

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

ContactSolver::ContactSolver(const mesh::Mesh& mesh, const Scene& scene, int threads, int min_dofs_per_thread,
                             par::Group group, Progress* progress, double expected_qps)
    : setup_(mesh, scene, threads, min_dofs_per_thread, std::move(group), progress, expected_qps),
      progress_(progress) {}

ContactSolver::Cached& ContactSolver::cached(const BondState& bonds) {
  Cached& c = bonds == intact() ? intact_ : other_;
  if (!c.dual || bonds != c.bonds) {
    c.dual = std::make_unique<DualProblem>(setup_, build_constraints(setup_.mesh(), setup_.scene(), bonds));
    c.bonds = bonds;
    c.norm_PFP = estimate_norm_PFP(*c.dual);
  }
  return c;
}

const DualProblem& ContactSolver::problem(const BondState& bonds) { return *cached(bonds).dual; }

Solution ContactSolver::solve_fixed(const Eigen::Vector3d& sigma, const BondState& bonds,
                                    const Eigen::VectorXd* warm_lambda, const Eigen::VectorXd* warm_multiplier) {
  if (setup_.scene().load.boundary == Boundary::symmetry && sigma(2) != 0)
    throw InputError("the symmetry boundary carries only sxx and syy (sxy must be 0)");
  if (setup_.scene().load.boundary == Boundary::edges && (sigma(1) != 0 || sigma(2) != 0))
    throw InputError("the edges boundary has one load coordinate, the load factor (t, 0, 0)");
  if (bonds.size() != setup_.mesh().interface_pairs.size())
    throw InputError("bond state has " + std::to_string(bonds.size()) + " entries, the mesh " +
                     std::to_string(setup_.mesh().interface_pairs.size()) + " interface pairs");
  const auto t0 = Clock::now();
  const Cached& before = bonds == intact() ? intact_ : other_;
  const bool rebuilt = !before.dual || bonds != before.bonds;
  if (rebuilt && progress_)
    progress_->update([&] { return "dual setup (B, G, GGᵀ), " + seconds_text(progress_->seconds()); });
  Cached& c = cached(bonds);
  const DualProblem& dual = *c.dual;
  const double dual_setup = rebuilt ? seconds_since(t0) : 0.0;
  Solution out = solve_problem(dual, c.norm_PFP, sigma, warm_lambda, warm_multiplier);
  // A well-posed problem must not end in "failed": when the QP converged but the recovered
  // primal solution misses its check (a stiffness contrast amplifies the dual residual in u),
  // the dual tolerance does not give the accuracy this problem needs. Tighten it a decade at a
  // time and go on from the multipliers reached, down to min_qp_tolerance.
  while (out.qp_converged() && !out.primal_ok && out.qp_tolerance > min_qp_tolerance) {
    const double tighter = std::max(out.qp_tolerance / 10, min_qp_tolerance);
    Solution next = solve_problem(dual, c.norm_PFP, sigma, &out.lambda, &out.multiplier, tighter);
    next.add_work(out);
    ++next.tightenings;
    out = std::move(next);
  }
  out.bonds = bonds;
  out.seconds.dual_setup = dual_setup;
  return out;
}

Solution ContactSolver::solve_problem(const DualProblem& dual, double norm_PFP, const Eigen::Vector3d& sigma,
                                      const Eigen::VectorXd* warm_lambda, const Eigen::VectorXd* warm_multiplier,
                                      double qp_tolerance) {
  Solution out;
  out.qp_tolerance = qp_tolerance > 0 ? qp_tolerance : setup_.scene().solver.tolerance;
  out.sigma = sigma;
  out.seconds.assembly = setup_.seconds_assembly;
  out.seconds.factorisation = setup_.seconds_factorisation;
  out.seconds.explicit_operators = setup_.seconds_explicit;
  out.subdomains = setup_.n_stiff_subdomains();
  out.explicit_subdomains = setup_.explicit_subdomains();
  const Constraints& con = dual.constraints();
  const int m = con.n_rows();
  out.n_rows = m;

  const auto t_qp = Clock::now();
  const DualProblem::Profile profile_before = dual.profile();
  const Eigen::VectorXd f = setup_.load(sigma);
  const Eigen::VectorXd e = dual.e(f);
  const Eigen::VectorXd lambda0 = dual.lambda_0(e);
  const Eigen::VectorXd d = dual.d(f, setup_.load_factor(sigma));
  Eigen::VectorXd b(m), tmp(m);
  dual.apply_F(lambda0, tmp);
  b = d - tmp;
  dual.apply_Q(b, tmp);
  b -= tmp;  // b = P(d − Fλ₀)

  // A = PFP, fused with SMALBE's shift: A + ρQ.
  ProjectedPlusShiftedQ A_plus_shifted_Q(dual, &DualProblem::apply_F, m);
  const qp::LinearOperator A = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { A_plus_shifted_Q(x, 0.0, y); };
  const qp::LinearOperator Q = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { dual.apply_Q(x, y); };
  const long extra_applications = 1;  // Fλ₀

  const Eigen::VectorXd lower = con.lower - lambda0, upper = con.upper - lambda0;
  // The QP's unknown: λ − λ₀ (scaled rows), zero or the caller's warm start.
  Eigen::VectorXd lambda_shift = Eigen::VectorXd::Zero(m);
  if (warm_lambda && warm_lambda->size() == m) lambda_shift = warm_lambda->cwiseQuotient(con.weight) - lambda0;

  const SolverSettings& settings = setup_.scene().solver;
  qp::SmalbeOptions options;
  options.relative_tolerance = out.qp_tolerance;
  options.equality_tolerance = out.qp_tolerance;
  options.max_outer_iterations = settings.max_outer_iterations;
  options.max_operator_applications = settings.max_operator_applications;
  options.rho0_factor = settings.rho_factor;
  options.rho_growth = settings.rho_growth;
  options.rho_patience = settings.rho_patience;
  options.inner.Gamma = settings.Gamma;
  options.inner.norm_A = norm_PFP;
  options.inner.max_iterations = settings.max_operator_applications;
  options.projected_operator = true;  // A = PFP: ‖A + ρQ‖ = max(‖A‖, ρ)
  // Progress: per application of F one clock read; the line (the last outer iteration's
  // stopping quantities against their tolerance, F so far, and what is left at the rate the
  // worse of the two has fallen per outer iteration) is formed only when one is due.
  long applications = 0;
  qp::OuterReport first{}, last{};
  double first_seconds = 0, last_seconds = 0;
  const auto qp_line = [&] {
    char text[320];
    const double tol = out.qp_tolerance;
    const double now = progress_->seconds();
    std::string left;
    // The distance to convergence, max(‖gᴾ‖, ‖Gλ−e‖)/tol, falls about geometrically per outer
    // iteration; from the rate seen since the first, the outer iterations and seconds left.
    const auto distance = [&](const qp::OuterReport& r) {
      return std::max(r.projected_gradient, r.equality_residual) / tol;
    };
    if (last.outer_iterations >= 3 && distance(last) > 1 && distance(first) > distance(last)) {
      const double steps = static_cast<double>(last.outer_iterations - first.outer_iterations);
      const double rate = std::pow(distance(last) / distance(first), 1 / steps);
      const double per_outer = (last_seconds - first_seconds) / steps;
      const double outers_left = std::log(distance(last)) / -std::log(rate);
      if (rate < 0.95)
        left = ", ~" + seconds_text(std::max(0.0, outers_left * per_outer - (now - last_seconds))) + " left";
    }
    if (last.outer_iterations == 0)
      std::snprintf(text, sizeof text, "QP (%d rows): %ld F applications, %s", m, applications,
                    seconds_text(now).c_str());
    else
      std::snprintf(text, sizeof text,
                    "QP (%d rows): outer %ld, |gP| %.1e, |G l - e| %.1e (tol %.0e), %ld F applications, %s%s", m,
                    last.outer_iterations, last.projected_gradient, last.equality_residual, tol, applications,
                    seconds_text(now).c_str(), left.c_str());
    return std::string(text);
  };
  options.A_plus_shifted_Q = [&](const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
    A_plus_shifted_Q(x, shift, y);
    if (progress_) {
      ++applications;
      progress_->update(qp_line);
    }
  };
  if (progress_)
    options.on_outer = [&](const qp::OuterReport& r) {
      if (r.outer_iterations == 1) {
        first = r;
        first_seconds = progress_->seconds();
      }
      last = r;
      last_seconds = progress_->seconds();
    };
  // The preconditioner of PFP on Im P: P M⁻¹ P, fused with SMALBE's Q/ρ like A + ρQ.
  std::optional<ProjectedPlusShiftedQ> M_plus_shifted_Q;
  if (settings.preconditioner != Preconditioner::none) {
    M_plus_shifted_Q.emplace(dual, &DualProblem::apply_preconditioner, m);
    options.preconditioner = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { (*M_plus_shifted_Q)(x, 0.0, y); };
    options.preconditioner_plus_shifted_Q = [&](const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
      (*M_plus_shifted_Q)(x, shift, y);
    };
  }
  // SMALBE's m = Ĝᵀμ, in λ-space; warm-started with the caller's when it fits this problem.
  Eigen::VectorXd multiplier = Eigen::VectorXd::Zero(m);
  if (warm_multiplier && warm_multiplier->size() == m) multiplier = *warm_multiplier;
  out.qp = qp::smalbe(A, Q, b, lower, upper, lambda_shift, multiplier, options);
  out.seconds.qp = seconds_since(t_qp);
  out.seconds.qp_F = dual.profile().F - profile_before.F;
  out.seconds.qp_Q = dual.profile().Q - profile_before.Q;
  out.seconds.qp_preconditioner = dual.profile().preconditioner - profile_before.preconditioner;
  out.seconds.qp_communication = dual.profile().communication - profile_before.communication;
  out.seconds.exchanges = dual.profile().exchanges - profile_before.exchanges;
  out.seconds.bytes_received = dual.profile().bytes_received - profile_before.bytes_received;
  out.counters = out.qp.counters;
  out.counters.operator_applications += extra_applications;

  const Eigen::VectorXd lambda_scaled = lambda0 + lambda_shift;
  out.lambda = lambda_scaled.cwiseProduct(con.weight);
  out.multiplier = multiplier;
  const auto t_rec = Clock::now();
  if (progress_) progress_->update([&] { return "recovery of u, " + seconds_text(progress_->seconds()); });
  recover(dual, f, d, lambda_scaled, multiplier, out);
  out.seconds.recovery = seconds_since(t_rec);
  report(dual, f, lambda_scaled, out);
  return out;
}

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
    if (value > limit) {
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
  out.average_stress = average_stress(mesh, scene.fibre, scene.matrix, out.u);
}

Solution ContactSolver::solve(const Eigen::Vector3d& sigma, const BondState& bonds, const Eigen::VectorXd* warm_lambda,
                              const Eigen::VectorXd* warm_multiplier) {
  BondState current = bonds;
  Solution total;
  Solution previous;  // the work of the rounds before the current one
  int newly_broken = 0;
  Eigen::VectorXd warm;
  if (warm_lambda) warm = *warm_lambda;
  const int max_rounds = setup_.scene().solver.max_debond_rounds;
  const bool adhesion = setup_.scene().interface.has_adhesion();
  for (int round = 1;; ++round) {
    // The caller's multiplier belongs to the first problem only: after breaks the rows change.
    Solution s = solve_fixed(sigma, current, warm.size() ? &warm : nullptr, round == 1 ? warm_multiplier : nullptr);
    // Bonds at their strength break, normal and tangential together (docs/method.md §11). No loop at
    // all without adhesion.
    std::vector<int> breaking;
    if (adhesion && s.qp_converged()) {
      const Constraints& con = problem(current).constraints();
      for (int r = 0; r < con.n_rows(); ++r) {
        if (!is_interface(con.kind[r]) || !current[con.pair[r]]) continue;
        if (law::bond::at_strength(s.lambda(r) / con.weight(r), {con.lower(r), con.upper(r)}))
          breaking.push_back(con.pair[r]);
      }
    }
    if (breaking.empty() || round >= max_rounds) {
      s.add_work(previous);
      total = std::move(s);
      total.debond_rounds = round;
      if (!breaking.empty()) {
        total.qp.message = "debonding did not settle within max_debond_rounds = " + std::to_string(max_rounds);
        total.qp.status = qp::Status::max_iterations;
      }
      break;
    }
    // Carry the multipliers of the rows that stay over to the next problem as a warm start.
    const Constraints& old = problem(current).constraints();
    for (int p : breaking) {
      newly_broken += current[p] ? 1 : 0;
      current[p] = 0;
    }
    const Constraints next = build_constraints(setup_.mesh(), setup_.scene(), current);
    warm.resize(next.n_rows());
    // Structural rows keep their order; interface rows are found by (kind, pair).
    std::map<std::pair<int, int>, double> by_key;
    for (int r = 0; r < old.n_rows(); ++r)
      by_key[{static_cast<int>(old.kind[r]), !is_interface(old.kind[r]) ? r : old.pair[r]}] = s.lambda(r);
    for (int r = 0; r < next.n_rows(); ++r) {
      const auto it = by_key.find({static_cast<int>(next.kind[r]), !is_interface(next.kind[r]) ? r : next.pair[r]});
      warm(r) = it == by_key.end()
                    ? 0.0
                    : std::clamp(it->second, next.lower(r) * next.weight(r), next.upper(r) * next.weight(r));
    }
    previous.add_work(s);
  }
  total.newly_broken = newly_broken;
  return total;
}

namespace {

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
  }
  return lifted_;
}

double ContactSolver::debond_onset(const Eigen::Vector3d& sigma, std::vector<int>* critical) {
  if (critical) critical->clear();
  if (!setup_.scene().interface.has_adhesion()) return std::numeric_limits<double>::infinity();
  Lifted& lifted = this->lifted();
  const Eigen::VectorXd &lower = lifted.lower, &upper = lifted.upper;
  const Solution s = solve_problem(*lifted.dual, lifted.norm_PFP, sigma, nullptr, nullptr,
                                   std::min(onset_qp_tolerance, setup_.scene().solver.tolerance));
  if (!s.converged()) return std::numeric_limits<double>::quiet_NaN();
  // The load factor at which row r reaches its bound (+inf where it never does along σ̄).
  const Constraints& c = lifted.dual->constraints();
  const auto reach = [&](int r) { return law::bond::reach(s.lambda(r) / c.weight(r), {lower(r), upper(r)}); };
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
  const Constraints& c = lifted.dual->constraints();
  // Row forces per unit stress: column j = λ(e_j) in force units.
  const int n_unit = setup_.scene().load.boundary == Boundary::symmetry ? 2 : 3;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(c.n_rows(), 3);
  for (int j = 0; j < n_unit; ++j) {
    const Solution s = solve_problem(*lifted.dual, lifted.norm_PFP, Eigen::Vector3d::Unit(j), nullptr, nullptr,
                                     std::min(onset_qp_tolerance, setup_.scene().solver.tolerance));
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
      rows.push_back(a.row(r).transpose() / bound);  // a·σ̄ ≥ ℓ (ℓ < 0) and a·σ̄ ≤ υ (υ > 0) alike: g·σ̄ ≤ 1
      out.pair.push_back(c.pair[r]);
      out.tangential.push_back(c.kind[r] == RowKind::tangential ? 1 : 0);
    }
  }
  out.facets.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) out.facets.row(static_cast<Eigen::Index>(k)) = rows[k].transpose();
  out.linear = true;
  return out;
}

}  // namespace dualcell::feti
