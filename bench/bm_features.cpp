// What a scene does not need costs nothing: paired benchmarks of a feature on
// and off, timed in the same process, batch by batch in alternating order, so
// that the ratio is measured under the same machine load.
//
// Every BM_Skip_* benchmark runs variant A (the feature skipped) and variant B
// (the feature present) on the same scene; each iteration times one batch of
// A and one of B (order alternating), every batch starting from its warm
// snapshot. Counters:
//   A_ns, B_ns   mean time of one step of each variant (ns)
//   A_over_B     A_ns / B_ns (below 1: skipping the feature saves time;
//                about 1: the feature costs nothing where it is absent)
// Google Benchmark's own time column is A + B per iteration; read the counters.
//
//   BM_Skip_Dashpot_V1/<integrator>   V1 drop, zeta = 0 vs 0.1
//   BM_Skip_Dashpot_Cloud/N           3D packing-like cloud, zeta = 0 vs 0.1
//   BM_Skip_Gravity_V1                V1 with g = 0 vs g = -9.81 (same start, moving)
//   BM_Skip_Gravity_Cloud/N           cloud with g = 0 vs g = -9.81
//   BM_Skip_Enrichment/elements       uncut X-FEM bar vs plain FEM bar (no interface);
//                                     a third counter C_ns is the cut X-FEM bar (tied)
//   BM_Skip_CouplingPasses            Case II (X-FEM) in free flight: one coupled step
//                                     vs its parts (a bar step and n particle substeps)
//
// BM_DemV1Step (bench/dem_only/v1_step.hpp) is also built into
// xfdem_bench_dem_only, linked against the DEM sources only.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "dem_only/v1_step.hpp"
#include "support/coupled_scenes.hpp"
#include "xfem/reference.hpp"
#include "xfdem/bar.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/platform/clock.hpp"

BENCHMARK(xfdem_bench::BM_DemV1Step);

namespace {

using namespace xfdem;

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "bm_features: %s\n", what);
    std::abort();
  }
}

/// One timed variant: restore() (untimed) then steps() run `batch` steps.
struct Variant {
  std::function<void()> restore;
  std::function<void()> step;
  std::int64_t batch = 1;
};

/// Seconds of one batch of `v` (restore excluded), per step, in ns.
double time_batch(const Variant& v) {
  v.restore();
  const std::int64_t t0 = platform::monotonic_ns();
  for (std::int64_t k = 0; k < v.batch; ++k) v.step();
  return static_cast<double>(platform::monotonic_ns() - t0) / static_cast<double>(v.batch);
}

/// Alternates batches of the variants every iteration; reports mean ns per step
/// of each (A_ns, B_ns, C_ns) and A_over_B.
void paired(benchmark::State& bench, const std::vector<Variant>& variants) {
  static const char* const kNames[] = {"A_ns", "B_ns", "C_ns"};
  std::array<double, 3> sum{};
  std::int64_t rounds = 0;
  for (auto _ : bench) {
    // A B C, then C B A: a drift in machine speed within a round cancels.
    const bool forward = rounds % 2 == 0;
    for (std::size_t i = 0; i < variants.size(); ++i) {
      const std::size_t k = forward ? i : variants.size() - 1 - i;
      sum[k] += time_batch(variants[k]);
    }
    ++rounds;
  }
  for (std::size_t k = 0; k < variants.size(); ++k) bench.counters[kNames[k]] = sum[k] / static_cast<double>(rounds);
  bench.counters["A_over_B"] = sum[0] / sum[1];
}

// ---- DEM ---------------------------------------------------------------------

template <int D>
struct DemRun {
  DemWorld<D> world;
  DemState<D> warm;

  DemRun(const DemDesc<D>& desc, int warm_steps) {
    require(world.build(desc).ok(), "dem: build failed");
    for (int k = 0; k < warm_steps; ++k)
      require(!has(world.step(), kStepNotTaken | StepStatus::non_finite), "dem: warm-up step");
    warm = world.state;
  }
  Variant variant(std::int64_t batch) {
    return {[this] { world.state = warm; }, [this] { benchmark::DoNotOptimize(world.step()); }, batch};
  }
};

DemDesc<1> v1(double zeta, double gravity, double v0, DemIntegrator integrator) {
  DemDesc<1> desc;
  desc.particles.push_back({.mass = 1.0, .radius = 0.1, .stiffness = 1e4, .position = {0.15}, .velocity = {v0}});
  desc.planes.push_back({.point = {0.0}, .normal = {1.0}});
  desc.gravity = {gravity};
  desc.damping_ratio = zeta;
  desc.integrator = integrator;
  desc.dt = 1e-4;
  return desc;
}

