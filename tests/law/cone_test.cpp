// The cone-wise linear law as a structure code evaluates it: convex energy, σ = ∂W/∂ε, the
// tangent = ∂σ/∂ε off the switching plane, σ continuous across it.
#include "law/cone.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace dualcell::law {
namespace {

// A random admissible law: C_c = LLᵀ + I/10 (SPD), unit c, β in [0, 5].
ConeLaw random_law(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3d L;
  for (int i = 0; i < 9; ++i) L(i / 3, i % 3) = u(rng);
  ConeLaw law;
  law.C_c = L * L.transpose() + 0.1 * Eigen::Matrix3d::Identity();
  law.c = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  law.beta = 2.5 * (u(rng) + 1);
  return law;
}

Eigen::Vector3d random_strain(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1e-2, 1e-2);
  return {u(rng), u(rng), u(rng)};
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
  // quotient is exact up to round-off, eps·W/h ≈ 1e-9·|σ|, away from the plane (a step across
  // it changes W by O(β h²) only); points within 10h of the plane are skipped for the tangent,
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
    if (std::abs(law.c.dot(e)) > 10 * h) {
      EXPECT_LE((jacobian - s.tangent).norm(), 1e-6 * s.tangent.norm()) << trial;
    }
    EXPECT_EQ(s.plus_side, law.c.dot(e) > 0);
  }
}

TEST(ConeLaw, StressIsContinuousAcrossTheSwitchingPlane) {
  // On the plane c·ε = 0 both sides give C_c ε; at distance δ on either side the stress moves
  // by at most ‖C_c + βccᵀ‖·δ, so σ(ε₀ + δc) − σ(ε₀ − δc) → 0 linearly with δ.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const ConeLaw law = random_law(rng);
    Eigen::Vector3d e0 = random_strain(rng);
    e0 -= law.c.dot(e0) * law.c;  // onto the plane
    const double bound = (law.C_c + law.beta * law.c * law.c.transpose()).norm();
    for (double delta : {1e-4, 1e-6, 1e-8}) {
      const Eigen::Vector3d jump = evaluate(law, e0 + delta * law.c).stress - evaluate(law, e0 - delta * law.c).stress;
      EXPECT_LE(jump.norm(), 2 * bound * delta * (1 + 1e-12)) << trial;
    }
    // The stiffer side is stiffer along c by exactly β: c·(C₊ − C_c)c = β.
    const Eigen::Vector3d e_plus = e0 + 1e-3 * law.c;
    EXPECT_NEAR(law.c.dot((evaluate(law, e_plus).tangent - law.C_c) * law.c), law.beta, 1e-12 * (1 + law.beta));
  }
}

TEST(ConeLaw, InadmissibleLawsAreNamed) {
  ConeLaw law;
  EXPECT_EQ(admissibility_problem(law), "");
  law.beta = -1;
  EXPECT_EQ(admissibility_problem(law), "beta is negative");
  law.beta = 1;
  law.C_c(0, 0) = -1;
  EXPECT_EQ(admissibility_problem(law), "C_c is not positive definite");
  law.C_c = Eigen::Matrix3d::Identity();
  law.C_c(0, 1) = 0.5;
  EXPECT_EQ(admissibility_problem(law), "C_c is not symmetric");
  law.C_c = Eigen::Matrix3d::Identity();
  law.c = {1, 1, 0};
  EXPECT_EQ(admissibility_problem(law), "c is not a unit vector");
}

}  // namespace
}  // namespace dualcell::law
