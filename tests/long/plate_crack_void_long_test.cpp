// Cracks from a circular hole on a finer mesh (label `long`): Bowie's factor
// for two symmetric cracks (tests/xfem/plate_crack_void.hpp), a = R and R/2,
// at h = R/10 on the plate 20 R wide (201² cells; 40 R wide would pass the
// build's bound on a matrix), its width term removed by the ratio the
// h = R/5 plates 20 R and 40 R wide give (test::infinite_plate): F∞ within
// 3 % of Tada's fit, and for a = R within 1 % of the h = R/5 value.
#include <gtest/gtest.h>

#include <cstdio>

#include "xfem/plate_crack_void.hpp"

namespace xfdem {

TEST(PlateCrackVoidLong, TwoCracksFromAHoleFollowBowieOnAFinerMesh) {
  struct Case {
    double half;
    int n;
  };
  for (const double a : {1.0, 0.5}) {
    double f[3] = {};
    const Case cases[3] = {{10.0, 101}, {20.0, 201}, {10.0, 201}};
    for (int c = 0; c < 3; ++c) {
      PlateModel m;
      PlateState s;
      PlateWorkspace ws;
      const BuildResult r = build_plate(test::bowie_plate(cases[c].half, cases[c].n, a, true), m, s, ws);
      ASSERT_TRUE(r.ok()) << r.message;
      f[c] = test::bowie_factor(m, s, a, 0.5 * a);
      std::printf("two cracks, a/R = %.1f, plate %.0f R wide, h = R/%.0f: F = %.4f within %.2f R\n", a,
                  2 * cases[c].half, cases[c].n / (2 * cases[c].half), f[c], 0.5 * a);
    }
    const double inf = f[2] * test::infinite_plate(f[0], f[1]) / f[0], exact = test::bowie_two(a);
    std::printf("  F of the infinite plate at h = R/10 %.4f, Bowie %.3f (%+.2f %%)\n", inf, exact,
                100.0 * (inf / exact - 1.0));
    EXPECT_NEAR(inf, exact, 0.03 * exact);
    if (a == 1.0) {
      EXPECT_NEAR(f[2], f[0], 0.01 * f[0]);
    }
  }
}

}  // namespace xfdem
