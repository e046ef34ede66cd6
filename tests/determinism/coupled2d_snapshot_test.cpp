// The coupled 2D state (Coupled2dState) across a snapshot, run after run
// and on 1 and 2 workers: N steps in one go equal k steps, save, restore
// into a fresh world built from the same description, N − k steps, bit for
// bit (state hash and every byte of the snapshot), with the disks' springs
// and torque input in use (friction, rolling resistance, hertz), with every
// integrator the coupled step takes, frictionless and frictional; and refusal of a snapshot of
// another kind of state, another layout or another model, which leaves the
// target untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/coupled2d_scenes.hpp"
#include "support/state_compare.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem {
namespace {

using Bytes = std::vector<std::byte>;
using xfdem::testing::expect_bitwise_equal;
using xfdem::testing::first_differing_field;
using xfdem::testing::disk;

/// The cracked free plate (2 m × 1 m, 8 × 4 cells, a crack across it) and
/// four spinning disks from its four sides, no gravity, ζ = 0.05, each at
/// another gap so that they reach the plate at other steps (the left one
/// 1 mm away, the top one over the crack's mouth 5 mm away, the right and
/// the bottom ones 10 mm away): within 120 steps contacts close, hold and
/// open while others are under way.
Coupled2dDesc cracked_plate_hit(DemIntegrator integrator, double friction, double rolling) {
  Coupled2dDesc d;
  d.plate = xfdem::testing::cracked_free_plate();
  d.dem.integrator = integrator;
  d.dem.damping_ratio = 0.05;
  d.dem.friction = friction;
  d.dem.rolling_friction = rolling;
  d.dem.tangential_stiffness_ratio = 0.8;
  auto spinning = [&](ParticleDesc<2> p, double w) {
    if (friction > 0 || rolling > 0) p.angular_velocity = {w};
    return p;
  };
  d.dem.particles.push_back(spinning(disk(2.0, 0.05, 1e6, -0.051, 0.37, 3.0, 0.4), 40.0));   // left
  d.dem.particles.push_back(spinning(disk(1.0, 0.05, 1e6, 2.06, 0.71, -2.0, 1.0), -60.0));   // right
  d.dem.particles.push_back(spinning(disk(1.5, 0.04, 2e6, 1.02, 1.045, 0.8, -2.5), 30.0));   // top
  d.dem.particles.push_back(spinning(disk(3.0, 0.06, 1e6, 0.51, -0.07, -0.9, 1.5), -20.0));  // bottom
  d.dem.split_from = 2;  // two parts of disks, so that a pool runs them on two workers
  d.dem_substeps = 10;
  return d;
}

/// The same with the hertz law (the plate's material the second body), with friction, e = 0.8.
Coupled2dDesc cracked_plate_hit_hertz() {
  Coupled2dDesc d = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.4, 0.0);
  d.dem.law = ContactLaw::hertz;
  d.dem.damping_ratio = 0;
  d.dem.restitution = 0.8;
  d.dem.tangential_stiffness_ratio = 0;  // Mindlin's
  for (auto& p : d.dem.particles) p.youngs_modulus = 7e10, p.poisson_ratio = 0.3, p.stiffness = 0;
  return d;
}

/// Steps `world` n times; every status must be the one `statuses` recorded
/// for those steps (or, when recording, is appended to it).
void run(Coupled2dWorld& world, std::int64_t n, std::vector<StepStatus>& statuses, bool record) {
  for (std::int64_t s = 0; s < n; ++s) {
    const StepStatus status = world.step();
    ASSERT_FALSE(has(status, kStepNotTaken)) << "step " << world.state.step;
    if (record) {
      statuses.push_back(status);
    } else {
      const auto at = static_cast<std::size_t>(world.state.step - 1);
      ASSERT_LT(at, statuses.size());
      EXPECT_EQ(status, statuses[at]) << "step " << at;
    }
  }
}

/// What of the coupling was in use at the end of the first k steps: the
/// springs (slots holding a chain), the torque input, the boundary's force.
struct InUse {
  int springs = 0, torques = 0, forces = 0;
};
InUse in_use(const Coupled2dWorld& w) {
  InUse u;
  for (std::int32_t c : w.state.springs.chain) u.springs += c >= 0 ? 1 : 0;
  for (const auto& t : w.state.dem.external_torque)
    for (double v : t) u.torques += v != 0.0 ? 1 : 0;
  for (std::int32_t i = 0; i < w.model.dem.n; ++i) {
    double f[2];
    if (coupled2d_boundary_force(w.model, w.state, i, f) && (f[0] != 0.0 || f[1] != 0.0)) ++u.forces;
  }
  return u;
}

