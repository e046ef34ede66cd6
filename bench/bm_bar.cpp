// Per-step cost of the bar (warm state: 1000 steps taken before timing) and the
// cost of build (assembly + factorisations), for 30, 300, 3000 elements, FEM and
// X-FEM, tied and unilateral interface (V2 rod, interface at 0.4833 L).
#include <benchmark/benchmark.h>

#include "xfdem/bar.hpp"
#include "xfem/reference.hpp"

namespace {

using xfdem::BarDesc;
using xfdem::BarInterfaceDesc;

BarDesc rod(int elements, bool fem, bool unilateral) {
  BarDesc d = xfdem::test::v2_rod(elements);
  d.method = fem ? BarDesc::Method::fem : BarDesc::Method::xfem;
  d.beta = 0.4;
  d.gamma = 0.6;
  // Tension opens a unilateral interface, so both branches of the active set run.
  if (unilateral) d.tip_amplitude = -d.tip_amplitude;
  d.interface = BarInterfaceDesc{14.5, 1.2e9,
                                 unilateral ? BarInterfaceDesc::Behaviour::unilateral : BarInterfaceDesc::Behaviour::tied};
  return d;
}

/// Builds `d` into (m, st, ws); on failure the benchmark is skipped with an error.
bool build_or_skip(benchmark::State& bench, const BarDesc& d, xfdem::BarModel& m, xfdem::BarState& st,
                   xfdem::BarWorkspace& ws) {
  if (xfdem::build_bar(d, m, st, ws).ok()) return true;
  bench.SkipWithError("build failed");
  return false;
}

/// Times bar_step() on `d` from a warm state (1000 steps in).
void time_steps(benchmark::State& bench, const BarDesc& d) {
  xfdem::BarModel m;
  xfdem::BarState st;
  xfdem::BarWorkspace ws;
  if (!build_or_skip(bench, d, m, st, ws)) return;
  for (int i = 0; i < 1000; ++i) xfdem::bar_step(m, st, ws);
  const xfdem::BarState warm = st;
  long steps = 0;
  for (auto _ : bench) {
    benchmark::DoNotOptimize(xfdem::bar_step(m, st, ws));
    // Keep the run inside the loaded and free-vibration phases, not at rest.
    if (++steps % 4000 == 0) {
      bench.PauseTiming();
      st = warm;
      bench.ResumeTiming();
    }
  }
  bench.counters["dofs"] = m.dofs;
  bench.SetItemsProcessed(bench.iterations());
}

// Args: elements, fem (0/1), unilateral (0/1).
void BM_BarStep(benchmark::State& bench) {
  time_steps(bench, rod(static_cast<int>(bench.range(0)), bench.range(1) != 0, bench.range(2) != 0));
}

// The energy balance check's share of a step: X-FEM, tied interface, Args:
// elements, EnergyCheck::interval (0: off; 16: the default; 1: every step).
void BM_BarStepEnergyCheck(benchmark::State& bench) {
  BarDesc d = rod(static_cast<int>(bench.range(0)), false, false);
  d.energy_check.interval = static_cast<int>(bench.range(1));
  time_steps(bench, d);
}

void BM_BarBuild(benchmark::State& bench) {
  const BarDesc d = rod(static_cast<int>(bench.range(0)), bench.range(1) != 0, bench.range(2) != 0);
  xfdem::BarModel m;
  xfdem::BarState st;
  xfdem::BarWorkspace ws;
  for (auto _ : bench) benchmark::DoNotOptimize(xfdem::build_bar(d, m, st, ws));
}

// One step of a unilateral interface under Newmark (¼, ½) that locates an
// interface event (range(1) = 1: the step is split where the gap is zero, each
// substep shorter than Δt refactoring its effective matrix) against a plain step
// of the same rod (range(1) = 0), both from a fixed state restored before each
// step (the restore is outside the timing; the pause costs both the same).
void BM_BarEventStep(benchmark::State& bench) {
  BarDesc d = rod(static_cast<int>(bench.range(0)), false, true);
  d.beta = 0.25;
  d.gamma = 0.5;
  d.tip_amplitude = -1e4;  // a compressive pulse: the interface closes when it arrives
  const bool split = bench.range(1) != 0;
  xfdem::BarModel m;
  xfdem::BarState st;
  xfdem::BarWorkspace ws;
  if (!build_or_skip(bench, d, m, st, ws)) return;
  // The state before the first step of the wanted kind.
  xfdem::BarState start = st;
  bool found = false;
  for (int i = 0; i < 100000 && !found; ++i) {
    start = st;
    xfdem::bar_step(m, st, ws);
    found = split ? ws.last_factorisations > 0 : (i >= 1000 && ws.last_events == 0);
  }
  if (!found) {
    bench.SkipWithError("no step of that kind");
    return;
  }
  for (auto _ : bench) {
    bench.PauseTiming();
    st = start;
    bench.ResumeTiming();
    benchmark::DoNotOptimize(xfdem::bar_step(m, st, ws));
  }
  bench.counters["events"] = ws.last_events;
  bench.counters["factorisations"] = ws.last_factorisations;
  bench.SetItemsProcessed(bench.iterations());
}

void arguments(benchmark::internal::Benchmark* b) {
  b->ArgNames({"elements", "fem", "unilateral"});
  for (int n : {30, 300, 3000})
    for (int fem : {0, 1})
      for (int uni : {0, 1}) b->Args({n, fem, uni});
}

}  // namespace

BENCHMARK(BM_BarStep)->Apply(arguments);
BENCHMARK(BM_BarStepEnergyCheck)->ArgsProduct({{300, 3000}, {0, 16, 1}});
BENCHMARK(BM_BarEventStep)->ArgsProduct({{30, 300, 3000}, {0, 1}});
BENCHMARK(BM_BarBuild)->Apply(arguments);
