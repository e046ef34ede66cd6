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
  test::expect_energy_kept(r);  // drift printed: 1e5 steps: 5.9e-14 of E0
}

}  // namespace xfdem
