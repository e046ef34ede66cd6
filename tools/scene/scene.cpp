#include "scene/scene.hpp"

#include "scene/continuum_json.hpp"
#include "scene/plate_json.hpp"
#include "xfdem/platform/memory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

namespace xfdem::scene {
namespace {

/// n = a / b when a is (to round-off) an integer multiple of b, else -1;
/// INT64_MAX when the multiple is too large to count (the callers reject it).
std::int64_t whole_multiple(double a, double b) {
  const double q = a / b;
  const double k = std::nearbyint(q);
  if (!(k >= 0) || std::fabs(q - k) > 1e-9 * std::max(1.0, k)) return -1;
  if (k >= 9.0e18) return std::numeric_limits<std::int64_t>::max();  // no int64 cast out of range
  return static_cast<std::int64_t>(k);
}

template <int D>
std::array<double, D> to_array(const std::vector<double>& v) {
  std::array<double, D> a{};
  for (int d = 0; d < D; ++d) a[d] = v[static_cast<std::size_t>(d)];
  return a;
}

/// A capacity the model would not use is refused, as any key with no effect
/// is: the scene says something that does not happen.
template <int D>
void refuse_unused_capacities(const ObjectReader& caps, const DemDesc<D>& desc, const std::string& integrator) {
  const auto n = static_cast<long long>(desc.particles.size());
  const BroadPhase broad_phase = dem_broad_phase(n, desc.all_pairs_up_to);
  if (broad_phase != BroadPhase::grid) {
    std::string why;
    if (broad_phase == BroadPhase::none) {
      why = "not used: " + std::to_string(n) + (n == 1 ? " particle has" : " particles have") + " no pairs to list";
    } else {
      why = "not used: " + std::to_string(n) + " particles, at most dem.all_pairs_up_to = " +
            std::to_string(desc.all_pairs_up_to) +
            ", are paired all with all in a fixed list; it bounds the grid that more particles use";
    }
    for (const char* key : {"max_pairs", "max_neighbors_per_particle", "max_grid_cells"})
      if (caps.has(key)) caps.fail(key, why);
  }
  if (desc.integrator != DemIntegrator::abm4_events && caps.has("max_events_per_step"))
    caps.fail("max_events_per_step", "not used: only dem.integrator abm4_events locates contact events (this scene's is " +
                                         integrator + ")");
}

template <int D>
DemDesc<D> parse_dem(ObjectReader& dem, const Scene& scene, std::vector<std::string>& names,
                     std::vector<std::string>& plane_names, std::vector<std::string>& warnings) {
  DemDesc<D> desc;
  desc.dt = scene.dt / scene.dem_substeps;
  desc.gravity = to_array<D>(scene.gravity);
  const std::string integrator =
      dem.choice_or("integrator", "abm4", {"abm4", "abm4_events", "verlet", "rk4", "symplectic_euler"});
  if (integrator == "abm4") desc.integrator = DemIntegrator::abm4;
  if (integrator == "abm4_events") desc.integrator = DemIntegrator::abm4_events;
  if (integrator == "verlet") desc.integrator = DemIntegrator::verlet;
  if (integrator == "rk4") desc.integrator = DemIntegrator::rk4;
  if (integrator == "symplectic_euler") desc.integrator = DemIntegrator::symplectic_euler;
  if (dem.has("contact")) {
    ObjectReader contact = dem.object("contact");
    const std::string law = contact.choice_or("law", "linear", {"linear", "linear_nontensile", "hertz"});
    desc.law = law == "linear" ? ContactLaw::linear : law == "hertz" ? ContactLaw::hertz : ContactLaw::linear_nontensile;
    // Each law's own keys; the other's are refused (a key without effect).
    const char* linear_only[] = {"damping_ratio", "tangential_stiffness_ratio"};
    for (const char* key : linear_only)
      if (desc.law == ContactLaw::hertz && contact.has(key))
        contact.fail(key, "used by the linear laws only (hertz is damped by 'restitution', its tangential stiffness is "
                          "Mindlin's)");
    if (desc.law != ContactLaw::hertz && contact.has("restitution"))
      contact.fail("restitution", "used by the hertz law only (the linear laws take 'damping_ratio')");
    desc.damping_ratio = contact.real_or("damping_ratio", 0.0, Range{0.0, 1.0, false, true});
    desc.restitution = contact.real_or("restitution", 1.0, Range{0.0, 1.0, true, false});
    desc.friction = contact.real_or("friction", 0.0, kNonNegative);
    desc.tangential_stiffness_ratio = contact.real_or("tangential_stiffness_ratio", 0.0, kPositive);
    desc.rolling_friction = contact.real_or("rolling_friction", 0.0, kNonNegative);
    // Accepted (a sweep of μ down to 0 keeps its other keys), but said.
    if (contact.has("tangential_stiffness_ratio") && desc.friction == 0)
      warnings.push_back(contact.key_path("tangential_stiffness_ratio") +
                         ": has no effect: friction is 0, so the contacts carry no tangential spring");
    contact.finish();
  }
  desc.skin = dem.real_or("skin", 0.0, kNonNegative);
  desc.all_pairs_up_to = static_cast<std::int32_t>(dem.integer_or("all_pairs_up_to", 8, 0, 1 << 16));
  desc.reject_unstable_dt = !dem.boolean_or("allow_unstable_dt", false);
  // What the arrays may take: refused at build, naming the key, before anything is allocated.
  desc.max_memory_bytes = platform::physical_memory_bytes();
  std::optional<ObjectReader> caps;
  if (dem.has("capacities")) {
    caps.emplace(dem.object("capacities"));
    // The type's range (the kernel counts in 32-bit integers); what fits in
    // memory is the build's to say.
    constexpr long long kMax = 2'000'000'000;
    desc.capacities.max_pairs = static_cast<std::int32_t>(caps->integer_or("max_pairs", 0, 0, kMax));
    desc.capacities.max_neighbors_per_particle =
        static_cast<std::int32_t>(caps->integer_or("max_neighbors_per_particle", 0, 0, 1 << 20));
    desc.capacities.max_grid_cells = static_cast<std::int32_t>(caps->integer_or("max_grid_cells", 0, 0, kMax));
    desc.capacities.max_events_per_step = static_cast<std::int32_t>(caps->integer_or("max_events_per_step", 0, 0, 1 << 20));
    caps->finish();
  }
  std::map<std::string, std::string> seen;  // name -> path
  std::vector<std::string> inertia_keys;   // particles given an inertia (said below when nothing turns)
  for (const auto& [value, path] : dem.array("particles")) {
    ObjectReader p(*value, path);
    ParticleDesc<D> particle;
    const std::string name = p.has("name") ? p.text("name") : "p" + std::to_string(names.size() + 1);
    if (name.empty() || name == "bar" || name == "plate") p.fail("name", "'" + name + "' is reserved or empty");
    if (seen.count(name)) p.fail("name", "'" + name + "' is also the name of " + seen[name]);
    seen[name] = path;
    particle.mass = p.real("mass", kPositive);
    particle.radius = p.real("radius", kPositive);
    if (desc.law == ContactLaw::hertz) {
      if (p.has("stiffness")) p.fail("stiffness", "used by the linear laws only (hertz takes youngs_modulus and poisson_ratio)");
      particle.youngs_modulus = p.real_or("youngs_modulus", NAN);
      particle.poisson_ratio = p.real_or("poisson_ratio", NAN);
    } else {
      for (const char* key : {"youngs_modulus", "poisson_ratio"})
        if (p.has(key)) p.fail(key, "used by the hertz law only (dem.contact.law)");
      particle.stiffness = p.real("stiffness", kPositive);
    }
    particle.position = to_array<D>(p.vector("position", D));
    particle.velocity = p.has("velocity") ? to_array<D>(p.vector("velocity", D)) : std::array<double, D>{};
    if (p.has("angular_velocity")) {
      if constexpr (D == 1) p.fail("angular_velocity", "rods on a line do not rotate (2D and 3D scenes only)");
      else if constexpr (D == 2) particle.angular_velocity[0] = p.real("angular_velocity");
      else particle.angular_velocity = to_array<3>(p.vector("angular_velocity", 3));
    }
    particle.inertia = p.real_or("inertia", 0.0, kPositive);
    if (p.has("inertia")) inertia_keys.push_back(p.key_path("inertia"));
    p.finish();
    names.push_back(name);
    desc.particles.push_back(particle);
  }
  if (dem.has("planes")) {
    for (const auto& [value, path] : dem.array("planes")) {
      ObjectReader p(*value, path);
      PlaneDesc<D> plane;
      const std::string name = p.has("name") ? p.text("name") : "plane" + std::to_string(plane_names.size());
      if (name == "bar" || name == "plate") p.fail("name", "'" + name + "' is reserved (it names the continuum)");
      if (seen.count(name)) p.fail("name", "'" + name + "' is also the name of " + seen[name]);
      seen[name] = path;
      plane.point = to_array<D>(p.vector("point", D));
      const auto normal = p.vector("normal", D);
      double len2 = 0;
      for (double c : normal) len2 += c * c;
      if (!(len2 > 0)) p.fail("normal", "must not be the zero vector");
      plane.normal = to_array<D>(normal);
      for (const char* key : {"youngs_modulus", "poisson_ratio"})
        if (desc.law != ContactLaw::hertz && p.has(key)) p.fail(key, "used by the hertz law only (dem.contact.law)");
      plane.youngs_modulus = p.real_or("youngs_modulus", NAN);
      plane.poisson_ratio = p.real_or("poisson_ratio", NAN);
      p.finish();
      plane_names.push_back(name);
      desc.planes.push_back(plane);
    }
  }
  // abm4_events with rotation (friction, rolling friction, hertz, a spin) takes a
  // fixed all-pairs list (the kernel refuses the grid: docs/dem.md); without
  // the key, a scene of up to kEventsAllPairsUpTo particles pairs them all
  // rather than being refused (O(N²) pairs: beyond that, the kernel's message
  // says what to change).
  constexpr std::int32_t kEventsAllPairsUpTo = 512;
  // The kernel's rule (DemFeatures::rotation): the law turns the particles, or one is given a spin.
  bool spin = false;
  for (const auto& p : desc.particles)
    for (double w : p.angular_velocity) spin = spin || w != 0.0;
  const bool rotates = D > 1 && (desc.friction > 0 || desc.rolling_friction > 0 || desc.law == ContactLaw::hertz || spin);
  if (!rotates)
    for (const std::string& key : inertia_keys)
      warnings.push_back(key + ": has no effect: " +
                         (D == 1 ? std::string("rods on a line do not rotate")
                                 : std::string("the particles do not rotate (no friction, rolling_friction, hertz law "
                                               "or angular_velocity)")));
  if (!dem.has("all_pairs_up_to") && desc.integrator == DemIntegrator::abm4_events && rotates)
    desc.all_pairs_up_to = std::max(desc.all_pairs_up_to,
                                    static_cast<std::int32_t>(std::min<std::size_t>(desc.particles.size(), kEventsAllPairsUpTo)));
  if (caps) refuse_unused_capacities(*caps, desc, integrator);
  return desc;
}

/// In a scene with particles and a plate, whether a probe is read as a
/// particle probe (position, contact_force, angular_velocity, rotation,
/// energy, a named particle's velocity) rather than by parse_plate_probe.
bool is_particle_probe(ObjectReader& p, const Scene& scene) {
  if (std::holds_alternative<std::monostate>(scene.dem) || !p.has("quantity") || !p.raw("quantity").is_string())
    return false;
  const std::string quantity = p.raw("quantity").get<std::string>();
  return quantity == "position" || quantity == "contact_force" || quantity == "angular_velocity" ||
         quantity == "rotation" || quantity == "energy" || (quantity == "velocity" && p.has("particle"));
}

}  // namespace

void apply_override(Json& document, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--set '" + assignment + "': expected KEY.PATH=VALUE");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  Json value;
  try {
    value = parse_json(text, path, /*ignore_comments=*/false);  // a key given twice in an object value is refused
  } catch (const Json::parse_error&) {
    value = text;  // a bare word such as rk4
  } catch (const Json::exception&) {
    throw SceneError("scene key '" + path + "': value '" + text + "' is not a finite number");
  }
  Json* node = &document;
  std::stringstream parts(path);
  std::string part, walked;
  std::vector<std::string> keys;
  while (std::getline(parts, part, '.')) keys.push_back(part);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::string& key = keys[k];
    const bool last = k + 1 == keys.size();
    walked = join_path(walked, key);
    if (key.empty()) throw SceneError("--set '" + path + "': empty path component");
    if (node->is_array()) {
      std::size_t index = 0;
      try {
        std::size_t used = 0;
        index = std::stoul(key, &used);
        if (used != key.size()) throw std::invalid_argument(key);
      } catch (const std::exception&) {
        throw SceneError("--set '" + path + "': '" + walked + "' indexes an array and must be a number");
      }
      if (index >= node->size())
        throw SceneError("--set '" + path + "': '" + walked + "' is past the end of the array (size " +
                         std::to_string(node->size()) + ")");
      node = &(*node)[index];
    } else if (node->is_object()) {
      if (!last && !node->contains(key)) (*node)[key] = Json::object();
      node = &(*node)[key];
    } else {
      throw SceneError("--set '" + path + "': '" + walked + "' is inside a value that is not an object or array");
    }
  }
  *node = value;
}

