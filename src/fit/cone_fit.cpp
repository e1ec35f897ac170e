#include "fit/cone_fit.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "core/directions.hpp"
#include "law/cone_check.hpp"
#include "qp/dense_qp.hpp"

namespace dualcell::fit {

namespace {

// The fit's round-off cuts, relative to unit vectors or to the terms they compare:
// - spd_floor: a stiffness's eigenvalues floored at this fraction of the largest, so that it has
//   a Cholesky factor;
// - nlinear_*: GSL's trust-region driver on the one-plane form (steps, gradient and cost);
// - nnls_round_off: a gradient entry of the nonnegative least squares below this share of ‖A‖‖b‖;
// - same_direction: two points' strain directions within this are one direction (a path's
//   points repeat the same three equations);
// - same_normal: two unit plane normals within this are the same (an orbit's images computed by
//   rotations differ by round-off only); same_matrix likewise two symmetries of the cell;
// - tie: the struts win only when they lower the cost by more than this fraction.
constexpr double spd_floor = 1e-6;
constexpr int nlinear_max_iterations = 500;
constexpr double nlinear_tolerance = 1e-12;
constexpr double nnls_round_off = 1e-12;
constexpr double same_direction = 1e-6;
constexpr double same_normal = 1e-9;
constexpr double same_matrix = 1e-12;
constexpr double tie = 1e-9;

constexpr int n_parameters = 9;

law::ConeLaw law_of(const double* p) {
  Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
  L(0, 0) = std::exp(p[0]);
  L(1, 0) = p[1];
  L(1, 1) = std::exp(p[2]);
  L(2, 0) = p[3];
  L(2, 1) = p[4];
  L(2, 2) = std::exp(p[5]);
  law::ConeLaw law;
  law.C_c = L * L.transpose();
  law.q = {{std::sin(p[6]) * std::cos(p[7]), std::sin(p[6]) * std::sin(p[7]), std::cos(p[6])}};
  law.beta = {p[8] * p[8]};
  return law;
}

// Parameters of C_c (its Cholesky factor), the unit vector c and β.
void parameters_of(const Eigen::Matrix3d& C, const Eigen::Vector3d& c, double beta, double* p) {
  const Eigen::Matrix3d L = C.llt().matrixL();
  p[0] = std::log(L(0, 0)), p[1] = L(1, 0), p[2] = std::log(L(1, 1));
  p[3] = L(2, 0), p[4] = L(2, 1), p[5] = std::log(L(2, 2));
  const Eigen::Vector3d u = c.normalized();
  p[6] = std::acos(std::clamp(u(2), -1.0, 1.0));
  p[7] = std::atan2(u(1), u(0));
  p[8] = std::sqrt(beta);
}

struct Data {
  const std::vector<ConePoint>* points;
};

int residuals(const gsl_vector* x, void* params, gsl_vector* f) {
  const auto& points = *static_cast<Data*>(params)->points;
  const law::ConeLaw law = law_of(x->data);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double scale = points[i].stress.norm();
    const Eigen::Vector3d r = (law::evaluate(law, points[i].strain).stress - points[i].stress) / scale;
    for (int k = 0; k < 3; ++k) gsl_vector_set(f, 3 * i + k, r(k));
  }
  return GSL_SUCCESS;
}

struct WorkspaceDelete {
  void operator()(gsl_multifit_nlinear_workspace* w) const { gsl_multifit_nlinear_free(w); }
};

// Sum of squared relative residuals of a law.
double cost(const std::vector<ConePoint>& points, const law::ConeLaw& law) {
  double sum = 0;
  for (const auto& p : points)
    sum += (law::evaluate(law, p.strain).stress - p.stress).squaredNorm() / p.stress.squaredNorm();
  return sum;
}

// The linear least-squares fit of all points, σ = C₀ε (rows weighted by 1/|σ_i|), symmetrised,
// its eigenvalues floored at 1e-6 of the largest so that it has a Cholesky factor.
Eigen::Matrix3d linear_fit(const std::vector<ConePoint>& points) {
  Eigen::MatrixXd A(points.size(), 3);
  Eigen::MatrixXd B(points.size(), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double w = 1 / points[i].stress.norm();
    A.row(i) = w * points[i].strain.transpose();
    B.row(i) = w * points[i].stress.transpose();
  }
  Eigen::Matrix3d C0 = A.colPivHouseholderQr().solve(B).transpose();
  C0 = 0.5 * (C0 + C0.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C0);
  const double top = std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(spd_floor * top).asDiagonal() * eig.eigenvectors().transpose();
}

// One free plane: GSL nlinear from 64 starting normals (and the guess); the smallest admissible
// cost, or +inf.
double fit_one_plane(const std::vector<ConePoint>& points, const Eigen::Vector3d& guess, law::ConeLaw& best_law) {
  const Eigen::Matrix3d C0 = linear_fit(points);
  if (!C0.allFinite()) return std::numeric_limits<double>::infinity();
  // Starting normals: 64 Fibonacci points on the unit sphere, and the caller's guess.
  std::vector<Eigen::Vector3d> starts;
  constexpr int n_starts = 64;
  for (int k = 0; k < n_starts; ++k) {
    const double z = 1 - (2 * k + 1.0) / n_starts, r = std::sqrt(1 - z * z);
    const double phi = k * std::numbers::pi * (3 - std::sqrt(5.0));
    starts.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  if (guess.norm() > 0 && guess.allFinite()) starts.push_back(guess.normalized());

  gsl_set_error_handler_off();  // statuses are checked; GSL must not abort the process
  gsl_multifit_nlinear_parameters settings = gsl_multifit_nlinear_default_parameters();
  const std::size_t n = 3 * points.size();
  std::unique_ptr<gsl_multifit_nlinear_workspace, WorkspaceDelete> w(
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &settings, n, n_parameters));
  Data data{&points};
  gsl_multifit_nlinear_fdf fdf{};
  fdf.f = residuals;
  fdf.n = n;
  fdf.p = n_parameters;
  fdf.params = &data;

  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : starts) {
    double p[n_parameters];
    parameters_of(C0, c, 0.1 * C0.trace() / 3, p);
    gsl_vector_view x = gsl_vector_view_array(p, n_parameters);
    if (gsl_multifit_nlinear_init(&x.vector, &fdf, w.get()) != GSL_SUCCESS) continue;
    int info = 0;
    gsl_multifit_nlinear_driver(nlinear_max_iterations, nlinear_tolerance, nlinear_tolerance, nlinear_tolerance,
                                nullptr, nullptr, &info, w.get());
    const law::ConeLaw candidate = law_of(gsl_multifit_nlinear_position(w.get())->data);
    const double c_value = cost(points, candidate);
    if (std::isfinite(c_value) && c_value < best && law::admissibility_problem(candidate).empty()) {
      best = c_value;
      best_law = candidate;
    }
  }
  return best;
}

