// Comparing two states of the same kind bit for bit, for the snapshot tests
// (tests/determinism/): the full-state hash, every byte of their snapshots,
// and the name of the first field that differs.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "xfdem/state_io.hpp"

namespace xfdem::testing {

/// Which field of two states differs first (by field hash), or "" when none.
template <class State>
std::string first_differing_field(const State& a, const State& b) {
  std::vector<std::uint64_t> ha(field_count(a)), hb(field_count(b));
  field_hashes(a, ha);
  field_hashes(b, hb);
  char name[128];
  for (std::size_t k = 0; k < ha.size() && k < hb.size(); ++k)
    if (ha[k] != hb[k]) return field_name(a, k, name, sizeof(name));
  return ha.size() == hb.size() ? "" : "(field count)";
}

/// Every array of a and b equal bit for bit: the snapshot payloads are the raw
/// bytes of every field.
template <class State>
void expect_bitwise_equal(const State& a, const State& b, const std::string& what) {
  EXPECT_EQ(state_hash(a), state_hash(b)) << what << ": first differing field " << first_differing_field(a, b);
  std::vector<std::byte> sa(snapshot_size(a)), sb(snapshot_size(b));
  ASSERT_TRUE(save_snapshot(a, sa).ok());
  ASSERT_TRUE(save_snapshot(b, sb).ok());
  EXPECT_TRUE(sa == sb) << what << ": snapshots differ; first differing field " << first_differing_field(a, b);
}

}  // namespace xfdem::testing