/// N steps in one go (on one worker) against k steps, a snapshot, a restore
/// into a fresh world (on `restored_workers` workers) and N − k steps.
/// Returns what was in use at step k.
InUse chop(const Coupled2dDesc& desc, std::int64_t n, std::int64_t k, int restored_workers, const std::string& what) {
  Coupled2dWorld whole, first, fresh;
  for (Coupled2dWorld* w : {&whole, &first, &fresh})
    if (const BuildResult built = w->build(desc); !built.ok()) {
      ADD_FAILURE() << what << ": " << built.message;
      return {};
    }
  platform::TwoWorkerPool pool;
  if (restored_workers == 2) fresh.workspace.dem.parallel = pool.parallel_for();
  std::vector<StepStatus> statuses;
  run(whole, n, statuses, true);
  run(first, k, statuses, false);
  const InUse used = in_use(first);
  Bytes buffer(snapshot_size(first.state));
  const std::uint64_t tag = model_fingerprint(first.model);
  EXPECT_EQ(tag, model_fingerprint(fresh.model));
  {
    platform::AllocationCounter counter;
    const SnapshotResult saved = save_snapshot(first.state, buffer, tag);
    EXPECT_TRUE(saved.ok()) << saved.message;
    const SnapshotResult restored = restore_snapshot(fresh.state, buffer, tag);
    EXPECT_TRUE(restored.ok()) << restored.message;
    EXPECT_EQ(state_hash(fresh.state), state_hash(first.state));
    EXPECT_EQ(counter.allocations(), 0u) << "save, restore and hash allocate nothing";
  }
  run(fresh, n - k, statuses, false);
  expect_bitwise_equal(whole.state, fresh.state,
                       what + ", k = " + std::to_string(k) + ", " + std::to_string(restored_workers) + " worker(s)");
  return used;
}

constexpr std::int64_t kSteps = 120;

TEST(Coupled2dChop, FrictionAndRollingResistanceSpringsAndTorquesCarriedAcross) {
  const Coupled2dDesc desc = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.02);
  InUse most;
  for (std::int64_t k : {1, 3, 25, 60})
    for (int workers : {1, 2}) {
      const InUse u = chop(desc, kSteps, k, workers, "friction");
      most.springs = std::max(most.springs, u.springs);
      most.torques = std::max(most.torques, u.torques);
      most.forces = std::max(most.forces, u.forces);
    }
  std::printf("friction: at the snapshot, up to %d springs in use, %d disks held at a torque, %d at a boundary force\n",
              most.springs, most.torques, most.forces);
  // The snapshot was taken with springs stretched and torques held.
  EXPECT_GE(most.springs, 2);
  EXPECT_GE(most.torques, 2);
  EXPECT_GE(most.forces, 2);
}

TEST(Coupled2dChop, HertzWithFriction) {
  const Coupled2dDesc desc = cracked_plate_hit_hertz();
  InUse most;
  for (std::int64_t k : {3, 25, 60}) {
    const InUse u = chop(desc, kSteps, k, 2, "hertz");
    most.springs = std::max(most.springs, u.springs);
  }
  EXPECT_GE(most.springs, 1);
}

class Coupled2dChopIntegrator : public ::testing::TestWithParam<DemIntegrator> {};

TEST_P(Coupled2dChopIntegrator, FrictionlessWithEveryIntegrator) {
  const Coupled2dDesc desc = cracked_plate_hit(GetParam(), 0.0, 0.0);
  int forces = 0;
  for (std::int64_t k : {1, 2, 25, 60})
    forces = std::max(forces, chop(desc, kSteps, k, 2, integrator_name(GetParam())).forces);
  EXPECT_GE(forces, 2);
}

INSTANTIATE_TEST_SUITE_P(EveryCoupledIntegrator, Coupled2dChopIntegrator,
                         ::testing::Values(DemIntegrator::symplectic_euler, DemIntegrator::verlet, DemIntegrator::rk4,
                                           DemIntegrator::abm4),
                         [](const auto& param_info) { return std::string(integrator_name(param_info.param)); });

// Friction and rolling resistance with the integrators that evaluate the
// boundary at their stages (the DEM's hook; no torque input): the springs
// and the multistep history carried across.
TEST_P(Coupled2dChopIntegrator, FrictionWithEveryIntegrator) {
  const Coupled2dDesc desc = cracked_plate_hit(GetParam(), 0.5, 0.02);
  InUse most;
  for (std::int64_t k : {1, 25, 60}) {
    const InUse u = chop(desc, kSteps, k, 2, std::string("friction, ") + integrator_name(GetParam()));
    most.springs = std::max(most.springs, u.springs);
    most.forces = std::max(most.forces, u.forces);
  }
  EXPECT_GE(most.springs, 2);
  EXPECT_GE(most.forces, 2);
}

