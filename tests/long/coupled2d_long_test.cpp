// The coupled 2D window's deep runs (label `long`):
//  - the randomized sweep of tests/coupling/coupled2d_sweep_test.cpp with
//    another seed, 100 variants of up to 50 disks;
//  - a bed of 1050 disks falling at 1 m/s onto a soft plate (E = 1e8 Pa)
//    with a void, and the frictional bed of the benchmark
//    (testing::disk_bed_on_plate) falling at 1 m/s onto the same E: every
//    step settles, and the exchange's books balance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/coupled2d_sweep_check.hpp"

namespace xfdem {
namespace {

/// The bed of Coupled2dCli.SameBytesOnOneAndTwoWorkers (70 × 15 disks of
/// 0.5 kg, r = 8 mm, k = 1e5 N/m, ζ = 0.2, the lowest row 0.2 mm above a
/// 2 m × 0.2 m plate of 40 × 4 cells held at its bottom, with a circular
/// void), falling at `speed` onto a plate of Young's modulus `e`.
Coupled2dDesc falling_bed(double speed, double e) {
  Coupled2dDesc d;
  d.plate = testing::plate(e, 2, 0.2, 40, 4);
  d.plate.density = 2000.0;
  d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
  d.plate.discontinuities.push_back(testing::circle(PlateDiscontinuity::Kind::hole, 1.0, 0.1, 0.06));
  d.dem.integrator = DemIntegrator::symplectic_euler;
  d.dem.gravity = {0.0, -9.81};
  d.dem.damping_ratio = 0.2;
  for (int j = 0; j < 15; ++j)
    for (int i = 0; i < 70; ++i)
      d.dem.particles.push_back(
          testing::disk(0.5, 0.008, 1e5, 0.11 + 0.0255 * i + 0.003 * (j % 2), 0.2082 + 0.017 * j, 0.0, -speed));
  d.dem_substeps = 10;
  return d;
}

void run_bed(const Coupled2dDesc& d, int steps, const char* what) {
  Coupled2dWorld w;
  const BuildResult r = w.build(d);
  ASSERT_TRUE(r.ok()) << r.message;
  double books = 0, exchange = 0;
  for (int step = 0; step < steps; ++step) {
    char said[256];
    const StepStatus s = w.step();
    ASSERT_EQ(s, StepStatus::ok) << what << ", step " << step << ": " << describe(s, said, sizeof(said));
    for (int axis = 0; axis < 2; ++axis) {
      books = std::max(books, std::fabs(w.state.impulse_to_particles[axis] + w.state.impulse_to_plate[axis]));
      exchange = std::max(exchange, std::fabs(w.state.impulse_to_particles[axis]));
    }
  }
  std::printf("%s, %d steps: peak passes %d, windows blended across a jump %lld, taken at their smallest residual "
              "%lld; books %.3g of the exchange %.3g N s\n",
              what, steps, w.state.peak_passes, static_cast<long long>(w.state.blended_windows),
              static_cast<long long>(w.state.unsettled_windows), books, exchange);
  EXPECT_EQ(w.state.unsettled_windows, 0);
  EXPECT_GT(exchange, 0.0);
  EXPECT_LT(books, 1e-12 * exchange);
}

}  // namespace

TEST(Coupled2dLong, AHundredRandomScenesSettleEveryWindowKeepMomentumAndCreateNoEnergy) {
  testing::run_sweep(7, 100, 50);
}

TEST(Coupled2dLong, ABedOf1050DisksFallingOntoASoftPlateSettlesEveryWindow) {
  run_bed(falling_bed(1.0, 1e8), 300, "1050 disks at 1 m/s onto E = 1e8 Pa");
}

TEST(Coupled2dLong, TheFrictionalBedFallingOntoASoftPlateSettlesEveryWindow) {
  Coupled2dDesc d = testing::disk_bed_on_plate(1050);
  d.plate.youngs_modulus = 1e8;
  for (auto& p : d.dem.particles) p.velocity = {0.0, -1.0};
  run_bed(d, 150, "1050 frictional disks at 1 m/s onto E = 1e8 Pa");
}

}  // namespace xfdem
