// Work-precision runner: for the validation scenes V1, V2, Case I and Case II,
// sweeps the time step (and the substep count n, the particle integrator and
// Newmark's β, γ), and records the run time per simulated second against the
// error from a reference the project computes itself:
//
//   v1_k1e4, v1_k1e5  the drop test against its closed form
//                     (tests/support/drop_closed_form.hpp): max relative error
//                     of the apex heights of every bounce in the 6 s run;
//   v2                the rod (30 elements, X-FEM, tied interface) against the
//                     exact solution of the same semi-discrete system
//                     (tests/xfem/reference.hpp): max |u_tip − u_exact| over
//                     samples every 10 ms in (0, 1] s, over max |u_exact|;
//                     the spatial error (semi-discrete vs the continuum) is
//                     written apart, in work_precision_v2_spatial.csv;
//   case1, case2      the coupled scenes against a much finer run of the same
//                     semi-discrete system (abm4_events, n = 10, β = ¼, γ = ½,
//                     dt = 1e-3/256) over the first second: the larger of
//                     max |y_i − y_i,ref| / max |y_i,ref − y_i(0)| over the
//                     particles and max |u_tip − u_tip,ref| / max |u_tip,ref|,
//                     sampled every 2 ms.
//
// Timing: every configuration runs once untimed-for-the-record (it measures
// the error and warms code and data), then is timed on a steady clock from a
// copy of its initial state, over the whole simulated interval, with nothing
// but the steps inside the timed region; the median of 5 repetitions (3 when
// one run takes over 50 ms, 1 over 0.5 s) is recorded. The machine may be
// shared: read the timings as ±10–20 %.
//
//   xfdem_work_precision [--quick] [--out DIR] [--only SCENE]
//
// writes DIR/work_precision_<scene>.csv (default DIR: out) with the columns
// scene, method, dt, n, beta, gamma, seconds_per_simulated_second, error.
// --quick: fewer and coarser configurations (about 15 s; the full sweep about 2 min).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "support/coupled_scenes.hpp"
#include "support/dem_scenes.hpp"
#include "support/drop_closed_form.hpp"
#include "xfdem/bar.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/dem.hpp"
#include "xfem/reference.hpp"

namespace {

using namespace xfdem;
using Clock = std::chrono::steady_clock;

struct Options {
  bool quick = false;
  std::string out = "out";
  std::string only;
};

struct Row {
  std::string scene, method;
  double dt = 0;
  int n = 1;
  double beta = NAN, gamma = NAN;
  double seconds_per_simulated_second = NAN, error = NAN;
};

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "xfdem_work_precision: %s\n", what.c_str());
  std::exit(1);
}

volatile double g_sink = 0;  // keeps the timed loops' results alive

