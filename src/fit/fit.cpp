#include "fit/fit.hpp"

#include <gsl/gsl_fit.h>
#include <gsl/gsl_multifit.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "core/error.hpp"
#include "core/error_tally.hpp"
#include "core/strain.hpp"
#include "core/version.hpp"
#include "fit/cone_fit.hpp"
#include "fit/small_ladder.hpp"

namespace dualcell::fit {

namespace {

// The compliance fit's design: a singular value below rank_cut of the largest is round-off (the
// directions do not determine that combination; the truncated SVD drops it alike), and an entry
// of S whose unit vector has at least undetermined_share in that null space is not determined
// (NaN) rather than set by round-off.
constexpr double rank_cut = 1e-10;
constexpr double undetermined_share = 1e-8;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// RAII for the GSL objects used here.
struct GslDelete {
  void operator()(gsl_matrix* m) const { gsl_matrix_free(m); }
  void operator()(gsl_vector* v) const { gsl_vector_free(v); }
  void operator()(gsl_multifit_linear_workspace* w) const { gsl_multifit_linear_free(w); }
};
template <typename T>
using Gsl = std::unique_ptr<T, GslDelete>;

struct LineFit {
  double slope = nan, slope_se = nan, r2 = nan;
  int n = 0;
};

// y = k x by least squares (gsl_fit_mul). se needs two points at least.
LineFit through_origin(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit fit;
  fit.n = static_cast<int>(x.size());
  if (x.empty()) return fit;
  double k = 0, cov = 0, sumsq = 0;
  gsl_fit_mul(x.data(), 1, y.data(), 1, x.size(), &k, &cov, &sumsq);
  double sum_y2 = 0;
  for (double v : y) sum_y2 += v * v;
  fit.slope = k;
  fit.slope_se = x.size() >= 2 ? std::sqrt(cov) : nan;
  fit.r2 = sum_y2 > 0 ? 1 - sumsq / sum_y2 : nan;
  return fit;
}

// y = c0 + c1 x (gsl_fit_linear); se needs three points at least.
LineFit with_intercept(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit fit;
  fit.n = static_cast<int>(x.size());
  if (x.size() < 2) return fit;
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(x.data(), 1, y.data(), 1, x.size(), &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  fit.slope = c1;
  fit.slope_se = x.size() >= 3 ? std::sqrt(cov11) : nan;
  return fit;
}

bool usable(const sweep::Step& s) { return s.broken_bonds == 0 && s.converged && s.load != 0; }

// Normal and transverse strain of a uniaxial path in direction θ.
std::pair<double, double> nn_tt(double theta_deg, const Eigen::Vector3d& e) {
  const double t = theta_deg * std::numbers::pi / 180, c = std::cos(t), s = std::sin(t);
  return {e(0) * c * c + e(1) * s * s + 2 * e(2) * c * s, e(0) * s * s + e(1) * c * c - 2 * e(2) * c * s};
}

// Fits the modulus and Poisson's ratio of one path; returns (E, se, r2, n, nu, nu_se).
void fit_path(const sweep::PathResult& p, double& E, double& E_se, double& r2, int& n, double& nu, double& nu_se) {
  std::vector<double> load, e_nn, e_tt;
  for (const auto& s : p.steps) {
    if (!usable(s)) continue;
    const auto [nn, tt] = nn_tt(p.spec.direction_deg, s.strain);
    load.push_back(s.load);
    e_nn.push_back(nn);
    e_tt.push_back(tt);
  }
  const LineFit compliance = through_origin(load, e_nn);
  n = compliance.n;
  E = compliance.slope != 0 ? 1 / compliance.slope : nan;
  E_se = compliance.slope_se / (compliance.slope * compliance.slope);
  r2 = compliance.r2;
  const LineFit poisson = through_origin(e_nn, e_tt);
  nu = -poisson.slope;
  nu_se = poisson.slope_se;
}

// S from all usable points of paths with the given sign.
law::ComplianceFit fit_compliance(const std::vector<sweep::PathResult>& paths, int sign,
                                  const std::vector<double>& directions) {
  law::ComplianceFit out;
  struct Point {
    Eigen::Vector3d N, e;  // normalised by the load: N = σ/s, e = ε_eng/s
    double direction;
  };
  std::vector<Point> points;
  for (const auto& p : paths) {
    // The sphere's paths have no tension or compression: they enter the cone-wise fit only.
    if (p.spec.sign != sign || p.spec.sphere) continue;
    for (const auto& s : p.steps) {
      if (!usable(s)) continue;
      points.push_back({s.stress / s.load, engineering_from_tensor(s.strain) / s.load, p.spec.direction_deg});
    }
  }
  out.n_points = static_cast<int>(points.size());
  out.direction_residual.assign(directions.size(), nan);
  if (points.empty()) return out;
  // Unknowns p = (S11, S22, S33, S12, S13, S23).
  const int rows = 3 * static_cast<int>(points.size());
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(rows, 6);
  Eigen::VectorXd y(rows);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& N = points[i].N;
    X.row(3 * i) << N(0), 0, 0, N(1), N(2), 0;
    X.row(3 * i + 1) << 0, N(1), 0, N(0), 0, N(2);
    X.row(3 * i + 2) << 0, 0, N(2), 0, N(0), N(1);
    y.segment<3>(3 * i) = points[i].e;
  }
  // Which entries the directions determine: those orthogonal to the null space of X.
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeFullV);
  int rank = 0;
  for (int j = 0; j < svd.singularValues().size(); ++j)
    rank += svd.singularValues()(j) > rank_cut * svd.singularValues()(0);
  out.rank = rank;
  const Eigen::MatrixXd null = svd.matrixV().rightCols(6 - rank);

