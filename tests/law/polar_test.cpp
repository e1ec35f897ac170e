// The apparent moduli around the circle (law/polar.hpp): every angle of 0…360°, the law asked at
// 0…179° only and the other half of the circle the same (n⊗n is), and the compact law's curve
// the law's own apparent modulus.
#include "law/polar.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "law/cone.hpp"

namespace dualcell::law {
namespace {

TEST(PolarModuli, EveryDegreeFromHalfTheCircle) {
  int calls = 0;
  const PolarModuli p = polar_moduli([&](double theta, double sign) {
    ++calls;
    EXPECT_LT(theta, 180);
    return sign > 0 ? 1 + std::cos(theta * 3.14159265358979 / 90) : 2.0;
  });
  EXPECT_EQ(calls, 2 * 180);
  ASSERT_EQ(p.deg.size(), 361u);
  for (int d = 0; d <= 360; ++d) {
    EXPECT_EQ(p.deg[d], d);
    EXPECT_EQ(p.E_tension[d], p.E_tension[d % 180]);
    EXPECT_EQ(p.E_compression[d], 2.0);
  }
}

TEST(PolarModuli, TheCompactLawsCurveIsItsApparentModulus) {
  ConeLaw law;
  law.C_c << 10, 3, 0, 3, 8, 0, 0, 0, 2;
  law.q = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  law.beta = {6.0, 4.0};
  ASSERT_EQ(admissibility_problem(law), "");
  const PolarModuli p = cone_polar(law);
  for (int d = 0; d < 180; d += 7) {
    EXPECT_EQ(p.E_tension[d], apparent_modulus(law, d, 1));
    EXPECT_EQ(p.E_compression[d], apparent_modulus(law, d, -1));
  }
  // The planes act on one side only: the two curves differ where a plane's normal points.
  EXPECT_NE(p.E_tension[0], p.E_compression[0]);
}

}  // namespace
}  // namespace dualcell::law
