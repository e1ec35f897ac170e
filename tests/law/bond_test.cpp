// The bond rule (law/bond.hpp): its table of bounds per kind and state, the at-strength test,
// the onset's reach and the one debond cascade, against the values written out by hand.
#include "law/bond.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

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
  // Along the fibres a tie holds the pair's tangential strength both ways; the value the solver
  // and the cell keep per pair (s_t·L) gives the same bounds.
  expect_bounds(bounds(Kind::along_fibres, State::intact, sn, st, L), -st * L, st * L);
  expect_bounds(bounds(Kind::along_fibres, State::broken, sn, st, L), 0, 0);
  expect_bounds(bounds(Kind::along_fibres, State::lifted, sn, st, L), -inf, inf);
  expect_bounds(intact_along_fibres(st * L), -st * L, st * L);
  // A facet row of a compact cell: at its strength on its facet g = 1, never from below; gone
  // past the fuse.
  expect_bounds(bounds(Kind::facet, State::intact, sn, st, L), -inf, 1);
  expect_bounds(bounds(Kind::facet, State::broken, sn, st, L), 0, 0);
  expect_bounds(bounds(Kind::facet, State::lifted, sn, st, L), -inf, inf);
  EXPECT_TRUE(at_strength(1.0, bounds(Kind::facet, State::intact, sn, st, L)));
  EXPECT_FALSE(at_strength(-1e30, bounds(Kind::facet, State::intact, sn, st, L)));
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

// The cascade on a chain of three pairs whose forces are written out: pair p is at its strength
// once the pairs before it broke (each break loads the next). Three breaking solves and one that
// breaks nothing; the warm-start hook runs between them with the pairs just broken.
TEST(BondRule, TheCascadeBreaksWhatIsAtItsStrengthAndSolvesAgain) {
  std::vector<char> bonded{1, 1, 1, 0};
  std::vector<std::vector<int>> carried;
  int solves = 0;
  const auto solve = [&] { return ++solves > 0; };
  const auto at_strength = [&](std::vector<int>& pairs) {
    for (int p = 0; p < 4; ++p)
      if (bonded[static_cast<std::size_t>(p)] && (p == 0 || !bonded[static_cast<std::size_t>(p - 1)]))
        pairs.push_back(p);
  };
  const auto next = [&](const std::vector<int>& pairs) { carried.push_back(pairs); };
  CascadeEnd end = cascade(bonded, 10, solve, at_strength, next);
  EXPECT_EQ(end.rounds, 4);
  EXPECT_EQ(solves, 4);
  EXPECT_EQ(end.newly_broken, 3);
  EXPECT_TRUE(end.solved && end.settled);
  EXPECT_EQ(bonded, (std::vector<char>{0, 0, 0, 0}));
  EXPECT_EQ(carried, (std::vector<std::vector<int>>{{0}, {1}, {2}}));

  // At most max_rounds solves: the last one's pairs stay bonded, and the end says so.
  bonded = {1, 1, 1, 0};
  end = cascade(bonded, 2, solve, at_strength, next);
  EXPECT_EQ(end.rounds, 2);
  EXPECT_EQ(end.newly_broken, 1);
  EXPECT_FALSE(end.settled);
  EXPECT_EQ(bonded, (std::vector<char>{0, 1, 1, 0}));

  // A failed solve stops the cascade there.
  bonded = {1, 1, 1, 0};
  end = cascade(
      bonded, 10, [] { return false; }, at_strength, next);
  EXPECT_EQ(end.rounds, 1);
  EXPECT_FALSE(end.solved);
  EXPECT_EQ(bonded, (std::vector<char>{1, 1, 1, 0}));
}

}  // namespace
}  // namespace dualcell::law::bond
