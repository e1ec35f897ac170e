// The cone-wise fit recovers a known admissible law from its own points, and its fitted law is
// admissible even for data no cone-wise law reproduces.
#include "fit/cone_fit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>

namespace dualcell::fit {
namespace {

// Points of a law: uniaxial and biaxial stress directions on the unit sphere of
// (σxx, σyy, √2σxy), both signs, two magnitudes each; the strain that gives each stress is found
// by solving σ(ε) = σ̄ on the side it lands on (the law is piecewise linear).
std::vector<ConePoint> points_of(const law::ConeLaw& law, int n_directions) {
  std::vector<ConePoint> points;
  const Eigen::Matrix3d C_plus = law.C_c + law.beta * law.c * law.c.transpose();
  for (int d = 0; d < n_directions; ++d) {
    // A Fibonacci point on the sphere.
    const double z = 1 - (2 * d + 1.0) / n_directions, r = std::sqrt(1 - z * z);
    const double phi = d * std::numbers::pi * (3 - std::sqrt(5.0));
    const Eigen::Vector3d sigma_unit(r * std::cos(phi), r * std::sin(phi), z / std::sqrt(2.0));
    for (double s : {-2.0, -1.0, 1.0, 2.0}) {
      const Eigen::Vector3d sigma = s * 0.01 * sigma_unit;
      Eigen::Vector3d e = law.C_c.ldlt().solve(sigma);
      if (law.c.dot(e) > 0) e = C_plus.ldlt().solve(sigma);
      points.push_back({e, sigma, d});
    }
  }
  return points;
}

TEST(ConeFit, RecoversAKnownLawFromItsOwnPoints) {
  law::ConeLaw truth;
  truth.C_c << 12, 4, 0.5, 4, 10, -0.3, 0.5, -0.3, 3;
  truth.c = Eigen::Vector3d(0.7, 0.6, 0.2).normalized();
  truth.beta = 6;
  const auto points = points_of(truth, 24);
  const law::ConeFit fit = fit_cone(points, 24);
  ASSERT_TRUE(fit.ok) << fit.message;
  // The data are exact: the fit must reproduce them to the solver's tolerance (1e-12 on the
  // step and gradient) and find the law's parameters (c up to its sign convention, which the
  // side of β fixes).
  EXPECT_LT(fit.relative_residual, 1e-8);
  EXPECT_LE((fit.law.C_c - truth.C_c).norm(), 1e-6 * truth.C_c.norm());
  EXPECT_LE((fit.law.c - truth.c).norm(), 1e-6);
  EXPECT_NEAR(fit.law.beta, truth.beta, 1e-6 * truth.beta);
  for (double r : fit.direction_residual) EXPECT_LT(r, 1e-8);
}

TEST(ConeFit, LinearDataGiveNoJump) {
  law::ConeLaw truth;
  truth.C_c << 5, 1, 0, 1, 5, 0, 0, 0, 2;
  truth.beta = 0;
  const law::ConeFit fit = fit_cone(points_of(truth, 12), 12);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_LT(fit.relative_residual, 1e-8);
  EXPECT_LE((fit.law.C_c - truth.C_c).norm(), 1e-6 * truth.C_c.norm());
  EXPECT_LT(fit.law.beta, 1e-6 * truth.C_c.norm());
}

TEST(ConeFit, DataNoConeReproducesStillGiveAnAdmissibleLawAndSayHowFarOff) {
  // Two switching planes (a stiffening along xx and one along yy): no single cone fits; the fit
  // is admissible by construction, and its residual is clearly non-zero.
  law::ConeLaw a, b;
  a.C_c << 10, 3, 0, 3, 10, 0, 0, 0, 3.5;
  b.C_c = a.C_c;
  a.c = Eigen::Vector3d::UnitX(), a.beta = 20;
  b.c = Eigen::Vector3d::UnitY(), b.beta = 20;
  std::vector<ConePoint> points = points_of(a, 10);
  for (auto p : points_of(b, 10)) {
    p.direction += 10;
    points.push_back(p);
  }
  const law::ConeFit fit = fit_cone(points, 20);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_EQ(law::admissibility_problem(fit.law), "");
  EXPECT_GT(fit.relative_residual, 1e-3);
}

TEST(ConeFit, TooFewPointsIsSaid) {
  const law::ConeFit fit = fit_cone({{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0), 0}}, 1);
  EXPECT_FALSE(fit.ok);
  EXPECT_EQ(fit.message, "fewer than 3 points");
}

}  // namespace
}  // namespace dualcell::fit
