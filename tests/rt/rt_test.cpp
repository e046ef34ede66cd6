// The real-time harness (xfdem_rt) end to end: its report has every field, the
// capacities it reports are the state's, the loop allocates nothing, bad flags
// exit 2 with the flag named, a step status exits 3. No timing of this machine
// is asserted: the step times, wake-up lateness and deadline misses are checked
// on runs with a deterministic clock preloaded (tests/rt/fake_clock.cpp), where
// the tests derive their values.
#include <gtest/gtest.h>

#include "support/command.hpp"
#include "xfdem/coupled2d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string out, err;
  std::map<std::string, std::string> fields;  ///< "key: value" lines of stdout
};

/// xfdem_rt is built next to the xfdem command line (tools/).
std::string harness() { return (fs::path(XFDEM_CLI).parent_path() / "xfdem_rt").string(); }

Result run(const std::string& args, const std::string& environment = "") {
  const xfdem::testing::CommandResult c = xfdem::testing::run_command(environment + harness(), args);
  Result r{c.exit_code, c.out, c.err, {}};
  std::istringstream lines(r.out);
  std::string line;
  while (std::getline(lines, line)) {
    const auto colon = line.find(": ");
    if (colon != std::string::npos) r.fields[line.substr(0, colon)] = line.substr(colon + 2);
  }
  return r;
}

std::string scene(const char* name) { return xfdem::testing::scene_file(name); }

/// The fake clock's tick: every read of CLOCK_MONOTONIC advances it by this.
constexpr long long kTick = 1000;

/// The harness with the fake clock preloaded: a read returns the fake time and
/// advances it by kTick ns, nanosleep advances it by the time asked for and
/// returns at once. (Under AddressSanitizer the preloaded library comes before
/// the sanitizer's runtime, so its link-order check is turned off.)
Result run_on_fake_clock(const std::string& args) {
  return run(args, "XFDEM_FAKE_TICK_NS=" + std::to_string(kTick) +
                       " ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0 LD_PRELOAD=" +
                       XFDEM_FAKE_CLOCK + " ");
}

/// Nearest-rank quantile index (0-based) of n sorted samples, as the harness reports.
std::size_t rank_index(long long n, double q) {
  return static_cast<std::size_t>(std::clamp<long long>(static_cast<long long>(std::ceil(q * static_cast<double>(n))), 1, n) - 1);
}

long long integer(const Result& r, const std::string& key) {
  const auto it = r.fields.find(key);
  EXPECT_NE(it, r.fields.end()) << "missing field " << key << "\n" << r.out;
  if (it == r.fields.end()) return -1;
  char* end = nullptr;
  const long long value = std::strtoll(it->second.c_str(), &end, 10);
  EXPECT_EQ(*end, '\0') << key << ": " << it->second;
  return value;
}

/// "P of C" -> {P, C}
std::pair<long long, long long> capacity(const Result& r, const std::string& name) {
  const auto it = r.fields.find("capacity_" + name);
  EXPECT_NE(it, r.fields.end()) << "missing capacity " << name << "\n" << r.out;
  if (it == r.fields.end()) return {-1, -1};
  long long peak = -1, cap = -1;
  EXPECT_EQ(std::sscanf(it->second.c_str(), "%lld of %lld", &peak, &cap), 2) << it->second;
  return {peak, cap};
}

void expect_step_statistics(const Result& r, long long steps) {
  EXPECT_EQ(integer(r, "steps"), steps);
  const long long median = integer(r, "step_median_ns"), p99 = integer(r, "step_p99_ns"),
                  p999 = integer(r, "step_p99.9_ns"), max = integer(r, "step_max_ns");
  EXPECT_LE(median, p99);
  EXPECT_LE(p99, p999);
  EXPECT_LE(p999, max);
  EXPECT_EQ(integer(r, "allocations_in_loop"), 0);
  EXPECT_EQ(r.fields.at("status"), "ok");
}

