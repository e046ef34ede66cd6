// Per-step cost of the DEM kernel.
//
// BM_DemDrop:    the V1 drop test (one sphere on a plane, 1D), per step.
// BM_DemPacking: a dense 3D packing of N equal spheres settled under gravity in
//                a box of six planes; counters report ns per particle-step,
//                mean contacts per particle and pair-list rebuilds per step.
//
// Every benchmark starts each batch of steps from the same warm snapshot (a
// copy of DemState), as MuJoCo's step benchmark does, so that the work timed
// does not drift with the number of iterations Google Benchmark picks.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <vector>

#include "xfdem/dem.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace {

using namespace xfdem;

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "bm_dem: %s\n", what);
    std::abort();
  }
}

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

// ---- dense 3D packing --------------------------------------------------------

// Glass-bead-like spheres: r = 1 mm, 2500 kg/m³, k = 2000 N/m (a pair spring of
// 1000 N/m: the weight of a 9 cm column compresses a contact by ~0.5 % of r).
constexpr double kRadius = 1e-3;
constexpr double kDensity = 2500.0;
constexpr double kStiffness = 2000.0;
constexpr double kGravity = -9.81;
const double kMass = 4.0 / 3.0 * 3.14159265358979323846 * kRadius * kRadius * kRadius * kDensity;

/// Deterministic uniform [0, 1) (splitmix64): the packing is the same on every machine.
struct Random {
  std::uint64_t s;
  double uniform() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

struct Packing {
  std::vector<std::array<double, 3>> position;  ///< in grid-cell order (see below)
  double side = 0;                              ///< box side in x and y (m)
  double top = 0;                               ///< height of the lid (m)
};

DemDesc<3> packing_desc(const std::vector<std::array<double, 3>>& position, double side, double top) {
  DemDesc<3> desc;
  desc.particles.reserve(position.size());
  for (const auto& p : position)
    desc.particles.push_back({.mass = kMass, .radius = kRadius, .stiffness = kStiffness, .position = p, .velocity = {}});
  desc.planes = {{.point = {0, 0, 0}, .normal = {1, 0, 0}},    {.point = {side, 0, 0}, .normal = {-1, 0, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 1, 0}},    {.point = {0, side, 0}, .normal = {0, -1, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 0, 1}},    {.point = {0, 0, top}, .normal = {0, 0, -1}}};
  desc.gravity = {0, 0, kGravity};
  return desc;
}

/// Settles N spheres from a loose jittered lattice under gravity with the
/// kernel itself (Verlet, heavy contact damping, kinetic energy bled off every
/// few steps), then sorts them in grid-cell order so that neighbours in space
/// are neighbours in memory (the kernel keeps the caller's particle order).
/// Built once per N and process.
const Packing& packing(std::int32_t n) {
  static std::map<std::int32_t, Packing> cache;
  if (auto it = cache.find(n); it != cache.end()) return it->second;

  const double spacing = 2.2 * kRadius;
  const auto per_side = static_cast<std::int32_t>(std::ceil(std::cbrt(static_cast<double>(n)) * 0.9));
  const std::int32_t layers = (n + per_side * per_side - 1) / (per_side * per_side);
  Packing pk;
  pk.side = per_side * spacing;
  pk.top = (layers + 1) * spacing;
  std::vector<std::array<double, 3>> start;
  Random random{0x5eedull + static_cast<std::uint64_t>(n)};
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t ix = k % per_side, iy = (k / per_side) % per_side, iz = k / (per_side * per_side);
    std::array<double, 3> p{(ix + 0.5) * spacing, (iy + 0.5) * spacing, (iz + 0.5) * spacing};
    for (auto& c : p) c += 0.08 * kRadius * (2.0 * random.uniform() - 1.0);
    start.push_back(p);
  }
  DemDesc<3> desc = packing_desc(start, pk.side, pk.top);
  desc.damping_ratio = 0.5;
  desc.integrator = DemIntegrator::verlet;
  DemModel<3> model;
  DemState<3> state;
  DemWorkspace<3> work;
  desc.dt = 1.0;
  desc.reject_unstable_dt = false;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");
  desc.dt = 0.5 * model.stable_dt;
  desc.reject_unstable_dt = true;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");

