// The heap (label `long`): 600 disks released in a triangle with 40° sides
// just above the floor (scenes/granular/heap_2d.json) settle into a pile whose angle of
// repose, fitted to its free surface (tests/support/heap.hpp), rises with the
// friction μ and with the rolling friction μ_r; frictionless, the pile spreads
// flat. The same runs as tools/validation/heap.py (docs/figures/heap_repose.png).
#include <gtest/gtest.h>

#include "support/heap.hpp"

namespace xfdem::testing {
namespace {

TEST(HeapLong, AngleOfReposeRisesWithFriction) {
  const double mus[] = {0.1, 0.2, 0.5, 1.0};
  double previous = 0;
  for (const double mu : mus) {
    const Heap heap = run_heap("granular/heap_2d.json", mu, 0.0);
    EXPECT_GT(heap.angle_deg, previous) << "mu " << mu;
    EXPECT_LT(heap.angle_deg, 40.0) << "the pile stood where it started";
    previous = heap.angle_deg;
  }
}

TEST(HeapLong, AngleOfReposeRisesWithRollingFriction) {
  const double rolling[] = {0.0, 0.05, 0.2};
  double previous = 0;
  for (const double mu_r : rolling) {
    const Heap heap = run_heap("granular/heap_2d.json", 0.5, mu_r);
    EXPECT_GT(heap.angle_deg, previous) << "mu_r " << mu_r;
    EXPECT_LT(heap.angle_deg, 40.0) << "the pile stood where it started";
    previous = heap.angle_deg;
  }
}

TEST(HeapLong, FrictionlessPileSpreadsFlat) {
  const Heap flat = run_heap("granular/heap_2d.json", 0.0, 0.0);
  const Heap low = run_heap("granular/heap_2d.json", 0.1, 0.0);
  // The 40° triangle reached 29 mean diameters up.
  EXPECT_LT(flat.height, 2.5 * flat.mean_diameter);
  EXPECT_LT(flat.height, low.height);
}

}  // namespace
}  // namespace xfdem::testing
