// xfdem_rt: the kernel in a fixed-rate loop, as a real-time host would run it.
//
//   xfdem_rt SCENE.json [--set KEY=VALUE ...] [--rate HZ | --budget-us US]
//            [--steps N] [--threads 1|2] [--pin]
//
// The host (this program) owns the clock: platform::monotonic_ns() releases
// step k at t0 + k·period, the step itself reads no clock. Without --rate or
// --budget-us the steps run back to back (as fast as possible) and no deadline
// applies. Every sample buffer is sized before the loop; the loop itself
// allocates nothing (the report counts global operator new calls inside it).
//
// Report (stdout, one "key: value" per line): step compute time (median, p99,
// p99.9, max), wake-up lateness, deadline misses (steps whose compute time
// exceeded the period, and steps that finished late because they started late),
// and the peak use of every capacity the state records against the capacity.
// A compute-time sample is the time between two clock reads around the step;
// `clock_read_ns` (the median cost of one such pair) says how much of it is
// the clock.
//
// Exit codes: 0 the run completed with every step ok; 2 bad input (usage,
// flags, scene); 3 a step returned a status other than ok (the report covers
// the steps up to and including it).
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "scene/coupled2d_run.hpp"
#include "scene/scene.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/clock.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace {

using xfdem::StepStatus;
using xfdem::scene::SceneError;

/// A bad command line (as opposed to a bad scene): reported with the usage.
struct UsageError : SceneError {
  using SceneError::SceneError;
};

constexpr const char* kUsage =
    "usage: xfdem_rt SCENE.json [--set KEY=VALUE ...] [--rate HZ | --budget-us US]\n"
    "                [--steps N] [--threads 1|2] [--pin]\n"
    "  --rate HZ       release one step every 1/HZ s (deadline = period)\n"
    "  --budget-us US  release one step every US microseconds\n"
    "                  (neither: back to back, as fast as possible, no deadline)\n"
    "  --steps N       steps to run (default: the scene's time.end / time.dt)\n"
    "  --threads 1|2   workers for models split into two parts (default 1)\n"
    "  --pin           pin the loop to the first allowed CPU (and the second\n"
    "                  worker to the next one, spinning while it waits)\n";

struct Options {
  std::string scene_path;
  std::vector<std::string> overrides;
  std::int64_t period_ns = 0;  ///< 0: as fast as possible
  std::string pacing = "as-fast-as-possible";
  std::int64_t steps = -1;  ///< -1: the scene's
  int threads = 1;
  bool pin = false;
};

double parse_number(const std::string& flag, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || !std::isfinite(value))
    throw UsageError(flag + ": expected a number, got '" + text + "'");
  return value;
}

std::int64_t parse_count(const std::string& flag, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0)
    throw UsageError(flag + ": expected a whole number, got '" + text + "'");
  return value;
}

Options parse_options(int argc, char** argv) {
  Options o;
  bool have_rate = false, have_budget = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* flag) -> std::string {
      if (i + 1 >= argc) throw UsageError(std::string(flag) + ": missing value");
      return argv[++i];
    };
    if (arg == "--set") {
      o.overrides.push_back(value("--set"));
    } else if (arg == "--rate") {
      const double hz = parse_number("--rate", value("--rate"));
      if (!(hz > 0.0) || hz > 1e9) throw UsageError("--rate: must be in (0, 1e9] Hz");
      o.period_ns = std::llround(1e9 / hz);
      have_rate = true;
      char text[64];
      std::snprintf(text, sizeof(text), "rate %g Hz", hz);
      o.pacing = text;
    } else if (arg == "--budget-us") {
      const double us = parse_number("--budget-us", value("--budget-us"));
      if (!(us >= 0.001) || us > 1e9) throw UsageError("--budget-us: must be in [0.001, 1e9] microseconds");
      o.period_ns = std::llround(us * 1e3);
      have_budget = true;
      char text[64];
      std::snprintf(text, sizeof(text), "budget %g us", us);
      o.pacing = text;
    } else if (arg == "--steps") {
      o.steps = parse_count("--steps", value("--steps"));
      if (o.steps < 1 || o.steps > 100'000'000) throw UsageError("--steps: must be in [1, 1e8]");
    } else if (arg == "--threads") {
      const std::string t = value("--threads");
      if (t != "1" && t != "2") throw UsageError("--threads: must be 1 or 2 (got '" + t + "')");
      o.threads = t == "2" ? 2 : 1;
    } else if (arg == "--pin") {
      o.pin = true;
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError("unknown option '" + arg + "'");
    } else if (o.scene_path.empty()) {
      o.scene_path = arg;
    } else {
      throw UsageError("more than one scene file given ('" + o.scene_path + "', '" + arg + "')");
    }
  }
  if (have_rate && have_budget) throw UsageError("--rate and --budget-us: give one of them, not both");
  if (o.scene_path.empty()) throw UsageError("no scene file given");
  return o;
}