void BM_Skip_Dashpot_V1(benchmark::State& bench, DemIntegrator integrator) {
  DemRun<1> off(v1(0.0, -9.81, 0.0, integrator), 100), on(v1(0.1, -9.81, 0.0, integrator), 100);
  require(!off.world.model.features.damped && on.world.model.features.damped, "V1: damped feature");
  paired(bench, {off.variant(5000), on.variant(5000)});
}
BENCHMARK_CAPTURE(BM_Skip_Dashpot_V1, abm4, DemIntegrator::abm4);
BENCHMARK_CAPTURE(BM_Skip_Dashpot_V1, verlet, DemIntegrator::verlet);

void BM_Skip_Gravity_V1(benchmark::State& bench) {
  // Both start 5 cm above contact moving down at 1 m/s, so both hit the plane
  // within the batch; without gravity the sphere leaves at its rebound speed.
  DemRun<1> off(v1(0.1, 0.0, -1.0, DemIntegrator::abm4), 10), on(v1(0.1, -9.81, -1.0, DemIntegrator::abm4), 10);
  require(!off.world.model.features.gravity && on.world.model.features.gravity, "V1: gravity feature");
  paired(bench, {off.variant(2000), on.variant(2000)});
}
BENCHMARK(BM_Skip_Gravity_V1);

/// A packing-like 3D cloud: N spheres (r = 1 mm, 2500 kg/m^3, k = 2000 N/m) on
/// a cubic lattice whose spacing (1.99 r) makes every neighbour pair overlap by
/// 0.5 % of r, with a small deterministic jitter, in a box of six planes that
/// touch the outer layer. About six contacts per interior particle, like a
/// dense packing; verlet at 0.2 of the single-contact stable step.
DemDesc<3> cloud(std::int32_t n, double zeta, double gravity) {
  constexpr double r = 1e-3, density = 2500.0, stiffness = 2000.0;
  const double mass = 4.0 / 3.0 * 3.14159265358979323846 * r * r * r * density;
  const auto side = static_cast<std::int32_t>(std::lround(std::cbrt(static_cast<double>(n))));
  require(side * side * side == n, "cloud: N must be a cube");
  const double spacing = 1.99 * r;
  const double box = (side - 1) * spacing + 2 * r * 0.995;
  DemDesc<3> desc;
  std::uint64_t seed = 0x5eedull;
  auto jitter = [&] {  // splitmix64 -> [-1, 1)
    std::uint64_t z = (seed += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return 2.0 * static_cast<double>(z >> 11) * 0x1.0p-53 - 1.0;
  };
  for (std::int32_t iz = 0; iz < side; ++iz)
    for (std::int32_t iy = 0; iy < side; ++iy)
      for (std::int32_t ix = 0; ix < side; ++ix) {
        std::array<double, 3> p{r * 0.995 + ix * spacing, r * 0.995 + iy * spacing, r * 0.995 + iz * spacing};
        for (double& c : p) c += 0.002 * r * jitter();
        desc.particles.push_back({.mass = mass, .radius = r, .stiffness = stiffness, .position = p, .velocity = {}});
      }
  desc.planes = {{.point = {0, 0, 0}, .normal = {1, 0, 0}},   {.point = {box, 0, 0}, .normal = {-1, 0, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 1, 0}},   {.point = {0, box, 0}, .normal = {0, -1, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 0, 1}},   {.point = {0, 0, box}, .normal = {0, 0, -1}}};
  desc.gravity = {0, 0, gravity};
  desc.damping_ratio = zeta;
  desc.integrator = DemIntegrator::verlet;
  // One dt for every variant: 0.2 of the smaller stable step (the damped one).
  desc.dt = 1.0;
  desc.reject_unstable_dt = false;
  DemDesc<3> probe = desc;
  probe.damping_ratio = 0.1;
  DemWorld<3> w;
  require(w.build(probe).ok(), "cloud: build failed");
  desc.dt = 0.2 * w.model.stable_dt;
  probe.damping_ratio = 0.0;
  require(w.build(probe).ok(), "cloud: build failed");
  desc.dt = std::min(desc.dt, 0.2 * w.model.stable_dt);
  desc.reject_unstable_dt = true;
  return desc;
}

std::int64_t cloud_batch(std::int32_t n) { return std::max<std::int64_t>(10, 1'000'000 / n); }

void BM_Skip_Dashpot_Cloud(benchmark::State& bench) {
  const auto n = static_cast<std::int32_t>(bench.range(0));
  DemRun<3> off(cloud(n, 0.0, -9.81), 50), on(cloud(n, 0.1, -9.81), 50);
  require(!off.world.model.features.damped && on.world.model.features.damped, "cloud: damped feature");
  paired(bench, {off.variant(cloud_batch(n)), on.variant(cloud_batch(n))});
  bench.counters["pairs_listed_per_particle"] = static_cast<double>(on.world.state.pair_count) / n;
}
BENCHMARK(BM_Skip_Dashpot_Cloud)->Arg(1000)->Arg(8000)->Unit(benchmark::kMillisecond);

void BM_Skip_Gravity_Cloud(benchmark::State& bench) {
  const auto n = static_cast<std::int32_t>(bench.range(0));
  DemRun<3> off(cloud(n, 0.1, 0.0), 50), on(cloud(n, 0.1, -9.81), 50);
  require(!off.world.model.features.gravity && on.world.model.features.gravity, "cloud: gravity feature");
  paired(bench, {off.variant(cloud_batch(n)), on.variant(cloud_batch(n))});
}
BENCHMARK(BM_Skip_Gravity_Cloud)->Arg(1000)->Arg(8000)->Unit(benchmark::kMillisecond);

// ---- bar ---------------------------------------------------------------------

/// The V2 rod (30 m, E = 3e7 Pa, A = 0.4 m^2, 2000 kg/m^3, Newmark 0.4/0.6,
/// dt = 1 ms, half-sine tip load), optionally cut by a tied interface at 14.5 m.
BarDesc rod(int elements, BarDesc::Method method, bool cut) {
  BarDesc d = test::v2_rod(elements);
  d.method = method;
  d.beta = 0.4;
  d.gamma = 0.6;
  if (cut) d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::tied};
  return d;
}

