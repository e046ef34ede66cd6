// The plate's step and build, uncut and with a tied cut (docs/benchmarks.md,
// "2D plate"): the plate of scenes/plate_tension.json (steel, plane stress, 2 m × 1 m, rollers
// on the left and bottom edges, a step traction on the right edge), Newmark
// (¼, ½), on 10 × 4, 32 × 16 and 100 × 50 cells (94, 1072 and 10150
// unknowns; each has a node at the right edge's middle, which the GetFEM
// script's check reads). tools/bench_getfem.py runs these next to the same plate in GetFEM.
//
//   BM_PlateStep:  plate_step() from a warm state: predictor, K u_pred, one
//                  back-substitution with the factor of M + βΔt²K computed at
//                  build, the Newmark updates and the energy books; energy
//                  check every 16 steps (the default) or off (arg check = 0).
//   BM_PlateSolve: the back-substitution alone: the step's (SparseLdlt::solve,
//                  sparse:1) and a profile factor's of the same matrix
//                  (BandLdlt::solve, sparse:0, what the step used before).
//   BM_PlateStiffnessProduct: the step's other large term, y −= K x, over
//                  K's profile (cells:0, SymmetricBand::subtract_product, what
//                  the step used before) and as the step computes it (cells:1,
//                  plate_subtract_stiffness_product: cell by cell from the
//                  8 × 8 element stiffness, touching only the nonzeros).
//   BM_PlateBuild: build_plate(): mesh, assembly of K and M, factorisation
//                  of M and of M + βΔt²K, the initial acceleration.
//   BM_PlateTiedCutStep: plate_step() as BM_PlateStep on the plate of
//                  scenes/plate_crack.json: the same plate with a tied crack
//                  at x = 1.03 across it (cut by its level set, off the
//                  mesh's lines at every size; Heaviside unknowns on the cut
//                  cells' nodes, penalty k = 1e13 Pa/m normal and tangential).
//
// Counters: dofs; factor_bytes and factor_nonzeros, the bytes and the
// entries below the diagonal of the step's sparse factor
// (SparseLdlt::bytes()); profile_factor_bytes, those of a profile factor of
// the same matrix (its stored entries, 8 bytes each, 1/D and the row offsets).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <vector>

#include "xfdem/plate.hpp"

namespace {

xfdem::PlateDesc plate(int nx, int ny, int energy_interval) {
  xfdem::PlateDesc d;
  d.max[0] = 2.0;
  d.max[1] = 1.0;
  d.cells[0] = nx;
  d.cells[1] = ny;
  d.plane = xfdem::PlateDesc::Plane::stress;
  d.thickness = 0.02;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.dt = 1e-5;
  d.supports.push_back({xfdem::PlateEdge::left, {true, false}, false});
  d.supports.push_back({xfdem::PlateEdge::bottom, {false, true}, false});
  xfdem::PlateLoad load;
  load.edge = xfdem::PlateEdge::right;
  load.value[0] = 1e6;
  d.loads.push_back(load);
  d.energy_check.interval = energy_interval;
  return d;
}

/// The plate with scenes/plate_crack.json's tied crack across it.
xfdem::PlateDesc tied_cut_plate(int nx, int ny, int energy_interval) {
  xfdem::PlateDesc d = plate(nx, ny, energy_interval);
  xfdem::PlateDiscontinuity crack;
  crack.name = "joint";
  crack.kind = xfdem::PlateDiscontinuity::Kind::crack;
  crack.points = {{1.03, -0.1}, {1.03, 1.1}};
  crack.faces = xfdem::PlateDiscontinuity::Faces::tied;
  crack.stiffness[0] = 1e13;
  crack.stiffness[1] = 1e13;
  d.discontinuities.push_back(crack);
  return d;
}

/// Bytes of a profile factor of the model's profile (what the step used
/// before): the stored lower triangle (row i from first_column(i) to i), 1/D
/// and the row offsets.
double profile_factor_bytes(const xfdem::PlateModel& m) {
  const xfdem::xfem::SymmetricBand& p = m.mass;
  double entries = 0.0;
  for (int i = 0; i < p.size(); ++i) entries += static_cast<double>(i - p.first_column(i) + 1);
  return entries * sizeof(double) + p.size() * (sizeof(double) + sizeof(long) + sizeof(int));
}

bool build_or_skip(benchmark::State& bench, const xfdem::PlateDesc& d, xfdem::PlateModel& m, xfdem::PlateState& st,
                   xfdem::PlateWorkspace& ws) {
  if (xfdem::build_plate(d, m, st, ws).ok()) return true;
  bench.SkipWithError("build failed");
  return false;
}

void counters(benchmark::State& bench, const xfdem::PlateModel& m) {
  bench.counters["dofs"] = m.dofs;
  bench.counters["factor_bytes"] = m.effective_factor.bytes();
  bench.counters["factor_nonzeros"] = static_cast<double>(m.effective_factor.nonzeros());
  bench.counters["profile_factor_bytes"] = profile_factor_bytes(m);
}

/// plate_step() from a warm state (100 steps from rest) on the plate `make`
/// builds from the arguments nx, ny and the energy check interval.
void time_step(benchmark::State& bench, xfdem::PlateDesc (*make)(int, int, int)) {
  xfdem::PlateModel m;
  xfdem::PlateState st;
  xfdem::PlateWorkspace ws;
  if (!build_or_skip(bench, make(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)),
                                 static_cast<int>(bench.range(2))),
                     m, st, ws))
    return;
  for (int i = 0; i < 100; ++i) xfdem::plate_step(m, st, ws);
  for (auto _ : bench) benchmark::DoNotOptimize(xfdem::plate_step(m, st, ws));
  counters(bench, m);
  bench.SetItemsProcessed(bench.iterations());
}