Probe::Kind energy_probe_kind(ObjectReader& p) {
  const std::string of = p.choice("of", {"total", "kinetic", "elastic", "potential"});
  return of == "total"     ? Probe::Kind::energy_total
         : of == "kinetic" ? Probe::Kind::energy_kinetic
         : of == "elastic" ? Probe::Kind::energy_elastic
                           : Probe::Kind::energy_potential;
}

Scene parse_scene(const Json& document) {
  Scene scene;
  ObjectReader top(document, "");
  scene.name = top.has("name") ? top.text("name") : "scene";
  scene.dimension = static_cast<int>(top.integer("dimension", 1, 3));
  scene.gravity = top.has("gravity") ? top.vector("gravity", static_cast<std::size_t>(scene.dimension))
                                     : std::vector<double>(static_cast<std::size_t>(scene.dimension), 0.0);
  // A static plate needs no time: one row at t = 0 (steps stays 0).
  const bool static_plate = is_static_plate(document);
  if (!static_plate || top.has("time")) {
    ObjectReader time = top.object("time");
    scene.end = time.real("end", kPositive);
    scene.dt = time.real("dt", kPositive);
    scene.dem_substeps = static_cast<int>(time.integer_or("dem_substeps", 1, 1, 1'000'000));
    time.finish();
    scene.steps = whole_multiple(scene.end, scene.dt);
    if (scene.steps < 1) time.fail("end", "must be a whole multiple of time.dt");
    if (scene.steps > 4'000'000'000LL) time.fail("end", "needs more than 4e9 steps");
  }
  if (static_plate) scene.steps = 0;
  if (top.has("energy_check")) {
    ObjectReader check = top.object("energy_check");
    scene.energy_check.interval =
        static_cast<int>(check.integer_or("interval", scene.energy_check.interval, 0, 1'000'000'000));
    scene.energy_check.tolerance = check.real_or("tolerance", scene.energy_check.tolerance, kPositive);
    check.finish();
  }
  scene.has_continuum = top.has("continuum");
  const bool plate = scene.has_continuum && document.at("continuum").is_object() &&
                     document.at("continuum").contains("type") && document.at("continuum").at("type") == "plate";
  if (plate) {
    if (scene.dimension != 2) throw SceneError("scene key 'dimension': a plate scene must have dimension 2");
    if (top.has("dem") && static_plate)
      throw SceneError("scene key 'continuum.analysis': particles against the plate need \"dynamic\" (got \"static\")");
    ObjectReader continuum = top.object("continuum");
    scene.plate = parse_plate(continuum, scene.dt, scene.gravity);
    scene.plate->energy_check = scene.energy_check;
  } else if (scene.has_continuum) {
    if (scene.dimension != 1)
      throw SceneError("scene key 'dimension': a continuum (bar) scene must have dimension 1");
    ObjectReader continuum = top.object("continuum");
    scene.bar = parse_continuum(continuum, scene.dt);
    scene.bar->energy_check = scene.energy_check;
  } else if (scene.dem_substeps != 1) {
    throw SceneError("scene key 'time.dem_substeps': must be 1 (or absent) in a scene without a continuum");
  }
  if (scene.dimension == 3 && scene.has_continuum)
    throw SceneError("scene key 'dimension': 3 is for DEM-only scenes");

  std::vector<std::string>& plane_names = scene.plane_names;
  if (top.has("dem")) {
    ObjectReader dem = top.object("dem");
    switch (scene.dimension) {
      case 1: scene.dem = parse_dem<1>(dem, scene, scene.particle_names, plane_names, scene.warnings); break;
      case 2: scene.dem = parse_dem<2>(dem, scene, scene.particle_names, plane_names, scene.warnings); break;
      default: scene.dem = parse_dem<3>(dem, scene, scene.particle_names, plane_names, scene.warnings); break;
    }
    dem.finish();
    std::visit(
        [&](auto& desc) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(desc)>, std::monostate>) desc.energy_check = scene.energy_check;
        },
        scene.dem);
  }

  auto particle_index = [&](const std::string& name) {
    for (std::size_t i = 0; i < scene.particle_names.size(); ++i)
      if (scene.particle_names[i] == name) return static_cast<int>(i);
    return -1;
  };
  auto plane_index = [&](const std::string& name) {
    for (std::size_t i = 0; i < plane_names.size(); ++i)
      if (plane_names[i] == name) return static_cast<int>(i);
    return -1;
  };

  ObjectReader output = top.object("output");
  if (static_plate) {
    if (output.has("every")) output.real("every", kPositive);  // one row at t = 0 either way
  } else {
    const double every = output.real("every", kPositive);
    scene.output_stride = whole_multiple(every, scene.dt);
    if (scene.output_stride < 1) output.fail("every", "must be a whole multiple of time.dt");
  }
  std::map<std::string, std::string> probe_names;
  for (const auto& [value, path] : output.array("probes")) {
    ObjectReader p(*value, path);
    Probe probe;
    probe.name = p.text("name");
    if (probe.name.empty() || probe.name == "t" || probe.name.find_first_of(",\"\n") != std::string::npos)
      p.fail("name", "'" + probe.name + "' cannot be a CSV column name");
    if (probe_names.count(probe.name)) p.fail("name", "'" + probe.name + "' is also the name of " + probe_names[probe.name]);
    probe_names[probe.name] = path;
    if (scene.plate && !is_particle_probe(p, scene)) {
      parse_plate_probe(p, *scene.plate, probe);
      p.finish();
      scene.probes.push_back(probe);
      continue;
    }
    const std::string quantity = p.choice("quantity", {"position", "velocity", "displacement", "contact_force",
                                                       "interface_gap", "energy", "angular_velocity", "rotation",
                                                       "momentum"});
    if (quantity == "momentum") {
      // scenes-2d.md: Σ m v of the particles (the plate's own is in plate_json.cpp)
      if (scene.has_continuum) p.fail("quantity", "'momentum': for particles alone or a plate, not the bar");
      if (p.choice("of", {"total", "continuum", "particles"}) == "continuum")
        p.fail("of", "'continuum': the scene has no continuum");
      probe.kind = Probe::Kind::momentum_particles;
      probe.component = static_cast<int>(p.integer("component", 0, scene.dimension - 1));
    } else if (quantity == "angular_velocity" || quantity == "rotation") {
      if (scene.dimension == 1) p.fail("quantity", "'" + quantity + "': rods on a line do not rotate");
      if (quantity == "rotation" && scene.dimension != 2) p.fail("quantity", "'rotation' (the angle turned) is 2D only");
      const std::string name = p.text("particle");
      probe.particle = particle_index(name);
      if (probe.particle < 0) p.fail("particle", "'" + name + "' is not a particle of this scene");
      if (quantity == "rotation") {
        probe.kind = Probe::Kind::particle_rotation;
      } else {
        probe.kind = Probe::Kind::particle_angular_velocity;
        if (scene.dimension == 3) probe.component = static_cast<int>(p.integer("component", 0, 2));
      }
    } else if (quantity == "energy") {
      probe.kind = energy_probe_kind(p);
    } else if (quantity == "contact_force") {
      const Json& between = p.raw("between");
      if (!between.is_array() || between.size() != 2 || !between[0].is_string() || !between[1].is_string())
        p.fail("between", "expected two names, e.g. [\"p1\", \"p2\"] or [\"p1\", \"bar\"]");
      const std::string a = between[0].get<std::string>(), b = between[1].get<std::string>();
      const int ia = particle_index(a), ib = particle_index(b);
      if (ia < 0 && ib < 0) p.fail("between", "neither '" + a + "' nor '" + b + "' is a particle");
      const int pi = ia >= 0 ? ia : ib;
      const std::string other = ia >= 0 ? b : a;
      probe.particle = pi;
      if (other == "bar") {
        if (!scene.bar) p.fail("between", "'bar' named but the scene has no bar");
        probe.kind = Probe::Kind::bar_contact_force;
      } else if (other == "plate") {
        if (!scene.plate) p.fail("between", "'plate' named but the scene has no plate");
        probe.kind = Probe::Kind::plate_contact_force;
      } else if (particle_index(other) >= 0) {
        if (particle_index(other) == pi) p.fail("between", "a particle cannot touch itself");
        probe.kind = Probe::Kind::pair_force;
        probe.other = particle_index(other);
      } else if (plane_index(other) >= 0) {
        probe.kind = Probe::Kind::plane_force;
        probe.other = plane_index(other);
      } else {
        p.fail("between", "'" + other + "' is not a particle, a plane or '" + (scene.plate ? "plate" : "bar") + "'");
      }
      if (p.choice_or("part", "normal", {"normal", "tangential"}) == "tangential") {
        if (scene.dimension == 1) p.fail("part", "'tangential': rods on a line have no tangential contact force");
        if (probe.kind == Probe::Kind::bar_contact_force) p.fail("part", "'tangential': the bar's contact is normal only");
        // The named order fixes the sign of the 2D tangent (scenes-2d.md).
        if (probe.kind == Probe::Kind::pair_force) {
          probe.kind = Probe::Kind::pair_tangential_force;
          probe.particle = ia;
          probe.other = ib;
        } else if (probe.kind == Probe::Kind::plate_contact_force) {
          probe.kind = Probe::Kind::plate_tangential_contact_force;
        } else {
          probe.kind = Probe::Kind::plane_tangential_force;
        }
      }
    } else if (quantity == "interface_gap") {
      if (!scene.has_continuum) p.fail("quantity", "interface_gap needs a continuum");
      probe.kind = Probe::Kind::interface_gap;
    } else if (p.has("particle")) {
      if (quantity == "displacement") p.fail("quantity", "particles have position and velocity, not displacement");
      const std::string name = p.text("particle");
      probe.particle = particle_index(name);
      if (probe.particle < 0) p.fail("particle", "'" + name + "' is not a particle of this scene");
      probe.kind = quantity == "position" ? Probe::Kind::particle_position : Probe::Kind::particle_velocity;
      probe.component = static_cast<int>(p.integer_or("component", 0, 0, scene.dimension - 1));
    } else if (p.has("bar_at")) {
      if (!scene.bar) p.fail("bar_at", "the scene has no bar");
      if (quantity == "position") p.fail("quantity", "the bar has displacement and velocity, not position");
      probe.bar_at = p.real("bar_at", Range{0.0, scene.bar->length, false, false});
      probe.kind = quantity == "velocity" ? Probe::Kind::bar_velocity : Probe::Kind::bar_displacement;
    } else {
      p.fail("quantity", "'" + quantity + "' needs \"particle\"" + (scene.plate ? "" : " or \"bar_at\""));
    }
    p.finish();
    scene.probes.push_back(probe);
  }
  output.finish();
  top.finish();
  if (std::holds_alternative<std::monostate>(scene.dem) && !scene.has_continuum)
    throw SceneError("scene: has neither a 'dem' nor a 'continuum' block; nothing to simulate");
  return scene;
}

Coupled2dDesc coupled2d_desc(const Scene& scene) {
  Coupled2dDesc desc;
  desc.dem = std::get<DemDesc<2>>(scene.dem);
  desc.plate = *scene.plate;
  desc.dem_substeps = scene.dem_substeps;
  desc.reject_unstable_coupling = desc.dem.reject_unstable_dt;
  desc.energy_check = scene.energy_check;
  return desc;
}

CoupledDesc coupled_desc(const Scene& scene) {
  CoupledDesc desc;
  desc.dem = std::get<DemDesc<1>>(scene.dem);
  desc.bar = *scene.bar;
  desc.dem_substeps = scene.dem_substeps;
  desc.reject_unstable_coupling = desc.dem.reject_unstable_dt;
  desc.energy_check = scene.energy_check;
  desc.max_memory_bytes = platform::physical_memory_bytes();
  return desc;
}

namespace {

/// "particles[12]" at `at` in `text`: the index, and where the token ends; -1 if none.
long long index_token(const std::string& text, std::size_t at, const std::string& word, std::size_t& end) {
  if (text.compare(at, word.size() + 1, word + "[") != 0) return -1;
  std::size_t k = at + word.size() + 1;
  long long index = 0;
  const std::size_t digits = k;
  while (k < text.size() && text[k] >= '0' && text[k] <= '9' && k - digits < 12) index = index * 10 + (text[k++] - '0');
  if (k == digits || k >= text.size() || text[k] != ']') return -1;
  end = k + 1;
  return index;
}

/// The kernel's "particles[3]" and "planes[0]" as the scene names them:
/// `dotted` gives the key form ("particles.3"), otherwise the names
/// ("particle 'p4'", "plane 'floor'").
std::string name_indices(const std::string& text, const Scene& scene, bool dotted) {
  std::string out;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = 0;
    bool named = false;
    for (const auto& [word, one, names] :
         {std::tuple<std::string, std::string, const std::vector<std::string>*>{"particles", "particle", &scene.particle_names},
          {"planes", "plane", &scene.plane_names}}) {
      const long long index = index_token(text, at, word, end);
      if (index < 0) continue;
      if (dotted)
        out += word + "." + std::to_string(index);
      else if (static_cast<std::size_t>(index) < names->size())
        out += one + " '" + (*names)[static_cast<std::size_t>(index)] + "'";
      else
        out += text.substr(at, end - at);
      at = end;
      named = true;
      break;
    }
    if (!named) out += text[at++];
  }
  return out;
}

}  // namespace

