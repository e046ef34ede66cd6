// Randomized sweep of the coupled stepper (label `stress`): a few hundred
// variants of the paper's Case I and II, every parameter drawn from a wide
// range with a fixed seed — masses, radii, stiffnesses and damping ratios of
// one or two particles, the rod (length, E, ρ, A, elements, fixed or absorbing
// base), the interface (position anywhere in (0, L), within 1e-12 of a node or
// on it, tied, FEM or X-FEM), Newmark's (β, γ), the particle
// integrator, n = 1 … 20 substeps and dt up to the build's stable limit.
// Every variant the build accepts must run to the end with no flag, its
// energy never above the start but for round-off, and its momentum books
// closing exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "stress/sweeps.hpp"
#include "support/coupled_scenes.hpp"

namespace xfdem::stress {
namespace {

/// splitmix64: the same draws on every platform (std's distributions are not).
struct Draw {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  double log_uniform(double lo, double hi) { return lo * std::pow(hi / lo, unit()); }
  int integer(int lo, int hi) { return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1)); }
  bool chance(double p) { return unit() < p; }
};

struct Variant {
  CoupledDesc desc;
  std::string text;  ///< the drawn values, to reproduce a failure
};

Variant draw_variant(Draw& r) {
  Variant v;
  CoupledDesc& d = v.desc;
  d = testing::coupled_scene("case2_xfem.json");
  BarDesc& b = d.bar;
  b.length = r.uniform(5, 60);
  b.youngs_modulus = r.log_uniform(1e6, 1e10);
  b.density = r.uniform(500, 8000);
  b.area = r.log_uniform(0.05, 2);
  b.elements = r.integer(4, 60);
  b.method = r.chance(0.5) ? BarDesc::Method::xfem : BarDesc::Method::fem;
  b.base = r.chance(0.8) ? BarDesc::Base::fixed : BarDesc::Base::absorbing;
  const double h = b.length / b.elements;
  const int node = r.integer(1, b.elements - 1);
  double position = 0;
  const double where = r.unit();
  if (where < 0.4) {
    position = r.uniform(0.01, 0.99) * b.length;
  } else if (where < 0.85) {  // a hair from a node, either side, down to 1e-12 of an element
    const double offset = h * r.log_uniform(1e-12, 1e-3);
    position = node * h + (r.chance(0.5) ? offset : -offset);
  } else {
    position = node * h;
  }
  b.interface = BarInterfaceDesc{position, 100 * b.youngs_modulus * b.area * r.log_uniform(1e-2, 1e2),
                                 BarInterfaceDesc::Behaviour::tied};
  const double scheme = r.unit();
  if (scheme < 0.35) {
    b.gamma = 0.5;
    b.beta = 0.25;
  } else if (scheme < 0.6) {
    b.gamma = 0.6;
    b.beta = 0.4;
  } else {
    b.gamma = r.uniform(0.5, 0.9);
    const double boundary = (b.gamma + 0.5) * (b.gamma + 0.5) / 4;
    b.beta = r.chance(0.3) ? boundary : boundary * r.uniform(1, 1.5);
  }
  // The integrators whose energy only falls with a contact dashpot (verlet's
  // and symplectic Euler's oscillates about a shadow energy whatever the
  // exchange does: docs/stability.md).
  const DemIntegrator integrators[] = {DemIntegrator::abm4, DemIntegrator::abm4, DemIntegrator::abm4_events,
                                       DemIntegrator::rk4};
  d.dem.integrator = integrators[r.integer(0, 3)];
  d.dem.damping_ratio = r.uniform(0.05, 0.5);
  d.dem_substeps = r.integer(1, 20);
  const int particles = r.integer(1, 2);
  d.dem.particles.resize(static_cast<std::size_t>(particles));
  double below = b.length, below_radius = 0;
  for (auto& p : d.dem.particles) {
    p.mass = r.log_uniform(1, 1e4);
    p.radius = r.uniform(0.05, 1);
    p.stiffness = r.log_uniform(1e5, 1e9);
    p.position = {below + below_radius + p.radius + r.uniform(0, 2)};
    p.velocity = {r.uniform(-5, 1)};
    below = p.position[0];
    below_radius = p.radius;
  }
  // dt up to the stable limit the build states: shrunk until it accepts.
  b.dt = r.log_uniform(1e-4, 2e-3);
  char text[400];
  std::snprintf(text, sizeof(text),
                "L %.4g E %.4g rho %.4g A %.4g elements %d %s %s xi %.17g (%s, k %.3g) beta %.6g gamma %.6g %s zeta "
                "%.3g n %d particles %d m1 %.4g k1 %.3g",
                b.length, b.youngs_modulus, b.density, b.area, b.elements,
                b.method == BarDesc::Method::xfem ? "xfem" : "fem",
                b.base == BarDesc::Base::fixed ? "fixed" : "absorbing", position,
                b.interface->behaviour == BarInterfaceDesc::Behaviour::tied ? "tied" : "unilateral",
                b.interface->stiffness, b.beta, b.gamma, integrator_name(d.dem.integrator), d.dem.damping_ratio,
                d.dem_substeps, particles, d.dem.particles[0].mass, d.dem.particles[0].stiffness);
  v.text = text;
  return v;
}

