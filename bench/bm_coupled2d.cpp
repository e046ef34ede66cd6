// Per-step cost of the coupled 2D stepper (coupled2d.hpp): a bed of N
// frictional disks on a plate with a void and a crack
// (testing::disk_bed_on_plate), symplectic Euler, 10 substeps per plate step.
// The bed first settles for kSettleSteps untimed steps (one run per N, kept for
// every row of that N); each batch then restores that warm state and times
// coupled2d_step.
//
// Counters: `per_particle_substep` (shown in ns) is the time of a plate step
// over N × 10; `passes_per_step` the window's fixed-point passes (each pass
// runs the 10 substeps again); `stage_dem_ns` the share of a step spent in the
// DEM's own steps (DemWorkspace::clock_ns, an untimed run of its own from the
// same warm state), the rest being the plate's steps, the boundary's contacts
// and the exchange (docs/coupled2d.md, "Cost", splits those with callgrind on
// run_steps).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "support/coupled2d_scenes.hpp"
#include "xfdem/platform/clock.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace {

using xfdem::Coupled2dState;
using xfdem::Coupled2dWorld;

constexpr int kSettleSteps = 200;  // 0.02 s

struct Bed {
  Coupled2dWorld world;
  Coupled2dState warm;
  bool ok = false;
  std::string error;
};

/// The settled bed of n disks, built and settled once.
Bed& settled_bed(int n) {
  static std::map<int, std::unique_ptr<Bed>> beds;
  std::unique_ptr<Bed>& bed = beds[n];
  if (bed) return *bed;
  bed = std::make_unique<Bed>();
  if (const xfdem::BuildResult r = bed->world.build(xfdem::testing::disk_bed_on_plate(n)); !r.ok()) {
    bed->error = std::string("build: ") + r.message;
    return *bed;
  }
  for (int k = 0; k < kSettleSteps; ++k)
    if (xfdem::has(bed->world.step(), xfdem::kStepNotTaken | xfdem::StepStatus::coupling_unstable)) {
      bed->error = "settling: coupling_unstable or a step not taken at step " + std::to_string(k);
      return *bed;
    }
  bed->ok = true;
  bed->warm = bed->world.state;
  return *bed;
}

/// The timed steps, in a function of their own so that callgrind can collect
/// them alone (--toggle-collect='*run_steps*').
[[gnu::noinline]] std::int64_t run_steps(Coupled2dWorld& w, std::int64_t count) {
  std::int64_t passes = 0;
  for (std::int64_t k = 0; k < count; ++k) {
    benchmark::DoNotOptimize(w.step());
    passes += w.state.last_passes;
  }
  return passes;
}

void BM_Coupled2dBed(benchmark::State& bm) {
  const auto n = static_cast<int>(bm.range(0));
  Bed& bed = settled_bed(n);
  if (!bed.ok) {
    bm.SkipWithError(bed.error.c_str());
    return;
  }
  Coupled2dWorld& w = bed.world;
  static xfdem::platform::TwoWorkerPool pool;
  w.workspace.dem.parallel = bm.range(1) == 2 ? pool.parallel_for() : xfdem::ParallelFor{};
  constexpr benchmark::IterationCount kBatch = 10;
  std::int64_t passes = 0, steps = 0, unsettled = 0;
  while (bm.KeepRunningBatch(kBatch)) {
    bm.PauseTiming();
    w.state = bed.warm;  // same-sized vectors: copies in place
    bm.ResumeTiming();
    passes += run_steps(w, kBatch);
    steps += kBatch;
    unsettled += w.state.unsettled_windows - bed.warm.unsettled_windows;
  }
  const double substeps = static_cast<double>(n) * w.model.substeps;
  bm.counters["per_particle_substep"] =
      benchmark::Counter(substeps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  bm.counters["passes_per_step"] = static_cast<double>(passes) / static_cast<double>(steps);
  // Windows taken at their smallest residual (a contact closing or opening
  // within the window as the force moves), per step.
  bm.counters["unsettled_per_step"] = static_cast<double>(unsettled) / static_cast<double>(steps);
  double fastest = 0;  // how far from rest the warm bed is (m/s)
  for (std::int32_t i = 0; i < w.model.dem.n; ++i)
    fastest = std::max(fastest, std::hypot(bed.warm.dem.v[0][i], bed.warm.dem.v[1][i]));
  bm.counters["warm_max_speed"] = fastest;
  bm.counters["parts"] = w.model.dem.parts;  // 2: the DEM runs on two workers when given them

  // The DEM's share, from an untimed run with the DEM's clock installed.
  w.state = bed.warm;
  w.workspace.dem.clock_ns = &xfdem::platform::monotonic_ns;
  w.workspace.dem.profile = {};
  const std::int64_t t0 = xfdem::platform::monotonic_ns();
  run_steps(w, kBatch);
  const std::int64_t total = xfdem::platform::monotonic_ns() - t0;
  w.workspace.dem.clock_ns = nullptr;
  bm.counters["stage_dem_share"] =
      static_cast<double>(w.workspace.dem.profile.step_ns) / static_cast<double>(total);
  w.workspace.dem.parallel = {};
}
// Arguments: {N disks, workers}. Wall time, so that one and two workers compare.
BENCHMARK(BM_Coupled2dBed)
    ->ArgsProduct({{100, 1000, 3000}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
