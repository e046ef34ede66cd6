// A small heap (scenes/granular/heap_2d_small.json, 150 disks released in a triangle
// with 40° sides just above the floor, 1.5 s): a frictionless pile spreads flat, and
// friction with rolling resistance holds a slope. The sweep over μ and μ_r on
// 600 disks is tests/long/heap_long_test.cpp; the figure tools/validation/heap.py.
#include <gtest/gtest.h>

#include "support/heap.hpp"

namespace xfdem::testing {
namespace {

TEST(Heap, FrictionlessSpreadsFlatAndFrictionHoldsASlope) {
  const Heap flat = run_heap("granular/heap_2d_small.json", 0.0, 0.0);
  const Heap low = run_heap("granular/heap_2d_small.json", 0.1, 0.0);
  const Heap high = run_heap("granular/heap_2d_small.json", 0.5, 0.2);
  // Frictionless disks cannot hold a slope: what is left of the 40° triangle
  // (its top 14 mean diameters up) is at most two disks deep.
  EXPECT_LT(flat.height, 2.0 * flat.mean_diameter);
  EXPECT_GT(high.angle_deg, low.angle_deg);
  EXPECT_GT(high.height, low.height);
  EXPECT_GT(low.height, flat.height);
}

}  // namespace
}  // namespace xfdem::testing
