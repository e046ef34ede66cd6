// Per-step cost of the DEM kernel.
//
// BM_DemDrop:    the V1 drop test (one sphere on a plane, 1D), per step.
// BM_DemPacking: a dense 3D packing of N equal spheres settled under gravity in
//                a box of six planes (bench/dem_packing.hpp); counters report
//                ns per particle-step, mean contacts per particle, pair-list
//                rebuilds per step and the kernel's stage profile (broad
//                phase, contacts, integration, ns per particle-step). The
//                vs_liggghts rows are the ones tools/bench_liggghts.py runs.
//
// Every benchmark starts each batch of steps from the same warm snapshot (a
// copy of DemState), as MuJoCo's step benchmark does, so that the work timed
// does not drift with the number of iterations Google Benchmark picks.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>

#include "dem_packing.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/platform/clock.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace {

using namespace xfdem;
using namespace xfdem_bench;

// ---- V1: one sphere dropped on a plane (1D) --------------------------------

void BM_DemDrop(benchmark::State& bench, DemIntegrator integrator) {
  DemDesc<1> desc;
  desc.particles.push_back({.mass = 1.0, .radius = 0.1, .stiffness = 1e4, .position = {0.15}, .velocity = {0.0}});
  desc.planes.push_back({.point = {0.0}, .normal = {1.0}});
  desc.gravity = {-9.81};
  desc.damping_ratio = 0.1;
  desc.integrator = integrator;
  desc.dt = 1e-4;
  DemModel<1> model;
  DemState<1> state;
  DemWorkspace<1> work;
  require(build_dem(desc, model, state, work).ok(), "drop: build failed");
  // Warm: past the RK4 start steps of abm4, still in free fall (impact at ~0.1 s).
  for (int k = 0; k < 100; ++k) require(!has(dem_step(model, state, work), kStepNotTaken), "drop: warm-up step");
  const DemState<1> warm = state;
  // A batch of 0.5 s covers the fall, the impact (about 300 steps in contact)
  // and the rebound, so every kind of step is in the average.
  constexpr benchmark::IterationCount kBatch = 5000;
  while (bench.KeepRunningBatch(kBatch)) {
    state = warm;  // same-sized vectors: copies in place
    for (benchmark::IterationCount k = 0; k < kBatch; ++k) benchmark::DoNotOptimize(dem_step(model, state, work));
  }
  benchmark::DoNotOptimize(state.x[0][0]);
}
BENCHMARK_CAPTURE(BM_DemDrop, abm4, DemIntegrator::abm4);
BENCHMARK_CAPTURE(BM_DemDrop, abm4_events, DemIntegrator::abm4_events);
BENCHMARK_CAPTURE(BM_DemDrop, verlet, DemIntegrator::verlet);

/// The second argument, when given, is the number of workers (1 or 2); a third,
/// when given, overrides DemDesc::split_from (0: never split, 1: always).
/// `energy_interval` ≥ 0 overrides EnergyCheck::interval; `friction`: the
/// frictional law of dem_packing.hpp (a kernel with friction only); `hertz`:
/// its Hertz–Mindlin law with friction.
void BM_DemPacking(benchmark::State& bench, DemIntegrator integrator, double skin_radii, int energy_interval = -1,
                   bool friction = false, bool hertz = false) {
  const auto n = static_cast<std::int32_t>(bench.range(0));
  const Packing& pk = packing(n);
  DemDesc<3> desc = packing_run_desc(pk, integrator, skin_radii);
  const bool two_workers = bench.range(1) == 2;
  if (bench.range(2) >= 0) desc.split_from = static_cast<std::int32_t>(bench.range(2));
  if (energy_interval >= 0) desc.energy_check.interval = energy_interval;
  if (friction && !set_packing_friction(desc)) {
    bench.SkipWithError("this kernel has no friction");
    return;
  }
  if (hertz && !set_packing_hertz(desc)) {
    bench.SkipWithError("this kernel has no hertz law");
    return;
  }
  DemModel<3> model;
  DemState<3> state;
  DemWorkspace<3> work;
  build_packing_run(desc, model, state, work);
  static xfdem::platform::TwoWorkerPool pool;
  if (two_workers) work.parallel = pool.parallel_for();
  for (int k = 0; k < 200; ++k)
    require(!has(dem_step(model, state, work), kStepNotTaken | StepStatus::non_finite), "packing: warm-up step");
  const DemState<3> warm = state;

  const benchmark::IterationCount batch = std::max<benchmark::IterationCount>(10, 2'000'000 / n);
  std::int64_t rebuilds = 0, steps = 0;
  while (bench.KeepRunningBatch(batch)) {
    bench.PauseTiming();
    state = warm;  // same-sized vectors: copies in place, no allocation
    bench.ResumeTiming();
    const std::int64_t builds_before = state.list_builds;
    for (benchmark::IterationCount k = 0; k < batch; ++k) benchmark::DoNotOptimize(dem_step(model, state, work));
    rebuilds += state.list_builds - builds_before;
    steps += batch;
  }
  // Seconds per particle-step (shown in ns; "per_particle_step" in the JSON).
  bench.counters["per_particle_step"] = benchmark::Counter(
      static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  bench.counters["contacts_per_particle"] = contacts_per_particle(model, state);
  bench.counters["pairs_listed_per_particle"] = static_cast<double>(state.pair_count) / n;
  bench.counters["rebuilds_per_step"] = steps > 0 ? static_cast<double>(rebuilds) / static_cast<double>(steps) : 0.0;
  bench.counters["dt_us"] = desc.dt * 1e6;

  // Where the time goes: the kernel's stage profile over a separate, untimed
  // run from the same warm state (a clock read per stage; the timed loop above
  // runs without it). ns per particle-step, wall time on the calling thread.
  state = warm;
  work.clock_ns = &xfdem::platform::monotonic_ns;
  work.profile = {};
  for (benchmark::IterationCount k = 0; k < batch; ++k) benchmark::DoNotOptimize(dem_step(model, state, work));
  work.clock_ns = nullptr;
  const double per = 1.0 / (static_cast<double>(work.profile.steps) * n);
  bench.counters["stage_broad_phase_ns"] = static_cast<double>(work.profile.broad_phase_ns) * per;
  bench.counters["stage_contacts_ns"] = static_cast<double>(work.profile.contacts_ns) * per;
  bench.counters["stage_integration_ns"] = static_cast<double>(work.profile.integration_ns()) * per;
}
// Arguments: {N, workers, split_from (-1: the kernel's default)}. Wall time, so
// that one and two workers compare.
BENCHMARK_CAPTURE(BM_DemPacking, verlet, DemIntegrator::verlet, 0.0)
    ->Args({1000, 1, -1})->Args({10000, 1, -1})->Args({100000, 1, -1})
    ->Args({1000, 2, -1})->Args({10000, 2, -1})->Args({100000, 2, -1})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DemPacking, abm4, DemIntegrator::abm4, 0.0)
    ->Args({1000, 1, -1})->Args({10000, 1, -1})->Args({100000, 1, -1})
    ->Args({1000, 2, -1})->Args({10000, 2, -1})->Args({100000, 2, -1})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
