#include "scene/continuum_json.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace xfdem::scene {

BarDesc parse_continuum(ObjectReader& c, double dt) {
  BarDesc d;
  c.choice("type", {"bar"});
  d.method = c.choice("method", {"xfem", "fem"}) == "fem" ? BarDesc::Method::fem : BarDesc::Method::xfem;
  d.length = c.real("length", kPositive);
  d.youngs_modulus = c.real("youngs_modulus", kPositive);
  d.area = c.real("area", kPositive);
  d.density = c.real("density", kPositive);
  d.elements = static_cast<int>(c.integer("elements", 1, 10'000'000));
  d.base = c.choice("base", {"fixed", "absorbing"}) == "absorbing" ? BarDesc::Base::absorbing : BarDesc::Base::fixed;
  if (c.has("base_stiffness")) {
    if (d.base == BarDesc::Base::fixed) c.fail("base_stiffness", "only an absorbing base has a spring");
    d.base_stiffness = c.real("base_stiffness", kNonNegative);
  }

  if (c.has("interface")) {
    ObjectReader i = c.object("interface");
    BarInterfaceDesc in;
    in.position = i.real("position", kAny);
    if (!(in.position > 0.0 && in.position < d.length))
      i.fail("position", "must lie strictly inside the bar (0, " + number(d.length) + ") m (got " + number(in.position) + ")");
    in.stiffness = i.real("stiffness", kPositive);
    in.behaviour = i.choice("behaviour", {"tied", "unilateral"}) == "unilateral"
                       ? BarInterfaceDesc::Behaviour::unilateral
                       : BarInterfaceDesc::Behaviour::tied;
    i.finish();
    d.interface = in;
  }

  {
    ObjectReader n = c.object("newmark");
    d.gamma = n.real("gamma", Range{0.5, std::numeric_limits<double>::infinity(), false, false});
    d.beta = n.real("beta", kPositive);
    const xfem::NewmarkScheme scheme{d.beta, d.gamma, 1.0};
    if (!scheme.unconditionally_stable())
      n.fail("beta", "must be >= (gamma + 1/2)^2 / 4 = " + number(0.25 * (d.gamma + 0.5) * (d.gamma + 0.5)) +
                         " for gamma = " + number(d.gamma) + " (unconditional stability; got " + number(d.beta) + ")");
    n.finish();
  }

  if (c.has("tip_load")) {
    ObjectReader t = c.object("tip_load");
    const std::string shape = t.choice("shape", {"none", "half_sine", "step"});
    if (shape == "none") {
      d.tip_load = BarDesc::TipLoad::none;
      if (t.has("amplitude")) t.fail("amplitude", "not used by shape 'none'");
    } else {
      d.tip_load = shape == "step" ? BarDesc::TipLoad::step : BarDesc::TipLoad::half_sine;
      d.tip_amplitude = t.real("amplitude", kAny);
    }
    if (shape == "half_sine") {
      d.tip_duration = t.real("duration", kPositive);
    } else if (t.has("duration")) {
      t.fail("duration", "not used by shape '" + shape + "'");
    }
    t.finish();
  }
  c.finish();

  if (!(std::isfinite(dt) && dt > 0.0)) throw SceneError("scene key 'time.dt': must be > 0 (got " + number(dt) + ")");
  d.dt = dt;
  // Everything above names its key; the kernel's own validation is the backstop.
  if (const BuildResult r = validate_bar(d); !r.ok()) throw SceneError("scene key '" + c.path() + "': " + r.message);
  return d;
}

}  // namespace xfdem::scene
