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

namespace dualcell::fit {

namespace {

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
  law.c = {std::sin(p[6]) * std::cos(p[7]), std::sin(p[6]) * std::sin(p[7]), std::cos(p[6])};
  law.beta = p[8] * p[8];
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

}  // namespace

law::ConeFit fit_cone(const std::vector<ConePoint>& points, int n_directions, const Eigen::Vector3d& guess) {
  law::ConeFit out;
  out.n_points = static_cast<int>(points.size());
  out.direction_residual.assign(n_directions, std::numeric_limits<double>::quiet_NaN());
  if (points.size() < 3) {
    out.message = "fewer than 3 points";
    return out;
  }
  // C₀: the linear law σ = C ε of all points by least squares (rows weighted by 1/|σ_i|),
  // symmetrised, its eigenvalues floored at 1e-6 of the largest so that it has a Cholesky factor.
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
  C0 = eig.eigenvectors() * eig.eigenvalues().cwiseMax(1e-6 * top).asDiagonal() * eig.eigenvectors().transpose();
  if (!C0.allFinite()) {
    out.message = "the linear fit of the points is not finite";
    return out;
  }

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
    gsl_multifit_nlinear_driver(500, 1e-12, 1e-12, 1e-12, nullptr, nullptr, &info, w.get());
    const law::ConeLaw candidate = law_of(gsl_multifit_nlinear_position(w.get())->data);
    const double c_value = cost(points, candidate);
    if (std::isfinite(c_value) && c_value < best && law::admissibility_problem(candidate).empty()) {
      best = c_value;
      out.law = candidate;
    }
  }
  if (!std::isfinite(best)) {
    out.message = "no start gave a finite, admissible fit";
    return out;
  }
  out.relative_residual = std::sqrt(best / points.size());
  std::vector<double> sum(n_directions, 0.0);
  std::vector<int> count(n_directions, 0);
  for (const auto& p : points) {
    if (p.direction < 0 || p.direction >= n_directions) continue;
    sum[p.direction] += (law::evaluate(out.law, p.strain).stress - p.stress).squaredNorm() / p.stress.squaredNorm();
    ++count[p.direction];
  }
  for (int d = 0; d < n_directions; ++d)
    if (count[d] > 0) out.direction_residual[d] = std::sqrt(sum[d] / count[d]);
  out.ok = true;
  return out;
}

}  // namespace dualcell::fit
