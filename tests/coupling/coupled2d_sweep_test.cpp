// The coupled 2D window over a randomized sweep of scenes (support/coupled2d_sweep.hpp):
// every window settles (no step says coupling_unstable, or anything else);
// a free plate keeps the total momentum; the exchange's work on the plate is
// the disks' work on the boundary, step by step; with no damping the scene's
// energy at contact-free instants never rises beyond round-off.
// A larger sweep runs in the long suite (tests/long/coupled2d_long_test.cpp).
#include "support/coupled2d_sweep_check.hpp"

TEST(Coupled2dSweep, FortyRandomScenesSettleEveryWindowKeepMomentumAndCreateNoEnergy) {
  xfdem::testing::run_sweep(20261125, 40, 30);
}