// min ‖Ax − b‖ subject to x ≥ 0 (the active-set method of docs/method.md §14): columns enter the
// passive set by the largest gradient and leave when an interpolation step would make them
// negative. Finite; each subproblem a small dense least-squares solve.
Eigen::VectorXd nonnegative_least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const Eigen::Index n = A.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(n, false);
  const double tolerance = nnls_round_off * std::max(A.norm() * b.norm(), 1e-300);
  const auto solve_passive = [&] {
    std::vector<Eigen::Index> columns;
    for (Eigen::Index j = 0; j < n; ++j)
      if (passive[j]) columns.push_back(j);
    Eigen::MatrixXd Ap(A.rows(), static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < columns.size(); ++k) Ap.col(static_cast<Eigen::Index>(k)) = A.col(columns[k]);
    const Eigen::VectorXd zp = Ap.colPivHouseholderQr().solve(b);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < columns.size(); ++k) z(columns[k]) = zp(static_cast<Eigen::Index>(k));
    return z;
  };
  for (Eigen::Index outer = 0; outer < 3 * n; ++outer) {
    const Eigen::VectorXd gradient = A.transpose() * (b - A * x);
    Eigen::Index entering = -1;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[j] && gradient(j) > tolerance && (entering < 0 || gradient(j) > gradient(entering))) entering = j;
    if (entering < 0) break;
    passive[entering] = true;
    for (Eigen::Index inner = 0; inner < 3 * n; ++inner) {
      const Eigen::VectorXd z = solve_passive();
      double alpha = 1;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[j] && z(j) <= 0) alpha = std::min(alpha, x(j) / (x(j) - z(j)));
      x += alpha * (z - x);
      if (alpha == 1) break;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[j] && x(j) <= 0) passive[j] = false, x(j) = 0;
    }
  }
  return x;
}

