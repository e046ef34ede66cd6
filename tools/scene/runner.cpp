#include <charconv>
#include "scene/runner.hpp"

#include <cinttypes>
#include <cmath>
#include <string>
#include <cstdio>
#include <vector>

#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/coupling/plate_boundary.hpp"
#include "xfdem/platform/clock.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "scene/coupled2d_run.hpp"
#include "scene/vtk.hpp"

#include <memory>
#include <new>
#include <optional>
#include <utility>

namespace xfdem::scene {
namespace {

double share(std::int64_t part, std::int64_t whole) {
  return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

/// "broad phase 3%, contacts 71%, integration 26%; peaks: pairs 512/8064, …"
template <int D>
std::string dem_stages(const DemModel<D>& m, const DemState<D>& s, const DemProfile& p) {
  char text[320];
  std::snprintf(text, sizeof(text),
                "particles: broad phase %.0f%%, contacts %.0f%%, integration %.0f%%; peaks: pairs %d/%d, neighbours "
                "%d/%d, grid cells %d/%d, events %d/%d",
                share(p.broad_phase_ns, p.step_ns), share(p.contacts_ns, p.step_ns), share(p.integration_ns(), p.step_ns),
                s.peak_pairs, m.capacities.max_pairs, s.peak_neighbors, m.capacities.max_neighbors_per_particle,
                s.peak_grid_cells, m.capacities.max_grid_cells, s.peak_events, m.capacities.max_events_per_step);
  return text;
}

/// The longest "%.17g" text: sign, 17 digits, point, "e-308".
constexpr std::size_t kValueChars = 25;

/// Appends printf's "%.17g" text of value (the standard defines to_chars by
/// it), which reads back bit-exact, without printf's locale and
/// multi-precision work: a long run's CSV notices.
void append_value(std::string& line, double value) {
  char text[kValueChars];
  const std::to_chars_result r = std::to_chars(text, text + sizeof(text), value, std::chars_format::general, 17);
  line.append(text, r.ptr);
}

/// The part of an energy (kinetic, elastic and potential, J) that an `energy`
/// probe asks for; total: their sum. NaN for other probes.
template <class Energy>
double energy_part(const Energy& e, Probe::Kind kind) {
  switch (kind) {
    case Probe::Kind::energy_total: return e.kinetic + e.elastic + e.potential;
    case Probe::Kind::energy_kinetic: return e.kinetic;
    case Probe::Kind::energy_elastic: return e.elastic;
    case Probe::Kind::energy_potential: return e.potential;
    default: return NAN;
  }
}

bool is_energy(Probe::Kind kind) {
  return kind == Probe::Kind::energy_total || kind == Probe::Kind::energy_kinetic ||
         kind == Probe::Kind::energy_elastic || kind == Probe::Kind::energy_potential;
}

/// A probe of the particles alone (their positions, velocities, rotation and
/// contacts with each other and with planes), as every system with particles
/// reads it; NaN for other kinds.
template <int D>
double particle_probe(const DemModel<D>& m, const DemState<D>& s, const Probe& p) {
  switch (p.kind) {
    case Probe::Kind::particle_position: return s.x[p.component][p.particle];
    case Probe::Kind::particle_velocity: return s.v[p.component][p.particle];
    case Probe::Kind::pair_force: return dem_pair_force(m, s, p.particle, p.other);
    case Probe::Kind::plane_force: return dem_plane_force(m, s, p.particle, p.other);
    case Probe::Kind::pair_tangential_force: return dem_pair_tangential_force(m, s, p.particle, p.other);
    case Probe::Kind::plane_tangential_force: return dem_plane_tangential_force(m, s, p.particle, p.other);
    case Probe::Kind::particle_angular_velocity: return dem_angular_velocity(m, s, p.particle, p.component);
    case Probe::Kind::particle_rotation: return dem_rotation(m, s, p.particle);
    case Probe::Kind::momentum_particles: return dem_momentum(m, s, p.component);
    default: return NAN;
  }
}

/// A probe of the plate's fields (at a point, of a crack) and its momentum,
/// as the plate alone and the plate with particles read it; NaN for other kinds.
double plate_probe(const PlateModel& m, const PlateState& s, const Probe& p) {
  switch (p.kind) {
    case Probe::Kind::plate_displacement: return plate_displacement(m, s, p.at[0], p.at[1], p.component);
    case Probe::Kind::plate_velocity: return plate_velocity(m, s, p.at[0], p.at[1], p.component);
    case Probe::Kind::plate_acceleration: return plate_acceleration(m, s, p.at[0], p.at[1], p.component);
    case Probe::Kind::plate_stress: return plate_stress(m, s, p.at[0], p.at[1], p.component);
    case Probe::Kind::plate_crack_opening: return plate_crack_opening(m, s, p.other, p.at[0], p.at[1], p.component);
    case Probe::Kind::plate_stress_intensity: {
      double k[2];
      plate_stress_intensity(m, s, p.other, p.tip_end, p.radius, k);
      return k[p.component];
    }
    case Probe::Kind::momentum_continuum: return plate_momentum(m, s, p.component);
    default: return NAN;
  }
}

/// The particles of a scene without a continuum.
template <int D>
class DemSystem {
 public:
  DemSystem(const Scene& scene, const DemDesc<D>& desc, ParallelFor parallel) {
    const BuildResult built = build_dem(desc, model_, state_, workspace_);
    if (!built.ok()) throw build_refusal(scene, Built::dem, built);
    workspace_.parallel = parallel;
  }
  void time_stages(bool on) { workspace_.clock_ns = on ? &platform::monotonic_ns : nullptr; }
  std::string stages() const { return dem_stages(model_, state_, workspace_.profile); }
  StepStatus step() { return dem_step(model_, state_, workspace_); }
  void write_vtk(VtkSeries& vtk) const { vtk.particles(model_, state_); }
  double probe(const Probe& p) const {
    if (is_energy(p.kind)) return energy_part(dem_energy(model_, state_), p.kind);
    return particle_probe(model_, state_, p);  // continuum probes are rejected at load for DEM-only scenes
  }

 private:
  DemModel<D> model_;
  DemState<D> state_;
  DemWorkspace<D> workspace_;
};

/// A bar alone (V2).
class BarSystem {
 public:
  BarSystem(const Scene& scene, const BarDesc& desc) {
    const BuildResult built = build_bar(desc, model_, state_, workspace_);
    if (!built.ok()) throw build_refusal(scene, Built::continuum, built);
  }
  StepStatus step() { return bar_step(model_, state_, workspace_); }
  void time_stages(bool) {}
  std::string stages() const { return "continuum only"; }
  double probe(const Probe& p) const {
    switch (p.kind) {
      case Probe::Kind::bar_displacement: return bar_displacement(model_, state_, p.bar_at);
      case Probe::Kind::bar_velocity: return bar_velocity(model_, state_, p.bar_at);
      case Probe::Kind::interface_gap: return bar_interface_gap(model_, state_);
      case Probe::Kind::energy_total: {
        const BarEnergy e = bar_energy(model_, state_);
        return e.kinetic + e.elastic;
      }
      case Probe::Kind::energy_kinetic: return bar_energy(model_, state_).kinetic;
      case Probe::Kind::energy_elastic: return bar_energy(model_, state_).elastic;
      case Probe::Kind::energy_potential: return 0.0;  // the rod carries no gravity
      default: return NAN;  // particle probes are rejected at load for bar-only scenes
    }
  }

 private:
  BarModel model_;
  BarState state_;
  BarWorkspace workspace_;
};

/// A plate alone (scenes-2d.md); a static one has no step and writes its one row.
class PlateSystem {
 public:
  PlateSystem(const Scene& scene, const PlateDesc& desc) {
    const BuildResult built = build_plate(desc, model_, state_, workspace_);
    if (!built.ok()) throw build_refusal(scene, Built::continuum, built);
  }
  StepStatus step() { return plate_step(model_, state_, workspace_); }
  void write_vtk(VtkSeries& vtk) const { vtk.plate(model_, state_); }
  void time_stages(bool) {}
  std::string stages() const { return "continuum only"; }
  double probe(const Probe& p) const {
    switch (p.kind) {
      case Probe::Kind::momentum_total: return plate_momentum(model_, state_, p.component);
      case Probe::Kind::momentum_particles: return 0.0;  // a plate alone has no particles
      default: break;
    }
    if (is_energy(p.kind)) return energy_part(plate_energy(model_, state_), p.kind);
    return plate_probe(model_, state_, p);  // other probes are rejected at load for plate scenes
  }

 private:
  PlateModel model_;
  PlateState state_;
  PlateWorkspace workspace_;
};

/// Particles and a bar together (Case I, Case II).
class CoupledSystem {
 public:
  explicit CoupledSystem(const Scene& scene) {
    const BuildResult built = world_.build(coupled_desc(scene));
    if (!built.ok()) throw build_refusal(scene, Built::coupled, built);
  }
  StepStatus step() { return world_.step(); }
  void time_stages(bool on) { world_.workspace.clock_ns = on ? &platform::monotonic_ns : nullptr; }
  std::string stages() const {
    const CoupledProfile& p = world_.workspace.profile;
    char text[200];
    std::snprintf(text, sizeof(text), "continuum %.0f%%, particles %.0f%%, exchange %.0f%%; passes per step %.2f (peak %d); ",
                  share(p.continuum_ns, p.step_ns), share(p.particles_ns, p.step_ns), share(p.coupling_ns(), p.step_ns),
                  p.steps ? static_cast<double>(p.passes) / static_cast<double>(p.steps) : 0.0, world_.state.peak_passes);
    return text + dem_stages(world_.model.dem, world_.state.dem, world_.workspace.dem.profile);
  }
  double probe(const Probe& p) const {
    const CoupledModel& m = world_.model;
    const CoupledState& s = world_.state;
    switch (p.kind) {
      case Probe::Kind::bar_contact_force: return coupled_top_force(m, s, p.particle);
      case Probe::Kind::bar_displacement: return bar_displacement(m.bar, s.bar, p.bar_at);
      case Probe::Kind::bar_velocity: return bar_velocity(m.bar, s.bar, p.bar_at);
      case Probe::Kind::interface_gap: return bar_interface_gap(m.bar, s.bar);
      default: break;
    }
    if (is_energy(p.kind)) return energy_part(energy(), p.kind);
    return particle_probe(m.dem, s.dem, p);  // plate probes are rejected at load for bar scenes
  }

 private:
  /// The energies of the row's state, computed once for the row's energy probes.
  const CoupledEnergy& energy() const {
    if (energy_step_ != world_.state.step) {
      energy_ = coupled_energy(world_.model, world_.state);
      energy_step_ = world_.state.step;
    }
    return energy_;
  }

  CoupledWorld world_;
  mutable CoupledEnergy energy_{};
  mutable std::int64_t energy_step_ = -1;
};

/// Particles and a plate together (scenes-2d.md, "Particles against the
/// continuum"), stepped with their energy check (scene/coupled2d_run.hpp).
class Coupled2dSystem {
 public:
  Coupled2dSystem(const Scene& scene, ParallelFor parallel) : run_(scene, parallel) {
    positions_.assign(2 * run_.world().model.boundary.vertices.size(), 0.0);
  }
  StepStatus step() { return run_.step(); }
  void time_stages(bool on) { run_.workspace().dem.clock_ns = on ? &platform::monotonic_ns : nullptr; }
  std::string stages() const {
    const Coupled2dState& s = run_.world().state;
    char text[200];
    std::snprintf(text, sizeof(text), "exchange passes per step: last %d, peak %d; windows taken at a jump %" PRId64
                  " (worst residual %.2g); ", s.last_passes, s.peak_passes, s.unsettled_windows, s.worst_unsettled);
    return text + dem_stages(run_.world().model.dem, s.dem, run_.world().workspace.dem.profile);
  }
  void write_vtk(VtkSeries& vtk) const {
    vtk.plate(run_.world().model.plate, run_.world().state.plate);
    vtk.particles(run_.world().model.dem, run_.world().state.dem);
  }
  double probe(const Probe& p) const {
    const Coupled2dModel& m = run_.world().model;
    const Coupled2dState& s = run_.world().state;
    switch (p.kind) {
      case Probe::Kind::plate_contact_force: return boundary_force(p.particle, false);
      case Probe::Kind::plate_tangential_contact_force: return boundary_force(p.particle, true);
      case Probe::Kind::momentum_total:
        return plate_momentum(m.plate, s.plate, p.component) + dem_momentum(m.dem, s.dem, p.component);
      default: break;
    }
    if (is_energy(p.kind)) return energy_part(run_.energy(), p.kind);
    const double value = particle_probe(m.dem, s.dem, p);
    return std::isnan(value) ? plate_probe(m.plate, s.plate, p) : value;
  }

 private:
  /// The features of the plate's boundary within `reach` of disk i's centre
  /// where both are now (nearest first); the boundary's place is computed
  /// once per row.
  int contacts(std::int32_t i, double reach, PlateBoundaryContact out[kPlateBoundaryMaxContacts]) const {
    const Coupled2dModel& m = run_.world().model;
    const Coupled2dState& s = run_.world().state;
    if (positions_step_ != s.step) {
      plate_boundary_positions(m.plate, m.boundary, s.plate.u.data(), s.plate.time, positions_.data());
      positions_step_ = s.step;
    }
    const auto iu = static_cast<std::size_t>(i);
    const double centre[2] = {s.dem.x[0][iu], s.dem.x[1][iu]};
    return plate_boundary_contacts(m.boundary, positions_.data(), centre, reach, out);
  }

  /// The force the boundary's contacts held on disk i over the last substep
  /// (coupled2d_boundary_force), split along the normal n (from the plate to
  /// the disk's centre) of the boundary's feature nearest to the centre now:
  /// normal F·n, compressive positive; tangential the force on the plate along
  /// t = (−n_y, n_x) of the normal from the disk to the plate, as for a plane.
  /// The nearest feature is looked for up to half the boundary's allowance
  /// beyond the radius, so that a disk that has just left the plate (a held
  /// force, pulling at the end of a linear contact, and no overlap now) keeps
  /// its sign; a disk farther away held no force.
  double boundary_force(std::int32_t i, bool tangential) const {
    double f[2];
    const Coupled2dModel& m = run_.world().model;
    coupled2d_boundary_force(m, run_.world().state, i, f);
    if (f[0] == 0.0 && f[1] == 0.0) return 0.0;
    PlateBoundaryContact c[kPlateBoundaryMaxContacts];
    if (contacts(i, m.dem.radius[static_cast<std::size_t>(i)] + 0.5 * m.boundary.allowance, c) == 0) return NAN;
    const double* n = c[0].normal;
    return tangential ? f[1] * n[0] - f[0] * n[1] : f[0] * n[0] + f[1] * n[1];
  }

  Coupled2dRun run_;
  mutable std::vector<double> positions_;
  mutable std::int64_t positions_step_ = -1;
};

/// Every kStageSample-th step is timed stage by stage (RunSummary::stages).
constexpr std::int64_t kStageSample = 64;

template <class System>
RunSummary run_system(const Scene& scene, System& system, std::ostream& csv, VtkSeries* vtk) {
  csv << "t";
  for (const auto& p : scene.probes) csv << ',' << p.name;
  csv << '\n';
  // A row is put together in `line` and written at once (a stream's operator<<
  // per separator costs more than the number's text).
  std::string line;
  line.reserve((scene.probes.size() + 1) * (kValueChars + 1));
  auto row = [&](std::int64_t step) {
    line.clear();
    append_value(line, static_cast<double>(step) * scene.dt);
    for (const auto& p : scene.probes) {
      line.push_back(',');
      append_value(line, system.probe(p));
    }
    line.push_back('\n');
    csv.write(line.data(), static_cast<std::streamsize>(line.size()));
  };
  std::int64_t rows = 0;
  const auto checked_row = [&](std::int64_t step) {
    row(step);
    if (!csv) throw OutputError(step, static_cast<double>(step) * scene.dt, rows);
    ++rows;
    if constexpr (requires { system.write_vtk(*vtk); })
      if (vtk != nullptr) {
        vtk->sample(static_cast<double>(step) * scene.dt);
        system.write_vtk(*vtk);
      }
  };
  checked_row(0);
  RunSummary summary;
  const std::int64_t start = platform::monotonic_ns();
  std::int64_t worst = 0;
  const StepStatus acknowledged = acknowledged_flags(scene);
  for (std::int64_t step = 1; step <= scene.steps; ++step) {
    // The stages are timed on a sample of the steps: a clock read costs tens
    // of ns, and a small scene's step reads it dozens of times.
    system.time_stages(step % kStageSample == 1);
    const std::int64_t t0 = platform::monotonic_ns();
    const StepStatus raw = system.step();
    worst = std::max(worst, platform::monotonic_ns() - t0);
    if (has(raw, StepStatus::unstable_time_step)) ++summary.unstable_steps;
    if (has(raw, StepStatus::energy_growth) && summary.first_energy_growth_step == 0)
      summary.first_energy_growth_step = step;
    const StepStatus status = without(raw, acknowledged | StepStatus::energy_growth);
    if (status != StepStatus::ok) {
      char text[200];
      char message[400];
      std::snprintf(message, sizeof(message), "step %" PRId64 " (t = %.17g s) returned %s", step,
                    static_cast<double>(step) * scene.dt, describe(status, text, sizeof(text)));
      throw SceneError(message);
    }
    if (step % scene.output_stride == 0) checked_row(step);
  }
  summary.steps = scene.steps;
  summary.wall_seconds = static_cast<double>(platform::monotonic_ns() - start) * 1e-9;
  summary.mean_step_seconds = scene.steps > 0 ? summary.wall_seconds / static_cast<double>(scene.steps) : 0.0;
  summary.worst_step_seconds = static_cast<double>(worst) * 1e-9;
  summary.stages = system.stages();
  return summary;
}

/// A system built from the scene. The kernel reports its own arrays' failures
/// by key; an allocation refused around them (copying the descriptions) is
/// reported here.
template <class System, class... Args>
std::unique_ptr<System> build_system(Args&&... args) {
  try {
    return std::make_unique<System>(std::forward<Args>(args)...);
  } catch (const std::bad_alloc&) {
    throw SceneError("out of memory while building the scene's model");
  }
}

template <int D>
RunSummary run_dem(const Scene& scene, const DemDesc<D>& desc, std::ostream& csv, ParallelFor parallel,
                   VtkSeries* vtk) {
  const auto system = build_system<DemSystem<D>>(scene, desc, parallel);
  return run_system(scene, *system, csv, vtk);
}

std::string output_error_text(std::int64_t step, double time, std::int64_t rows) {
  char text[200];
  std::snprintf(text, sizeof(text), "the CSV output failed at step %" PRId64 " (t = %.17g s), after %" PRId64 " rows",
                step, time, rows);
  return text;
}

}  // namespace

OutputError::OutputError(std::int64_t step_, double time_, std::int64_t rows_)
    : SceneError(output_error_text(step_, time_, rows_)), step(step_), rows(rows_), time(time_) {}

RunSummary run_scene(const Scene& scene, std::ostream& csv, int threads, VtkSeries* vtk) {
  if (threads < 1 || threads > 2) throw SceneError("--threads: must be 1 or 2");
  if (vtk != nullptr) require_vtk_output(scene);
  // Two workers run the parts a large model splits its work into; the results
  // do not depend on it (docs/determinism.md). Scenes too small to be split
  // (and the coupled cases) run on one worker either way.
  std::optional<platform::TwoWorkerPool> pool;
  if (threads == 2) pool.emplace();
  const ParallelFor parallel = pool ? pool->parallel_for() : ParallelFor{};
  if (scene.bar && !std::holds_alternative<std::monostate>(scene.dem)) {
    const auto system = build_system<CoupledSystem>(scene);
    return run_system(scene, *system, csv, nullptr);
  }
  if (scene.plate && !std::holds_alternative<std::monostate>(scene.dem)) {
    const auto system = build_system<Coupled2dSystem>(scene, parallel);
    return run_system(scene, *system, csv, vtk);
  }
  if (const auto* d1 = std::get_if<DemDesc<1>>(&scene.dem)) return run_dem<1>(scene, *d1, csv, parallel, vtk);
  if (const auto* d2 = std::get_if<DemDesc<2>>(&scene.dem)) return run_dem<2>(scene, *d2, csv, parallel, vtk);
  if (const auto* d3 = std::get_if<DemDesc<3>>(&scene.dem)) return run_dem<3>(scene, *d3, csv, parallel, vtk);
  if (scene.bar) {
    const auto system = build_system<BarSystem>(scene, *scene.bar);
    return run_system(scene, *system, csv, nullptr);
  }
  if (scene.plate) {
    PlateSystem system(scene, *scene.plate);
    return run_system(scene, system, csv, vtk);
  }
  throw SceneError("scene: nothing to run");
}

}  // namespace xfdem::scene
