// The small-system step (DemModel::small_step) against the general one: the
// same scene built twice, once with DemDesc::small_system_path off, stepped
// side by side with the same inputs; after every step the whole state must
// have the same bits (state_hash), the statuses and the contact signatures
// must agree. Randomized small scenes (seeded): 1-8 particles in 1D, 2D and
// 3D, fixed and driven planes (axis-aligned and oblique), damping on and off,
// both laws, gravity on and off, external forces, every integrator the small
// step covers, time steps past the stable one, and NaNs put into the state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "xfdem/dem.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kCovered[] = {DemIntegrator::abm4, DemIntegrator::rk4, DemIntegrator::verlet,
                                      DemIntegrator::symplectic_euler};

/// What the sweep saw, to show that it reached what it claims to test.
struct Seen {
  int scenes = 0;
  long steps = 0, contact_steps = 0, non_finite = 0, unstable = 0, energy_growth = 0, coincident = 0;
  // Scenes of one or two particles (their count compiled in) with one plane
  // (its count compiled in too) and with 0, 2 or 3 (the count read).
  int few_one_plane = 0, few_other_planes = 0;
};

/// Whether particle i starts deeper in a plane or an earlier particle than
/// the build allows (its radius; the smaller radius of a pair).
template <int D>
bool too_deep(const DemDesc<D>& d, int i) {
  const ParticleDesc<D>& p = d.particles[static_cast<std::size_t>(i)];
  for (const PlaneDesc<D>& pl : d.planes) {
    double gap = 0, norm2 = 0;
    for (int k = 0; k < D; ++k) {
      gap += (p.position[k] - pl.point[k]) * pl.normal[k];
      norm2 += pl.normal[k] * pl.normal[k];
    }
    if (p.radius - gap / std::sqrt(norm2) > p.radius) return true;
  }
  for (int j = 0; j < i; ++j) {
    const ParticleDesc<D>& q = d.particles[static_cast<std::size_t>(j)];
    double dist2 = 0;
    for (int k = 0; k < D; ++k) dist2 += (p.position[k] - q.position[k]) * (p.position[k] - q.position[k]);
    if (p.radius + q.radius - std::sqrt(dist2) > std::min(p.radius, q.radius)) return true;
  }
  return false;
}

template <int D>
DemDesc<D> random_scene(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto coin = [&](double p) { return u(rng) < p; };
  DemDesc<D> d;
  const int n = 1 + static_cast<int>(rng() % 8);
  for (int i = 0; i < n; ++i) {
    ParticleDesc<D> p;
    p.mass = 0.2 + u(rng);
    p.radius = 0.08 + 0.12 * u(rng);
    p.stiffness = 1e3 * (1.0 + 9.0 * u(rng));
    for (int k = 0; k < D; ++k) {
      p.position[k] = 0.2 + 0.6 * u(rng);  // in a unit box: many overlaps at the start
      p.velocity[k] = 2.0 * (u(rng) - 0.5);
    }
    d.particles.push_back(p);
  }
  const int planes = static_cast<int>(rng() % 4);
  for (int q = 0; q < planes; ++q) {
    PlaneDesc<D> pl;
    const int axis = static_cast<int>(rng() % D);
    const bool low = coin(0.5);
    pl.point[axis] = low ? 0.0 : 1.0;
    pl.normal[axis] = low ? 1.0 : -1.0;
    if (D > 1 && coin(0.4))
      for (int k = 0; k < D; ++k) pl.normal[k] += 0.5 * (u(rng) - 0.5);  // oblique
    d.planes.push_back(pl);
  }
  // Overlaps at the start up to the radius (deeper ones the build refuses):
  // redraw a position until it keeps within that of every plane and earlier particle.
  // A particle that finds no such place (eight on a line between two planes)
  // is left out.
  for (int i = 0; i < static_cast<int>(d.particles.size());) {
    ParticleDesc<D>& p = d.particles[static_cast<std::size_t>(i)];
    int attempt = 0;
    for (; attempt < 200 && too_deep(d, i); ++attempt)
      for (int k = 0; k < D; ++k) p.position[k] = 0.2 + 0.6 * u(rng);
    if (too_deep(d, i))
      d.particles.erase(d.particles.begin() + i);
    else
      ++i;
  }
  if (coin(0.7))
    for (int k = 0; k < D; ++k) d.gravity[k] = k == 0 ? -9.81 : 2.0 * (u(rng) - 0.5);
  d.damping_ratio = coin(0.6) ? 0.3 * u(rng) : 0.0;
  d.law = coin(0.5) ? ContactLaw::linear : ContactLaw::linear_nontensile;
  d.integrator = kCovered[rng() % 4];
  d.external_forces = coin(0.3);
  d.dt = 1.0;
  d.reject_unstable_dt = false;
  DemWorld<D> probe;  // the stable step of this scene
  EXPECT_TRUE(probe.build(d).ok());
  // Mostly below the stable step; one scene in eight past it (unstable_time_step,
  // growth, and at last non-finite values).
  const double stable = std::isfinite(probe.model.stable_dt) ? probe.model.stable_dt : 1e-3;  // no contact possible
  d.dt = stable * (coin(0.125) ? 1.0 + 2.0 * u(rng) : 0.1 + 0.8 * u(rng));
  d.reject_unstable_dt = d.dt <= probe.model.stable_dt;
  d.energy_check.interval = static_cast<std::int32_t>(rng() % 3) * 8;  // off, every 8, every 16
  return d;
}

