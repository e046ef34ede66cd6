// A scene file (shared spec: scenes.md) turned into kernel descriptions.
// load_scene() validates everything before anything runs: a bad key or value is
// a SceneError naming it.
#pragma once
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "scene/json_reader.hpp"
#include "xfdem/bar.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/plate.hpp"

namespace xfdem::scene {

/// What a probe measures. Particle and contact probes refer to particles by
/// index once loaded.
struct Probe {
  enum class Kind {
    particle_position,
    particle_velocity,
    pair_force,
    plane_force,
    bar_contact_force,
    bar_displacement,
    bar_velocity,
    interface_gap,
    energy_total,
    energy_kinetic,
    energy_elastic,
    energy_potential,
    // The plate (scenes-2d.md): fields at `at`, stress component 0 xx, 1 yy, 2 xy.
    plate_displacement,
    plate_velocity,
    plate_acceleration,
    plate_stress,
    plate_crack_opening,  ///< other: the crack's index; component 0 normal, 1 tangential
    plate_stress_intensity,  ///< other: the crack's index, tip_end, radius; component 0 K_I, 1 K_II
    momentum_continuum,
    momentum_particles,
    momentum_total,
    // Rotating particles (scenes-2d.md, "Particles: rotation and friction").
    particle_angular_velocity,
    particle_rotation,
    pair_tangential_force,
    plane_tangential_force,
    // A disk against the plate (scenes-2d.md, "Particles against the continuum").
    plate_contact_force,
    plate_tangential_contact_force,
  };
  std::string name;
  Kind kind = Kind::energy_total;
  int particle = -1;   ///< particle index (position, velocity, contact forces)
  int other = -1;      ///< second particle or plane index
  int component = 0;   ///< axis for position and velocity (and the 3D angular velocity)
  double bar_at = 0;   ///< coordinate along the bar (m)
  double at[2] = {0, 0};  ///< point of the plate (m)
  bool tip_end = false;   ///< stress_intensity: the crack's last point (false: its first)
  double radius = 0;      ///< stress_intensity: the interaction integral's domain, m
};

struct Scene {
  std::string name;
  int dimension = 1;
  std::vector<double> gravity;  ///< one entry per axis
  double end = 0;               ///< s
  double dt = 0;                ///< s, continuum step (or particle step without continuum)
  int dem_substeps = 1;
  std::int64_t steps = 0;       ///< end / dt
  std::int64_t output_stride = 1;  ///< steps between CSV rows
  /// Particles and planes, for the scene's dimension (empty variant: no `dem`).
  std::variant<std::monostate, DemDesc<1>, DemDesc<2>, DemDesc<3>> dem;
  std::vector<std::string> particle_names;
  std::vector<std::string> plane_names;  ///< the scene's planes (a coupled model adds the bar's tip after them)
  bool has_continuum = false;
  /// The continuum (a bar: 1D only).
  std::optional<BarDesc> bar;
  /// The 2D continuum (dimension 2; alone, or with particles: coupled2d_desc()).
  std::optional<PlateDesc> plate;
  std::vector<Probe> probes;
  /// The steppers' energy balance check (key `energy_check`, optional).
  EnergyCheck energy_check;
  /// Keys accepted but without effect in this scene ("<key>: has no effect: <why>"):
  /// the CLI prints each as a warning on stderr.
  std::vector<std::string> warnings;
};

/// The coupled stepper's description of a scene with particles and a bar.
/// Its memory budget, as the particles' own (DemDesc::max_memory_bytes), is
/// this machine's physical memory.
CoupledDesc coupled_desc(const Scene& scene);

/// The coupled 2D stepper's description of a scene with particles and a plate.
Coupled2dDesc coupled2d_desc(const Scene& scene);

/// Which of a scene's models a build result came from.
enum class Built { dem, continuum, coupled };

/// A kernel build failure as the scene key the user wrote and the reason. The
/// kernel names its own description's fields ("dt: …", "particles[1].mass: …",
/// a coupled model "dem.…", "bar.…", "time.…") and refers to particles and
/// planes by index; here the key is the scene's ("dem.particles.1.mass",
/// "time.dt", "continuum.newmark.beta") and they are named as the scene names
/// them ("particle 'p2'", "plane 'floor'"). A coupled model's particles step
/// at time.dt / time.dem_substeps: a refused particle dt is that substep.
SceneError build_refusal(const Scene& scene, Built model, const BuildResult& built);

/// Step flags a run of this scene carries on past: unstable_time_step when the
/// scene asked for it (dem.allow_unstable_dt), nothing otherwise.
StepStatus acknowledged_flags(const Scene& scene);

/// Applies one `--set key.path=value` override to a parsed JSON document.
/// Array elements are addressed by index ("dem.particles.0.mass"); the value is
/// read as JSON when it parses as JSON (a key given twice in one of its
/// objects is refused, naming it), otherwise as a string.
void apply_override(Json& document, const std::string& assignment);

/// The kind of an `energy` probe from its "of" (total | kinetic | elastic |
/// potential): the bar's, the plate's and the particles' probes read it alike.
Probe::Kind energy_probe_kind(ObjectReader& p);

/// Reads, overrides and validates a scene file.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides);
/// Same, from an already parsed document.
Scene parse_scene(const Json& document);

}  // namespace xfdem::scene