// Hertz (Mindlin's tangential history) with friction, the same.
TEST_P(Coupled2dChopIntegrator, HertzWithFrictionWithEveryIntegrator) {
  Coupled2dDesc desc = cracked_plate_hit_hertz();
  desc.dem.integrator = GetParam();
  InUse most;
  most.springs = chop(desc, kSteps, 25, 2, std::string("hertz, ") + integrator_name(GetParam())).springs;
  EXPECT_GE(most.springs, 1);
}

TEST(Coupled2dChop, TheSpringsArePartOfTheSnapshot) {
  // Restoring the disks and the plate but not the springs is not enough: the
  // fresh world's contacts restart their springs and drift from the one-go run.
  const Coupled2dDesc desc = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.0);
  Coupled2dWorld whole, fresh;
  ASSERT_TRUE(whole.build(desc).ok());
  ASSERT_TRUE(fresh.build(desc).ok());
  const Coupled2dSprings unstretched = fresh.state.springs;
  for (int s = 0; s < 25; ++s) ASSERT_FALSE(has(whole.step(), kStepNotTaken));
  ASSERT_GT(in_use(whole).springs, 0);
  Bytes buffer(snapshot_size(whole.state));
  ASSERT_TRUE(save_snapshot(whole.state, buffer).ok());
  ASSERT_TRUE(restore_snapshot(fresh.state, buffer).ok());
  fresh.state.springs = unstretched;
  for (int s = 0; s < 25; ++s) whole.step(), fresh.step();
  EXPECT_NE(state_hash(whole.state), state_hash(fresh.state));
}

TEST(Coupled2dDeterminism, RunAfterRunAndOnTwoWorkersTheSameHashAtEveryStep) {
  for (const Coupled2dDesc& desc :
       {cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.02), cracked_plate_hit(DemIntegrator::rk4, 0, 0),
        cracked_plate_hit(DemIntegrator::abm4, 0.5, 0.02)}) {
    Coupled2dWorld one, again, two;
    ASSERT_TRUE(one.build(desc).ok());
    ASSERT_TRUE(again.build(desc).ok());
    ASSERT_TRUE(two.build(desc).ok());
    platform::TwoWorkerPool pool;
    two.workspace.dem.parallel = pool.parallel_for();
    EXPECT_EQ(state_hash(one.state), state_hash(two.state));
    int differing = 0;
    for (std::int64_t s = 0; s < kSteps; ++s) {
      one.step(), again.step(), two.step();
      const std::uint64_t h = state_hash(one.state);
      differing += (h != state_hash(again.state)) + (h != state_hash(two.state));
    }
    EXPECT_EQ(differing, 0) << "first differing field: " << first_differing_field(one.state, two.state);
    EXPECT_GT(std::fabs(one.state.impulse_to_particles[0]), 0.0);  // the disks did hit the plate
  }
}

// ---- refusals ----------------------------------------------------------------------------

struct Saved {
  Coupled2dWorld world;
  Bytes bytes;
  std::uint64_t tag = 0;
  explicit Saved(const Coupled2dDesc& desc, int steps = 30) {
    EXPECT_TRUE(world.build(desc).ok());
    for (int s = 0; s < steps; ++s) world.step();
    tag = model_fingerprint(world.model);
    bytes.resize(snapshot_size(world.state));
    EXPECT_TRUE(save_snapshot(world.state, bytes, tag).ok());
  }
};

/// Restores into a world of `desc` stepped a little (with its own model's
/// tag), expects the status, a message containing `words`, and the state
/// untouched.
void expect_refused(const Coupled2dDesc& desc, const Bytes& bytes, SnapshotStatus status, const std::string& words) {
  Coupled2dWorld target;
  ASSERT_TRUE(target.build(desc).ok());
  for (int s = 0; s < 7; ++s) target.step();
  const std::uint64_t before = state_hash(target.state);
  const SnapshotResult r = restore_snapshot(target.state, bytes, model_fingerprint(target.model));
  EXPECT_EQ(r.status, status) << snapshot_status_name(r.status) << ": " << r.message;
  EXPECT_NE(std::string(r.message).find(words), std::string::npos) << r.message;
  EXPECT_EQ(state_hash(target.state), before) << "a refused snapshot must leave the state untouched";
}

