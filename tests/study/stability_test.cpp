// The fast subset of the stability matrix: every case converges with its checks passed and
// finite results, or stops with a diagnostic; never a silent NaN or Inf.
#include "study/stability.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace dualcell::study {
namespace {

TEST(Stability, FastSubsetConvergesOrSaysWhy) {
  const auto cases = stability_cases(true);
  ASSERT_GE(cases.size(), 100u);
  int converged = 0;
  for (const auto& c : cases) {
    const StabilityRow row = run_stability_case(c);
    EXPECT_TRUE(row.ok) << to_string(c.boundary) << " " << c.direction_deg << "° E_f/E_m " << c.stiffness_ratio
                        << " nu_m " << c.nu_matrix << " r " << c.radius << " offset " << c.offset << " adhesion "
                        << c.adhesion << " load " << c.load << ": " << row.status << " " << row.message;
    // A converged case is finite and checked; one that stopped says why.
    if (row.status == "converged" && row.primal_ok) {
      ++converged;
      EXPECT_TRUE(row.finite);
      EXPECT_LE(row.relative_projected_gradient, 1e-8 * 1.0001);
      EXPECT_TRUE(std::isfinite(row.modulus));
    } else {
      EXPECT_FALSE(row.message.empty());
    }
  }
  // Every case converges, tiny-strength bonds at narrow boxes included (SMALBE's outer
  // iterations grow like ‖m*‖/(ρ·width); ρ_max = 1e4‖A‖ keeps them within the budget).
  EXPECT_EQ(converged, static_cast<int>(cases.size()));
}

}  // namespace
}  // namespace dualcell::study