template <int D>
void run_scene(std::uint64_t seed, Seen& seen) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  DemDesc<D> desc = random_scene<D>(rng);
  DemWorld<D> small, general;
  const BuildResult built = small.build(desc);
  ASSERT_TRUE(built.ok()) << "seed " << seed << ": " << built.message;
  desc.small_system_path = false;
  ASSERT_TRUE(general.build(desc).ok()) << "seed " << seed;
  ASSERT_NE(small.model.small_step, nullptr) << "seed " << seed;
  ASSERT_EQ(general.model.small_step, nullptr);
  ASSERT_EQ(state_hash(small.state), state_hash(general.state));
  if (desc.particles.size() <= 2) ++(desc.planes.size() == 1 ? seen.few_one_plane : seen.few_other_planes);
  const int steps = 300;
  const int nan_at = rng() % 6 == 0 ? static_cast<int>(rng() % steps) : -1;
  // Inputs between steps, the same for both worlds.
  auto inputs = [&](int k) {
    const std::size_t planes = desc.planes.size();
    if (planes > 0 && k % 10 == 0) {
      const auto p = static_cast<std::int32_t>(rng() % planes);
      const double offset = 0.05 * (u(rng) - 0.5), speed = u(rng) - 0.5;
      dem_drive_plane(small.model, small.state, p, offset, speed);
      dem_drive_plane(general.model, general.state, p, offset, speed);
    }
    if (desc.external_forces && k % 25 == 0) {
      for (int d = 0; d < D; ++d)
        for (std::size_t i = 0; i < desc.particles.size(); ++i) {
          const double f = 5.0 * (u(rng) - 0.5);
          small.state.external_force[d][i] = f;
          general.state.external_force[d][i] = f;
        }
      dem_inputs_changed(small.state);
      dem_inputs_changed(general.state);
    }
    if (k == nan_at) {
      // A NaN in one value the step reads or checks, both worlds alike.
      const int d = static_cast<int>(rng() % D);
      const auto i = static_cast<std::size_t>(rng() % desc.particles.size());
      const int which = static_cast<int>(rng() % 3);
      auto poison = [&](DemState<D>& s) {
        if (which == 0) s.x[d][i] = NAN;
        if (which == 1) s.v[d][i] = NAN;
        if (which == 2) s.hist_v[(s.history_head + 1) & 3][d][i] = NAN;  // the oldest slot
      };
      poison(small.state);
      poison(general.state);
    }
  };
  ++seen.scenes;
  platform::AllocationCounter counter;
  for (int k = 0; k < steps; ++k) {
    inputs(k);
    const StepStatus a = small.step();
    const StepStatus b = general.step();
    ASSERT_EQ(static_cast<unsigned>(a), static_cast<unsigned>(b))
        << "seed " << seed << " D " << D << " step " << k << " " << integrator_name(desc.integrator);
    ASSERT_EQ(state_hash(small.state), state_hash(general.state))
        << "seed " << seed << " D " << D << " step " << k << " " << integrator_name(desc.integrator);
    ASSERT_EQ(small.workspace.contact_signature, general.workspace.contact_signature) << "seed " << seed;
    ++seen.steps;
    const std::int32_t head = small.state.history_head;
    bool touching = small.state.network_omega2 > 0;
    for (double f : small.state.hist_plane_force[head]) touching |= f != 0.0;
    seen.contact_steps += touching ? 1 : 0;
    seen.non_finite += has(a, StepStatus::non_finite) ? 1 : 0;
    seen.unstable += has(a, StepStatus::unstable_time_step) ? 1 : 0;
    seen.energy_growth += has(a, StepStatus::energy_growth) ? 1 : 0;
    seen.coincident += has(a, StepStatus::coincident_centres) ? 1 : 0;
  }
  EXPECT_EQ(counter.allocations(), 0u) << "seed " << seed;
}

