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
// (σxx, σyy, √2σxy), both signs, two magnitudes each; the strain that gives each stress from
// the law's own inverse (law::strain_for, exact to round-off).
std::vector<ConePoint> points_of(const law::ConeLaw& law, int n_directions) {
  std::vector<ConePoint> points;
  for (int d = 0; d < n_directions; ++d) {
    // A Fibonacci point on the sphere.
    const double z = 1 - (2 * d + 1.0) / n_directions, r = std::sqrt(1 - z * z);
    const double phi = d * std::numbers::pi * (3 - std::sqrt(5.0));
    const Eigen::Vector3d sigma_unit(r * std::cos(phi), r * std::sin(phi), z / std::sqrt(2.0));
    for (double s : {-2.0, -1.0, 1.0, 2.0}) {
      const Eigen::Vector3d sigma = s * 0.01 * sigma_unit;
      points.push_back({law::strain_for(law, sigma), sigma, d});
    }
  }
  return points;
}

// The strut normal at θ: −n⊗n in engineering shear, normalised.
Eigen::Vector3d strut(double theta_deg) {
  const double t = theta_deg * std::numbers::pi / 180, c = std::cos(t), s = std::sin(t);
  return -Eigen::Vector3d(c * c, s * s, c * s).normalized();
}

TEST(ConeFit, RecoversAKnownLawFromItsOwnPoints) {
  law::ConeLaw truth;
  truth.C_c << 12, 4, 0.5, 4, 10, -0.3, 0.5, -0.3, 3;
  truth.q = {Eigen::Vector3d(0.7, 0.6, 0.2).normalized()};
  truth.beta = {6};
  const auto points = points_of(truth, 24);
  const law::ConeFit fit = fit_cone(points, 24);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_EQ(fit.form, "one plane");
  ASSERT_EQ(fit.law.q.size(), 1u);
  EXPECT_GT(fit.struts_residual, 1e-3);  // no strut is this plane
  // The data are exact: the fit must reproduce them to the solver's tolerance (1e-12 on the
  // step and gradient) and find the law's parameters (c up to its sign convention, which the
  // side of β fixes).
  EXPECT_LT(fit.relative_residual, 1e-8);
  EXPECT_LE((fit.law.C_c - truth.C_c).norm(), 1e-6 * truth.C_c.norm());
  EXPECT_LE((fit.law.q[0] - truth.q[0]).norm(), 1e-6);
  EXPECT_NEAR(fit.law.beta[0], truth.beta[0], 1e-6 * truth.beta[0]);
  for (double r : fit.direction_residual) EXPECT_LT(r, 1e-8);
}

TEST(ConeFit, LinearDataGiveNoJump) {
  law::ConeLaw truth;
  truth.C_c << 5, 1, 0, 1, 5, 0, 0, 0, 2;
  truth.beta = {0};
  const law::ConeFit fit = fit_cone(points_of(truth, 12), 12);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_LT(fit.relative_residual, 1e-8);
  EXPECT_LE((fit.law.C_c - truth.C_c).norm(), 1e-6 * truth.C_c.norm());
  for (double beta : fit.law.beta) EXPECT_LT(beta, 1e-6 * truth.C_c.norm());
}

// A cell whose gaps close under compression along x and along y (two struts, the bimodular
// cell's mechanism): the struts form recovers it exactly (its normals are among the twelve; the
// fit is a linear least-squares problem with β ≥ 0 there), where one plane cannot: the fit
// takes the struts, and the residual falls from that of one plane to round-off.
TEST(ConeFit, StrutsRecoverACellThatStiffensInCompressionAlongTwoDirections) {
  law::ConeLaw truth;
  truth.C_c << 2.0, 0.9, 0.05, 0.9, 2.0, 0.05, 0.05, 0.05, 0.6;
  truth.q = {strut(0), strut(90), strut(45)};
  truth.beta = {7.0, 7.0, 1.5};
  const law::ConeFit fit = fit_cone(points_of(truth, 40), 40);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_EQ(fit.form, "compression struts");
  EXPECT_EQ(law::admissibility_problem(fit.law), "");
  EXPECT_GT(fit.one_plane_residual, 0.05);
  EXPECT_LT(fit.relative_residual, 1e-8);
  EXPECT_LE((fit.law.C_c - truth.C_c).norm(), 1e-6 * truth.C_c.norm());
  // The struts the data ask for, and no other.
  ASSERT_EQ(fit.law.q.size(), 3u) << "planes";
  for (std::size_t k = 0; k < truth.q.size(); ++k) {
    bool found = false;
    for (std::size_t j = 0; j < fit.law.q.size(); ++j)
      if ((fit.law.q[j] - truth.q[k]).norm() < 1e-12) {
        found = true;
        EXPECT_NEAR(fit.law.beta[j], truth.beta[k], 1e-6 * truth.beta[k]);
      }
    EXPECT_TRUE(found) << "strut " << k;
  }
}

TEST(ConeFit, DataNoConeReproducesStillGiveAnAdmissibleLawAndSayHowFarOff) {
  // Two switching planes (a stiffening along xx and one along yy): no single cone fits; the fit
  // is admissible by construction, and its residual is clearly non-zero.
  law::ConeLaw a, b;
  a.C_c << 10, 3, 0, 3, 10, 0, 0, 0, 3.5;
  b.C_c = a.C_c;
  a.q = {Eigen::Vector3d::UnitX()}, a.beta = {20};
  b.q = {Eigen::Vector3d::UnitY()}, b.beta = {20};
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