/// Builds, shrinking dt by 0.7 while the build refuses it as unstable.
bool build_variant(CoupledDesc& d, CoupledWorld& w, std::string& message) {
  for (int tries = 0; tries < 60; ++tries) {
    const BuildResult r = w.build(d);
    if (r.ok()) return true;
    message = r.message;
    if (r.code != BuildResult::Code::unstable_time_step) return false;
    d.bar.dt *= 0.7;
  }
  return false;
}

constexpr std::uint64_t kSeed = 0x14c0ffeeull;
constexpr int kVariants = 300;
constexpr std::int64_t kSteps = 3000;

TEST(CoupledStress, RandomizedCaseVariants) {
  Draw r{kSeed};
  int built = 0, contacts = 0;
  double worst_energy = 0, worst_ledger = 0, worst_particles = 0;
  std::int64_t passes = 0, steps = 0;
  int peak_passes = 0;
  for (int k = 0; k < kVariants; ++k) {
    Variant v = draw_variant(r);
    SCOPED_TRACE("variant " + std::to_string(k) + ": " + v.text);
    CoupledWorld w;
    std::string message;
    ASSERT_TRUE(build_variant(v.desc, w, message)) << message;
    ++built;
    const CoupledModel& m = w.model;
    const double e0 = testing::total_energy(m, w.state);
    const double available = e0 - coupled_rest_energy(v.desc);
    const double p0 = testing::particle_momentum(m, w.state);
    double weight = 0;
    for (std::int32_t i = 0; i < m.dem.n; ++i) weight += m.dem.mass[i] * v.desc.dem.gravity[0];
    double gravity = 0, scale = 0, highest = 0;
    StepStatus flags = StepStatus::ok;
    std::int64_t first = -1;
    for (std::int64_t n = 0; n < kSteps; ++n) {
      const StepStatus s = w.step();
      if (s != StepStatus::ok && first < 0) first = n;
      flags |= s;
      gravity += weight * m.dt;
      highest = std::max(highest, testing::total_energy(m, w.state) - e0);
      scale = std::max(scale, std::fabs(w.state.impulse_to_particles));
      passes += w.state.last_passes;
      ++steps;
    }
    peak_passes = std::max(peak_passes, w.state.peak_passes);
    EXPECT_EQ(flags, StepStatus::ok) << flag_text(flags) << " from step " << first;
    // Energy: contact dashpots, γ ≥ ½ and the absorbing base only take energy
    // out, and the exchange at its fixed point does no net work.
    worst_energy = std::max(worst_energy, highest / available);
    // Round-off: 1e-12 of the largest term the energy sums (|E0| holds the
    // particles' potential m g x, large beside A when the rod is long).
    EXPECT_LE(highest, 1e-12 * (available + std::fabs(e0))) << "rise/A " << highest / available;
    // Momentum: the books close exactly, the unbalanced rest is round-off, and
    // the particles' momentum changed by gravity plus what the top gave them.
    const CoupledState& s = w.state;
    EXPECT_EQ(s.pending_impulse, s.impulse_to_particles + s.impulse_to_bar);
    if (scale > 0) {
      ++contacts;
      worst_ledger = std::max(worst_ledger, std::fabs(s.pending_impulse) / scale);
      worst_particles =
          std::max(worst_particles,
                   std::fabs(testing::particle_momentum(m, s) - p0 - gravity - s.impulse_to_particles) / scale);
    }
    EXPECT_LE(std::fabs(s.pending_impulse), 1e-10 * scale);
    EXPECT_LE(std::fabs(testing::particle_momentum(m, s) - p0 - gravity - s.impulse_to_particles),
              1e-11 * std::max(scale, std::fabs(gravity)));
  }
  std::printf("%d variants built, %d with contact; worst (E - E0)/A %.2e, unbalanced impulse %.2e, particle "
              "momentum books %.2e of the largest impulse; passes per step %.3f (peak %d)\n",
              built, contacts, worst_energy, worst_ledger, worst_particles,
              static_cast<double>(passes) / static_cast<double>(steps), peak_passes);
}

}  // namespace
}  // namespace xfdem::stress