// Args: nx, ny, energy check interval (0: off, 16: the default).
void BM_PlateStep(benchmark::State& bench) { time_step(bench, plate); }

// Args: nx, ny, energy check interval (0: off, 16: the default).
void BM_PlateTiedCutStep(benchmark::State& bench) { time_step(bench, tied_cut_plate); }

// Args: nx, ny, sparse (1: the step's SparseLdlt, 0: a BandLdlt of the
// same matrix over its profile, what the step used before).
void BM_PlateSolve(benchmark::State& bench) {
  xfdem::PlateModel m;
  xfdem::PlateState st;
  xfdem::PlateWorkspace ws;
  if (!build_or_skip(bench, plate(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)), 16), m, st, ws))
    return;
  for (int i = 0; i < 100; ++i) xfdem::plate_step(m, st, ws);
  const bool sparse = bench.range(2) != 0;
  xfdem::xfem::BandLdlt band;
  if (!sparse) {
    // M + βΔt²K over the profile (the plate has no dashpots).
    xfdem::xfem::SymmetricBand eff = m.mass;
    const double fac0 = m.scheme.fac0();
    for (int i = 0; i < m.dofs; ++i)
      for (int j = m.mass.first_column(i); j <= i; ++j) eff.add(i, j, fac0 * m.stiffness.get(i, j));
    if (!band.factor(eff)) {
      bench.SkipWithError("profile factor failed");
      return;
    }
  }
  std::vector<double> x = st.a, work(st.a.size(), 0.0);
  for (auto _ : bench) {
    // The same right-hand side every time (the copy is a small share of a solve).
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = st.a[k];
    if (sparse)
      m.effective_factor.solve(x.data(), work.data());
    else
      band.solve(x.data());
    benchmark::DoNotOptimize(x.data());
  }
  counters(bench, m);
}

// Args: nx, ny, cells (0: over the profile, 1: cell by cell).
void BM_PlateStiffnessProduct(benchmark::State& bench) {
  xfdem::PlateModel m;
  xfdem::PlateState st;
  xfdem::PlateWorkspace ws;
  if (!build_or_skip(bench, plate(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)), 16), m, st, ws))
    return;
  for (int i = 0; i < 100; ++i) xfdem::plate_step(m, st, ws);
  const bool cells = bench.range(2) != 0;
  std::vector<double> y(st.u.size(), 0.0), check(st.u.size(), 0.0);
  // Both give the same product (to round-off of the sums' order).
  m.stiffness.subtract_product(st.u.data(), y.data());
  xfdem::plate_subtract_stiffness_product(m, st.u.data(), check.data());
  double scale = 0.0, diff = 0.0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    scale = std::max(scale, std::fabs(y[k]));
    diff = std::max(diff, std::fabs(y[k] - check[k]));
  }
  if (!(diff <= 1e-12 * scale)) {
    bench.SkipWithError("the two products differ");
    return;
  }
  for (auto _ : bench) {
    if (cells)
      xfdem::plate_subtract_stiffness_product(m, st.u.data(), y.data());
    else
      m.stiffness.subtract_product(st.u.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  counters(bench, m);
}

// Args: nx, ny.
void BM_PlateBuild(benchmark::State& bench) {
  const xfdem::PlateDesc d = plate(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)), 16);
  xfdem::PlateModel m;
  xfdem::PlateState st;
  xfdem::PlateWorkspace ws;
  for (auto _ : bench) benchmark::DoNotOptimize(xfdem::build_plate(d, m, st, ws));
  counters(bench, m);
}

/// The three sizes, each with every value of a third argument (none: two arguments).
void sizes(benchmark::internal::Benchmark* b, std::initializer_list<int> third) {
  const int cells[3][2] = {{10, 4}, {32, 16}, {100, 50}};
  for (const auto& c : cells) {
    if (third.size() == 0) b->Args({c[0], c[1]});
    for (int v : third) b->Args({c[0], c[1], v});
  }
}

}  // namespace

BENCHMARK(BM_PlateStep)->ArgNames({"nx", "ny", "check"})->Apply([](auto* b) { sizes(b, {16, 0}); });
BENCHMARK(BM_PlateTiedCutStep)->ArgNames({"nx", "ny", "check"})->Apply([](auto* b) { sizes(b, {16, 0}); });
BENCHMARK(BM_PlateSolve)->ArgNames({"nx", "ny", "sparse"})->Apply([](auto* b) { sizes(b, {1, 0}); });
BENCHMARK(BM_PlateStiffnessProduct)->ArgNames({"nx", "ny", "cells"})->Apply([](auto* b) { sizes(b, {0, 1}); });
BENCHMARK(BM_PlateBuild)->ArgNames({"nx", "ny"})->Unit(benchmark::kMicrosecond)->Apply([](auto* b) { sizes(b, {}); });