  // GSL's SVD needs at least as many rows as unknowns (it aborts otherwise): one point gives 3,
  // so pad with zero rows, which change neither the solution nor the truncated SVD's rank.
  const int gsl_rows = std::max(rows, 6);
  Gsl<gsl_matrix> gX(gsl_matrix_calloc(gsl_rows, 6)), cov(gsl_matrix_alloc(6, 6));
  Gsl<gsl_vector> gy(gsl_vector_calloc(gsl_rows)), c(gsl_vector_alloc(6));
  for (int i = 0; i < rows; ++i) {
    gsl_vector_set(gy.get(), i, y(i));
    for (int j = 0; j < 6; ++j) gsl_matrix_set(gX.get(), i, j, X(i, j));
  }
  Gsl<gsl_multifit_linear_workspace> work(gsl_multifit_linear_alloc(gsl_rows, 6));
  double chisq = 0;
  if (rank == 6 && rows > 6) {
    gsl_multifit_linear(gX.get(), gy.get(), c.get(), cov.get(), &chisq, work.get());
  } else {
    size_t gsl_rank = 0;
    gsl_multifit_linear_tsvd(gX.get(), gy.get(), rank_cut, c.get(), cov.get(), &chisq, &gsl_rank, work.get());
  }
  Eigen::Matrix<double, 6, 1> p, p_se;
  for (int j = 0; j < 6; ++j) {
    const bool determined = null.cols() == 0 || null.row(j).lpNorm<Eigen::Infinity>() < undetermined_share;
    p(j) = determined ? gsl_vector_get(c.get(), j) : nan;
    // With as many equations as unknowns there is no residual to estimate an error from.
    p_se(j) = determined && rows > rank ? std::sqrt(gsl_matrix_get(cov.get(), j, j)) : nan;
  }
  auto symmetric = [](const Eigen::Matrix<double, 6, 1>& v) {
    Eigen::Matrix3d S;
    S << v(0), v(3), v(4), v(3), v(1), v(5), v(4), v(5), v(2);
    return S;
  };
  out.S = symmetric(p);
  out.S_se = symmetric(p_se);
  // Residuals with the determined part (undetermined entries multiply zero stresses).
  const Eigen::Matrix3d S0 = out.S.unaryExpr([](double v) { return std::isnan(v) ? 0.0 : v; });
  double r2 = 0, e2 = 0;
  std::map<double, std::pair<double, double>> per_direction;
  for (const auto& pt : points) {
    const double r = (pt.e - S0 * pt.N).squaredNorm(), e = pt.e.squaredNorm();
    r2 += r;
    e2 += e;
    if (!std::isnan(pt.direction)) {
      per_direction[pt.direction].first += r;
      per_direction[pt.direction].second += e;
    }
  }
  out.relative_residual = e2 > 0 ? std::sqrt(r2 / e2) : nan;
  for (std::size_t d = 0; d < directions.size(); ++d) {
    const auto it = per_direction.find(directions[d]);
    if (it != per_direction.end() && it->second.second > 0)
      out.direction_residual[d] = std::sqrt(it->second.first / it->second.second);
  }
  if (rank == 6) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(out.S, Eigen::EigenvaluesOnly);
    out.symmetric_positive_definite = eig.eigenvalues().minCoeff() > 0;
  }
  return out;
}

}  // namespace

