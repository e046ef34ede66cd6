#include "scene/plate_json.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace xfdem::scene {

namespace {

/// The stress_intensity probe's interaction-integral radius, in cells (the
/// larger side): q = 1 on the nodes within it (docs/xfem2d.md).
constexpr double kStressIntensityCells = 4;
constexpr double kStressIntensityMinCells = 1.5;
// q = 1 on nodes strictly nearer the tip than the boundary is.
constexpr double kStressIntensityShrink = 0.999;


PlateEdge read_edge(ObjectReader& r) {
  const std::string e = r.choice("edge", {"left", "right", "bottom", "top"});
  return e == "left" ? PlateEdge::left : e == "right" ? PlateEdge::right : e == "bottom" ? PlateEdge::bottom : PlateEdge::top;
}

void read_shape(ObjectReader& r, PlateLoad& load) {
  const std::string shape = r.choice("shape", {"none", "step", "half_sine"});
  load.shape = shape == "none" ? PlateLoadShape::none : shape == "step" ? PlateLoadShape::step : PlateLoadShape::half_sine;
  if (shape == "half_sine") {
    load.duration = r.real("duration", kPositive);
  } else if (r.has("duration")) {
    r.fail("duration", "not used by shape '" + shape + "'");
  }
}

/// Inside the domain (its edges included, as the kernel's 1e-9 of a cell).
bool inside(const PlateDesc& d, const std::vector<double>& at) {
  for (int c = 0; c < 2; ++c) {
    const double h = (d.max[c] - d.min[c]) / d.cells[c];
    if (!(at[static_cast<std::size_t>(c)] >= d.min[c] - 1e-9 * h && at[static_cast<std::size_t>(c)] <= d.max[c] + 1e-9 * h))
      return false;
  }
  return true;
}

std::vector<std::array<double, 2>> read_points(ObjectReader& r, const char* key, std::size_t at_least) {
  const Json& points = r.raw(key);
  if (!points.is_array() || points.size() < at_least)
    r.fail(key, "expected a list of at least " + std::to_string(at_least) + " points [x, y]");
  std::vector<std::array<double, 2>> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Json& p = points[i];
    if (!p.is_array() || p.size() != 2) r.fail(key, "point " + std::to_string(i) + " is not [x, y]");
    out.push_back({read_real(p[0], r.key_path(key) + "." + std::to_string(i)),
                   read_real(p[1], r.key_path(key) + "." + std::to_string(i))});
  }
  return out;
}

/// One entry of `discontinuities` (scenes-2d.md): crack | inclusion | void.
PlateDiscontinuity read_discontinuity(const Json& value, const std::string& path, const PlateDesc& d) {
  ObjectReader r(value, path);
  PlateDiscontinuity q;
  q.name = r.text("name");
  if (q.name.empty()) r.fail("name", "must not be empty");
  const std::string type = r.choice("type", {"crack", "inclusion", "void"});
  if (type == "crack") {
    q.kind = PlateDiscontinuity::Kind::crack;
    q.shape = PlateDiscontinuity::Shape::polyline;
    q.points = read_points(r, "points", 2);
    const std::string faces = r.choice_or("faces", "free", {"free", "tied", "unilateral"});
    q.faces = faces == "free"   ? PlateDiscontinuity::Faces::free
              : faces == "tied" ? PlateDiscontinuity::Faces::tied
                                : PlateDiscontinuity::Faces::unilateral;
    if (faces == "free") {
      if (r.has("stiffness")) r.fail("stiffness", "free faces have no penalty (faces tied or unilateral take one)");
    } else {
      const std::vector<double> k = r.vector("stiffness", 2, kPositive);
      q.stiffness[0] = k[0], q.stiffness[1] = k[1];
    }
  } else {
    q.kind = type == "inclusion" ? PlateDiscontinuity::Kind::inclusion : PlateDiscontinuity::Kind::hole;
    if (r.has("circle") == r.has("polygon")) r.fail("circle", "an " + type + " takes exactly one of circle and polygon");
    if (r.has("circle")) {
      q.shape = PlateDiscontinuity::Shape::circle;
      ObjectReader circle = r.object("circle");
      const std::vector<double> centre = circle.vector("centre", 2);
      q.centre[0] = centre[0], q.centre[1] = centre[1];
      q.radius = circle.real("radius", kPositive);
      circle.finish();
    } else {
      q.shape = PlateDiscontinuity::Shape::polygon;
      q.points = read_points(r, "polygon", 3);
    }
    if (type == "inclusion") {
      ObjectReader m = r.object("material");
      q.material.youngs_modulus = m.real("youngs_modulus", kPositive);
      q.material.poisson_ratio = m.real("poisson_ratio", Range{-1.0, 0.5, true, false});
      if (d.plane == PlateDesc::Plane::strain && q.material.poisson_ratio >= 0.5)
        m.fail("poisson_ratio", "must be < 0.5 in plane strain (got " + number(q.material.poisson_ratio) + ")");
      q.material.density = m.real("density", kPositive);
      m.finish();
    }
  }
  r.finish();
  return q;
}

}  // namespace

