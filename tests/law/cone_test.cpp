// The cone-wise linear law as a structure code evaluates it, with one to several planes: convex
// energy, σ = ∂W/∂ε, the tangent = ∂σ/∂ε off the switching planes, σ continuous across them,
// and its inverse (the strain for a stress).
#include "law/cone.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace dualcell::law {
namespace {

// A random admissible law: C_c = LLᵀ + I/10 (SPD), 1 to 4 unit normals q_k, β_k in [0, 5].
ConeLaw random_law(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3d L;
  for (int i = 0; i < 9; ++i) L(i / 3, i % 3) = u(rng);
  ConeLaw law;
  law.C_c = L * L.transpose() + 0.1 * Eigen::Matrix3d::Identity();
  const int planes = 1 + static_cast<int>(rng() % 4);
  law.q.clear();
  law.beta.clear();
  for (int k = 0; k < planes; ++k) {
    law.q.push_back(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized());
    law.beta.push_back(2.5 * (u(rng) + 1));
  }
  return law;
}

Eigen::Vector3d random_strain(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1e-2, 1e-2);
  return {u(rng), u(rng), u(rng)};
}

// Distance of ε to the nearest switching plane.
double to_nearest_plane(const ConeLaw& law, const Eigen::Vector3d& e) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& c : law.q) d = std::min(d, std::abs(c.dot(e)));
  return d;
}

TEST(ConeLaw, EnergyIsConvexOnRandomPairs) {
  // W(½(a + b)) ≤ ½(W(a) + W(b)) up to round-off of W (~1e-16·W).
  std::mt19937 rng(1);
  for (int trial = 0; trial < 2000; ++trial) {
    const ConeLaw law = random_law(rng);
    ASSERT_EQ(admissibility_problem(law), "");
    const Eigen::Vector3d a = random_strain(rng), b = random_strain(rng);
    const double mean = 0.5 * (evaluate(law, a).energy + evaluate(law, b).energy);
    EXPECT_LE(evaluate(law, 0.5 * (a + b)).energy, mean + 1e-14 * std::abs(mean)) << trial;
  }
}

TEST(ConeLaw, StressIsTheEnergyGradientAndTangentItsDerivative) {
  // Central differences with step h = 1e-9 (strains ~1e-2): W is piecewise quadratic, so the
  // quotient is exact up to round-off, eps·W/h ≈ 1e-9·|σ|, away from the planes (a step across
  // one changes W by O(β h²) only); points within 10h of a plane are skipped for the tangent,
  // which jumps there.
  std::mt19937 rng(2);
  const double h = 1e-9;
  for (int trial = 0; trial < 500; ++trial) {
    const ConeLaw law = random_law(rng);
    const Eigen::Vector3d e = random_strain(rng);
    const ConeState s = evaluate(law, e);
    Eigen::Vector3d gradient;
    Eigen::Matrix3d jacobian;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(i);
      gradient(i) = (evaluate(law, e + step).energy - evaluate(law, e - step).energy) / (2 * h);
      jacobian.col(i) = (evaluate(law, e + step).stress - evaluate(law, e - step).stress) / (2 * h);
    }
    EXPECT_LE((gradient - s.stress).norm(), 1e-6 * s.stress.norm() + 1e-12) << trial;
    if (to_nearest_plane(law, e) > 10 * h) {
      EXPECT_LE((jacobian - s.tangent).norm(), 1e-6 * s.tangent.norm()) << trial;
    }
    for (std::size_t k = 0; k < law.q.size(); ++k) EXPECT_EQ((s.open >> k) & 1u, law.q[k].dot(e) > 0 ? 1u : 0u);
  }
}

TEST(ConeLaw, StressIsContinuousAcrossEverySwitchingPlane) {
  // On the plane q_k·ε = 0 both sides of it give the same stress; at distance δ on either side
  // the stress moves by at most ‖C_c + Σβ_j q_j q_jᵀ‖·δ, so σ(ε₀ + δq_k) − σ(ε₀ − δq_k) → 0
  // linearly with δ.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const ConeLaw law = random_law(rng);
    Eigen::Matrix3d stiffest = law.C_c;
    for (std::size_t j = 0; j < law.q.size(); ++j) stiffest += law.beta[j] * law.q[j] * law.q[j].transpose();
    const double bound = stiffest.norm();
    for (std::size_t k = 0; k < law.q.size(); ++k) {
      const Eigen::Vector3d& c = law.q[k];
      Eigen::Vector3d e0 = random_strain(rng);
      e0 -= c.dot(e0) * c;  // onto plane k
      for (double delta : {1e-4, 1e-6, 1e-8}) {
        const Eigen::Vector3d jump = evaluate(law, e0 + delta * c).stress - evaluate(law, e0 - delta * c).stress;
        EXPECT_LE(jump.norm(), 2 * bound * delta * (1 + 1e-12)) << trial;
      }
    }
  }
  // One plane: the stiffer side is stiffer along c by exactly β, c·(C₊ − C_c)c = β.
  ConeLaw one;
  one.q = {Eigen::Vector3d(0.6, 0.0, 0.8)};
  one.beta = {3.5};
  const Eigen::Vector3d e_plus = 1e-3 * one.q[0];
  EXPECT_NEAR(one.q[0].dot((evaluate(one, e_plus).tangent - one.C_c) * one.q[0]), 3.5, 1e-12 * 4.5);
}

TEST(ConeLaw, StrainForAStressInvertsTheLaw) {
  // σ(strain_for(σ̄)) = σ̄ to round-off (1e-13 relative: the tangents' condition numbers stay
  // below 1e3 here), for stresses on every side of the planes.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 1000; ++trial) {
    const ConeLaw law = random_law(rng);
    const Eigen::Vector3d sigma(u(rng), u(rng), u(rng));
    const Eigen::Vector3d e = strain_for(law, sigma);
    EXPECT_LE((evaluate(law, e).stress - sigma).norm(), 1e-13 * sigma.norm()) << trial;
  }
}

TEST(ConeLaw, InadmissibleLawsAreNamed) {
  ConeLaw law;
  EXPECT_EQ(admissibility_problem(law), "");
  law.beta = {-1};
  EXPECT_EQ(admissibility_problem(law), "beta is negative");
  law.beta = {1};
  law.C_c(0, 0) = -1;
  EXPECT_EQ(admissibility_problem(law), "C_c is not positive definite");
  law.C_c = Eigen::Matrix3d::Identity();
  law.C_c(0, 1) = 0.5;
  EXPECT_EQ(admissibility_problem(law), "C_c is not symmetric");
  law.C_c = Eigen::Matrix3d::Identity();
  law.q = {{1, 1, 0}};
  EXPECT_EQ(admissibility_problem(law), "q is not a unit vector");
  law.q = {{1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(admissibility_problem(law), "there are not as many beta as planes");
  law.q.clear();
  law.beta.clear();
  EXPECT_EQ(admissibility_problem(law), "the number of planes is 0, not 1 to 32");
}

}  // namespace
}  // namespace dualcell::law