// ---- the systems a scene can hold --------------------------------------------

struct Capacity {
  const char* name;
  std::int64_t peak;
  std::int64_t capacity;
};

template <int D>
void dem_capacities(const xfdem::DemModel<D>& m, const xfdem::DemState<D>& s, std::vector<Capacity>& out) {
  out.push_back({"pairs", s.peak_pairs, m.capacities.max_pairs});
  out.push_back({"neighbors", s.peak_neighbors, m.capacities.max_neighbors_per_particle});
  out.push_back({"grid_cells", s.peak_grid_cells, m.capacities.max_grid_cells});
  out.push_back({"events", s.peak_events, m.capacities.max_events_per_step});
}

const char* broad_phase_name(xfdem::BroadPhase b) {
  switch (b) {
    case xfdem::BroadPhase::none: return "none";
    case xfdem::BroadPhase::all_pairs: return "all_pairs";
    case xfdem::BroadPhase::grid: return "grid";
  }
  return "?";
}

template <int D>
class DemSystem {
 public:
  DemSystem(const xfdem::scene::Scene& scene, const xfdem::DemDesc<D>& desc, xfdem::ParallelFor parallel) {
    const xfdem::BuildResult built = world_.build(desc);
    if (!built.ok()) throw xfdem::scene::build_refusal(scene, xfdem::scene::Built::dem, built);
    world_.workspace.parallel = parallel;
  }
  StepStatus step() { return world_.step(); }
  std::string describe() const {
    const auto& m = world_.model;
    char text[200];
    std::snprintf(text, sizeof(text), "dem %dD, %d particles, broad phase %s, %d part(s)", D, m.n,
                  broad_phase_name(m.features.broad_phase), m.parts);
    return text;
  }
  void capacities(std::vector<Capacity>& out) const { dem_capacities(world_.model, world_.state, out); }
  std::int64_t list_builds() const { return world_.state.list_builds; }

 private:
  xfdem::DemWorld<D> world_;
};

class BarSystem {
 public:
  BarSystem(const xfdem::scene::Scene& scene, const xfdem::BarDesc& desc) {
    const xfdem::BuildResult built = xfdem::build_bar(desc, model_, state_, workspace_);
    if (!built.ok()) throw xfdem::scene::build_refusal(scene, xfdem::scene::Built::continuum, built);
  }
  StepStatus step() { return xfdem::bar_step(model_, state_, workspace_); }
  std::string describe() const {
    char text[200];
    std::snprintf(text, sizeof(text), "bar, %d elements, %d unknowns, %s", model_.desc.elements, model_.dofs,
                  model_.has_interface ? (model_.unilateral ? "unilateral interface" : "tied interface")
                                       : "no interface");
    return text;
  }
  void capacities(std::vector<Capacity>&) const {}  // a bar step has no capacity that varies
  std::int64_t list_builds() const { return 0; }

 private:
  xfdem::BarModel model_;
  xfdem::BarState state_;
  xfdem::BarWorkspace workspace_;
};

class CoupledSystem {
 public:
  CoupledSystem(const xfdem::scene::Scene& scene, xfdem::ParallelFor parallel) {
    const xfdem::BuildResult built = world_.build(xfdem::scene::coupled_desc(scene));
    if (!built.ok()) throw xfdem::scene::build_refusal(scene, xfdem::scene::Built::coupled, built);
    world_.workspace.dem.parallel = parallel;
  }
  StepStatus step() { return world_.step(); }
  std::string describe() const {
    const auto& m = world_.model;
    char text[200];
    std::snprintf(text, sizeof(text), "coupled, %d particles x %d substeps, bar %d elements (%d unknowns)", m.dem.n,
                  m.substeps, m.bar.desc.elements, m.bar.dofs);
    return text;
  }
  void capacities(std::vector<Capacity>& out) const {
    dem_capacities(world_.model.dem, world_.state.dem, out);
    out.push_back({"coupled_passes", world_.state.peak_passes, xfdem::kCoupledMaxPasses});
  }
  std::int64_t list_builds() const { return world_.state.dem.list_builds; }