// Fixed planes q_k: σ(ε) is linear in the unknowns (the six entries of a symmetric C_c and β_k),
// so the fit is a least-squares problem with β ≥ 0: C_c eliminated by its QR projection, β by
// nonnegative least squares, then C_c from β. Only the planes with β_k > 0 are kept (the
// law::max_planes largest, refitted, where more are in use); a law whose C_c is not positive
// definite is refused (+inf). Returns the cost Σ r_i².
double fit_planes(const std::vector<ConePoint>& points, const std::vector<Eigen::Vector3d>& normals,
                  law::ConeLaw& out) {
  const int n_planes = static_cast<int>(normals.size());
  // Unknowns: C_c entries (0,0), (0,1), (0,2), (1,1), (1,2), (2,2), then β_k.
  constexpr int entries[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  const Eigen::Index rows = 3 * static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, 6 + n_planes);
  Eigen::VectorXd b(rows);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double w = 1 / points[i].stress.norm();
    const Eigen::Vector3d& e = points[i].strain;
    const Eigen::Index r = 3 * static_cast<Eigen::Index>(i);
    for (int j = 0; j < 6; ++j) {
      const int a = entries[j][0], c = entries[j][1];
      A(r + a, j) += w * e(c);
      if (a != c) A(r + c, j) += w * e(a);
    }
    for (int k = 0; k < n_planes; ++k) A.block<3, 1>(r, 6 + k) = w * std::max(normals[k].dot(e), 0.0) * normals[k];
    b.segment<3>(r) = w * points[i].stress;
  }
  const Eigen::MatrixXd A_C = A.leftCols(6), A_beta = A.rightCols(n_planes);
  Eigen::VectorXd beta, entry(6);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A_C);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(rows, 6);
  beta = nonnegative_least_squares(A_beta - Q * (Q.transpose() * A_beta), b - Q * (Q.transpose() * b));
  entry = A_C.colPivHouseholderQr().solve(b - A_beta * beta);
  // More planes in use than a law may have: the ones that add the most stiffness, refitted.
  if ((beta.array() > 0).count() > law::max_planes) {
    std::vector<int> order(n_planes);
    for (int k = 0; k < n_planes; ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](int a, int c) { return beta(a) > beta(c); });
    std::vector<Eigen::Vector3d> kept;
    for (int k = 0; k < law::max_planes; ++k) kept.push_back(normals[order[k]]);
    return fit_planes(points, kept, out);
  }
  law::ConeLaw law;
  for (int j = 0; j < 6; ++j) law.C_c(entries[j][0], entries[j][1]) = law.C_c(entries[j][1], entries[j][0]) = entry(j);
  law.q.clear();
  law.beta.clear();
  for (int k = 0; k < n_planes; ++k)
    if (beta(k) > 0) law.q.push_back(normals[k]), law.beta.push_back(beta(k));
  if (law.q.empty()) law.q = {normals[0]}, law.beta = {0.0};
  if (!law::admissibility_problem(law).empty()) return std::numeric_limits<double>::infinity();
  out = law;
  return cost(points, law);
}

