// The bond rule (law/bond.hpp): its table of bounds per kind and state, the at-strength test and
// the onset's reach, against the values written out by hand.
#include "law/bond.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dualcell::law::bond {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

void expect_bounds(Bounds b, double lower, double upper) {
  EXPECT_EQ(b.lower, lower);
  EXPECT_EQ(b.upper, upper);
}

TEST(BondRule, BoundsPerKindAndState) {
  const double sn = 0.05, st = 0.03, L = 0.2;
  expect_bounds(bounds(Kind::normal, State::intact, sn, st, L), -sn * L, inf);
  expect_bounds(bounds(Kind::normal, State::broken, sn, st, L), 0, inf);
  expect_bounds(bounds(Kind::normal, State::lifted, sn, st, L), -inf, inf);
  expect_bounds(bounds(Kind::tangential, State::intact, sn, st, L), -st * L, st * L);
  expect_bounds(bounds(Kind::tangential, State::broken, sn, st, L), 0, 0);
  expect_bounds(bounds(Kind::tangential, State::lifted, sn, st, L), -inf, inf);
  // A bond without normal strength stays a contact row when lifted (the response a cone, not
  // linear); without shear strength its tangential row carries nothing (and is left out).
  expect_bounds(bounds(Kind::normal, State::lifted, 0, st, L), 0, inf);
  EXPECT_FALSE(bounds(Kind::tangential, State::intact, sn, 0, L).carries_force());
  EXPECT_FALSE(bounds(Kind::tangential, State::broken, sn, st, L).carries_force());
  EXPECT_TRUE(bounds(Kind::normal, State::broken, sn, st, L).carries_force());
}

TEST(BondRule, AtStrengthWithinItsTolerance) {
  const Bounds normal{-2.0, inf}, tangential{-3.0, 3.0};
  EXPECT_TRUE(at_strength(-2.0, normal));
  EXPECT_TRUE(at_strength(-2.0 * (1 - 0.5 * at_strength_tolerance), normal));
  EXPECT_FALSE(at_strength(-2.0 * (1 - 2 * at_strength_tolerance), normal));
  EXPECT_FALSE(at_strength(1e30, normal));  // compression never breaks a bond
  EXPECT_TRUE(at_strength(3.0, tangential));
  EXPECT_TRUE(at_strength(-3.0, tangential));
  EXPECT_FALSE(at_strength(2.9, tangential));
  // Broken or contact rows have no strength to reach.
  EXPECT_FALSE(at_strength(0.0, Bounds{0.0, inf}));
  EXPECT_FALSE(at_strength(0.0, Bounds{0.0, 0.0}));
}

TEST(BondRule, ReachIsTheInverseOfTheStrengthUsed) {
  const Bounds normal{-2.0, inf}, tangential{-3.0, 3.0};
  EXPECT_EQ(strength_use(-1.0, normal), 0.5);
  EXPECT_EQ(reach(-1.0, normal), 2.0);
  EXPECT_EQ(strength_use(1.0, normal), 0.0);  // compression: no strength used
  EXPECT_EQ(reach(1.0, normal), inf);
  EXPECT_EQ(strength_use(-1.5, tangential), 0.5);
  EXPECT_EQ(reach(1.5, tangential), 2.0);
  EXPECT_EQ(reach(0.0, tangential), inf);
  EXPECT_TRUE(reaches_at_onset(2.0 * (1 + 0.5 * at_strength_tolerance), 2.0));
  EXPECT_FALSE(reaches_at_onset(2.0 * (1 + 2 * at_strength_tolerance), 2.0));
}

}  // namespace
}  // namespace dualcell::law::bond