/// Median wall time (s) of `run` (which restores its own initial state outside
/// the measured region through `reset`), with repetitions chosen from the
/// duration of a first run.
double time_median(const std::function<void()>& reset, const std::function<void()>& run, double first_seconds) {
  const int reps = first_seconds < 0.05 ? 5 : first_seconds < 0.5 ? 3 : 1;
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    reset();
    const auto t0 = Clock::now();
    run();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

std::string fmt(double x) {
  if (std::isnan(x)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

void write_csv(const Options& o, const std::string& scene, const std::vector<Row>& rows) {
  std::filesystem::create_directories(o.out);
  const std::string path = o.out + "/work_precision_" + scene + ".csv";
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail("cannot write " + path);
  std::fprintf(f, "scene,method,dt,n,beta,gamma,seconds_per_simulated_second,error\n");
  for (const Row& r : rows)
    std::fprintf(f, "%s,%s,%s,%d,%s,%s,%s,%s\n", r.scene.c_str(), r.method.c_str(), fmt(r.dt).c_str(), r.n,
                 fmt(r.beta).c_str(), fmt(r.gamma).c_str(), fmt(r.seconds_per_simulated_second).c_str(),
                 fmt(r.error).c_str());
  std::fclose(f);
  std::printf("wrote %s (%zu rows)\n", path.c_str(), rows.size());
}

void print_row(const Row& r) {
  std::printf("  %-8s %-17s dt %-9.3g n %-2d beta %-6s gamma %-4s  %10.3e s/s  error %.3e\n", r.scene.c_str(),
              r.method.c_str(), r.dt, r.n, fmt(r.beta).c_str(), fmt(r.gamma).c_str(), r.seconds_per_simulated_second,
              r.error);
  std::fflush(stdout);
}

// ---- V1: the drop test -------------------------------------------------------

constexpr double kV1End = 6.0;

/// One V1 configuration: error (max relative apex error over every bounce
/// whose apex falls before kV1End) and cost. Returns false if it does not build.
bool v1_run(double k, DemIntegrator integrator, double dt, Row& row, double& first_seconds) {
  testing::DropParameters p;
  p.stiffness = k;
  std::vector<double> exact_apex;
  for (const auto& b : testing::drop_bounces(p, kV1End))
    if (b.duration && b.t_apex < kV1End) exact_apex.push_back(b.apex);

  DemWorld<1> w;
  if (!w.build(testing::drop_scene(p, integrator, dt)).ok()) return false;
  const DemState<1> initial = w.state;
  const auto steps = static_cast<long>(std::llround(kV1End / dt));

  // Error pass: an apex is where v turns from positive to non-positive in
  // flight after a contact; its height is y + v²/(2g) at the last sample with
  // v > 0 (exact in free flight for every integrator but symplectic Euler,
  // whose own error this then includes).
  std::vector<double> apex;
  bool touched = false;
  double y_prev = w.state.x[0][0], v_prev = w.state.v[0][0];
  const auto t0 = Clock::now();
  for (long s = 0; s < steps; ++s) {
    if (has(w.step(), kStepNotTaken)) fail("V1 step not taken");
    const double y = w.state.x[0][0], v = w.state.v[0][0];
    if (y < p.radius) touched = true;
    if (touched && y >= p.radius && y_prev >= p.radius && v_prev > 0 && v <= 0)
      apex.push_back(y_prev + v_prev * v_prev / (2 * p.g));
    y_prev = y;
    v_prev = v;
  }
  first_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  double err = 0;
  for (std::size_t b = 0; b < exact_apex.size(); ++b)
    err = std::max(err, b < apex.size() ? std::fabs(apex[b] / exact_apex[b] - 1) : 1.0);

  const double sec = time_median([&] { w.state = initial; },
                                 [&] {
                                   for (long s = 0; s < steps; ++s) w.step();
                                   g_sink = w.state.x[0][0];
                                 },
                                 first_seconds);
  row.method = integrator_name(integrator);
  row.dt = dt;
  row.n = 1;
  row.seconds_per_simulated_second = sec / kV1End;
  row.error = err;
  return true;
}

void v1(const Options& o, double k, const std::string& scene) {
  std::printf("%s: drop test, k = %g, error = max relative apex error over the bounces of a %.0f s run\n",
              scene.c_str(), k, kV1End);
  const std::vector<double> dts = {2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6,
                                   1e-6, 5e-7, 2e-7, 1e-7, 5e-8, 2e-8, 1e-8};
  // A configuration is skipped when its predicted run time exceeds this, or
  // once the error is below the floor (nothing left to learn below it).
  const double max_run = o.quick ? 0.25 : 4.5;
  const double floor = 1e-9;
  std::vector<Row> rows;
  for (DemIntegrator integ : {DemIntegrator::abm4_events, DemIntegrator::abm4, DemIntegrator::rk4,
                              DemIntegrator::verlet, DemIntegrator::symplectic_euler}) {
    double last_seconds = 0, last_dt = 0;
    for (double dt : dts) {
      if (last_dt > 0 && last_seconds * (last_dt / dt) > max_run) break;
      Row r;
      r.scene = scene;
      double first = 0;
      if (!v1_run(k, integ, dt, r, first)) continue;  // above the stable step
      rows.push_back(r);
      print_row(r);
      last_seconds = first;
      last_dt = dt;
      if (r.error < floor) break;
    }
  }
  write_csv(o, scene, rows);
}

// ---- V2: the rod ------------------------------------------------------------

constexpr double kV2End = 1.0, kV2Sample = 0.01;

BarDesc v2_desc(int elements, double dt, double beta, double gamma) {
  BarDesc d = test::v2_rod(elements, dt);
  d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::tied};
  d.beta = beta;
  d.gamma = gamma;
  return d;
}

void v2(const Options& o) {
  std::printf("v2: rod, 30 elements, X-FEM, tied interface; error = max |u_tip - exact| / max |exact| over (0, 1] s,"
              " exact = the semi-discrete system's modal solution\n");
  const int samples = static_cast<int>(std::lround(kV2End / kV2Sample));
  // The semi-discrete exact solution depends on the mesh only (not on dt, β, γ).
  auto exact_tip = [&](int elements) {
    BarModel m;
    BarState st;
    BarWorkspace ws;
    const BarDesc d = v2_desc(elements, 1e-3, 0.25, 0.5);
    if (!build_bar(d, m, st, ws).ok()) fail("V2 build");
    const test::SemiDiscreteExact exact(test::dense(m.mass), test::dense_stiffness(m), m.tip_dof, d.tip_amplitude,
                                        d.tip_duration);
    std::vector<double> u;
    for (int s = 1; s <= samples; ++s) u.push_back(exact.displacement(s * kV2Sample)(m.tip_dof));
    return u;
  };
  const std::vector<double> ref = exact_tip(30);
  double ref_max = 0;
  for (double u : ref) ref_max = std::max(ref_max, std::fabs(u));

  // Spatial error, apart: the semi-discrete exact tip vs the continuum series.
  {
    std::filesystem::create_directories(o.out);
    const std::string path = o.out + "/work_precision_v2_spatial.csv";
    FILE* f = std::fopen(path.c_str(), "w");
    if (!f) fail("cannot write " + path);
    std::fprintf(f, "elements,error\n");
    const BarDesc b = test::v2_rod(30);
    std::vector<double> cont;
    double cmax = 0;
    for (int s = 1; s <= samples; ++s) {
      cont.push_back(test::continuum_tip_displacement(b.length, b.youngs_modulus, b.area, b.density, b.tip_amplitude,
                                                      b.tip_duration, s * kV2Sample));
      cmax = std::max(cmax, std::fabs(cont.back()));
    }
    for (int ne : {15, 30, 60, 120}) {
      const std::vector<double> u = ne == 30 ? ref : exact_tip(ne);
      double e = 0;
      for (int s = 0; s < samples; ++s) e = std::max(e, std::fabs(u[s] - cont[s]));
      std::fprintf(f, "%d,%.6g\n", ne, e / cmax);
      std::printf("  spatial error (semi-discrete exact vs continuum), %d elements: %.3e of max |u_tip|\n", ne,
                  e / cmax);
    }
    std::fclose(f);
  }

  std::vector<double> dts = {5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5};
  if (o.quick) dts = {5e-3, 1e-3, 2e-4, 5e-5};
  std::vector<Row> rows;
  for (auto [beta, gamma] : {std::pair{0.25, 0.5}, std::pair{0.4, 0.6}, std::pair{0.3025, 0.6}}) {
    for (double dt : dts) {
      BarModel m;
      BarState st;
      BarWorkspace ws;
      if (!build_bar(v2_desc(30, dt, beta, gamma), m, st, ws).ok()) fail("V2 build");
      const BarState initial = st;
      const long per_sample = std::lround(kV2Sample / dt);
      double err = 0;
      const auto t0 = Clock::now();
      for (int s = 0; s < samples; ++s) {
        for (long i = 0; i < per_sample; ++i) bar_step(m, st, ws);
        err = std::max(err, std::fabs(bar_tip_displacement(m, st) - ref[s]));
      }
      const double first = std::chrono::duration<double>(Clock::now() - t0).count();
      const long steps = per_sample * samples;
      const double sec = time_median([&] { st = initial; },
                                     [&] {
                                       for (long i = 0; i < steps; ++i) bar_step(m, st, ws);
                                       g_sink = st.u[m.tip_dof];
                                     },
                                     first);
      Row r;
      r.scene = "v2";
      r.method = "newmark";
      r.dt = dt;
      r.n = 0;
      r.beta = beta;
      r.gamma = gamma;
      r.seconds_per_simulated_second = sec / kV2End;
      r.error = err / ref_max;
      rows.push_back(r);
      print_row(r);
    }
  }
  write_csv(o, "v2", rows);
}

// ---- Case I and II: the coupled scenes ---------------------------------------

constexpr double kCoupledEnd = 1.0, kCoupledSample = 2e-3;

struct Trace {
  std::vector<std::vector<double>> y;  ///< [particle][sample]
  std::vector<double> tip;
};

struct CoupledRun {
  CoupledWorld world;
  CoupledState initial;
  long per_sample = 0;
};

bool coupled_build(const std::string& file, DemIntegrator integ, int n, double beta, double gamma, double dt,
                   CoupledRun& run) {
  CoupledDesc d = testing::coupled_scene(file);
  d.bar.dt = dt;
  d.bar.beta = beta;
  d.bar.gamma = gamma;
  d.dem_substeps = n;
  d.dem.integrator = integ;
  if (!run.world.build(d).ok()) return false;
  run.initial = run.world.state;
  run.per_sample = std::lround(kCoupledSample / dt);
  return true;
}

Trace coupled_trace(CoupledRun& run) {
  CoupledWorld& w = run.world;
  const int samples = static_cast<int>(std::lround(kCoupledEnd / kCoupledSample));
  Trace t;
  t.y.resize(static_cast<std::size_t>(w.model.dem.n));
  for (int s = 0; s < samples; ++s) {
    for (long i = 0; i < run.per_sample; ++i)
      if (has(w.step(), kStepNotTaken)) fail("coupled step not taken");
    for (std::int32_t p = 0; p < w.model.dem.n; ++p) t.y[p].push_back(w.state.dem.x[0][p]);
    t.tip.push_back(bar_tip_displacement(w.model.bar, w.state.bar));
  }
  return t;
}

double trace_error(const Trace& a, const Trace& ref, const std::vector<double>& y0) {
  double err = 0;
  for (std::size_t p = 0; p < ref.y.size(); ++p) {
    double scale = 0, e = 0;
    for (std::size_t s = 0; s < ref.y[p].size(); ++s) {
      scale = std::max(scale, std::fabs(ref.y[p][s] - y0[p]));
      e = std::max(e, std::fabs(a.y[p][s] - ref.y[p][s]));
    }
    err = std::max(err, e / scale);
  }
  double scale = 0, e = 0;
  for (std::size_t s = 0; s < ref.tip.size(); ++s) {
    scale = std::max(scale, std::fabs(ref.tip[s]));
    e = std::max(e, std::fabs(a.tip[s] - ref.tip[s]));
  }
  return std::max(err, e / scale);
}

void coupled(const Options& o, const std::string& scene, const std::string& file) {
  const double ref_dt = 1e-3 / (o.quick ? 128 : 256);
  std::printf("%s: %s, first second; reference: abm4_events, n = 10, beta = 0.25, gamma = 0.5, dt = %.4g\n",
              scene.c_str(), file.c_str(), ref_dt);
  auto reference = [&](double dt) {
    CoupledRun run;
    if (!coupled_build(file, DemIntegrator::abm4_events, 10, 0.25, 0.5, dt, run)) fail("reference build");
    return coupled_trace(run);
  };
  const Trace ref = reference(ref_dt);
  std::vector<double> y0;
  {
    CoupledRun run;
    coupled_build(file, DemIntegrator::abm4, 10, 0.4, 0.6, 1e-3, run);
    y0 = run.initial.dem.x[0];
  }
  // The reference's own error, estimated from the run at twice its step.
  const double ref_error = trace_error(reference(2 * ref_dt), ref, y0);
  std::printf("  reference at 2 dt differs from it by %.2e (a bound on the reference's own error, given order >= 1)\n",
              ref_error);

  std::vector<double> dts = {2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5};
  if (o.quick) dts = {2e-3, 1e-3, 5e-4, 2.5e-4};
  std::vector<Row> rows;
  for (auto [beta, gamma] : {std::pair{0.4, 0.6}, std::pair{0.25, 0.5}})
    for (DemIntegrator integ : {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::verlet})
      for (int n : {10, 1})
        for (double dt : dts) {
          CoupledRun run;
          if (!coupled_build(file, integ, n, beta, gamma, dt, run)) continue;  // outside the stable region
          const auto t0 = Clock::now();
          const Trace tr = coupled_trace(run);
          const double first = std::chrono::duration<double>(Clock::now() - t0).count();
          const long steps = std::lround(kCoupledEnd / dt);
          const double sec = time_median([&] { run.world.state = run.initial; },
                                         [&] {
                                           for (long i = 0; i < steps; ++i) run.world.step();
                                           g_sink = run.world.state.dem.x[0][0];
                                         },
                                         first);
          Row r;
          r.scene = scene;
          r.method = integrator_name(integ);
          r.dt = dt;
          r.n = n;
          r.beta = beta;
          r.gamma = gamma;
          r.seconds_per_simulated_second = sec / kCoupledEnd;
          r.error = trace_error(tr, ref, y0);
          rows.push_back(r);
          print_row(r);
        }
  Row floor;  // the reference's self-difference, for the plot's floor line
  floor.scene = scene;
  floor.method = "reference_floor";
  floor.dt = ref_dt;
  floor.n = 10;
  floor.beta = 0.25;
  floor.gamma = 0.5;
  floor.error = ref_error;
  rows.push_back(floor);
  write_csv(o, scene, rows);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      o.out = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      o.only = argv[++i];
    } else {
      std::fprintf(stderr, "usage: xfdem_work_precision [--quick] [--out DIR] [--only v1_k1e4|v1_k1e5|v2|case1|case2]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  auto want = [&](const char* s) { return o.only.empty() || o.only == s; };
  const auto t0 = Clock::now();
  if (want("v1_k1e4")) v1(o, 1e4, "v1_k1e4");
  if (want("v1_k1e5")) v1(o, 1e5, "v1_k1e5");
  if (want("v2")) v2(o);
  if (want("case1")) coupled(o, "case1", "case1_xfem.json");
  if (want("case2")) coupled(o, "case2", "case2_xfem.json");
  std::printf("sweep took %.1f s\n", std::chrono::duration<double>(Clock::now() - t0).count());
  return 0;
}
