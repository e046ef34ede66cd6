#include <gtest/gtest.h>

#include <memory>

#include "xfdem/platform/alloc_guard.hpp"

// The guard itself must see allocations, or every "zero allocations" test
// elsewhere would pass vacuously.
TEST(AllocGuard, CountsHeapAllocations) {
  xfdem::platform::AllocationCounter counter;
  auto p = std::make_unique<int[]>(100);
  p[3] = 1;
  EXPECT_GE(counter.allocations(), 1u);
}

TEST(AllocGuard, StackWorkCountsNothing) {
  xfdem::platform::AllocationCounter counter;
  volatile double sum = 0;
  for (int i = 0; i < 100; ++i) sum = sum + i;
  EXPECT_EQ(counter.allocations(), 0u);
}