namespace {

// The moduli, Poisson ratios and fuse figures of one uniaxial direction θ from its paths.
law::DirectionLaw fit_direction(const std::vector<sweep::PathResult>& paths, double theta) {
  law::DirectionLaw d;
  d.direction_deg = theta;
  d.E_tension = d.E_tension_se = d.E_tension_r2 = nan;
  d.E_compression = d.E_compression_se = d.E_compression_r2 = nan;
  d.nu_tension = d.nu_tension_se = d.nu_compression = d.nu_compression_se = nan;
  d.onset_stress = d.fuse_stress = d.fuse_stress_after = d.fuse_strain_jump = d.fuse_strain_ratio = nan;
  d.E_after_fuse = d.E_after_fuse_se = nan;
  for (const auto& p : paths) {
    if (p.spec.direction_deg != theta) continue;
    if (!(p.spec.sign > 0)) {
      fit_path(p, d.E_compression, d.E_compression_se, d.E_compression_r2, d.n_compression, d.nu_compression,
               d.nu_compression_se);
      continue;
    }
    fit_path(p, d.E_tension, d.E_tension_se, d.E_tension_r2, d.n_tension, d.nu_tension, d.nu_tension_se);
    if (!p.fuse) continue;
    // The tension fuse: the largest jump of the path.
    const auto& f = *p.fuse;
    const double before = nn_tt(theta, f.strain_before).first, after = nn_tt(theta, f.strain_after).first;
    d.onset_stress = f.onset_load;
    d.fuse_stress = f.load_before;
    d.fuse_stress_after = f.load_after;
    d.fuse_strain_jump = after - before;
    d.fuse_strain_ratio = before != 0 ? after / before : nan;
    std::vector<double> e_nn, load;
    for (const auto& s : p.steps)
      if (s.load >= f.load_after && s.converged) {
        e_nn.push_back(nn_tt(theta, s.strain).first);
        load.push_back(s.load);
      }
    const LineFit tangent = with_intercept(e_nn, load);
    d.E_after_fuse = tangent.slope;
    d.E_after_fuse_se = tangent.slope_se;
  }
  return d;
}

// Cone-wise linear form (§14): is the stiffness jump C_t − C_c rank-one? Sets the ratio of its
// second to its largest eigenvalue, the normal and β of the largest.
void rank_one_test(law::Law& law) {
  law.cone_rank_one_ratio = nan;
  if (!law.tension.symmetric_positive_definite || !law.compression.symmetric_positive_definite) return;
  const Eigen::Matrix3d dC = law.tension.S.inverse() - law.compression.S.inverse();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(dC);
  int first = 0;
  for (int j = 1; j < 3; ++j)
    if (std::abs(eig.eigenvalues()(j)) > std::abs(eig.eigenvalues()(first))) first = j;
  double second = 0;
  for (int j = 0; j < 3; ++j)
    if (j != first) second = std::max(second, std::abs(eig.eigenvalues()(j)));
  const double largest = std::abs(eig.eigenvalues()(first));
  law.cone_rank_one_ratio = largest > 0 ? second / largest : nan;
  law.cone_normal = eig.eigenvectors().col(first);
  law.cone_beta = eig.eigenvalues()(first);
  law.cone_wise_linear = law.cone_rank_one_ratio < 0.05;
}

// The stress directions at which a compact law is checked against the exact law (about as many
// on the sphere; law::sample_cell).
constexpr int check_directions = 1000;

// Law::small_note when the fit was asked for no small cell.
constexpr const char* not_asked = "not asked for (dualcell-fit --no-small-cell)";

// With the exact law: the compact laws measured against it, fitted to it as well, and for each
// the one that misses it least (measured on directions other than those it was fitted to) kept;
// the law past the fuse likewise against the exact law past the fuse (with adhesion).
void check_against_cell(law::Law& law, const std::vector<ConePoint>& bonded, const std::vector<ConePoint>& debonded,
                        int n_directions, const FitOptions& options, Progress* progress) {
  const auto keep_better = [&](law::ConeFit& cone, law::ConeCheck& kept, const law::CellSample& sample,
                               law::ConeFit from_cell) {
    if (cone.ok) kept = law::check_cone(cone.law, sample);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double sweep_fit_max = cone.ok ? kept.max_error : nan, sweep_fit_rms = cone.ok ? kept.rms_error : nan;
    if (from_cell.ok) {
      const law::ConeCheck check = law::check_cone(from_cell.law, sample);
      if (!cone.ok || check.max_error < kept.max_error) {
        from_cell.one_plane_residual = cone.one_plane_residual;  // the sweep's forms, as tried
        from_cell.struts_residual = cone.struts_residual;
        cone = from_cell;
        kept = check;
      }
    }
    kept.sweep_fit_max_error = sweep_fit_max;
    kept.sweep_fit_rms_error = sweep_fit_rms;
  };
  const law::CondensedCell& cell = *law.cell;
  const law::CellSample check = law::sample_cell(cell, check_directions, progress);
  keep_better(law.cone, law.cone_check, check, fit_cone_to_cell(cell, bonded, n_directions, Fitted::bonded));
  // Past the fuse each direction runs its cascade, tens of factorisations (0.025 s at 256 rows),
  // so fewer directions: about 280 to check and others to fit (no direction in common), as many
  // as give the small cell's small_cell_directions with their images under the cell's
  // symmetries, at least 250 (with the square cell's four symmetries 366 directions, 1 464 with
  // their images). The cone-wise law after the fuse and the small cell with a fuse are fitted to
  // the same paths. (Images stand in for directions at a quarter of the cost, but not fully: at
  // 250 directions, 1 000 with images, the default cell's small cell missed the check by 7.6 %,
  // at 366 by 6.3 %, as at 1 002 directions without images, 6.4 %.)
  constexpr int past_fuse_check_directions = 300, fit_directions = 250;
  std::optional<law::CellSample> past_fuse, past_fuse_paths;
  std::vector<Eigen::Matrix3d> group = {Eigen::Matrix3d::Identity()};
  if (cell.adhesion() && law.onset.linear) {
    past_fuse = law::sample_cell_past_fuse(cell, past_fuse_check_directions, law::past_fuse_load_ratio, progress);
    group = cell_symmetries(cell, law::sample_cell(cell, fit_directions, progress));
    const int images = static_cast<int>(group.size());
    past_fuse_paths =
        law::sample_cell_past_fuse(cell, std::max(fit_directions, (small_cell_directions + images - 1) / images),
                                   law::past_fuse_load_ratio, progress);
  }
  if (options.small_cell)
    fit_small(law, check, past_fuse ? &*past_fuse : nullptr, past_fuse_paths ? &*past_fuse_paths : nullptr, group,
              options.law_tolerance, progress);
  else
    law.small_note = not_asked;
  if (!law.cone_check.directions.empty()) law.cone_check.polar = law::exact_polar(cell);
  if (cell.adhesion() && law.cone_after_fuse.ok)
    keep_better(law.cone_after_fuse, law.cone_after_fuse_check,
                past_fuse
                    ? *past_fuse
                    : law::sample_cell_past_fuse(cell, past_fuse_check_directions, law::past_fuse_load_ratio, progress),
                fit_cone_to_cell(cell, debonded, n_directions, Fitted::past_fuse, fit_directions,
                                 past_fuse_paths ? &*past_fuse_paths : nullptr, past_fuse_paths ? &group : nullptr));
}

// Where the exact law is too large to sample (or missing) the sweep built the cell on a basis of
// its own solutions (SweepHeader::cell_basis) for a scene with sphere paths. Every
// held_out_every-th sphere path (fewer paths: as many as leave min_held_out) is then held out of
// both compact laws: the cone-wise law is fitted to the other points, the small cell starts from
// the basis cell and is fitted to them, and both are measured at the held-out paths' full solves
// (docs/method.md §16c). False (nothing done) without a basis cell or with too few sphere paths.
bool check_against_solves(law::Law& law, const std::vector<sweep::PathResult>& paths, const sweep::SweepHeader& header,
                          const std::vector<double>& directions, const Eigen::Vector3d& guess,
                          const FitOptions& options, Progress* progress) {
  std::vector<const sweep::PathResult*> sphere;
  for (const auto& p : paths)
    if (p.spec.sphere) sphere.push_back(&p);
  const int every = std::min(held_out_every, static_cast<int>(sphere.size()) / min_held_out);
  if (!header.cell_basis || every < 2) return false;
  std::vector<const sweep::PathResult*> held;
  for (std::size_t i = 0; i < sphere.size(); ++i)
    if (static_cast<int>(i % every) == every / 2) held.push_back(sphere[i]);
  std::vector<ConePoint> fitted;
  law::CellSample training, check;
  for (const auto& p : paths) {
    const bool held_out = std::find(held.begin(), held.end(), &p) != held.end();
    const auto at = std::find(directions.begin(), directions.end(), p.spec.direction_deg);
    const int index = at == directions.end() ? -1 : static_cast<int>(at - directions.begin());
    for (const auto& s : p.steps) {
      if (!s.converged || s.load == 0 || !usable(s)) continue;
      const ConePoint point{engineering_from_tensor(s.strain), s.stress, index};
      law::CellSample& sample = held_out ? check : training;
      sample.direction.push_back(s.stress.normalized());
      sample.strain.push_back(point.strain);
      sample.stress.push_back(s.stress);
      if (!held_out) fitted.push_back(point);
    }
  }
  law.cone = fit_cone(fitted, static_cast<int>(directions.size()), guess);
  if (law.cone.ok) {
    law.cone_check = law::check_cone(law.cone.law, check);
    law.cone_check.against = law::CheckedAgainst::held_out_solves;
  }
  if (!options.small_cell) {
    law.small_note = not_asked;
    return true;
  }
  const law::CondensedCell& basis = *header.cell_basis;
  const law::CellSample start = law::sample_cell(basis, small_cell_directions, progress);
  fit_small_ladder(law, basis, training, &start, check, law::CheckedAgainst::held_out_solves, options.law_tolerance, {},
                   progress);
  return true;
}

// Without an exact law the compact law is measured on the sweep's own points: each uniaxial
// direction (both signs) held out in turn, the law refitted to the others and evaluated at the
// held-out strains (law::check_cone), so every error is at points the law was not built from.
// The refit starts, as the fit does, from the rank-one normal of the compliances, here fitted
// without the held-out paths: nothing of them enters the law evaluated on them. A direction
// whose refit fails counts as an unbounded error (the law cannot be vouched for there); with one
// direction only there is nothing to hold out and the check stays empty.
law::ConeCheck check_held_out(const std::vector<sweep::PathResult>& paths, const std::vector<double>& directions,
                              const std::vector<ConePoint>& points) {
  const int n_directions = static_cast<int>(directions.size());
  law::ConeCheck check;
  check.against = law::CheckedAgainst::held_out_directions;
  if (n_directions < 2) return check;
  ErrorTally tally;
  for (int d = 0; d < n_directions; ++d) {
    std::vector<ConePoint> others;
    law::CellSample held;
    for (const ConePoint& p : points) {
      if (p.direction != d) {
        others.push_back(p);
        continue;
      }
      held.direction.push_back(p.stress.normalized());
      held.strain.push_back(p.strain);
      held.stress.push_back(p.stress);
    }
    if (held.direction.empty()) continue;
    std::vector<sweep::PathResult> other_paths;
    for (const auto& p : paths)
      if (p.spec.direction_deg != directions[d]) other_paths.push_back(p);
    std::vector<double> other_directions = directions;
    other_directions.erase(other_directions.begin() + d);
    law::Law without;
    without.tension = fit_compliance(other_paths, +1, other_directions);
    without.compression = fit_compliance(other_paths, -1, other_directions);
    rank_one_test(without);
    const Eigen::Vector3d guess = without.cone_normal.allFinite() ? without.cone_normal : Eigen::Vector3d::Zero();
    const law::ConeFit refit = fit_cone(others, n_directions, guess);
    const law::ConeCheck part = refit.ok ? law::check_cone(refit.law, held) : law::ConeCheck{};
    for (std::size_t i = 0; i < held.direction.size(); ++i) {
      const double error = refit.ok ? part.error[i] : std::numeric_limits<double>::infinity();
      check.directions.push_back(held.direction[i]);
      check.error.push_back(error);
      if (std::isnan(error)) continue;  // no point of the sweep there: not counted
      if (tally.add(error)) check.worst = held.direction[i];
    }
  }
  check.max_error = tally.max_error();
  check.rms_error = tally.rms_error();
  return check;
}

}  // namespace

