// Placeholder removed once the step benchmarks exist.
#include <benchmark/benchmark.h>
#include "xfdem/version.hpp"
static void BM_Version(benchmark::State& s) { for (auto _ : s) benchmark::DoNotOptimize(xfdem::version_string()); }
BENCHMARK(BM_Version);
