// The macro state (core/macro_state.hpp): the applied value of each component, scaled by the load
// factor or held; the ply's six strains in the law's order; and that a state passes the values it
// was given bit for bit (a factor of 1 multiplies exactly, so the layers that now pass a state give
// the results they gave before).
#include "core/macro_state.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace dualcell {
namespace {

TEST(MacroState, ScaledComponentsFollowTheFactorAndHeldOnesStay) {
  MacroState s = MacroState::stress(Eigen::Vector3d(1, -2, 0.5), 3);
  s.hold(MacroState::zz, 1e-3).hold_shear(Eigen::Vector2d(2e-3, -4e-3));
  EXPECT_TRUE(s.in_plane_stress());
  EXPECT_EQ(s.in_plane(), Eigen::Vector3d(3, -6, 1.5));
  EXPECT_EQ(s.eps33(), 1e-3);
  EXPECT_EQ(s.gamma(), Eigen::Vector2d(2e-3, -4e-3));
  EXPECT_EQ(s.delta_T(), 0);
  EXPECT_TRUE(s.beyond_plane());
  // Held components are strains, whatever the in-plane part is.
  EXPECT_EQ(s.stress_driven, MacroState::in_plane_mask);
  const MacroState half = s.at_factor(0.5);
  EXPECT_EQ(half.in_plane(), Eigen::Vector3d(0.5, -1, 0.25));
  EXPECT_EQ(half.eps33(), 1e-3);
  EXPECT_EQ(MacroState::stress(Eigen::Vector3d(0, 0, 1)).nonzero(), 1 << MacroState::xy);
  EXPECT_FALSE(MacroState::strain(Eigen::Vector3d(1, 0, 0)).beyond_plane());
}

TEST(MacroState, ThePlysSixStrainsInTheLawsOrder) {
  Eigen::Matrix<double, 6, 1> e;
  e << 1e-3, -2e-3, 3e-3, 4e-3, -5e-3, 6e-3;
  const MacroState s = MacroState::ply_strain(e);
  EXPECT_TRUE(s.in_plane_strain());
  EXPECT_EQ(s.in_plane(), e.head<3>());
  EXPECT_EQ(s.eps33(), e(3));
  EXPECT_EQ(s.gamma(), e.tail<2>());
  EXPECT_EQ(s.nonzero(), MacroState::in_plane_mask | MacroState::along_mask | MacroState::shear_mask);
}

TEST(MacroState, AtFactorOneTheValuesPassBitForBit) {
  // Values with every bit of the mantissa in use, signed zeros and subnormals among them.
  const Eigen::Vector3d v(0.1 + 0.2, -0.0, 4.9e-324);
  const MacroState s = MacroState::strain(v);
  const Eigen::Vector3d back = s.in_plane();
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(back(k), v(k)) << k;
    EXPECT_EQ(std::signbit(back(k)), std::signbit(v(k))) << k;
  }
}

}  // namespace
}  // namespace dualcell