law::Law fit_law(const std::vector<sweep::PathResult>& all_paths, const sweep::SweepHeader& header,
                 const FitOptions& options, Progress* progress) {
  const int checked_rows = options.checked_rows;
  law::Law law;
  // The fitted forms are in-plane: the paths with a strain or shears along the fibres check the
  // exact law only (its replay).
  std::vector<sweep::PathResult> paths;
  for (const sweep::PathResult& p : all_paths)
    if (p.spec.in_plane()) paths.push_back(p);
  std::vector<double> directions;
  for (const auto& p : paths)
    if (!std::isnan(p.spec.direction_deg)) directions.push_back(p.spec.direction_deg);
  std::sort(directions.begin(), directions.end());
  directions.erase(std::unique(directions.begin(), directions.end()), directions.end());
  if (directions.empty())
    throw InputError("the sweep has no uniaxial path (every path's direction_deg is NaN): no direction to fit");
  for (double theta : directions) law.directions.push_back(fit_direction(paths, theta));
  law.tension = fit_compliance(paths, +1, directions);
  law.compression = fit_compliance(paths, -1, directions);
  rank_one_test(law);

  // The cone-wise law over every point before any break, and over the points past each path's
  // largest jump (law/cone.hpp): engineering shear, per-direction residuals by the direction's
  // index (general stress paths, direction NaN, count in the overall residual only).
  std::vector<ConePoint> bonded, debonded;
  for (const auto& p : paths) {
    const auto at = std::find(directions.begin(), directions.end(), p.spec.direction_deg);
    const int index = at == directions.end() ? -1 : static_cast<int>(at - directions.begin());
    for (const auto& s : p.steps) {
      if (!s.converged || s.load == 0) continue;
      const ConePoint point{engineering_from_tensor(s.strain), s.stress, index};
      if (usable(s)) bonded.push_back(point);
      if (p.fuse && s.load >= p.fuse->load_after) debonded.push_back(point);
    }
  }
  const int n_directions = static_cast<int>(directions.size());
  const Eigen::Vector3d guess = law.cone_normal.allFinite() ? law.cone_normal : Eigen::Vector3d::Zero();
  law.cone = fit_cone(bonded, n_directions, guess);
  law.cone_after_fuse = fit_cone(debonded, n_directions, guess);

  // The onset surface, checked against the onset each path solved for itself (a separate
  // solve along that path's stress).
  law.onset = header.onset;
  if (law.onset.linear) {
    for (const auto& p : paths) {
      const Eigen::Vector3d N = p.spec.sign * p.spec.state.in_plane();
      law.onset.path_stress.push_back(N);
      law.onset.path_onset.push_back(law::onset_along(law.onset, N));
      law.onset.path_sweep_onset.push_back(p.fuse ? std::abs(p.fuse->onset_load) : nan);
    }
  }

  law.cell = header.cell;
  law.cell_note = header.cell_note;
  law.ply.expansion = header.expansion;
  if (law.cell) {
    try {
      law.cell_replay = replay_cell(*law.cell, all_paths, header.qp_tolerance,
                                    replay_stride(all_paths, law.cell->n_rows(), checked_rows));
      if (law.cell->longitudinal == 1)
        law.cell_longitudinal_replay = replay_longitudinal(*law.cell, header.longitudinal_points, header.qp_tolerance);
      if (law.cell->shear == 2)
        law.cell_shear_replay = replay_shear(*law.cell, header.shear_points, header.qp_tolerance);
      law.ply = law::ply_constants(*law.cell);
      law.ply.expansion = header.expansion;
      // A temperature change the sweep checked (the bonded ply's expansion from full solves,
      // which needs bonds and the strain along the fibres) is kept with its check; one it could
      // not check (a contact or a transverse cell) is left out of the law (the summary says so).
      if (law.cell->thermal == 1 && law.cell->longitudinal == 1 && header.expansion.ok) {
        law.cell_thermal_replay = replay_expansion(*law.cell, header.expansion, header.qp_tolerance);
      } else if (law.cell->thermal == 1) {
        law.cell->thermal = 0;
        law.cell->AT.resize(0, 0), law.cell->CT.resize(0, 0), law.cell->yT.resize(0, 0);
      }
    } catch (const ExactLawFailed& e) {
      // The condensation may be right and its QP still beyond the dense method (an RVE of many
      // hundred interface rows): the law is not kept, and the file says why.
      law.cell.reset();
      law.cell_note = e.what();
    }
  }
  // The dense check samples the exact law at ~1800 directions (check and fit, more past the
  // fuse), each a dense QP whose factorisations cost n³: 1.5–3 min at the 700 rows of a 16-fibre
  // RVE, over 16 min at the ~1500 of a 36-fibre one. Above checked_rows the exact law is
  // kept (replayed above) and the compact law measured on held-out directions instead.
  if (law.cell && law.cell->n_rows() <= checked_rows) {
    check_against_cell(law, bonded, debonded, n_directions, options, progress);
  } else if (check_against_solves(law, paths, header, directions, guess, options, progress)) {
    if (law.cone_after_fuse.ok) law.cone_after_fuse_check = check_held_out(paths, directions, debonded);
  } else {
    law.small_note = law.cell ? "the exact law has " + std::to_string(law.cell->n_rows()) +
                                    " rows, above the dense check's " + std::to_string(checked_rows) +
                                    ": too costly to sample for a small cell"
                              : "no exact law to fit it to (" + law.cell_note + ")";
    if (law.cone.ok) law.cone_check = check_held_out(paths, directions, bonded);
    if (law.cone_after_fuse.ok) law.cone_after_fuse_check = check_held_out(paths, directions, debonded);
  }
  // The compact laws' curves for the polar picture, from the laws kept (derived data, stored by
  // the fit so that no writer or picture re-implements a law).
  for (law::ConeFit* fit : {&law.cone, &law.cone_after_fuse})
    if (fit->ok) fit->polar = law::cone_polar(fit->law);
  law.constituents = header.constituents;
  law.provenance = header.provenance;
  law.provenance.code_version = code_version;  // the fit's
  return law;
}

}  // namespace dualcell::fit