TEST(Coupled2dRefusal, ASnapshotOfAnotherKindOfState) {
  const Coupled2dDesc desc = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.02);
  Saved saved(desc);
  // A coupled 2D snapshot into the disks alone, and the disks' or the plate's alone into a coupled 2D state.
  DemDesc<2> alone = desc.dem;
  alone.dt = 1e-5;
  DemWorld<2> disks;
  ASSERT_TRUE(disks.build(alone).ok());
  const std::uint64_t before = state_hash(disks.state);
  const SnapshotResult r = restore_snapshot(disks.state, saved.bytes, saved.tag);
  EXPECT_EQ(r.status, SnapshotStatus::other_state_kind) << r.message;
  EXPECT_NE(std::string(r.message).find("Coupled2dState cannot be restored into a DemState<2>"), std::string::npos)
      << r.message;
  EXPECT_EQ(state_hash(disks.state), before);
  Bytes dem_bytes(snapshot_size(saved.world.state.dem));
  ASSERT_TRUE(save_snapshot(saved.world.state.dem, dem_bytes).ok());
  expect_refused(desc, dem_bytes, SnapshotStatus::other_state_kind,
                 "DemState<2> cannot be restored into a Coupled2dState");
  Bytes plate_bytes(snapshot_size(saved.world.state.plate));
  ASSERT_TRUE(save_snapshot(saved.world.state.plate, plate_bytes).ok());
  expect_refused(desc, plate_bytes, SnapshotStatus::other_state_kind,
                 "PlateState cannot be restored into a Coupled2dState");
}

TEST(Coupled2dRefusal, ASnapshotOfAnotherModelOrLayout) {
  const Coupled2dDesc desc = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.02);
  const Saved saved(desc);
  // The same sizes, another model: a heavier disk, another friction, another crack, more substeps.
  Coupled2dDesc heavier = desc;
  heavier.dem.particles[1].mass = 1.25;
  Coupled2dDesc slipperier = desc;
  slipperier.dem.friction = 0.4;
  Coupled2dDesc other_crack = desc;
  other_crack.plate.discontinuities[0].points[1] = {1.12, 1.2};
  Coupled2dDesc finer = desc;
  finer.dem_substeps = 12;
  for (const Coupled2dDesc* other : {&heavier, &slipperier, &other_crack, &finer}) {
    Coupled2dWorld w;
    ASSERT_TRUE(w.build(*other).ok());
    ASSERT_EQ(layout_hash(w.state), layout_hash(saved.world.state));
    expect_refused(*other, saved.bytes, SnapshotStatus::other_model, "another model");
  }
  // Other sizes: frictionless disks keep no springs and no torque input; a disk more.
  expect_refused(cracked_plate_hit(DemIntegrator::symplectic_euler, 0, 0), saved.bytes, SnapshotStatus::other_layout,
                 "another state layout");
  Coupled2dDesc more = desc;
  more.dem.particles.push_back(disk(1.0, 0.05, 1e6, 1.5, 1.3, 0.0, -1.0));
  expect_refused(more, saved.bytes, SnapshotStatus::other_layout, "another state layout");
}

TEST(Coupled2dRefusal, ACorruptedByte) {
  const Coupled2dDesc desc = cracked_plate_hit(DemIntegrator::symplectic_euler, 0.5, 0.02);
  const Saved saved(desc);
  Bytes bytes = saved.bytes;
  bytes.back() ^= std::byte{0x01};
  expect_refused(desc, bytes, SnapshotStatus::corrupted_payload, "payload checksum");
  bytes = saved.bytes;
  bytes[21] ^= std::byte{0x01};  // the kind
  expect_refused(desc, bytes, SnapshotStatus::corrupted_header, "header checksum");
}

TEST(Coupled2dNames, FieldsAreNamedForReplayReports) {
  Coupled2dWorld w;
  ASSERT_TRUE(w.build(cracked_plate_hit(DemIntegrator::rk4, 0, 0)).ok());
  char name[128];
  std::vector<std::string> names;
  for (std::size_t k = 0; k < field_count(w.state); ++k) names.push_back(field_name(w.state, k, name, sizeof(name)));
  for (const char* wanted : {"dem.x[1]", "dem.hist_a[3]", "plate.u", "plate.energy_exceeded", "springs.xi",
                             "coupling_force", "boundary_force[1]", "impulse_to_plate", "worst_unsettled"})
    EXPECT_NE(std::find(names.begin(), names.end(), wanted), names.end()) << wanted;
  EXPECT_EQ(names.front(), "dem.time");
  EXPECT_EQ(names.back(), "time");
}

}  // namespace
}  // namespace xfdem
