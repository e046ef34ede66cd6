// The two-worker pool runs every part exactly once per call, in any timing:
// no lost wake-ups when the waiting threads go to sleep at once (spins = 0)
// or spin first, with tasks of very different lengths.
#include <gtest/gtest.h>

#include <atomic>

#include "xfdem/platform/worker_pool.hpp"

namespace {

struct Work {
  int* counts;
  int uneven;  // loop length of part 1, to let either side finish first
};

TEST(TwoWorkerPool, EveryPartRunsOncePerCallWhateverTheTiming) {
  for (int spins : {0, 50, 2000}) {
    xfdem::platform::TwoWorkerPool pool(-1, spins);
    const xfdem::ParallelFor parallel = pool.parallel_for();
    int counts[3] = {0, 0, 0};
    constexpr int kCalls = 20000;
    for (int call = 0; call < kCalls; ++call) {
      volatile int sink = 0;
      xfdem::for_parts(parallel, 3, [&](int part) {
        ++counts[part];
        if (part == 1)
          for (int k = 0; k < call % 97; ++k) sink = sink + k;  // part 1 sometimes longer, sometimes shorter
      });
    }
    EXPECT_EQ(counts[0], kCalls) << "spins " << spins;
    EXPECT_EQ(counts[1], kCalls) << "spins " << spins;
    EXPECT_EQ(counts[2], kCalls) << "spins " << spins;
  }
}

}  // namespace
