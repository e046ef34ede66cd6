#pragma once
// One check shared by the rotating laws' tests: a description stepped on one
// and on two workers, with a snapshot taken half-way and restored into a
// fresh world, gives the same bits, and no step allocates.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "xfdem/dem.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem::testing {

/// Steps `one` (built here from `d`) `steps` times and compares it with the
/// two-worker run and the restored one; `one` is left at the end for the
/// caller's own assertions.
template <int D>
void expect_same_bits_on_two_workers_and_after_a_snapshot(const DemDesc<D>& d, DemWorld<D>& one, int steps = 4000) {
  DemWorld<D> two, restored;
  const BuildResult built = one.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  ASSERT_TRUE(two.build(d).ok());
  ASSERT_TRUE(restored.build(d).ok());
  platform::TwoWorkerPool pool;
  two.workspace.parallel = pool.parallel_for();
  std::vector<std::byte> buffer(snapshot_size(one.state));
  const int half = steps / 2;
  platform::AllocationCounter counter;
  for (int k = 0; k < steps; ++k) {
    ASSERT_FALSE(has(one.step(), kStepNotTaken));
    ASSERT_FALSE(has(two.step(), kStepNotTaken));
    if (k == half - 1) {
      ASSERT_EQ(save_snapshot(one.state, buffer, model_fingerprint(one.model)).status, SnapshotStatus::ok);
    }
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(state_hash(one.state), state_hash(two.state));
  ASSERT_EQ(restore_snapshot(restored.state, buffer, model_fingerprint(restored.model)).status, SnapshotStatus::ok);
  for (int k = half; k < steps; ++k) ASSERT_FALSE(has(restored.step(), kStepNotTaken));
  EXPECT_EQ(state_hash(restored.state), state_hash(one.state));
}

}  // namespace xfdem::testing
