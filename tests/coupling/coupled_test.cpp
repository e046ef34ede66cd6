// The coupled X-FE-DEM stepper on the paper's Case I and Case II.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "support/coupled_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"

namespace xfdem::testing {
namespace {

struct Trace {
  std::vector<double> t, p1, tip, top_force;
};

Trace run(const CoupledDesc& d, double t_end) {
  CoupledWorld w;
  const BuildResult r = w.build(d);
  EXPECT_TRUE(r.ok()) << r.message;
  Trace tr;
  const long steps = std::lround(t_end / d.bar.dt);
  for (long k = 0; k < steps; ++k) {
    EXPECT_EQ(w.step(), StepStatus::ok);
    tr.t.push_back(w.state.time);
    tr.p1.push_back(w.state.dem.x[0][0]);
    tr.tip.push_back(bar_tip_displacement(w.model.bar, w.state.bar));
    tr.top_force.push_back(coupled_top_force(w.model, w.state, 0));
  }
  return tr;
}

/// Index of the start of the k-th contact of particle 0 with the top (k = 1, 2, …).
std::size_t contact_start(const Trace& tr, int k) {
  int seen = 0;
  for (std::size_t i = 1; i < tr.t.size(); ++i)
    if (tr.top_force[i - 1] == 0 && tr.top_force[i] != 0 && ++seen == k) return i;
  return tr.t.size();
}

// In 1D the shifted-Heaviside space on the uniform mesh and the conforming
// mesh with a duplicated node span the same functions, so FE-DEM and X-FE-DEM
// solve the same discrete system: they differ only by round-off, until the
// bouncing's sensitivity amplifies it (see Sensitivity below).
TEST(Coupled, FemAndXfemAgreeToRoundOffUntilTheSecondImpact) {
  for (const char* which : {"case1", "case2"}) {
    const Trace fem = run(coupled_scene(std::string(which) + "_fem.json"), 10.0);
    const Trace xfem = run(coupled_scene(std::string(which) + "_xfem.json"), 10.0);
    const std::size_t second = contact_start(fem, 2);
    ASSERT_LT(second, fem.t.size());
    double worst_p = 0, worst_u = 0;
    for (std::size_t i = 0; i < second; ++i) {
      worst_p = std::max(worst_p, std::fabs(fem.p1[i] - xfem.p1[i]));
      worst_u = std::max(worst_u, std::fabs(fem.tip[i] - xfem.tip[i]));
    }
    std::printf("%s: second impact at t = %.3f s; before it max |dy_p1| = %.2e m, max |du_tip| = %.2e m\n", which,
                fem.t[second], worst_p, worst_u);
    // Round-off of 30 m positions (~4e-15 m) amplified by a few impacts.
    EXPECT_LT(worst_p, 1e-11);
    EXPECT_LT(worst_u, 1e-12);
  }
}

// The exchange conserves momentum exactly: the particles' impulse from the top
// (their integrator's own weights) is what they gained beyond gravity, the bar
// receives minus each window's impulse one step later, and the bar's momentum
// ∫ρAv dx changes by exactly that plus its base dashpot's impulse (absorbing
// base, so that every external force on the bar is known).
TEST(Coupled, MomentumExchangeIsExactToRoundOff) {
  for (const char* file : {"case2_xfem.json", "case2_fem.json"}) {
    CoupledDesc d = coupled_scene(file, {"continuum.base=absorbing"});
    CoupledWorld w;
    ASSERT_TRUE(w.build(d).ok());
    const double c = d.bar.density * d.bar.area * std::sqrt(d.bar.youngs_modulus / d.bar.density);
    const double gamma = d.bar.gamma, dt = d.bar.dt;
    const double pp0 = particle_momentum(w.model, w.state), pb0 = bar_momentum(w.model, w.state);
    double gravity = 0, base = 0, scale = 0;
    for (int k = 0; k < 4000; ++k) {
      const double vb0 = bar_velocity(w.model.bar, w.state.bar, 0.0);
      ASSERT_EQ(w.step(), StepStatus::ok);
      const double vb1 = bar_velocity(w.model.bar, w.state.bar, 0.0);
      base += -c * dt * ((1 - gamma) * vb0 + gamma * vb1);
      gravity += 150.0 * -9.81 * dt;
      scale = std::max(scale, std::fabs(w.state.impulse_to_particles));
    }
    const CoupledState& s = w.state;
    ASSERT_GT(scale, 1e3);  // the particles landed and bounced
    // Particles: Σ m Δv = gravity + what the top gave them (pairs cancel).
    EXPECT_NEAR(particle_momentum(w.model, s) - pp0, gravity + s.impulse_to_particles, 1e-12 * scale) << file;
    // The bar got minus what the particles took, window by window; what is left
    // over is a round-off-sized fixed-point residual, carried forward.
    EXPECT_NEAR(s.impulse_to_bar, -s.impulse_to_particles, 1e-12 * scale) << file;
    EXPECT_EQ(s.pending_impulse, s.impulse_to_particles + s.impulse_to_bar) << file;
    // And Newmark delivered exactly that: Δ∫ρAv = impulse_to_bar + base dashpot.
    EXPECT_NEAR(bar_momentum(w.model, s) - pb0, s.impulse_to_bar + base, 1e-10 * scale) << file;
  }
}

TEST(Coupled, StepNeverAllocates) {
  for (const char* file : {"case1_fem.json", "case1_xfem.json", "case2_fem.json", "case2_xfem.json"}) {
    CoupledWorld w;
    ASSERT_TRUE(w.build(coupled_scene(file)).ok());
    platform::AllocationCounter counter;
    for (int k = 0; k < 3000; ++k) ASSERT_EQ(w.step(), StepStatus::ok);
    EXPECT_EQ(counter.allocations(), 0u) << file;
  }
}

// Sensitivity: the issue expected a 1e-9 m change of the initial height to
// change the trajectories visibly after the second impact. With the window
// iterated to its fixed point the exchange creates no energy and Case I is
// not sensitive: the difference never exceeds 1.13e-9 m and fades as the
// particle settles. Case II is: while the two particles rattle on the rod
// (t ≈ 2–3 s) the difference grows about 80-fold, then fades too. Pointwise
// comparisons therefore stop at the second impact; robust facts cover the rest.
TEST(Coupled, SensitivityAfterTheSecondImpact) {
  for (const char* file : {"case1_xfem.json", "case2_xfem.json"}) {
    const Trace a = run(coupled_scene(file), 10.0);
    const Trace b = run(coupled_scene(file, {"dem.particles.0.position=[33.500000001]"}), 10.0);
    const std::size_t second = contact_start(a, 2);
    double before = 0, after = 0, last = 0;
    for (std::size_t i = 0; i < a.t.size(); ++i) {
      const double d = std::fabs(a.p1[i] - b.p1[i]);
      if (i < second) before = std::max(before, d);
      else after = std::max(after, d);
      last = d;
    }
    std::printf("%s, start 1e-9 m higher: max |dy| %.2e m before the 2nd impact (t=%.2f), %.2e m after, %.2e m at 10 s\n",
                file, before, a.t[second], after, last);
    EXPECT_LT(before, 2e-9);
    EXPECT_LT(last, after);  // dissipation brings the two runs back together
    if (std::string(file) == "case2_xfem.json") {
      EXPECT_GT(after, 10 * before);
    } else {
      EXPECT_LT(after, 2 * before);
    }
  }
}

// Robust facts of the paper's runs (ζ = 0.1, β = 0.4, γ = 0.6): no particle
// passes through the rod or the other particle, and the total energy never
// rises (dashpots and the dissipative Newmark only take energy out; the
// one-step delay of the exchange injects some, less than they take).
TEST(Coupled, NoPassThroughAndEnergyNeverRises) {
  for (const char* file : {"case1_fem.json", "case1_xfem.json", "case2_fem.json", "case2_xfem.json"}) {
    CoupledWorld w;
    ASSERT_TRUE(w.build(coupled_scene(file)).ok());
    double e_prev = total_energy(w.model, w.state), worst_rise = 0, deepest = 0;
    const double e0 = e_prev;
    for (int k = 0; k < 10000; ++k) {
      ASSERT_EQ(w.step(), StepStatus::ok);
      const double top = w.model.top_position + bar_tip_displacement(w.model.bar, w.state.bar);
      for (std::int32_t i = 0; i < w.model.dem.n; ++i)
        deepest = std::max(deepest, (w.model.dem.radius[i] - (w.state.dem.x[0][i] - top)) / w.model.dem.radius[i]);
      if (w.model.dem.n == 2) {
        EXPECT_GT(w.state.dem.x[0][1] - w.state.dem.x[0][0], 0.5 * (w.model.dem.radius[0] + w.model.dem.radius[1]));
      }
      const double e = total_energy(w.model, w.state);
      worst_rise = std::max(worst_rise, e - e_prev);
      e_prev = e;
    }
    std::printf("%s: deepest overlap with the top %.2e of the radius; largest one-step energy rise %.2e J (E0 %.0f J)\n",
                file, deepest, worst_rise, e0);
    // A rigid top would stop the 7.7 m/s particle within v√(m/k) = 2.4 cm; the
    // rod only yields, so the overlap stays below that, far from the radius.
    EXPECT_LT(deepest, std::sqrt(2 * 9.81 * 3.0) * std::sqrt(100.0 / 1e7) / 0.5);
    EXPECT_LE(worst_rise, 1e-9 * e0);  // round-off of the energy sum
  }
}

// With the paper's dissipative Newmark the particle ends up riding the rod at
// the static overlap mg/k and the rod, on average, shortened by the weight
// (mgL/(EA) plus the interface spring's mg/k_i). The rod's fundamental mode
// (ω₁ = 6.4 rad/s, ω₁dt = 0.0064) is barely damped by γ = 0.6 — its numerical
// damping ratio is about (γ − ½)ω₁dt/2 = 3e-4 — so it still rings after a
// minute: check the means over whole periods and that the ringing decays.
TEST(Coupled, ParticleComesToRestOnTheRodShortenedByItsWeight) {
  CoupledWorld w;
  ASSERT_TRUE(w.build(coupled_scene("case1_xfem.json")).ok());
  const double weight = 100 * 9.81;
  const double static_tip = -weight * 30.0 / (3e7 * 0.4) - weight / 1.2e9;
  const double static_overlap = weight / 1e7;
  const double period = 2 * M_PI / 6.412339;  // semi-discrete ω₁ (V2 report)
  auto window = [&](double t_end, double& mean_tip, double& mean_overlap, double& range) {
    const long steps = std::lround(5 * period / 1e-3);  // five whole periods
    while (w.state.time < t_end - 5 * period) ASSERT_EQ(w.step(), StepStatus::ok);
    double lo = INFINITY, hi = -INFINITY, sum_u = 0, sum_d = 0;
    for (long k = 0; k < steps; ++k) {
      ASSERT_EQ(w.step(), StepStatus::ok);
      const double u = bar_tip_displacement(w.model.bar, w.state.bar);
      lo = std::min(lo, u);
      hi = std::max(hi, u);
      sum_u += u;
      sum_d += 0.5 - (w.state.dem.x[0][0] - 30.0 - u);
    }
    mean_tip = sum_u / steps;
    mean_overlap = sum_d / steps;
    range = hi - lo;
  };
  double tip20, d20, r20, tip60, d60, r60;
  window(20.0, tip20, d20, r20);
  window(60.0, tip60, d60, r60);
  std::printf("mean tip u %.5e m (static %.5e), mean overlap %.5e m (static %.5e); ringing %.2e m at 20 s, %.2e m at 60 s\n",
              tip60, static_tip, d60, static_overlap, r20, r60);
  // Five periods of a ringing mode average out to within its residual phase:
  // a few per cent of the static values.
  EXPECT_NEAR(tip60 / static_tip, 1.0, 0.03);
  EXPECT_NEAR(d60 / static_overlap, 1.0, 0.05);
  EXPECT_LT(r60, r20);
}

// A window whose contacts stay closed has an exchange impulse J affine in the
// force (the linear law, the particles' linear integrators, the bar's linear
// step), and so is the particles' end state: once two passes of a window that
// saw the same contacts have measured its sensitivity, a window that sees them
// again settles in one pass (a Newton step, and the pass moved along the
// sensitivity). Both particles rest on the rod from about t = 4 s in Case II.
// The one-pass window is compared with the iterated one: a copy of the world
// with its sensitivity dropped (which takes two passes) steps the same window;
// both settle within 1e-10 of the force's scale, so their forces differ by at
// most 2e-10 of it (|g'| ≥ 1: g = −J/Δt − f with J decreasing in f), and the
// particles' momenta by that times Δt.
TEST(Coupled, ResidentContactsSettleInOnePass) {
  for (const char* file : {"case2_fem.json", "case2_xfem.json"}) {
    CoupledWorld w;
    ASSERT_TRUE(w.build(coupled_scene(file)).ok());
    while (w.state.time < 8.0) ASSERT_EQ(w.step(), StepStatus::ok);
    double worst_force = 0, worst_momentum = 0;
    for (int k = 0; k < 1000; ++k) {
      CoupledWorld iterated = w;
      iterated.state.sensitivity_width = 0;
      ASSERT_EQ(iterated.step(), StepStatus::ok);
      ASSERT_EQ(w.step(), StepStatus::ok);
      ASSERT_GT(coupled_top_force(w.model, w.state, 0), 0.0) << file << " at t = " << w.state.time;
      EXPECT_EQ(w.state.last_passes, 1) << file << " at t = " << w.state.time;
      EXPECT_EQ(iterated.state.last_passes, 2) << file << " at t = " << w.state.time;
      const double f = w.state.coupling_force;
      const double scale = 2e-10 * std::fabs(f);
      worst_force = std::max(worst_force, std::fabs(f - iterated.state.coupling_force) / scale);
      double momentum = 0;
      for (std::int32_t i = 0; i < w.model.dem.n; ++i)
        momentum += w.model.dem.mass[i] * (w.state.dem.v[0][i] - iterated.state.dem.v[0][i]);
      worst_momentum = std::max(worst_momentum, std::fabs(momentum) / (scale * w.model.dt));
    }
    std::printf("%s: one pass vs iterated: force within %.3f and momentum within %.3f of the bound\n", file,
                worst_force, worst_momentum);
    EXPECT_LE(worst_force, 1.0) << file;
    EXPECT_LE(worst_momentum, 1.0) << file;
  }
}

// Undamped (ζ = 0, β = 1/4, γ = 1/2): the exchange at its fixed point creates
// no energy, Newmark's trapezoidal rule conserves the rod's, and what is left
// is the particle integrator's error at each impact: total energy is kept to
// the order of the scheme over the whole run (the rod keeps ringing and the
// particle keeps rattling on it).
TEST(Coupled, UndampedEnergyConservedToTheSchemesOrder) {
  auto drift = [](double dt) {
    CoupledDesc d = coupled_scene("case1_xfem.json", {"dem.contact.damping_ratio=0", "continuum.newmark.beta=0.25",
                                                      "continuum.newmark.gamma=0.5"});
    d.bar.dt = dt;
    CoupledWorld w;
    EXPECT_TRUE(w.build(d).ok());
    const double e0 = total_energy(w.model, w.state);
    double worst = 0;
    const long steps = std::lround(10.0 / dt);
    for (long k = 0; k < steps; ++k) {
      EXPECT_EQ(w.step(), StepStatus::ok);
      worst = std::max(worst, std::fabs(total_energy(w.model, w.state) - e0) / e0);
    }
    return worst;
  };
  const double e1 = drift(1e-3), e2 = drift(5e-4), e3 = drift(2.5e-4);
  const double order = std::log2(e1 / e3) / 2;
  std::printf("undamped Case I: max |E - E0|/E0 over 10 s: %.2e (dt 1e-3), %.2e (5e-4), %.2e (2.5e-4): order %.2f\n", e1, e2,
              e3, order);
  EXPECT_LT(e1, 1e-3);
  // The particle's ABM4 is second order across an undamped contact's kink
  // (tests/dem/collision_test.cpp); the coupled run keeps at least that.
  EXPECT_GT(order, 1.7);
}

}  // namespace
}  // namespace xfdem::testing