// The compression struts: planes q_k = −n_k⊗n_k/|n_k⊗n_k| (engineering shear: (cos², sin²,
// cos·sin)) at θ_k = kπ/12.
double fit_struts(const std::vector<ConePoint>& points, law::ConeLaw& out) {
  constexpr int n_struts = 12;
  // Identifiable only with more equations than unknowns (6 + 12) from distinct strain
  // directions: points along one direction (a path without adhesion is positively
  // homogeneous) repeat the same three equations.
  std::vector<Eigen::Vector3d> distinct;
  for (const auto& p : points) {
    const Eigen::Vector3d u = p.strain.normalized();
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](const Eigen::Vector3d& v) { return (u - v).norm() < same_direction; }))
      distinct.push_back(u);
  }
  if (3 * distinct.size() <= 6 + n_struts) return std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> normals;
  for (int k = 0; k < n_struts; ++k) {
    normals.push_back(-uniaxial_stress(k * std::numbers::pi / n_struts).normalized());
  }
  return fit_planes(points, normals, out);
}

// The residual of out.law per load direction of the points.
void set_direction_residuals(const std::vector<ConePoint>& points, law::ConeFit& out) {
  const int n_directions = static_cast<int>(out.direction_residual.size());
  std::vector<double> sum(n_directions, 0.0);
  std::vector<int> count(n_directions, 0);
  for (const auto& p : points) {
    if (p.direction < 0 || p.direction >= n_directions) continue;
    sum[p.direction] += (law::evaluate(out.law, p.strain).stress - p.stress).squaredNorm() / p.stress.squaredNorm();
    ++count[p.direction];
  }
  for (int d = 0; d < n_directions; ++d)
    if (count[d] > 0) out.direction_residual[d] = std::sqrt(sum[d] / count[d]);
}

}  // namespace

// One is kept when the law maps about 24 evenly spaced sampled states onto their images: ε̄(Rσ̄) = R ε̄(σ̄) to 1e-8
// (the QP's round-off is 1e-11; a cell off its symmetry, an off-centre fibre or a 2 × 1 block,
// misses by far more).
std::vector<Eigen::Matrix3d> cell_symmetries(const law::CondensedCell& cell, const law::CellSample& sample) {
  if (cell.n_macro != 3) return {Eigen::Matrix3d::Identity()};
  Eigen::Matrix3d flip = Eigen::Vector3d(1, 1, -1).asDiagonal(), swap;
  swap << 0, 1, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d candidates[] = {
      flip, swap, swap * flip, flip * swap, swap * flip * swap, flip * swap * flip, swap * flip * swap * flip};
  std::vector<Eigen::Matrix3d> group = {I};
  law::CellEvaluator law(cell);
  for (const Eigen::Matrix3d& R : candidates) {
    bool holds = true;
    for (std::size_t i = 0; holds && i < sample.stress.size();
         i += std::max<std::size_t>(1, sample.stress.size() / 24)) {
      law::CellHistory h = law.unloaded();
      const law::CellResponse r = law.at_stress(R * sample.stress[i], h);
      holds = r.ok && (r.strain - R * sample.strain[i]).norm() <= 1e-8 * sample.strain[i].norm();
    }
    if (!holds) continue;
    bool known = false;
    for (const auto& G : group) known = known || (G - R).norm() < same_matrix;
    if (!known) group.push_back(R);
  }
  return group;
}