 private:
  xfdem::CoupledWorld world_;
};

/// Disks against a plate: the world `xfdem run` steps (scene/coupled2d_run.hpp),
/// with the energy check of the scene's `energy_check` inside its step.
class Coupled2dSystem {
 public:
  Coupled2dSystem(const xfdem::scene::Scene& scene, xfdem::ParallelFor parallel) : run_(scene, parallel) {}
  StepStatus step() { return run_.step(); }
  std::string describe() const {
    const auto& m = run_.world().model;
    char text[240];
    std::snprintf(text, sizeof(text),
                  "coupled 2D, %d disks x %d substeps, broad phase %s, %d part(s), plate %dx%d cells (%d unknowns), "
                  "%zu boundary segments",
                  m.dem.n, m.substeps, broad_phase_name(m.dem.features.broad_phase), m.dem.parts,
                  m.plate.desc.cells[0], m.plate.desc.cells[1], m.plate.dofs, m.boundary.segments.size());
    return text;
  }
  /// A window's passes: at most kCoupled2dMaxPasses, and one more when it is
  /// taken at its smallest residual (re-run at that force).
  void capacities(std::vector<Capacity>& out) const {
    dem_capacities(run_.world().model.dem, run_.world().state.dem, out);
    out.push_back({"coupled_passes", run_.world().state.peak_passes, xfdem::kCoupled2dMaxPasses + 1});
  }
  std::int64_t list_builds() const { return run_.world().state.dem.list_builds; }
  void extras() const {
    std::printf("windows_at_a_jump: %" PRId64 "\n", run_.world().state.unsettled_windows);
  }

 private:
  xfdem::scene::Coupled2dRun run_;
};

// ---- the loop ------------------------------------------------------------------

/// Sleeps (coarsely) until `target_ns` minus a margin, then spins on the clock:
/// nanosleep's wake-up is late by tens of microseconds on a loaded host.
void wait_until(std::int64_t target_ns) {
  constexpr std::int64_t kSpinMargin = 100'000;  // ns spent spinning before a release
  for (;;) {
    const std::int64_t now = xfdem::platform::monotonic_ns();
    const std::int64_t left = target_ns - now;
    if (left <= 0) return;
    if (left > kSpinMargin) {
      const std::int64_t sleep = left - kSpinMargin;
      timespec ts{static_cast<time_t>(sleep / 1'000'000'000), static_cast<long>(sleep % 1'000'000'000)};
      nanosleep(&ts, nullptr);
    }
  }
}

bool pin_current_thread(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return sched_setaffinity(0, sizeof(set), &set) == 0;
}

/// The first two CPUs this process may run on (-1 where there is none).
std::pair<int, int> allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::pair<int, int> cpus{-1, -1};
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    if (cpus.first < 0) {
      cpus.first = c;
    } else {
      cpus.second = c;
      break;
    }
  }
  return cpus;
}

struct Samples {
  std::vector<std::int64_t> compute;  ///< ns per step
  std::vector<std::int64_t> late;     ///< ns between a step's release and its start (paced runs)
};

/// Nearest-rank quantile of a sorted sample.
std::int64_t quantile(const std::vector<std::int64_t>& sorted, std::size_t n, double q) {
  if (n == 0) return 0;
  auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(n)));
  rank = std::clamp<std::size_t>(rank, 1, n);
  return sorted[rank - 1];
}

/// Median cost of one clock read around a step (two back-to-back reads), ns:
/// included in every compute-time sample, so it is reported with them.
std::int64_t clock_read_ns() {
  std::array<std::int64_t, 1001> d{};
  for (auto& x : d) {
    const std::int64_t a = xfdem::platform::monotonic_ns();
    x = xfdem::platform::monotonic_ns() - a;
  }
  std::nth_element(d.begin(), d.begin() + 500, d.end());
  return d[500];
}

