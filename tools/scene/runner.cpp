#include "scene/runner.hpp"

#include <cinttypes>
#include <cstdio>

#include "xfdem/platform/clock.hpp"

namespace xfdem::scene {
namespace {

void write_value(std::ostream& out, double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  out << text;
}

template <int D>
double probe_value(const Probe& p, const DemModel<D>& m, const DemState<D>& s) {
  switch (p.kind) {
    case Probe::Kind::particle_position: return s.x[p.component][p.particle];
    case Probe::Kind::particle_velocity: return s.v[p.component][p.particle];
    case Probe::Kind::pair_force: return dem_pair_force(m, s, p.particle, p.other);
    case Probe::Kind::plane_force: return dem_plane_force(m, s, p.particle, p.other);
    case Probe::Kind::energy_total: {
      const DemEnergy e = dem_energy(m, s);
      return e.kinetic + e.elastic + e.potential;
    }
    case Probe::Kind::energy_kinetic: return dem_energy(m, s).kinetic;
    case Probe::Kind::energy_elastic: return dem_energy(m, s).elastic;
    case Probe::Kind::energy_potential: return dem_energy(m, s).potential;
    default: return NAN;  // continuum probes are rejected at load in DEM-only builds
  }
}

template <int D>
RunSummary run_dem(const Scene& scene, const DemDesc<D>& desc, std::ostream& csv) {
  DemModel<D> model;
  DemState<D> state;
  DemWorkspace<D> workspace;
  const BuildResult built = build_dem(desc, model, state, workspace);
  if (!built.ok()) throw SceneError(std::string("scene key 'dem.") + built.message);

  csv << "t";
  for (const auto& p : scene.probes) csv << ',' << p.name;
  csv << '\n';
  auto row = [&](std::int64_t step) {
    write_value(csv, static_cast<double>(step) * scene.dt);
    for (const auto& p : scene.probes) {
      csv << ',';
      write_value(csv, probe_value(p, model, state));
    }
    csv << '\n';
  };
  row(0);
  RunSummary summary;
  const std::int64_t start = platform::monotonic_ns();
  std::int64_t worst = 0;
  for (std::int64_t step = 1; step <= scene.steps; ++step) {
    const std::int64_t t0 = platform::monotonic_ns();
    const StepStatus status = dem_step(model, state, workspace);
    worst = std::max(worst, platform::monotonic_ns() - t0);
    if (status != StepStatus::ok) {
      char text[200];
      char message[400];
      std::snprintf(message, sizeof(message), "step %" PRId64 " (t = %.17g s) returned %s", step,
                    static_cast<double>(step) * scene.dt, describe(status, text, sizeof(text)));
      throw SceneError(message);
    }
    if (step % scene.output_stride == 0) row(step);
  }
  summary.steps = scene.steps;
  summary.wall_seconds = static_cast<double>(platform::monotonic_ns() - start) * 1e-9;
  summary.mean_step_seconds = summary.wall_seconds / static_cast<double>(scene.steps);
  summary.worst_step_seconds = static_cast<double>(worst) * 1e-9;
  return summary;
}

}  // namespace

RunSummary run_scene(const Scene& scene, std::ostream& csv, int threads) {
  if (threads < 1 || threads > 2) throw SceneError("--threads: must be 1 or 2");
  if (const auto* d1 = std::get_if<DemDesc<1>>(&scene.dem)) return run_dem<1>(scene, *d1, csv);
  if (const auto* d2 = std::get_if<DemDesc<2>>(&scene.dem)) return run_dem<2>(scene, *d2, csv);
  if (const auto* d3 = std::get_if<DemDesc<3>>(&scene.dem)) return run_dem<3>(scene, *d3, csv);
  throw SceneError("scene: nothing to run");
}

}  // namespace xfdem::scene