namespace {

// σ(ε) = C ε + Σ_orbits β_o Σ_{q ∈ o} ⟨q·ε⟩₊ q with C fixed and β ≥ 0: one β per orbit of
// planes under the cell's symmetries, so that the law has them too. Nonnegative least squares on
// the normal equations (orbits² numbers, not rows × orbits) by the exact active-set method, each
// row weighted by 1/|σ_i|. Where the orbits in use have more than law::max_planes planes, the
// orbits that add the most stiffness are kept and refitted. Returns the cost Σ r_i², +inf when
// the method fails.
double fit_plane_orbits(const std::vector<ConePoint>& points, const std::vector<std::vector<Eigen::Vector3d>>& orbits,
                        const Eigen::Matrix3d& C, law::ConeLaw& out) {
  const int n_orbits = static_cast<int>(orbits.size());
  const Eigen::Index rows = 3 * static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, n_orbits);
  Eigen::VectorXd b(rows);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double w = 1 / points[i].stress.norm();
    const Eigen::Vector3d& e = points[i].strain;
    const Eigen::Index r = 3 * static_cast<Eigen::Index>(i);
    for (int o = 0; o < n_orbits; ++o)
      for (const Eigen::Vector3d& q : orbits[o]) A.block<3, 1>(r, o) += w * std::max(q.dot(e), 0.0) * q;
    b.segment<3>(r) = w * (points[i].stress - C * e);
  }
  const Eigen::MatrixXd gram = A.transpose() * A;
  const Eigen::VectorXd rhs = A.transpose() * b;
  std::vector<qp::Bound> active(n_orbits, qp::Bound::lower);
  const Eigen::MatrixXd no_rows(0, n_orbits);
  qp::DenseActiveSet nnls(gram, no_rows);
  const qp::DenseQpResult r =
      nnls.solve(rhs, Eigen::VectorXd::Zero(n_orbits),
                 Eigen::VectorXd::Constant(n_orbits, std::numeric_limits<double>::infinity()), active);
  if (!r.converged) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd beta = r.x.cwiseMax(0.0);
  std::size_t planes = 0;
  for (int o = 0; o < n_orbits; ++o) planes += beta(o) > 0 ? orbits[o].size() : 0;
  if (planes > static_cast<std::size_t>(law::max_planes)) {
    std::vector<int> order(n_orbits);
    for (int o = 0; o < n_orbits; ++o) order[o] = o;
    std::sort(order.begin(), order.end(), [&](int a, int c) { return beta(a) > beta(c); });
    std::vector<std::vector<Eigen::Vector3d>> kept;
    std::size_t count = 0;
    for (int o : order) {
      if (!(beta(o) > 0) || count + orbits[o].size() > static_cast<std::size_t>(law::max_planes)) continue;
      kept.push_back(orbits[o]);
      count += orbits[o].size();
    }
    return fit_plane_orbits(points, kept, C, out);
  }
  law::ConeLaw law;
  law.C_c = C;
  law.q.clear();
  law.beta.clear();
  for (int o = 0; o < n_orbits; ++o)
    if (beta(o) > 0)
      for (const Eigen::Vector3d& q : orbits[o]) law.q.push_back(q), law.beta.push_back(beta(o));
  if (law.q.empty()) law.q = {orbits.empty() ? Eigen::Vector3d::UnitX() : orbits[0][0]}, law.beta = {0.0};
  if (!law::admissibility_problem(law).empty()) return std::numeric_limits<double>::infinity();
  double cost = 0;
  for (const auto& p : points)
    cost += (law::evaluate(law, p.strain).stress - p.stress).squaredNorm() / p.stress.squaredNorm();
  out = law;
  return cost;
}

}  // namespace