struct LoopResult {
  std::int64_t steps_run = 0;
  std::int64_t wall_ns = 0;
  std::int64_t compute_misses = 0;  ///< compute time > period
  std::int64_t late_misses = 0;     ///< compute fitted, but the step ended after its deadline (late start)
  std::uint64_t allocations = 0;
  StepStatus status = StepStatus::ok;
  std::int64_t status_step = -1;
  std::int64_t energy_growth_step = -1;  ///< first step that said energy_growth (the loop carries on)
};

template <class System>
LoopResult run_loop(System& system, std::int64_t steps, std::int64_t period, StepStatus acknowledged,
                    Samples& samples) {
  LoopResult r;
  const xfdem::platform::AllocationCounter allocations;
  const std::int64_t start = xfdem::platform::monotonic_ns();
  std::int64_t release = start;
  for (std::int64_t k = 0; k < steps; ++k) {
    if (period > 0) wait_until(release);
    const std::int64_t t0 = xfdem::platform::monotonic_ns();
    const StepStatus raw = system.step();
    // The flags the scene allowed, and energy_growth, which is booked and carried past.
    const StepStatus status = xfdem::without(raw, acknowledged | StepStatus::energy_growth);
    const std::int64_t t1 = xfdem::platform::monotonic_ns();
    const std::int64_t compute = t1 - t0;
    samples.compute[static_cast<std::size_t>(k)] = compute;
    if (period > 0) {
      samples.late[static_cast<std::size_t>(k)] = t0 - release;
      const std::int64_t deadline = release + period;
      if (compute > period) {
        ++r.compute_misses;
      } else if (t1 > deadline) {
        ++r.late_misses;
      }
      release += period;  // a fixed schedule: a late step does not shift the next releases
    }
    r.steps_run = k + 1;
    if (xfdem::has(raw, StepStatus::energy_growth) && r.energy_growth_step < 0) r.energy_growth_step = k + 1;
    if (status != StepStatus::ok) {
      r.status = status;
      r.status_step = k + 1;
      break;
    }
  }
  r.wall_ns = xfdem::platform::monotonic_ns() - start;
  r.allocations = allocations.allocations();
  return r;
}

template <class System>
int run_and_report(const Options& o, const xfdem::scene::Scene& scene, System& system, const char* pinned) {
  const std::int64_t steps = o.steps > 0 ? o.steps : scene.steps;
  Samples samples;
  samples.compute.assign(static_cast<std::size_t>(steps), 0);
  samples.late.assign(o.period_ns > 0 ? static_cast<std::size_t>(steps) : 0, 0);
  std::vector<Capacity> capacities;
  capacities.reserve(8);
  const std::int64_t clock_cost = clock_read_ns();

  const LoopResult r = run_loop(system, steps, o.period_ns, xfdem::scene::acknowledged_flags(scene), samples);

  const auto n = static_cast<std::size_t>(r.steps_run);
  std::sort(samples.compute.begin(), samples.compute.begin() + static_cast<std::ptrdiff_t>(n));
  system.capacities(capacities);

  std::printf("scene: %s\n", scene.name.c_str());
  std::printf("system: %s\n", system.describe().c_str());
  std::printf("pacing: %s\n", o.pacing.c_str());
  std::printf("period_ns: %" PRId64 "\n", o.period_ns);
  std::printf("threads: %d\n", o.threads);
  std::printf("pinned: %s\n", pinned);
  std::printf("steps: %" PRId64 "\n", r.steps_run);
  std::printf("sim_time_s: %.9g\n", static_cast<double>(r.steps_run) * scene.dt);
  std::printf("wall_time_s: %.6f\n", static_cast<double>(r.wall_ns) * 1e-9);
  std::printf("realtime_factor: %.3f\n",
              r.wall_ns > 0 ? static_cast<double>(r.steps_run) * scene.dt / (static_cast<double>(r.wall_ns) * 1e-9)
                            : 0.0);
  std::printf("clock_read_ns: %" PRId64 "\n", clock_cost);
  std::printf("step_median_ns: %" PRId64 "\n", quantile(samples.compute, n, 0.5));
  std::printf("step_p99_ns: %" PRId64 "\n", quantile(samples.compute, n, 0.99));
  std::printf("step_p99.9_ns: %" PRId64 "\n", quantile(samples.compute, n, 0.999));
  std::printf("step_max_ns: %" PRId64 "\n", n > 0 ? samples.compute[n - 1] : 0);
  if (o.period_ns > 0) {
    std::sort(samples.late.begin(), samples.late.begin() + static_cast<std::ptrdiff_t>(n));
    std::printf("wakeup_late_median_ns: %" PRId64 "\n", quantile(samples.late, n, 0.5));
    std::printf("wakeup_late_p99_ns: %" PRId64 "\n", quantile(samples.late, n, 0.99));
    std::printf("wakeup_late_max_ns: %" PRId64 "\n", n > 0 ? samples.late[n - 1] : 0);
    std::printf("deadline_misses: %" PRId64 "\n", r.compute_misses + r.late_misses);
    std::printf("misses_compute_over_period: %" PRId64 "\n", r.compute_misses);
    std::printf("misses_late_wakeup: %" PRId64 "\n", r.late_misses);
  } else {
    std::printf("deadline_misses: n/a (no period)\n");
  }
  std::printf("allocations_in_loop: %" PRIu64 "\n", r.allocations);
  for (const Capacity& c : capacities)
    std::printf("capacity_%s: %" PRId64 " of %" PRId64 "\n", c.name, c.peak, c.capacity);
  if (!capacities.empty()) std::printf("list_builds: %" PRId64 "\n", system.list_builds());
  if constexpr (requires { system.extras(); }) system.extras();
  char text[200];
  std::printf("energy_growth_from_step: %" PRId64 "\n", r.energy_growth_step);
  std::printf("status: %s\n", xfdem::describe(r.status, text, sizeof(text)));
  if (r.status != StepStatus::ok) {
    std::fprintf(stderr, "xfdem_rt: step %" PRId64 " (t = %.17g s) returned %s\n", r.status_step,
                 static_cast<double>(r.status_step) * scene.dt, text);
    return 3;
  }
  return 0;
}