/// On the fake clock a step is timed by two consecutive reads, one tick apart,
/// and so is the clock-read cost.
void expect_fake_step_times(const Result& r) {
  for (const char* key : {"step_median_ns", "step_p99_ns", "step_p99.9_ns", "step_max_ns", "clock_read_ns"})
    EXPECT_EQ(integer(r, key), kTick) << key;
}

TEST(RealTimeHarness, V1AsFastAsPossibleReportsEveryField) {
  Result r = run_on_fake_clock(scene("v1_k1e4.json") + " --steps 2000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.fields["scene"], "v1_k1e4");
  EXPECT_EQ(r.fields["pacing"], "as-fast-as-possible");
  EXPECT_EQ(integer(r, "period_ns"), 0);
  EXPECT_EQ(r.fields["deadline_misses"], "n/a (no period)");
  EXPECT_EQ(r.fields.count("wakeup_late_max_ns"), 0u);
  EXPECT_EQ(r.fields["sim_time_s"], "0.2");
  expect_step_statistics(r, 2000);
  expect_fake_step_times(r);
  // Back to back: one read at the start, two per step, one at the end.
  EXPECT_EQ(r.fields["wall_time_s"], "0.004001");  // (2·2000 + 1) ticks
  // One particle: no broad phase, no pairs (docs/dem.md).
  EXPECT_NE(r.fields["system"].find("broad phase none"), std::string::npos) << r.fields["system"];
  EXPECT_EQ(capacity(r, "pairs").first, 0);
  EXPECT_EQ(capacity(r, "neighbors").first, 0);
  EXPECT_EQ(capacity(r, "grid_cells").first, 0);
  EXPECT_EQ(capacity(r, "events").first, 0);
  EXPECT_EQ(capacity(r, "events").second, 16);
  EXPECT_EQ(r.fields.count("capacity_coupled_passes"), 0u);
}

// 1 kHz on the fake clock: the harness sleeps to 100 us before each release
// (its spin margin) and spins from there, one tick per read, reaching the
// release exactly; the step starts one tick later (the first one two ticks
// later: it starts at its release, with no wait) and ends a tick after that,
// far inside its 1 ms deadline. So no misses, lateness of one tick (two for the
// first step), and the last step ends 999 periods and three ticks after the
// start.
TEST(RealTimeHarness, Case2AtOneKilohertzReportsLatenessAndCoupledPasses) {
  Result r = run_on_fake_clock(scene("case2_xfem.json") + " --rate 1000 --steps 1000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.fields["scene"], "case2_xfem");
  EXPECT_EQ(r.fields["pacing"], "rate 1000 Hz");
  EXPECT_EQ(integer(r, "period_ns"), 1'000'000);
  expect_step_statistics(r, 1000);
  expect_fake_step_times(r);
  EXPECT_EQ(integer(r, "deadline_misses"), 0);
  EXPECT_EQ(integer(r, "misses_compute_over_period"), 0);
  EXPECT_EQ(integer(r, "misses_late_wakeup"), 0);
  EXPECT_EQ(integer(r, "wakeup_late_median_ns"), kTick);
  EXPECT_EQ(integer(r, "wakeup_late_p99_ns"), kTick);
  EXPECT_EQ(integer(r, "wakeup_late_max_ns"), 2 * kTick);
  EXPECT_EQ(r.fields["wall_time_s"], "0.999003");
  // Two particles: the all_pairs list holds their one pair.
  EXPECT_EQ(capacity(r, "pairs"), std::make_pair(1LL, 1LL));
  const auto passes = capacity(r, "coupled_passes");
  EXPECT_GE(passes.first, 1);
  EXPECT_LE(passes.first, passes.second);
  EXPECT_EQ(passes.second, 100);  // kCoupledMaxPasses
}

// A period P between one and three ticks: step k starts without waiting, at
// (3k + 2) ticks (a read in the wait, two around each step), fits its compute
// time (one tick) in P, but ends at (3k + 3) ticks, after its deadline
// (k + 1)·P: every step is a late-wake-up miss, and the lateness,
// (3k + 2)·tick − k·P, grows step by step. A period below one tick: every step's
// compute time exceeds it.
TEST(RealTimeHarness, DeadlineMissesAreCountedByKind) {
  const long long steps = 400, period = 2500;  // 2.5 ticks
  Result late = run_on_fake_clock(scene("v1_k1e4.json") + " --budget-us 2.5 --steps 400");
  ASSERT_EQ(late.exit_code, 0) << late.err;
  EXPECT_EQ(integer(late, "period_ns"), period);
  expect_step_statistics(late, steps);
  expect_fake_step_times(late);
  EXPECT_EQ(integer(late, "misses_compute_over_period"), 0);
  EXPECT_EQ(integer(late, "misses_late_wakeup"), steps);
  EXPECT_EQ(integer(late, "deadline_misses"), steps);
  auto lateness = [&](std::size_t k) { return (3 * static_cast<long long>(k) + 2) * kTick - static_cast<long long>(k) * period; };
  EXPECT_EQ(integer(late, "wakeup_late_median_ns"), lateness(rank_index(steps, 0.5)));
  EXPECT_EQ(integer(late, "wakeup_late_p99_ns"), lateness(rank_index(steps, 0.99)));
  EXPECT_EQ(integer(late, "wakeup_late_max_ns"), lateness(static_cast<std::size_t>(steps - 1)));

  Result over = run_on_fake_clock(scene("v1_k1e4.json") + " --budget-us 0.5 --steps 400");
  ASSERT_EQ(over.exit_code, 0) << over.err;
  EXPECT_EQ(integer(over, "period_ns"), 500);
  expect_step_statistics(over, steps);
  EXPECT_EQ(integer(over, "misses_compute_over_period"), steps);
  EXPECT_EQ(integer(over, "misses_late_wakeup"), 0);
  EXPECT_EQ(integer(over, "deadline_misses"), steps);
}

// The real clock, paced, on two workers: the report is complete and ordered
// (no value of it is asserted).
TEST(RealTimeHarness, BudgetTwoWorkersAndPinningRun) {
  Result budget = run(scene("case2_xfem.json") + " --budget-us 250 --steps 400 --threads 2");
  ASSERT_EQ(budget.exit_code, 0) << budget.err;
  EXPECT_EQ(integer(budget, "period_ns"), 250'000);
  EXPECT_EQ(integer(budget, "threads"), 2);
  expect_step_statistics(budget, 400);
  EXPECT_EQ(integer(budget, "deadline_misses"),
            integer(budget, "misses_compute_over_period") + integer(budget, "misses_late_wakeup"));
  EXPECT_LE(integer(budget, "wakeup_late_median_ns"), integer(budget, "wakeup_late_p99_ns"));
  EXPECT_LE(integer(budget, "wakeup_late_p99_ns"), integer(budget, "wakeup_late_max_ns"));

  Result pinned = run(scene("v1_k1e4.json") + " --steps 500 --pin");
  ASSERT_EQ(pinned.exit_code, 0) << pinned.err;
  EXPECT_EQ(pinned.fields["pinned"].rfind("loop on cpu ", 0), 0u) << pinned.fields["pinned"];
}

TEST(RealTimeHarness, OverridesApplyAndAStepStatusExitsThree) {
  Result ok = run(scene("v1_k1e4.json") + " --steps 100 --set dem.contact.damping_ratio=0");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  // An overflowing velocity makes the first step non-finite.
  Result bad = run(scene("v1_k1e4.json") + " --steps 100 --set 'dem.particles.0.velocity=[1e308]'");
  EXPECT_EQ(bad.exit_code, 3) << bad.err;
  EXPECT_EQ(bad.fields["status"], "non_finite");
  EXPECT_EQ(integer(bad, "steps"), 1);
  EXPECT_NE(bad.err.find("step 1"), std::string::npos) << bad.err;
}

// energy_growth does not stop the loop: it is reported with the step it was
// first raised at (undamped impacts under symplectic Euler, first order, at a
// quarter of its stable step: docs/stability.md), and is -1 on a scene that
// never raises it.
TEST(RealTimeHarness, EnergyGrowthIsReportedAndTheLoopCarriesOn) {
  Result grown = run(scene("v1_k1e4.json") +
                     " --steps 1200 --set dem.integrator=symplectic_euler --set dem.contact.damping_ratio=0"
                     " --set time.dt=5e-3 --set output.every=0.01");
  ASSERT_EQ(grown.exit_code, 0) << grown.err;
  EXPECT_EQ(integer(grown, "steps"), 1200);
  EXPECT_GT(integer(grown, "energy_growth_from_step"), 0);
  EXPECT_LE(integer(grown, "energy_growth_from_step"), 1200);
  EXPECT_EQ(grown.fields["status"], "ok");
  Result plain = run(scene("case1_xfem.json") + " --steps 3000");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(integer(plain, "energy_growth_from_step"), -1);
}

// A coupled 2D scene (disks against a plate) runs through the world `xfdem run`
// steps (scene/coupled2d_run.hpp). Case II as a one-cell column at 1 kHz on
// the fake clock: the same schedule as the 1D Case II above (no misses, one
// tick late, the last step ending 999 periods and three ticks after the
// start), no allocation, the disks' capacities and the window's passes
// against their bound, and the energy check (on by default) silent.
TEST(RealTimeHarness, Coupled2dCaseIIAtOneKilohertzReportsItsDeadlineStatistics) {
  Result r = run_on_fake_clock(scene("coupled2d_case2_xfem.json") + " --rate 1000 --steps 1000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.fields["scene"], "coupled2d_case2_xfem");
  EXPECT_EQ(r.fields["system"].rfind("coupled 2D, 2 disks x 10 substeps", 0), 0u) << r.fields["system"];
  expect_step_statistics(r, 1000);
  expect_fake_step_times(r);
  EXPECT_EQ(integer(r, "deadline_misses"), 0);
  EXPECT_EQ(integer(r, "misses_compute_over_period"), 0);
  EXPECT_EQ(integer(r, "misses_late_wakeup"), 0);
  EXPECT_EQ(integer(r, "wakeup_late_median_ns"), kTick);
  EXPECT_EQ(integer(r, "wakeup_late_max_ns"), 2 * kTick);
  EXPECT_EQ(r.fields["wall_time_s"], "0.999003");
  EXPECT_EQ(capacity(r, "pairs"), std::make_pair(1LL, 1LL));
  const auto passes = capacity(r, "coupled_passes");
  EXPECT_GE(passes.first, 1);
  EXPECT_LE(passes.first, passes.second);
  EXPECT_EQ(passes.second, xfdem::kCoupled2dMaxPasses + 1);  // and the re-run of the smallest residual's pass
  EXPECT_EQ(integer(r, "windows_at_a_jump"), 0);
  EXPECT_EQ(integer(r, "energy_growth_from_step"), -1);
}

/// A bed of 300 disks falling onto a supported plate with a void
/// (tests/rt/coupled2d_bed.json, the bed of docs/realtime.md's table).
std::string bed() { return std::string(XFDEM_SOURCE_DIR) + "/tests/rt/coupled2d_bed.json"; }

// The bed on the real clock, on two workers and paced: the report is complete
// and ordered, nothing is allocated in the loop, the grid's capacities are
// reported against the model's (no timing is asserted).
TEST(RealTimeHarness, Coupled2dBedRunsPacedWithoutAllocating) {
  Result r = run(bed() + " --steps 100 --budget-us 10000 --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.fields["system"].rfind("coupled 2D, 300 disks x 10 substeps, broad phase grid", 0), 0u)
      << r.fields["system"];
  expect_step_statistics(r, 100);
  EXPECT_EQ(integer(r, "deadline_misses"),
            integer(r, "misses_compute_over_period") + integer(r, "misses_late_wakeup"));
  for (const char* name : {"pairs", "neighbors", "grid_cells"}) {
    const auto [peak, cap] = capacity(r, name);
    EXPECT_GT(peak, 0) << name;
    EXPECT_LE(peak, cap) << name;
  }
  EXPECT_GT(integer(r, "list_builds"), 0);
  EXPECT_EQ(integer(r, "energy_growth_from_step"), -1);
}

// The energy check of a coupled 2D scene inside the loop: the free plate's
// disks made 400 times stiffer with one substep (ω h past symplectic Euler's
// stable step, allowed by dem.allow_unstable_dt) gain energy; the loop says so
// from the same step as `xfdem run` of the same scene (the same books), carries
// on to the end, and allocates nothing.
TEST(RealTimeHarness, Coupled2dEnergyGrowthIsTheCommandLinesAndTheLoopCarriesOn) {
  std::string stiff = " --set time.dem_substeps=1 --set dem.allow_unstable_dt=true --set dem.contact.damping_ratio=0";
  for (int i = 0; i < 4; ++i) stiff += " --set dem.particles." + std::to_string(i) + ".stiffness=4e8";
  Result r = run(scene("coupled2d_free_plate.json") + stiff);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(integer(r, "steps"), 600);
  EXPECT_EQ(integer(r, "allocations_in_loop"), 0);
  EXPECT_EQ(r.fields["status"], "ok");
  const long long from = integer(r, "energy_growth_from_step");
  EXPECT_GT(from, 0);
  const xfdem::testing::CommandResult cli = xfdem::testing::run_command(
      XFDEM_CLI, "run " + scene("coupled2d_free_plate.json") + stiff + " --csv " +
                     (xfdem::testing::scratch("rt_test") / "stiff.csv").string());
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_NE(cli.err.find("warning: from step " + std::to_string(from) + " on"), std::string::npos) << cli.err;
}

struct BadFlags {
  const char* args;
  const char* named;  ///< text the error must contain
};

class RealTimeHarnessRejects : public ::testing::TestWithParam<BadFlags> {};

TEST_P(RealTimeHarnessRejects, WithExitTwoAndTheFlagNamed) {
  std::string args = GetParam().args;
  const std::string with_scene = args.find("SCENE") == std::string::npos
                                     ? args
                                     : args.replace(args.find("SCENE"), 5, scene("v1_k1e4.json"));
  Result r = run(with_scene);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(GetParam().named), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

INSTANTIATE_TEST_SUITE_P(
    Flags, RealTimeHarnessRejects,
    ::testing::Values(BadFlags{"", "no scene file given"}, BadFlags{"SCENE --rate 0", "--rate"},
                      BadFlags{"SCENE --rate -5", "--rate"}, BadFlags{"SCENE --rate fast", "--rate"},
                      BadFlags{"SCENE --rate", "--rate: missing value"},
                      BadFlags{"SCENE --budget-us 0", "--budget-us"},
                      BadFlags{"SCENE --rate 1000 --budget-us 500", "not both"},
                      BadFlags{"SCENE --steps 0", "--steps"}, BadFlags{"SCENE --steps 12x", "--steps"},
                      BadFlags{"SCENE --threads 3", "--threads"}, BadFlags{"SCENE --bogus", "unknown option '--bogus'"},
                      BadFlags{"SCENE SCENE", "more than one scene file"},
                      BadFlags{"/nonexistent/scene.json", "scene.json"},
                      BadFlags{"SCENE --set dem.particles.0.mass=-1", "mass"}));

}  // namespace