struct BarRun {
  BarModel model;
  BarState state, warm;
  BarWorkspace workspace;
  explicit BarRun(const BarDesc& d) {
    require(build_bar(d, model, state, workspace).ok(), "bar: build failed");
    for (int k = 0; k < 100; ++k) bar_step(model, state, workspace);
    warm = state;
  }
  Variant variant(std::int64_t batch) {
    return {[this] { state = warm; }, [this] { benchmark::DoNotOptimize(bar_step(model, state, workspace)); }, batch};
  }
};

void BM_Skip_Enrichment(benchmark::State& bench) {
  const auto elements = static_cast<int>(bench.range(0));
  BarRun uncut(rod(elements, BarDesc::Method::xfem, false)), fem(rod(elements, BarDesc::Method::fem, false)),
      cut(rod(elements, BarDesc::Method::xfem, true));
  require(uncut.model.dofs == fem.model.dofs && !uncut.model.has_interface, "bar: uncut X-FEM is not the FEM mesh");
  const std::int64_t batch = std::max<std::int64_t>(50, 200'000 / elements);
  paired(bench, {uncut.variant(batch), fem.variant(batch), cut.variant(batch)});
  bench.counters["dofs_uncut"] = uncut.model.dofs;
  bench.counters["dofs_cut"] = cut.model.dofs;
}
BENCHMARK(BM_Skip_Enrichment)->Arg(30)->Arg(300)->Arg(3000)->Unit(benchmark::kMicrosecond);

// ---- coupled -------------------------------------------------------------------

/// Case II (X-FEM) at t = 0.5 s, both particles in free flight: a coupled step
/// takes one pass. A: the coupled step; B: the same work done by hand (one bar
/// step, n particle substeps, the plane driven once) without the coupled
/// stepper's bookkeeping; C: a resting window (t = 8 s, several passes).
void BM_Skip_CouplingPasses(benchmark::State& bench) {
  const CoupledDesc desc = xfdem::testing::coupled_scene("case2_xfem.json");
  CoupledWorld free_flight, parts, resting;
  require(free_flight.build(desc).ok() && parts.build(desc).ok() && resting.build(desc).ok(), "coupled: build");
  while (free_flight.state.time < 0.5) free_flight.step();
  while (resting.state.time < 8.0) resting.step();
  parts.state = free_flight.state;
  const CoupledState warm_free = free_flight.state, warm_rest = resting.state;
  const std::int64_t batch = 200;
  std::int64_t passes_free = 0, passes_rest = 0;
  const Variant a{[&] { free_flight.state = warm_free; },
                  [&] {
                    benchmark::DoNotOptimize(free_flight.step());
                    passes_free += free_flight.state.last_passes;
                  },
                  batch};
  const Variant b{[&] { parts.state = warm_free; },
                  [&] {
                    CoupledModel& m = parts.model;
                    CoupledState& s = parts.state;
                    benchmark::DoNotOptimize(bar_step(m.bar, s.bar, parts.workspace.bar));
                    dem_drive_plane(m.dem, s.dem, m.top_plane, bar_tip_displacement(m.bar, s.bar),
                                    bar_tip_velocity(m.bar, s.bar));
                    for (int k = 0; k < m.substeps; ++k) benchmark::DoNotOptimize(dem_step(m.dem, s.dem, parts.workspace.dem));
                  },
                  batch};
  const Variant c{[&] { resting.state = warm_rest; },
                  [&] {
                    benchmark::DoNotOptimize(resting.step());
                    passes_rest += resting.state.last_passes;
                  },
                  batch};
  paired(bench, {a, b, c});
  const double rounds = static_cast<double>(bench.iterations()) * static_cast<double>(batch);
  bench.counters["passes_free"] = static_cast<double>(passes_free) / rounds;
  bench.counters["passes_resting"] = static_cast<double>(passes_rest) / rounds;
}
BENCHMARK(BM_Skip_CouplingPasses)->Unit(benchmark::kMicrosecond);

}  // namespace