bool is_static_plate(const Json& document) {
  if (!document.is_object() || !document.contains("continuum")) return false;
  const Json& c = document["continuum"];
  return c.is_object() && c.contains("type") && c["type"] == "plate" && c.contains("analysis") &&
         c["analysis"] == "static";
}

PlateDesc parse_plate(ObjectReader& c, double dt, const std::vector<double>& gravity) {
  PlateDesc d;
  c.choice("type", {"plate"});
  if (c.has("tip_enrichment")) {
    ObjectReader tip = c.object("tip_enrichment");
    d.tip_radius = tip.real("radius", kNonNegative);
    tip.finish();
  }
  d.plane = c.choice_or("plane", "strain", {"strain", "stress"}) == "stress" ? PlateDesc::Plane::stress
                                                                            : PlateDesc::Plane::strain;
  d.thickness = c.real_or("thickness", 1.0, kPositive);
  {
    ObjectReader domain = c.object("domain");
    const std::vector<double> lo = domain.vector("min", 2), hi = domain.vector("max", 2);
    for (int k = 0; k < 2; ++k) {
      d.min[k] = lo[static_cast<std::size_t>(k)];
      d.max[k] = hi[static_cast<std::size_t>(k)];
      if (!(d.max[k] > d.min[k]))
        domain.fail("max", std::string("must exceed min in ") + (k == 0 ? "x" : "y") + " (got " + number(d.max[k]) +
                               " <= " + number(d.min[k]) + ")");
    }
    domain.finish();
  }
  {
    const Json& cells = c.raw("cells");
    if (!cells.is_array() || cells.size() != 2 || !cells[0].is_number_integer() || !cells[1].is_number_integer())
      c.fail("cells", "expected two whole numbers [nx, ny]");
    for (int k = 0; k < 2; ++k) {
      const long long n = cells[static_cast<std::size_t>(k)].get<long long>();
      if (n < 1 || n > 100'000) c.fail("cells", "each count must be in [1, 100000] (got " + std::to_string(n) + ")");
      d.cells[k] = static_cast<int>(n);
    }
  }
  {
    ObjectReader m = c.object("material");
    d.youngs_modulus = m.real("youngs_modulus", kPositive);
    d.poisson_ratio = m.real("poisson_ratio", Range{-1.0, 0.5, true, false});
    if (d.plane == PlateDesc::Plane::strain && d.poisson_ratio >= 0.5)
      m.fail("poisson_ratio", "must be < 0.5 in plane strain (got " + number(d.poisson_ratio) + ")");
    d.density = m.real("density", kPositive);
    m.finish();
  }
  d.self_weight = c.boolean_or("self_weight", false);
  if (d.self_weight)
    for (int k = 0; k < 2; ++k) d.gravity[k] = gravity[static_cast<std::size_t>(k)];
  d.analysis = c.choice_or("analysis", "dynamic", {"dynamic", "static"}) == "static" ? PlateDesc::Analysis::statics
                                                                                      : PlateDesc::Analysis::dynamic;
  if (c.has("newmark")) {
    ObjectReader n = c.object("newmark");
    d.gamma = n.real_or("gamma", 0.5, Range{0.5, INFINITY, false, false});
    d.beta = n.real_or("beta", 0.25, kPositive);
    if (!xfem::NewmarkScheme{d.beta, d.gamma, 1.0}.unconditionally_stable())
      n.fail("beta", "must be >= (gamma + 1/2)^2 / 4 = " + number(0.25 * (d.gamma + 0.5) * (d.gamma + 0.5)) +
                         " for gamma = " + number(d.gamma) + " (unconditional stability; got " + number(d.beta) + ")");
    n.finish();
  }
  if (c.has("supports"))
    for (const auto& [value, path] : c.array("supports")) {
      ObjectReader s(*value, path);
      PlateSupport sp;
      sp.edge = read_edge(s);
      if (s.has("fix")) {
        const Json& fix = s.raw("fix");
        if (!fix.is_array()) s.fail("fix", "expected a list of components, e.g. [\"x\", \"y\"]");
        for (const Json& f : fix) {
          if (!(f == "x" || f == "y")) s.fail("fix", "components are \"x\" and \"y\"");
          sp.fix[f == "x" ? 0 : 1] = true;
        }
      }
      sp.absorbing = s.boolean_or("absorbing", false);
      if (sp.absorbing && d.analysis == PlateDesc::Analysis::statics)
        s.fail("absorbing", "a static analysis has no dashpots");
      s.finish();
      d.supports.push_back(sp);
    }
  if (c.has("prescribed"))
    for (const auto& [value, path] : c.array("prescribed")) {
      ObjectReader p(*value, path);
      PlatePrescribed pr;
      const std::vector<double> at = p.vector("at", 2), u = p.vector("displacement", 2);
      for (int k = 0; k < 2; ++k) {
        pr.at[k] = at[static_cast<std::size_t>(k)];
        pr.displacement[k] = u[static_cast<std::size_t>(k)];
      }
      // An extension of the spec (docs/xfem2d.md, "Prescribed nodes with a
      // time shape"): without "shape", the value from t = 0 as before.
      const std::string shape = p.choice_or("shape", "step", {"step", "half_sine", "ramp"});
      pr.shape = shape == "step"        ? PlatePrescribedShape::step
                 : shape == "half_sine" ? PlatePrescribedShape::half_sine
                                        : PlatePrescribedShape::ramp;
      if (shape != "step") {
        if (d.analysis == PlateDesc::Analysis::statics)
          p.fail("shape", "a static analysis has no time; " + shape + " needs \"analysis\": \"dynamic\" (use step)");
        pr.duration = p.real("duration", kPositive);
      } else if (p.has("duration")) {
        p.fail("duration", "not used by shape 'step'");
      }
      p.finish();
      d.prescribed.push_back(pr);
    }
  if (c.has("loads"))
    for (const auto& [value, path] : c.array("loads")) {
      ObjectReader l(*value, path);
      PlateLoad load;
      std::vector<double> v;
      if (l.has("edge")) {
        load.kind = PlateLoad::Kind::edge_traction;
        load.edge = read_edge(l);
        if (l.has("force")) l.fail("force", "an edge load takes a traction (Pa); a point load takes \"at\" and \"force\"");
        v = l.vector("traction", 2);
      } else if (l.has("at")) {
        load.kind = PlateLoad::Kind::point_force;
        const std::vector<double> at = l.vector("at", 2);
        if (!inside(d, at)) l.fail("at", "(" + number(at[0]) + ", " + number(at[1]) + ") is outside the plate's domain");
        load.at[0] = at[0], load.at[1] = at[1];
        if (l.has("traction")) l.fail("traction", "a point load takes a force (N); an edge load takes a traction");
        v = l.vector("force", 2);
      } else {
        l.fail("edge", "a load needs \"edge\" (with \"traction\") or \"at\" (with \"force\")");
      }
      load.value[0] = v[0], load.value[1] = v[1];
      read_shape(l, load);
      if (load.shape == PlateLoadShape::half_sine && d.analysis == PlateDesc::Analysis::statics)
        l.fail("shape", "a static analysis has no time; half_sine needs \"analysis\": \"dynamic\" (use step)");
      l.finish();
      d.loads.push_back(load);
    }
  if (c.has("discontinuities"))
    for (const auto& [value, path] : c.array("discontinuities")) d.discontinuities.push_back(read_discontinuity(*value, path, d));
  c.finish();
  if (d.analysis == PlateDesc::Analysis::dynamic) {
    if (!(std::isfinite(dt) && dt > 0.0)) throw SceneError("scene key 'time.dt': must be > 0 (got " + number(dt) + ")");
    d.dt = dt;
  }
  // Everything above names its key; the kernel's own validation is the backstop.
  if (const BuildResult r = validate_plate(d); !r.ok()) {
    const std::string message = r.message;
    const std::size_t colon = message.find(": ");
    const std::string field = message.substr(0, colon), reason = message.substr(colon + 2);
    const std::string key = field == "dt" ? "time.dt" : c.path() + "." + field;
    throw SceneError("scene key '" + key + "': " + reason);
  }
  return d;
}

namespace {

/// The index of the crack the probe's "crack" names (refused when there is none).
int probe_crack(ObjectReader& p, const PlateDesc& d, std::string& name) {
  name = p.text("crack");
  for (std::size_t k = 0; k < d.discontinuities.size(); ++k)
    if (d.discontinuities[k].name == name && d.discontinuities[k].kind == PlateDiscontinuity::Kind::crack)
      return static_cast<int>(k);
  p.fail("crack", "no crack named '" + name + "' in continuum.discontinuities");
}

}  // namespace

void parse_plate_probe(ObjectReader& p, const PlateDesc& d, Probe& probe) {
  const std::string quantity = p.choice("quantity", {"displacement", "velocity", "acceleration", "stress", "energy",
                                                     "momentum", "crack_opening", "stress_intensity"});
  if (quantity == "stress_intensity") {
    std::string name;
    const int index = probe_crack(p, d, name);
    const bool at_end = p.choice("tip", {"start", "end"}) == "end";
    const auto& points = d.discontinuities[static_cast<std::size_t>(index)].points;
    const std::array<double, 2> tip = at_end ? points.back() : points.front();
    const std::string which = "the " + std::string(at_end ? "end" : "start") + " of crack '" + name + "' at (" +
                              number(tip[0]) + ", " + number(tip[1]) + ") is not a crack tip: ";
    // The kernel's own rule (an end within 1e-6 of a cell of the boundary is on it).
    switch (plate_crack_end(d, index, at_end)) {
      case PlateCrackEnd::on_boundary:
        p.fail("tip", which + "it ends on or outside the plate's boundary (within 1e-6 of a cell counts as on it)");
      case PlateCrackEnd::in_void:
        p.fail("tip", which + "it ends inside void '" +
                          d.discontinuities[static_cast<std::size_t>(plate_void_at(d, tip[0], tip[1]))].name +
                          "' (no material about it)");
      case PlateCrackEnd::tip: break;
    }
    // The interaction integral's domain: the nodes within `radius` of the tip
    // (q = 1 there), which must all be inside the plate. The radius is
    // kStressIntensityCells cells, or less for a tip nearer the boundary than
    // that, down to kStressIntensityMinCells cells (fewer nodes in the ring,
    // a larger error: docs/xfem2d.md).
    const double cell = std::max((d.max[0] - d.min[0]) / d.cells[0], (d.max[1] - d.min[1]) / d.cells[1]);
    const double reach = std::min({tip[0] - d.min[0], d.max[0] - tip[0], tip[1] - d.min[1], d.max[1] - tip[1]});
    const double radius = std::min(kStressIntensityCells * cell, kStressIntensityShrink * reach);
    if (!(radius >= kStressIntensityMinCells * cell))
      p.fail("tip", "the " + std::string(at_end ? "end" : "start") + " tip of crack '" + name + "' is " + number(reach) +
                        " m from the boundary: the interaction integral's domain (at least " +
                        number(kStressIntensityMinCells) + " cells, " + number(kStressIntensityMinCells * cell) +
                        " m) must stay inside the plate (refine the mesh)");
    probe.kind = Probe::Kind::plate_stress_intensity;
    probe.other = index;
    probe.tip_end = at_end;
    probe.radius = radius;
    probe.component = p.choice("mode", {"I", "II"}) == "I" ? 0 : 1;
    return;
  }
  if (quantity == "energy") {
    probe.kind = energy_probe_kind(p);
    return;
  }
  if (quantity == "momentum") {
    const std::string of = p.choice("of", {"total", "continuum", "particles"});
    probe.kind = of == "particles"   ? Probe::Kind::momentum_particles
                 : of == "continuum" ? Probe::Kind::momentum_continuum
                                     : Probe::Kind::momentum_total;
    probe.component = static_cast<int>(p.integer("component", 0, 1));
    return;
  }
  const std::vector<double> at = p.vector("at", 2);
  if (!inside(d, at)) p.fail("at", "(" + number(at[0]) + ", " + number(at[1]) + ") is outside the plate's domain");
  probe.at[0] = at[0], probe.at[1] = at[1];
  const double tolerance = 1e-9 * std::min((d.max[0] - d.min[0]) / d.cells[0], (d.max[1] - d.min[1]) / d.cells[1]);
  if (quantity == "crack_opening") {
    std::string name;
    const int index = probe_crack(p, d, name);
    const PlateDesc one = [&] {
      PlateDesc only = d;
      only.discontinuities = {d.discontinuities[static_cast<std::size_t>(index)]};
      return only;
    }();
    if (plate_point_region(one, at[0], at[1], tolerance) != 1)
      p.fail("at", "(" + number(at[0]) + ", " + number(at[1]) + ") is not on the crack '" + name +
                       "' (within 1e-9 of a cell)");
    probe.kind = Probe::Kind::plate_crack_opening;
    probe.other = index;
    probe.component = p.choice("component", {"normal", "tangential"}) == "normal" ? 0 : 1;
    return;
  }
  switch (plate_point_region(d, at[0], at[1], tolerance)) {
    case 1:
      p.fail("at", "(" + number(at[0]) + ", " + number(at[1]) +
                       ") is on a discontinuity (within 1e-9 of a cell): its value there has two sides");
    case 2:
      p.fail("at", "(" + number(at[0]) + ", " + number(at[1]) + ") is inside void '" +
                       d.discontinuities[static_cast<std::size_t>(plate_void_at(d, at[0], at[1]))].name +
                       "': there is no material there");
    default: break;
  }
  if (quantity == "stress") {
    const std::string c = p.choice("component", {"xx", "yy", "xy"});
    probe.kind = Probe::Kind::plate_stress;
    probe.component = c == "xx" ? 0 : c == "yy" ? 1 : 2;
    return;
  }
  probe.kind = quantity == "displacement" ? Probe::Kind::plate_displacement
               : quantity == "velocity"   ? Probe::Kind::plate_velocity
                                          : Probe::Kind::plate_acceleration;
  probe.component = static_cast<int>(p.integer("component", 0, 1));
}

}  // namespace xfdem::scene
