// Snapshots: N steps in one go equal k steps, save, restore into a fresh world
// built from the same description, N − k steps, bit for bit (full-state hash
// and every array), for every particle integrator, the V2 bar (tied and
// unilateral) and the coupled Case II; and refusal of corrupted, truncated and
// foreign snapshots, which leave the target state untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "scene/scene_world.hpp"
#include "support/state_compare.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem {
namespace {

using Bytes = std::vector<std::byte>;
using xfdem::testing::expect_bitwise_equal;
using xfdem::testing::first_differing_field;

// ---- a 2D DEM scene that uses every part of the state ------------------------------

/// 20 disks (grid broad phase: more than all_pairs_up_to) dropped in a box onto
/// each other, damped, at half the integrator's stable step: pairs, planes,
/// plane impulses, list rebuilds and the multistep history all change.
DemDesc<2> disks(DemIntegrator integrator) {
  DemDesc<2> d;
  d.gravity = {0.0, -9.81};
  d.damping_ratio = 0.1;
  d.integrator = integrator;
  std::uint64_t s = 12345;
  auto jitter = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(s >> 11) * 0x1.0p-53 - 0.5;
  };
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 5; ++col)
      d.particles.push_back({.mass = 0.01,
                             .radius = 0.01,
                             .stiffness = 1e4,
                             .position = {0.015 + 0.021 * col + 0.002 * jitter(), 0.012 + 0.021 * row},
                             .velocity = {0.05 * jitter(), 0.0}});
  d.planes = {{.point = {0, 0}, .normal = {0, 1}}, {.point = {0, 0}, .normal = {1, 0}},
              {.point = {0.12, 0}, .normal = {-1, 0}}};
  DemModel<2> m;
  DemState<2> st;
  DemWorkspace<2> w;
  d.dt = 1.0;
  d.reject_unstable_dt = false;
  EXPECT_TRUE(build_dem(d, m, st, w).ok());
  d.dt = 0.5 * m.stable_dt;
  d.reject_unstable_dt = true;
  return d;
}

template <int D>
void chop_dem(const DemDesc<D>& desc, std::int64_t n, std::int64_t k, const std::string& what) {
  DemWorld<D> whole, first, fresh;
  ASSERT_TRUE(whole.build(desc).ok());
  ASSERT_TRUE(first.build(desc).ok());
  ASSERT_TRUE(fresh.build(desc).ok());
  for (std::int64_t s = 0; s < n; ++s) ASSERT_EQ(whole.step(), StepStatus::ok) << what << " step " << s;
  for (std::int64_t s = 0; s < k; ++s) ASSERT_EQ(first.step(), StepStatus::ok);
  Bytes buffer(snapshot_size(first.state));
  const std::uint64_t tag = model_fingerprint(first.model);
  {
    platform::AllocationCounter counter;
    const SnapshotResult saved = save_snapshot(first.state, buffer, tag);
    ASSERT_TRUE(saved.ok()) << saved.message;
    const SnapshotResult restored = restore_snapshot(fresh.state, buffer, tag);
    ASSERT_TRUE(restored.ok()) << restored.message;
    EXPECT_EQ(state_hash(fresh.state), state_hash(first.state));
    EXPECT_EQ(counter.allocations(), 0u) << "save, restore and hash allocate nothing";
  }
  for (std::int64_t s = k; s < n; ++s) ASSERT_EQ(fresh.step(), StepStatus::ok);
  expect_bitwise_equal(whole.state, fresh.state, what + ", k = " + std::to_string(k));
}

class DemChop : public ::testing::TestWithParam<DemIntegrator> {};

