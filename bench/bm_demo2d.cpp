// Per-step cost of the demonstration scene (docs/coupled2d.md, "Demonstration"):
// scenes/demo/retaining_wall.json, 2912 frictional disks of a backfill settling
// against a concrete wall with an edge crack and a weep hole, read through the
// scene reader as `xfdem run` reads it (symplectic Euler, 10 substeps per plate
// step of 1e-4 s). The backfill first takes kSettleSteps untimed steps (one run,
// kept for both rows); each batch then restores that state and times
// coupled2d_step, as BM_Coupled2dBed does (bench/bm_coupled2d.cpp; the same
// counters).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/platform/clock.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace {

using xfdem::Coupled2dState;
using xfdem::Coupled2dWorld;

constexpr int kSettleSteps = 2000;  // 0.2 s: the backfill has collapsed onto the floor and leans on the wall

struct Wall {
  Coupled2dWorld world;
  Coupled2dState warm;
  bool ok = false;
  std::string error;
};

Wall& settled_wall() {
  static std::unique_ptr<Wall> wall;
  if (wall) return *wall;
  wall = std::make_unique<Wall>();
  try {
    const xfdem::scene::Scene scene =
        xfdem::scene::load_scene(std::string(XFDEM_SOURCE_DIR) + "/scenes/demo/retaining_wall.json", {});
    if (const xfdem::BuildResult r = wall->world.build(xfdem::scene::coupled2d_desc(scene)); !r.ok()) {
      wall->error = std::string("build: ") + r.message;
      return *wall;
    }
  } catch (const xfdem::scene::SceneError& e) {
    wall->error = std::string("scene: ") + e.what();
    return *wall;
  }
  for (int k = 0; k < kSettleSteps; ++k)
    if (xfdem::has(wall->world.step(), xfdem::kStepNotTaken | xfdem::StepStatus::coupling_unstable)) {
      wall->error = "settling: coupling_unstable or a step not taken at step " + std::to_string(k);
      return *wall;
    }
  wall->ok = true;
  wall->warm = wall->world.state;
  return *wall;
}

/// The timed steps, alone in a function for callgrind (--toggle-collect='*run_wall_steps*').
[[gnu::noinline]] std::int64_t run_wall_steps(Coupled2dWorld& w, std::int64_t count) {
  std::int64_t passes = 0;
  for (std::int64_t k = 0; k < count; ++k) {
    benchmark::DoNotOptimize(w.step());
    passes += w.state.last_passes;
  }
  return passes;
}

void BM_Coupled2dRetainingWall(benchmark::State& bm) {
  Wall& wall = settled_wall();
  if (!wall.ok) {
    bm.SkipWithError(wall.error.c_str());
    return;
  }
  Coupled2dWorld& w = wall.world;
  static xfdem::platform::TwoWorkerPool pool;
  w.workspace.dem.parallel = bm.range(0) == 2 ? pool.parallel_for() : xfdem::ParallelFor{};
  constexpr benchmark::IterationCount kBatch = 10;
  std::int64_t passes = 0, steps = 0, unsettled = 0;
  while (bm.KeepRunningBatch(kBatch)) {
    bm.PauseTiming();
    w.state = wall.warm;
    bm.ResumeTiming();
    passes += run_wall_steps(w, kBatch);
    steps += kBatch;
    unsettled += w.state.unsettled_windows - wall.warm.unsettled_windows;
  }
  const double substeps = static_cast<double>(w.model.dem.n) * w.model.substeps;
  bm.counters["per_particle_substep"] =
      benchmark::Counter(substeps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  bm.counters["passes_per_step"] = static_cast<double>(passes) / static_cast<double>(steps);
  bm.counters["unsettled_per_step"] = static_cast<double>(unsettled) / static_cast<double>(steps);
  double fastest = 0;
  for (std::int32_t i = 0; i < w.model.dem.n; ++i)
    fastest = std::max(fastest, std::hypot(wall.warm.dem.v[0][i], wall.warm.dem.v[1][i]));
  bm.counters["warm_max_speed"] = fastest;
  bm.counters["parts"] = w.model.dem.parts;

  w.state = wall.warm;
  w.workspace.dem.clock_ns = &xfdem::platform::monotonic_ns;
  w.workspace.dem.profile = {};
  const std::int64_t t0 = xfdem::platform::monotonic_ns();
  run_wall_steps(w, kBatch);
  const std::int64_t total = xfdem::platform::monotonic_ns() - t0;
  w.workspace.dem.clock_ns = nullptr;
  bm.counters["stage_dem_share"] =
      static_cast<double>(w.workspace.dem.profile.step_ns) / static_cast<double>(total);
  w.workspace.dem.parallel = {};
}
// Argument: workers. Wall time, so that one and two workers compare.
BENCHMARK(BM_Coupled2dRetainingWall)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
