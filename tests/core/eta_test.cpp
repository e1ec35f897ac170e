// The time-left estimate of a geometrically converging iteration (core/progress.hpp), on
// distances whose rate is known.
#include <gtest/gtest.h>

#include "core/progress.hpp"

namespace dualcell {
namespace {

TEST(GeometricEta, FromTheRateSinceStepOne) {
  GeometricEta eta;
  EXPECT_EQ(eta.left(0), "");
  // A tenfold fall per step, one second a step: from 100 two steps and two seconds are left.
  eta.observe(1, 1e4, 0.0);
  eta.observe(2, 1e3, 1.0);
  EXPECT_EQ(eta.left(1.0), "");  // before step 3 it cannot tell
  eta.observe(3, 1e2, 2.0);
  EXPECT_EQ(eta.left(2.0), ", ~" + seconds_text(2.0) + " left");
  EXPECT_EQ(eta.left(3.5), ", ~" + seconds_text(0.5) + " left");
  EXPECT_EQ(eta.left(10.0), ", ~" + seconds_text(0.0) + " left");
}

TEST(GeometricEta, SaysNothingWhenNotFallingFastEnough) {
  GeometricEta stalled;
  for (long step = 1; step <= 5; ++step) stalled.observe(step, 50.0, static_cast<double>(step));
  EXPECT_EQ(stalled.left(5), "");
  GeometricEta slow;  // 2 % a step
  double d = 100;
  for (long step = 1; step <= 5; ++step, d *= 0.98) slow.observe(step, d, static_cast<double>(step));
  EXPECT_EQ(slow.left(5), "");
  GeometricEta converged;
  converged.observe(1, 10.0, 0), converged.observe(2, 1.0, 1), converged.observe(3, 0.1, 2);
  EXPECT_EQ(converged.left(2), "");
}

}  // namespace
}  // namespace dualcell