law::ConeFit fit_cone_to_cell(const law::CondensedCell& cell, const std::vector<ConePoint>& points, int n_directions,
                              Fitted fitted, int n, const law::CellSample* past_fuse_sample,
                              const std::vector<Eigen::Matrix3d>* symmetries) {
  law::ConeFit out;
  out.n_points = static_cast<int>(points.size());
  out.direction_residual.assign(n_directions, std::numeric_limits<double>::quiet_NaN());
  out.one_plane_residual = out.struts_residual = std::numeric_limits<double>::quiet_NaN();
  if (cell.n_macro != 3) {
    out.message = "the cell carries no shear (symmetry boundary)";
    return out;
  }
  // The sample and its images under the cell's symmetries (measured on the law itself, bonded:
  // the bonds the cascade leaves are the images of the image's).
  const law::CellSample bonded =
      fitted == Fitted::bonded || !symmetries ? law::sample_cell(cell, n) : law::CellSample{};
  const std::vector<Eigen::Matrix3d> group = symmetries ? *symmetries : cell_symmetries(cell, bonded);
  const law::CellSample sample = fitted == Fitted::bonded ? bonded
                                 : past_fuse_sample       ? *past_fuse_sample
                                                    : law::sample_cell_past_fuse(cell, n, law::past_fuse_load_ratio);
  std::vector<ConePoint> exact;
  for (std::size_t i = 0; i < sample.direction.size(); ++i)
    if (sample.strain[i].allFinite())
      for (const Eigen::Matrix3d& R : group) exact.push_back({R * sample.strain[i], R * sample.stress[i], -1});
  // Candidate planes: a Fibonacci set of unit strain directions, each with its orbit under the
  // symmetries (a candidate already in an orbit adds nothing).
  std::vector<std::vector<Eigen::Vector3d>> orbits;
  constexpr int n_candidates = 240;
  const auto known = [&](const Eigen::Vector3d& q) {
    for (const auto& orbit : orbits)
      for (const Eigen::Vector3d& p : orbit)
        if ((p - q).norm() < same_normal) return true;
    return false;
  };
  for (const Eigen::Vector3d& q : fibonacci_sphere(n_candidates)) {
    if (known(q)) continue;
    std::vector<Eigen::Vector3d> orbit;
    for (const Eigen::Matrix3d& R : group) {
      const Eigen::Vector3d image = R * q;
      bool seen = false;
      for (const Eigen::Vector3d& p : orbit) seen = seen || (p - image).norm() < same_normal;
      if (!seen) orbit.push_back(image);
    }
    orbits.push_back(orbit);
  }
  // C_c the open cell's stiffness S₀⁻¹ (every gap open: the softest the cell can be), each plane
  // adding stiffness where it opens: positive definite and convex by construction.
  const Eigen::Matrix3d C_open = Eigen::Matrix3d(cell.S0).inverse();
  law::ConeLaw law;
  const double c = fit_plane_orbits(exact, orbits, 0.5 * (C_open + C_open.transpose()), law);
  out.form = "planes fitted to the exact law, " + std::to_string(group.size()) + " symmetries of the cell";
  if (!std::isfinite(c) || exact.empty()) {
    out.message = "no admissible law fitted to the exact law";
    return out;
  }
  out.law = law;
  double sum = 0;
  for (const auto& p : points)
    sum += (law::evaluate(law, p.strain).stress - p.stress).squaredNorm() / p.stress.squaredNorm();
  out.relative_residual = points.empty() ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(sum / points.size());
  set_direction_residuals(points, out);
  out.ok = true;
  return out;
}

law::ConeFit fit_cone(const std::vector<ConePoint>& points, int n_directions, const Eigen::Vector3d& guess) {
  law::ConeFit out;
  out.n_points = static_cast<int>(points.size());
  out.direction_residual.assign(n_directions, std::numeric_limits<double>::quiet_NaN());
  out.one_plane_residual = out.struts_residual = std::numeric_limits<double>::quiet_NaN();
  if (points.size() < 3) {
    out.message = "fewer than 3 points";
    return out;
  }
  law::ConeLaw one_plane, struts;
  const double one_plane_cost = fit_one_plane(points, guess, one_plane);
  const double struts_cost = fit_struts(points, struts);
  const auto residual_of = [&](double c) {
    return std::isfinite(c) ? std::sqrt(c / points.size()) : std::numeric_limits<double>::quiet_NaN();
  };
  out.one_plane_residual = residual_of(one_plane_cost);
  out.struts_residual = residual_of(struts_cost);
  if (!std::isfinite(one_plane_cost) && !std::isfinite(struts_cost)) {
    out.message = "no start gave a finite, admissible fit";
    return out;
  }
  // The better form; the one plane where they tie (fewer parameters).
  const bool take_struts = struts_cost < one_plane_cost * (1 - tie);
  out.law = take_struts ? struts : one_plane;
  out.form = take_struts ? "compression struts" : "one plane";
  out.relative_residual = residual_of(take_struts ? struts_cost : one_plane_cost);
  set_direction_residuals(points, out);
  out.ok = true;
  return out;
}

}  // namespace dualcell::fit