int run(const Options& o) {
  const xfdem::scene::Scene scene = xfdem::scene::load_scene(o.scene_path, o.overrides);
  if (o.steps <= 0 && scene.steps <= 0) throw SceneError("the scene has no steps (time.end / time.dt)");

  std::string pinned = "no";
  int worker_cpu = -1;
  if (o.pin) {
    const auto [first, second] = allowed_cpus();
    if (first < 0 || !pin_current_thread(first)) throw SceneError("--pin: cannot pin the loop to a CPU");
    pinned = "loop on cpu " + std::to_string(first);
    if (o.threads == 2) {
      if (second < 0) throw SceneError("--pin with --threads 2: only one CPU is available");
      worker_cpu = second;
      pinned += ", worker on cpu " + std::to_string(second);
    }
  }
  // Pinned, the two workers own their cores: the waiting one may spin long
  // (20000 pauses) rather than sleep; unpinned, the pool's short default
  // leaves a shared core to the thread it waits for.
  std::optional<xfdem::platform::TwoWorkerPool> pool;
  if (o.threads == 2) {
    if (o.pin) {
      pool.emplace(worker_cpu, 20000);
    } else {
      pool.emplace(-1);
    }
  }
  const xfdem::ParallelFor parallel = pool ? pool->parallel_for() : xfdem::ParallelFor{};

  if (scene.plate && !std::holds_alternative<std::monostate>(scene.dem)) {
    Coupled2dSystem system(scene, parallel);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  if (scene.bar && !std::holds_alternative<std::monostate>(scene.dem)) {
    CoupledSystem system(scene, parallel);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  if (const auto* d1 = std::get_if<xfdem::DemDesc<1>>(&scene.dem)) {
    DemSystem<1> system(scene, *d1, parallel);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  if (const auto* d2 = std::get_if<xfdem::DemDesc<2>>(&scene.dem)) {
    DemSystem<2> system(scene, *d2, parallel);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  if (const auto* d3 = std::get_if<xfdem::DemDesc<3>>(&scene.dem)) {
    DemSystem<3> system(scene, *d3, parallel);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  if (scene.bar) {
    BarSystem system(scene, *scene.bar);
    return run_and_report(o, scene, system, pinned.c_str());
  }
  throw SceneError("scene: nothing to run");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  try {
    return run(parse_options(argc, argv));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "xfdem_rt: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const SceneError& e) {
    std::fprintf(stderr, "xfdem_rt: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "xfdem_rt: %s\n", e.what());
    return 2;
  }
}
