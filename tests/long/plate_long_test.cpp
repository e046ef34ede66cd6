// The plate's deep run (label `long`): a plate with an edge crack (a tip,
// branch enrichment) and a void, kicked by a short traction and then left
// alone for 1e5 steps of Newmark (¼, ½): its energy stays constant within the
// round-off allowance of tests/xfem/plate_free_vibration.hpp (16 κ u N).
#include <gtest/gtest.h>

#include <cstdio>

#include "xfem/plate_free_vibration.hpp"

namespace xfdem {

TEST(PlateLong, CrackedPlateWithAVoidKeepsItsEnergyOverAHundredThousandSteps) {
  const test::FreeVibration r = test::run_free_vibration(100000);
  ASSERT_TRUE(r.built);
  std::printf("cracked plate with a void, %d unknowns (%d enriched), %lld unloaded steps of (1/4, 1/2): energy "
              "drift %.3g of E0 = %.6g J (%.3g relative; allowance 16 kappa u N = %.3g, kappa = %.3g); elastic peak "
              "%.3g J\n",
              r.dofs, r.enriched, static_cast<long long>(r.steps), r.drift, r.energy0, r.drift / r.energy0,
              r.allowance, r.condition, r.elastic_peak);
  EXPECT_TRUE(r.statuses_ok);
  EXPECT_GT(r.elastic_peak, 0.1 * r.energy0);
  EXPECT_LE(r.drift, r.allowance * r.energy0);
  // and, as the uncut plate's run (TrapezoidalRuleConserves…), within 1e-12 of E0 (1e5 steps: 5.9e-14 printed)
  EXPECT_LE(r.drift, 1e-12 * r.energy0);
}

}  // namespace xfdem