/// `scenes` random scenes of dimension D, then what they reached: contacts,
/// and each status the two steps must agree on.
template <int D>
void sweep(int scenes) {
  Seen seen;
  for (int k = 0; k < scenes; ++k) {
    run_scene<D>(0x5EED0000u + 1000u * D + static_cast<std::uint64_t>(k), seen);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("D = %d: %d scenes (%d of 1-2 particles with one plane, %d with another plane count), %ld steps, "
              "%ld with a contact, statuses: non_finite %ld, unstable_time_step %ld, energy_growth %ld, "
              "coincident_centres %ld\n",
              D, seen.scenes, seen.few_one_plane, seen.few_other_planes, seen.steps, seen.contact_steps,
              seen.non_finite, seen.unstable, seen.energy_growth, seen.coincident);
  EXPECT_GT(seen.contact_steps, seen.steps / 8);
  EXPECT_GT(seen.few_one_plane, 0);
  EXPECT_GT(seen.few_other_planes, 0);
  EXPECT_GT(seen.non_finite, 0);
  EXPECT_GT(seen.unstable, 0);
  EXPECT_GT(seen.energy_growth, 0);
}

/// dem_steps: a window of steps in one call of the small-system step (its
/// history ring loaded once and stored once) against the general step taken
/// one by one, with the inputs changed between windows as a coupled host
/// does, and now and then a NaN put into the history or into a value no step
/// writes: the same bits after every window and the same statuses together.
template <int D>
void windows(int scenes) {
  int nan_windows = 0;
  for (int k = 0; k < scenes; ++k) {
    const std::uint64_t seed = 0x3A1D0000u + 1000u * D + static_cast<std::uint64_t>(k);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    DemDesc<D> desc = random_scene<D>(rng);
    DemWorld<D> small, general;
    ASSERT_TRUE(small.build(desc).ok()) << "seed " << seed;
    desc.small_system_path = false;
    ASSERT_TRUE(general.build(desc).ok()) << "seed " << seed;
    ASSERT_NE(small.model.small_step, nullptr) << "seed " << seed;
    const int window = 1 + static_cast<int>(rng() % 12);
    const int nan_at = rng() % 6 == 0 ? static_cast<int>(rng() % 30) : -1;
    platform::AllocationCounter counter;
    for (int j = 0; j < 30; ++j) {
      if (!desc.planes.empty()) {
        const auto p = static_cast<std::int32_t>(rng() % desc.planes.size());
        const double offset = 0.05 * (u(rng) - 0.5), speed = u(rng) - 0.5;
        dem_drive_plane(small.model, small.state, p, offset, speed);
        dem_drive_plane(general.model, general.state, p, offset, speed);
      }
      if (j == nan_at) {
        // The oldest history slot, or a value no step writes (checked once
        // per call of the small step): x_ref, a plane's speed.
        const int d = static_cast<int>(rng() % D);
        const auto i = static_cast<std::size_t>(rng() % desc.particles.size());
        const int which = desc.planes.empty() ? static_cast<int>(rng() % 2) : static_cast<int>(rng() % 3);
        for (DemState<D>* s : {&small.state, &general.state}) {
          if (which == 0) s->hist_v[(s->history_head + 1) & 3][d][i] = NAN;
          if (which == 1) s->x_ref[d][i] = NAN;
          if (which == 2) s->plane_speed[0] = NAN;
        }
        ++nan_windows;
      }
      const StepStatus a = dem_steps(small.model, small.state, small.workspace, window);
      StepStatus b = StepStatus::ok;
      for (int s = 0; s < window; ++s) b |= general.step();
      ASSERT_EQ(static_cast<unsigned>(a), static_cast<unsigned>(b)) << "seed " << seed << " window " << j;
      ASSERT_EQ(state_hash(small.state), state_hash(general.state)) << "seed " << seed << " window " << j;
      ASSERT_EQ(small.workspace.contact_signature, general.workspace.contact_signature) << "seed " << seed;
    }
    EXPECT_EQ(counter.allocations(), 0u) << "seed " << seed;
  }
  EXPECT_GT(nan_windows, 0);
}

TEST(SmallSystem, WindowInOneCallSameBitsAsStepByStep) {
  windows<1>(100);
  windows<2>(60);
  windows<3>(60);
}

TEST(SmallSystem, SameBitsAsTheGeneralStep1D) { sweep<1>(300); }
TEST(SmallSystem, SameBitsAsTheGeneralStep2D) { sweep<2>(300); }
TEST(SmallSystem, SameBitsAsTheGeneralStep3D) { sweep<3>(300); }

// Where it applies: few particles, one part, a fixed pair list, no event location.
TEST(SmallSystem, TakenOnlyWhereItApplies) {
  DemDesc<2> d;
  d.dt = 1e-5;
  for (int i = 0; i < 8; ++i) d.particles.push_back({1.0, 0.1, 1e4, {0.3 * i, 0.0}, {0.0, 0.0}});
  auto small = [&](const DemDesc<2>& desc) {
    DemWorld<2> w;
    EXPECT_TRUE(w.build(desc).ok());
    return w.model.small_step != nullptr;
  };
  EXPECT_TRUE(small(d));
  DemDesc<2> e = d;
  e.integrator = DemIntegrator::abm4_events;
  EXPECT_FALSE(small(e));
  e = d;
  e.all_pairs_up_to = 4;  // grid
  EXPECT_FALSE(small(e));
  e = d;
  e.split_from = 2;  // two parts
  EXPECT_FALSE(small(e));
  e = d;
  e.particles.push_back({1.0, 0.1, 1e4, {3.0, 0.0}, {0.0, 0.0}});
  e.all_pairs_up_to = 9;  // nine particles
  EXPECT_FALSE(small(e));
  e = d;
  e.small_system_path = false;
  EXPECT_FALSE(small(e));
}

}  // namespace
}  // namespace xfdem::testing