SceneError build_refusal(const Scene& scene, Built model, const BuildResult& built) {
  std::string message = built.message;
  std::string block = model == Built::dem ? "dem" : "continuum";
  bool substep = false;
  if (model == Built::coupled) {
    // "dem.…", "bar.…" and "continuum.…" (a plate) name the half; "time.dt: …" and "dem_substeps: …" the
    // coupling's own keys.
    if (message.rfind("dem.", 0) == 0) {
      block = "dem";
      substep = true;
      message = message.substr(4);
    } else if (message.rfind("bar.", 0) == 0) {
      message = message.substr(4);
    } else if (message.rfind("continuum.", 0) == 0) {
      message = message.substr(10);
    } else if (message.rfind("continuum: ", 0) == 0) {
      message = message.substr(11);  // the block itself
    } else {
      block = "time";
    }
  }
  const std::size_t colon = message.find(": ");
  std::string field = colon == std::string::npos ? std::string() : message.substr(0, colon);
  std::string reason = colon == std::string::npos ? message : message.substr(colon + 2);
  std::string key;
  if (field == "dt" || field.rfind("time.", 0) == 0) {
    key = field == "dt" ? "time.dt" : field;
    if (field == "dt" && substep)
      reason = "the particle substep time.dt / time.dem_substeps = " + reason + "; reduce time.dt or raise time.dem_substeps";
  } else if (block == "dem" && (field == "damping_ratio" || field == "friction" || field == "rolling_friction" ||
                                  field == "tangential_stiffness_ratio" || field == "restitution" || field == "law")) {
    key = "dem.contact." + field;
  } else if (block == "continuum" && (field == "beta" || field == "gamma")) {
    key = "continuum.newmark." + field;
  } else if (field == "dem_substeps") {
    key = "time.dem_substeps";
  } else if (field.empty()) {
    key = block;
  } else {
    key = block + "." + name_indices(field, scene, true);
  }
  // A refusal about one particle says which, by the name the scene gives it.
  std::size_t end = 0;
  const long long particle = block == "dem" ? index_token(field, 0, "particles", end) : -1;
  reason = name_indices(reason, scene, false);
  if (particle >= 0) reason = name_indices(field.substr(0, end), scene, false) + " " + reason;
  // The budget the scene loader gave the kernel is the machine's memory.
  const std::string budget = " (max_memory_bytes)";
  if (built.code == BuildResult::Code::memory && reason.size() >= budget.size() &&
      reason.compare(reason.size() - budget.size(), budget.size(), budget) == 0)
    reason = reason.substr(0, reason.size() - budget.size()) + " (this machine's physical memory)";
  return SceneError("scene key '" + key + "': " + reason);
}

StepStatus acknowledged_flags(const Scene& scene) {
  const bool allowed = std::visit(
      [](const auto& dem) {
        if constexpr (std::is_same_v<std::decay_t<decltype(dem)>, std::monostate>) {
          return false;
        } else {
          return !dem.reject_unstable_dt;
        }
      },
      scene.dem);
  return allowed ? StepStatus::unstable_time_step : StepStatus::ok;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError("cannot open scene file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  Json document;
  try {
    document = parse_json(text.str(), "", /*ignore_comments=*/true);
  } catch (const Json::exception& e) {
    throw SceneError("scene file '" + path + "' is not valid JSON: " + e.what());
  }
  // One value per key, as in the file: a key set twice is the same mistake as
  // a key written twice.
  std::set<std::string> overridden;
  for (const auto& o : overrides) {
    const std::string key = o.substr(0, o.find('='));
    if (!overridden.insert(key).second) throw SceneError("--set " + key + ": given twice");
    apply_override(document, o);
  }
  return parse_scene(document);
}

}  // namespace xfdem::scene