TEST_P(DemChop, StepsInOneGoEqualSaveRestoreIntoAFreshWorldAndContinue) {
  const DemDesc<2> desc = disks(GetParam());
  // k = 1, 2: inside the RK4 start of the multistep history; 900: mid-run, contacts active.
  for (std::int64_t k : {1, 2, 3, 900}) chop_dem(desc, 2000, k, integrator_name(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, DemChop,
                         ::testing::Values(DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::verlet,
                                           DemIntegrator::symplectic_euler, DemIntegrator::rk4),
                         [](const auto& param_info) { return std::string(integrator_name(param_info.param)); });

TEST(DemChop, TheHistoryIsPartOfTheSnapshot) {
  // Restoring only positions and velocities is not enough for abm4: the fresh
  // world would restart its history and drift from the one-go run.
  const DemDesc<2> desc = disks(DemIntegrator::abm4);
  DemWorld<2> whole, fresh;
  ASSERT_TRUE(whole.build(desc).ok());
  ASSERT_TRUE(fresh.build(desc).ok());
  for (int s = 0; s < 500; ++s) whole.step();
  fresh.state.x = whole.state.x;
  fresh.state.v = whole.state.v;
  fresh.state.time = whole.state.time;
  fresh.state.step = whole.state.step;
  for (int s = 0; s < 500; ++s) whole.step(), fresh.step();
  EXPECT_NE(state_hash(whole.state), state_hash(fresh.state));
}

// ---- scenes: the V2 bar and the coupled cases ------------------------------------------

scene::Scene load(const char* file, const std::vector<std::string>& overrides = {}) {
  return scene::load_scene(std::string(XFDEM_SOURCE_DIR) + "/scenes/" + file, overrides);
}

void chop_scene(const scene::Scene& sc, std::int64_t n, std::int64_t k, const std::string& what) {
  scene::SceneWorld whole(sc), first(sc), fresh(sc);
  for (std::int64_t s = 0; s < n; ++s) ASSERT_FALSE(has(whole.step(), kStepNotTaken)) << what;
  for (std::int64_t s = 0; s < k; ++s) ASSERT_FALSE(has(first.step(), kStepNotTaken));
  Bytes buffer(first.snapshot_size());
  ASSERT_TRUE(first.save(buffer).ok());
  const SnapshotResult restored = fresh.restore(buffer);
  ASSERT_TRUE(restored.ok()) << restored.message;
  for (std::int64_t s = k; s < n; ++s) ASSERT_FALSE(has(fresh.step(), kStepNotTaken));
  EXPECT_EQ(whole.hash(), fresh.hash()) << what << ", k = " << k;
  Bytes a(whole.snapshot_size()), b(fresh.snapshot_size());
  ASSERT_TRUE(whole.save(a).ok());
  ASSERT_TRUE(fresh.save(b).ok());
  EXPECT_TRUE(a == b) << what << ", k = " << k << ": some array differs";
}

TEST(BarChop, TiedXfem) {
  for (std::int64_t k : {1, 137, 2500}) chop_scene(load("v2_xfem.json"), 5000, k, "v2_xfem tied");
}
TEST(BarChop, TiedFem) { chop_scene(load("v2_fem.json"), 3000, 1234, "v2_fem tied"); }
TEST(BarChop, Unilateral) {
  // Under a tensile tip load the unilateral interface opens, so the active set changes.
  const auto sc = load("v2_xfem.json", {"continuum.interface.behaviour=unilateral", "continuum.tip_load.amplitude=10000"});
  for (std::int64_t k : {1, 100, 2500}) chop_scene(sc, 5000, k, "v2_xfem unilateral");
}

TEST(CoupledChop, CaseTwo) {
  // Through the first impacts (the particles land near t = 0.6 s) and on.
  for (std::int64_t k : {1, 700, 3000}) chop_scene(load("case2_xfem.json"), 6000, k, "case2_xfem");
  chop_scene(load("case2_fem.json"), 6000, 2345, "case2_fem");
}

// ---- refusals ----------------------------------------------------------------------------

struct Saved {
  scene::SceneWorld world;
  Bytes bytes;
  explicit Saved(const scene::Scene& sc, int steps = 50) : world(sc) {
    for (int s = 0; s < steps; ++s) world.step();
    bytes.resize(world.snapshot_size());
    EXPECT_TRUE(world.save(bytes).ok());
  }
};

/// Restores `bytes` into a fresh world of `sc` stepped a little, expects the
/// status, a message containing `words`, and the state untouched.
void expect_refused(const scene::Scene& sc, const Bytes& bytes, SnapshotStatus status, const std::string& words) {
  scene::SceneWorld target(sc);
  for (int s = 0; s < 7; ++s) target.step();
  const std::uint64_t before = target.hash();
  const SnapshotResult r = target.restore(bytes);
  EXPECT_EQ(r.status, status) << snapshot_status_name(r.status) << ": " << r.message;
  EXPECT_NE(std::string(r.message).find(words), std::string::npos) << r.message;
  EXPECT_EQ(target.hash(), before) << "a refused snapshot must leave the state untouched";
}

TEST(Refusal, ACorruptedPayloadByte) {
  const auto sc = load("case2_xfem.json");
  Saved saved(sc);
  Bytes bytes = saved.bytes;
  bytes[kSnapshotHeaderBytes + 100] ^= std::byte{0x01};
  expect_refused(sc, bytes, SnapshotStatus::corrupted_payload, "payload checksum");
  bytes = saved.bytes;
  bytes.back() ^= std::byte{0x80};
  expect_refused(sc, bytes, SnapshotStatus::corrupted_payload, "payload checksum");
}

TEST(Refusal, ACorruptedHeaderByte) {
  const auto sc = load("case2_xfem.json");
  Saved saved(sc);
  for (std::size_t at : {8u, 20u, 30u, 44u, 50u}) {
    Bytes bytes = saved.bytes;
    bytes[at] ^= std::byte{0x04};
    expect_refused(sc, bytes, SnapshotStatus::corrupted_header, "header checksum");
  }
  Bytes bytes = saved.bytes;
  bytes[0] = std::byte{'Y'};
  expect_refused(sc, bytes, SnapshotStatus::not_a_snapshot, "not an xfdem snapshot");
}

TEST(Refusal, ATruncatedBuffer) {
  const auto sc = load("v2_xfem.json");
  Saved saved(sc);
  for (std::size_t keep : {std::size_t{0}, std::size_t{10}, kSnapshotHeaderBytes, saved.bytes.size() - 1}) {
    const Bytes bytes(saved.bytes.begin(), saved.bytes.begin() + static_cast<std::ptrdiff_t>(keep));
    expect_refused(sc, bytes, SnapshotStatus::truncated, "truncated");
  }
}

TEST(Refusal, ASnapshotOfAnotherScene) {
  // Other array sizes: case 1 has one particle, case 2 two.
  expect_refused(load("case1_xfem.json"), Saved(load("case2_xfem.json")).bytes, SnapshotStatus::other_layout,
                 "another state layout");
  // The same sizes, another model: the model tag tells them apart.
  expect_refused(load("v1_k1e3.json"), Saved(load("v1_k1e4.json")).bytes, SnapshotStatus::other_model,
                 "another model");
  // Another kind of state altogether.
  expect_refused(load("v2_xfem.json"), Saved(load("case2_xfem.json")).bytes, SnapshotStatus::other_state_kind,
                 "CoupledState cannot be restored into a BarState");
}

TEST(Refusal, AnotherFormatVersionOrPrecision) {
  const auto sc = load("v2_xfem.json");
  Saved saved(sc);
  auto rewrite = [&](std::size_t at, std::byte value) {
    Bytes bytes = saved.bytes;
    bytes[at] = value;
    const std::uint64_t sum = fnv1a(bytes.data(), 56);  // a well-formed header of another build
    std::memcpy(bytes.data() + 56, &sum, 8);
    return bytes;
  };
  expect_refused(sc, rewrite(8, std::byte{kSnapshotVersion + 1}), SnapshotStatus::unsupported_version,
                 "format version " + std::to_string(kSnapshotVersion + 1));
  expect_refused(sc, rewrite(20, std::byte{4}), SnapshotStatus::foreign_precision, "4-byte reals");
  Bytes swapped = saved.bytes;
  const std::uint32_t tag = 0x04030201u;
  std::memcpy(swapped.data() + 16, &tag, 4);
  const std::uint64_t sum = fnv1a(swapped.data(), 56);
  std::memcpy(swapped.data() + 56, &sum, 8);
  expect_refused(sc, swapped, SnapshotStatus::foreign_byte_order, "byte order");
}

// Found by fuzz/snapshot_restore_fuzz: a payload with matching checksums but a
// history slot, pair count, pair index or 0/1 flag out of range was restored,
// and the next step indexed out of bounds (history_head = 245760 in a V1
// snapshot). Such values are now refused as a corrupted payload.

/// Byte offset in a snapshot of the first field named `part.name` ("" part: the
/// state's own), from the state's visitor.
template <class State>
std::size_t offset_of(State& state, const std::string& part, const std::string& name) {
  std::size_t at = kSnapshotHeaderBytes, found = 0;
  bool done = false;
  for_each_field(state, [&](const char* p, const char* n, auto* data, std::size_t count) {
    if (!done && part == p && name == n) found = at, done = true;
    at += count * sizeof(*data);
  });
  EXPECT_TRUE(done) << part << "." << name;
  return found;
}

/// `bytes` with an int32 written at `at` and both checksums recomputed: a
/// well-formed snapshot holding a value no step produces.
Bytes with_int(Bytes bytes, std::size_t at, std::int32_t value) {
  std::memcpy(bytes.data() + at, &value, 4);
  const std::uint64_t payload = fnv1a(bytes.data() + kSnapshotHeaderBytes, bytes.size() - kSnapshotHeaderBytes);
  std::memcpy(bytes.data() + 48, &payload, 8);
  const std::uint64_t header = fnv1a(bytes.data(), 56);
  std::memcpy(bytes.data() + 56, &header, 8);
  return bytes;
}

TEST(Refusal, IndicesOutOfRangeUnderMatchingChecksums) {
  {
    const auto sc = load("v1_k1e4.json");
    DemWorld<1> layout;
    ASSERT_TRUE(layout.build(std::get<DemDesc<1>>(sc.dem)).ok());
    Saved saved(sc);
    auto refuse = [&](const char* field, std::int32_t value) {
      expect_refused(sc, with_int(saved.bytes, offset_of(layout.state, "", field), value),
                     SnapshotStatus::corrupted_payload, std::string("field '") + field + "'");
    };
    refuse("history_head", 245760);  // the fuzzer's input
    refuse("history_head", -1);
    refuse("history_head", 4);
    refuse("history_count", 5);
    refuse("pair_count", -1);
    refuse("pair_count", static_cast<std::int32_t>(layout.state.pair_i.size()) + 1);
    refuse("pairs_valid", 2);
    // The values a step produces are accepted, and the world steps on.
    scene::SceneWorld target(sc);
    ASSERT_TRUE(target.restore(with_int(saved.bytes, offset_of(layout.state, "", "history_head"), 3)).ok());
    EXPECT_FALSE(has(target.step(), kStepNotTaken));
  }
  {
    const auto sc = load("v2_fem.json");
    BarModel model;
    BarState state;
    BarWorkspace workspace;
    ASSERT_TRUE(build_bar(*sc.bar, model, state, workspace).ok());
    expect_refused(sc, with_int(Saved(sc).bytes, offset_of(state, "", "interface_closed"), 2),
                   SnapshotStatus::corrupted_payload, "field 'interface_closed' holds 2");
    // The energy check's flag is 0/1 as well (snapshot format 2).
    expect_refused(sc, with_int(Saved(sc).bytes, offset_of(state, "", "energy_exceeded"), -1),
                   SnapshotStatus::corrupted_payload, "field 'energy_exceeded' holds -1");
  }
  {
    const auto sc = load("case2_fem.json");
    CoupledWorld layout;
    ASSERT_TRUE(layout.build(scene::coupled_desc(sc)).ok());
    expect_refused(sc, with_int(Saved(sc).bytes, offset_of(layout.state, "dem", "history_head"), 7),
                   SnapshotStatus::corrupted_payload, "field 'history_head' holds 7");
    // A pair naming a particle that does not exist (two particles), under a pair count that covers it.
    ASSERT_GE(layout.state.dem.pair_i.size(), 1u);
    const Bytes bytes = with_int(Saved(sc).bytes, offset_of(layout.state, "dem", "pair_count"), 1);
    expect_refused(sc, with_int(bytes, offset_of(layout.state, "dem", "pair_j"), 2), SnapshotStatus::corrupted_payload,
                   "field 'pair_j' holds 2");
  }
}

TEST(Refusal, SaveIntoASmallBufferWritesNothing) {
  DemWorld<2> world;
  ASSERT_TRUE(world.build(disks(DemIntegrator::verlet)).ok());
  Bytes bytes(snapshot_size(world.state) - 1, std::byte{0x5a});
  const SnapshotResult r = save_snapshot(world.state, bytes);
  EXPECT_EQ(r.status, SnapshotStatus::buffer_too_small);
  EXPECT_NE(std::string(r.message).find("needs"), std::string::npos) << r.message;
  for (std::byte b : bytes) ASSERT_EQ(b, std::byte{0x5a});
}

TEST(Names, FieldsAreNamedForReplayReports) {
  scene::SceneWorld world(load("case2_xfem.json"));
  char name[128];
  std::vector<std::string> names;
  for (std::size_t k = 0; k < world.field_count(); ++k) names.push_back(world.field_name(k, name, sizeof(name)));
  EXPECT_EQ(names.front(), "dem.time");
  EXPECT_NE(std::find(names.begin(), names.end(), "dem.x"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "dem.hist_a[3]"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "bar.u"), names.end());
  EXPECT_EQ(names.back(), "time");
  DemWorld<2> disks2;
  ASSERT_TRUE(disks2.build(disks(DemIntegrator::abm4)).ok());
  EXPECT_STREQ(field_name(disks2.state, 3, name, sizeof(name)), "x[1]");
}

}  // namespace
}  // namespace xfdem
