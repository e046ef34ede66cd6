// A step never touches the heap: many steps of every DEM scene in scenes/ and
// of a 3D cloud whose pair list is rebuilt, under every integrator, inside a
// global allocation counter (platform/alloc_guard).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "scene/scene.hpp"
#include "support/dem_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4,
                                  DemIntegrator::verlet, DemIntegrator::symplectic_euler};

/// What a run did, besides allocating: pair-list builds and the most contact
/// events one step located (abm4_events).
struct RunCounts {
  std::int64_t list_builds = 0;
  std::int32_t peak_events = 0;
};

template <int D>
std::uint64_t allocations_during_steps(DemDesc<D> desc, DemIntegrator integrator, int steps,
                                       RunCounts* counts = nullptr) {
  desc.integrator = integrator;
  DemWorld<D> world;
  const BuildResult built = world.build(desc);
  EXPECT_TRUE(built.ok()) << built.message;
  platform::AllocationCounter counter;
  for (int s = 0; s < steps; ++s) {
    const StepStatus status = world.step();
    if (status != StepStatus::ok) {
      ADD_FAILURE() << "step " << s << " status " << static_cast<unsigned>(status);
      break;
    }
  }
  const std::uint64_t n = counter.allocations();
  EXPECT_GT(world.state.step, steps / 2);
  if (counts) *counts = {world.state.list_builds, world.state.peak_events};
  return n;
}

TEST(Allocation, EveryDemSceneStepsWithoutAllocating) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(XFDEM_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    const scene::Scene s = [&] {
      try {
        return scene::load_scene(entry.path().string(), {});
      } catch (const scene::SceneError&) {
        return scene::Scene{};  // a continuum scene in a DEM-only build
      }
    }();
    if (const auto* d = std::get_if<DemDesc<1>>(&s.dem); d && !s.has_continuum) {
      for (DemIntegrator integ : kAll) {
        // 3 s of the drop test: free flight, impacts, releases, restarts.
        EXPECT_EQ(allocations_during_steps<1>(*d, integ, 30000), 0u) << entry.path() << " " << integrator_name(integ);
      }
      ++scenes;
    }
  }
  EXPECT_GE(scenes, 3);
}

TEST(Allocation, GridRebuildsAndEventsDoNotAllocate) {
  DemDesc<3> d;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  d.gravity = {0, 0, -9.81};
  d.damping_ratio = 0.1;
  d.dt = 2e-5;
  d.all_pairs_up_to = 0;
  for (int i = 0; i < 150; ++i) {
    ParticleDesc<3> p{0.01, 0.005, 1e4, {}, {}};
    do {  // no pair starts deeper than the smaller radius (the build refuses that)
      p.position = {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)};
    } while (starts_too_deep(d.particles, p));
    p.velocity = {u(rng) - 0.5, u(rng) - 0.5, 0};
    d.particles.push_back(p);
  }
  for (int k = 0; k < 3; ++k) {
    PlaneDesc<3> lo, hi;
    lo.normal[k] = 1;
    hi.normal[k] = -1;
    hi.point[k] = 0.1;
    d.planes.push_back(lo);
    d.planes.push_back(hi);
  }
  for (DemIntegrator integ : kAll) {
    RunCounts counts;
    EXPECT_EQ(allocations_during_steps<3>(d, integ, 1000, &counts), 0u) << integrator_name(integ);
    std::printf("%-17s list builds %lld, peak events per step %d\n", integrator_name(integ),
                static_cast<long long>(counts.list_builds), counts.peak_events);
    // What the name says happened: the grid list was rebuilt during the steps,
    // and abm4_events located contact events.
    EXPECT_GT(counts.list_builds, 1) << integrator_name(integ);
    if (integ == DemIntegrator::abm4_events) {
      EXPECT_GT(counts.peak_events, 0);
    }
  }
}

}  // namespace
}  // namespace xfdem::testing