// A thinner skin lists fewer non-touching pairs and rebuilds more often.
BENCHMARK_CAPTURE(BM_DemPacking, verlet_skin_0.2r, DemIntegrator::verlet, 0.2)
    ->Args({1000, 1, -1})->Args({10000, 1, -1})->Args({100000, 1, -1})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
// The energy balance check's share: off, and at every step (the default, every
// 16 steps, is the `verlet` rows above).
BENCHMARK_CAPTURE(BM_DemPacking, verlet_energy_check_off, DemIntegrator::verlet, 0.0, 0)
    ->Args({10000, 1, -1})->Args({10000, 2, -1})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DemPacking, verlet_energy_check_every_step, DemIntegrator::verlet, 0.0, 1)
    ->Args({10000, 1, -1})->Args({10000, 2, -1})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
// The sizes tools/bench_liggghts.py compares with LIGGGHTS (the range of
// dense packings, 10^4 to 6·10^4 spheres), on one and two workers.
BENCHMARK_CAPTURE(BM_DemPacking, vs_liggghts, DemIntegrator::verlet, 0.0)
    ->ArgsProduct({{10000, 60000}, {1, 2}, {-1}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);
// The same with Coulomb friction and rotation, registered when the kernel has
// friction (tools/bench_liggghts.py --friction).
[[maybe_unused]] const bool kFrictionRowsRegistered = [] {
  if (!kHasFriction<DemDesc<3>>) return false;
  benchmark::RegisterBenchmark("BM_DemPacking/vs_liggghts_friction",
                               [](benchmark::State& bench) { BM_DemPacking(bench, DemIntegrator::verlet, 0.0, -1, true); })
      ->ArgsProduct({{10000, 60000}, {1, 2}, {-1}})
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
  return true;
}();
// Hertz–Mindlin with friction (tools/bench_liggghts.py --hertz).
[[maybe_unused]] const bool kHertzRowsRegistered = [] {
  if (!kHasHertz<DemDesc<3>>) return false;
  benchmark::RegisterBenchmark("BM_DemPacking/vs_liggghts_hertz", [](benchmark::State& bench) {
    BM_DemPacking(bench, DemIntegrator::verlet, 0.0, -1, false, true);
  })
      ->ArgsProduct({{10000, 60000}, {1, 2}, {-1}})
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
  return true;
}();
// Where two workers start to pay: the packing unsplit on one worker against
// split on two, from 250 to 8000 particles (DemDesc::split_from's default).
BENCHMARK_CAPTURE(BM_DemPacking, threshold, DemIntegrator::verlet, 0.0)
    ->ArgsProduct({{250, 500, 1000, 2000, 4000, 8000}, {1}, {0}})
    ->ArgsProduct({{250, 500, 1000, 2000, 4000, 8000}, {2}, {1}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
