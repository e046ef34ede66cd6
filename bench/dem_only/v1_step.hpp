// The V1 drop-test step (one sphere on a plane, 1D: m = 1 kg, r = 0.1 m,
// k = 1e4 N/m, zeta = 0.1, g = -9.81 m/s^2, abm4, dt = 1e-4 s), compiled into
// both xfdem_bench (full kernel: DEM, bar, coupling) and xfdem_bench_dem_only
// (a library made from the DEM and core sources only), so that the two
// binaries time the same code and the ratio shows what a DEM-only scene pays
// for the continuum being linked in (nothing, if the phases are skipped).
#pragma once
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>

#include "xfdem/dem.hpp"

namespace xfdem_bench {

inline void BM_DemV1Step(benchmark::State& bench) {
  using namespace xfdem;
  DemDesc<1> desc;
  desc.particles.push_back({.mass = 1.0, .radius = 0.1, .stiffness = 1e4, .position = {0.15}, .velocity = {0.0}});
  desc.planes.push_back({.point = {0.0}, .normal = {1.0}});
  desc.gravity = {-9.81};
  desc.damping_ratio = 0.1;
  desc.integrator = DemIntegrator::abm4;
  desc.dt = 1e-4;
  DemWorld<1> world;
  if (!world.build(desc).ok()) {
    bench.SkipWithError("V1: build failed");
    return;
  }
  // Past the RK4 start steps, still in free fall (impact at about 0.1 s).
  for (int k = 0; k < 100; ++k) world.step();
  const DemState<1> warm = world.state;
  // A batch of 0.5 s: the fall, the impact and the rebound.
  constexpr benchmark::IterationCount kBatch = 5000;
  while (bench.KeepRunningBatch(kBatch)) {
    world.state = warm;  // same-sized vectors: copies in place
    for (benchmark::IterationCount k = 0; k < kBatch; ++k) benchmark::DoNotOptimize(world.step());
  }
  benchmark::DoNotOptimize(world.state.x[0][0]);
}

}  // namespace xfdem_bench
