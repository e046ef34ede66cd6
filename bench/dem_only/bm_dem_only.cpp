// xfdem_bench_dem_only: the V1 step benchmark linked against a library made
// from the DEM and core sources only (no bar, no coupling). Compare its
// BM_DemV1Step with the same benchmark in xfdem_bench (docs/benchmarks.md,
// "Features").
#include <benchmark/benchmark.h>

#include "dem_only/v1_step.hpp"

BENCHMARK(xfdem_bench::BM_DemV1Step);