  // Fall under gravity with contact damping only, then bleed off what is left
  // of the kinetic energy (velocities halved every 25 steps).
  const double fall = std::sqrt(2.0 * 0.5 * pk.top / -kGravity);  // generous: half the height
  const auto fall_steps = static_cast<std::int64_t>(1.5 * fall / desc.dt);
  const auto quench_steps = static_cast<std::int64_t>(0.1 / desc.dt);
  for (std::int64_t k = 0; k < fall_steps + quench_steps; ++k) {
    require(!has(dem_step(model, state, work), kStepNotTaken | StepStatus::non_finite), "packing: settle step");
    if (k >= fall_steps && k % 25 == 24)
      for (auto& column : state.v)
        for (double& v : column) v *= 0.5;
  }
  // Cell order: z layers of one diameter, then y rows, then x.
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const double cell = 2.0 * kRadius;
  auto key = [&](std::int32_t i) {
    const auto cx = static_cast<std::int64_t>(state.x[0][i] / cell);
    const auto cy = static_cast<std::int64_t>(state.x[1][i] / cell);
    const auto cz = static_cast<std::int64_t>(state.x[2][i] / cell);
    return (cz * 4096 + cy) * 4096 + cx;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) { return key(a) < key(b); });
  for (std::int32_t i : order) pk.position.push_back({state.x[0][i], state.x[1][i], state.x[2][i]});
  return cache.emplace(n, std::move(pk)).first->second;
}

/// Overlapping particle pairs ×2 plus wall contacts, per particle.
double contacts_per_particle(const DemModel<3>& model, const DemState<3>& state) {
  std::int64_t ends = 0;
  for (std::int32_t c = 0; c < state.pair_count; ++c) {
    const std::int32_t i = state.pair_i[c], j = state.pair_j[c];
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += (state.x[d][j] - state.x[d][i]) * (state.x[d][j] - state.x[d][i]);
    const double reach = model.radius[i] + model.radius[j];
    if (d2 < reach * reach) ends += 2;
  }
  for (std::size_t p = 0; p < model.plane_point.size(); ++p)
    for (std::int32_t i = 0; i < model.n; ++i) {
      double gap = 0;
      for (int d = 0; d < 3; ++d) gap += (state.x[d][i] - model.plane_point[p][d]) * model.plane_normal[p][d];
      if (gap < model.radius[i]) ++ends;
    }
  return static_cast<double>(ends) / model.n;
}

/// The second argument, when given, is the number of workers (1 or 2); a third,
/// when given, overrides DemDesc::split_from (0: never split, 1: always).
/// `energy_interval` ≥ 0 overrides EnergyCheck::interval.
void BM_DemPacking(benchmark::State& bench, DemIntegrator integrator, double skin_radii, int energy_interval = -1) {
  const auto n = static_cast<std::int32_t>(bench.range(0));
  const Packing& pk = packing(n);
  DemDesc<3> desc = packing_desc(pk.position, pk.side, pk.top);
  const bool two_workers = bench.range(1) == 2;
  if (bench.range(2) >= 0) desc.split_from = static_cast<std::int32_t>(bench.range(2));
  desc.damping_ratio = 0.1;
  desc.integrator = integrator;
  desc.skin = skin_radii * kRadius;  // 0: the kernel's default, half a radius
  if (energy_interval >= 0) desc.energy_check.interval = energy_interval;
  DemModel<3> model;
  DemState<3> state;
  DemWorkspace<3> work;
  desc.dt = 1.0;
  desc.reject_unstable_dt = false;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");
  // A packed sphere has several contacts and higher frequencies than one
  // contact: a fifth of the single-contact stable step.
  desc.dt = 0.2 * model.stable_dt;
  desc.reject_unstable_dt = true;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");
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
// Where two workers start to pay: the packing unsplit on one worker against
// split on two, from 250 to 8000 particles (DemDesc::split_from's default).
BENCHMARK_CAPTURE(BM_DemPacking, threshold, DemIntegrator::verlet, 0.0)
    ->ArgsProduct({{250, 500, 1000, 2000, 4000, 8000}, {1}, {0}})
    ->ArgsProduct({{250, 500, 1000, 2000, 4000, 8000}, {2}, {1}})
    ->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
