// Observed order of each integrator: on a smooth problem (a contact that never
// opens) and on the full drop test (contacts open and close inside steps).
#include <gtest/gtest.h>

#include <cstdio>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4,
                                  DemIntegrator::verlet, DemIntegrator::symplectic_euler};

int formal_order(DemIntegrator i) {
  switch (i) {
    case DemIntegrator::abm4:
    case DemIntegrator::abm4_events:
    case DemIntegrator::rk4: return 4;
    case DemIntegrator::verlet: return 2;
    case DemIntegrator::symplectic_euler: return 1;
  }
  return 0;
}

// Smooth: a sphere resting on the plane under gravity, displaced by A from its
// static overlap δs = mg/k with A < δs, undamped: the contact never opens and
// y(t) = r − δs − A cos(ωt + φ) exactly. A generic phase φ and end time keep
// special symmetries (a start or end at a turning point) from hiding errors.
double smooth_error(DemIntegrator integrator, double wh) {
  const double m = 2.0, k = 5e4, r = 0.05, g = 9.81, phase = 0.7;
  const double w = std::sqrt(k / m), ds = m * g / k, A = 0.5 * ds;
  const double dt = wh / w;
  DemDesc<1> d;
  d.gravity = {-g};
  d.integrator = integrator;
  d.dt = dt;
  d.particles.push_back({m, r, k, {r - ds - A * std::cos(phase)}, {A * w * std::sin(phase)}});
  d.planes.push_back({{0.0}, {1.0}});
  DemWorld<1> world;
  EXPECT_TRUE(world.build(d).ok());
  const int steps = static_cast<int>(std::lround(3.3 * 2 * M_PI / wh));  // 3.3 periods
  for (int n = 0; n < steps; ++n) EXPECT_EQ(world.step(), StepStatus::ok);
  const double t = world.state.time;
  const double ey = world.state.x[0][0] - (r - ds - A * std::cos(w * t + phase));
  const double ev = world.state.v[0][0] - A * w * std::sin(w * t + phase);
  return std::hypot(ey / A, ev / (A * w));
}

TEST(Convergence, SmoothContactReachesEachIntegratorsFormalOrder) {
  for (DemIntegrator integ : kAll) {
    std::vector<double> dts, errors;
    for (double wh : {0.08, 0.04, 0.02, 0.01}) {
      dts.push_back(wh);
      errors.push_back(smooth_error(integ, wh));
    }
    const double p = observed_order(dts, errors);
    std::printf("smooth contact  %-17s order %.2f (errors %.2e .. %.2e)\n", integrator_name(integ), p, errors.front(),
                errors.back());
    // A fitted slope over a factor 8 in dt: within 0.25 of the formal order.
    EXPECT_NEAR(p, formal_order(integ), 0.25) << integrator_name(integ);
  }
}

// Full drop test, k = 1e4, ζ = 0.1: error of the height at t = 1.2 s (in the
// flight after the first bounce), which carries the error of the whole impact.
double drop_error(DemIntegrator integrator, double dt) {
  DropParameters p;
  p.stiffness = 1e4;
  const auto exact = drop_bounces(p, 2.0);
  DemWorld<1> world;
  EXPECT_TRUE(world.build(drop_scene(p, integrator, dt)).ok());
  const long steps = std::lround(1.2 / dt);
  for (long n = 0; n < steps; ++n) EXPECT_EQ(world.step(), StepStatus::ok);
  return std::fabs(world.state.x[0][0] - drop_height(p, exact, world.state.time));
}

TEST(Convergence, DropTestIsFirstOrderUnlessEventsAreLocated) {
  for (DemIntegrator integ : kAll) {
    std::vector<double> dts, errors;
    // ωh from 0.02 down to 0.0025: abm4_events is in its asymptotic range
    // there (successive error ratios 13–15; at ωh = 0.04–0.08 they are ~9).
    for (double dt : {2e-4, 1e-4, 5e-5, 2.5e-5}) {
      dts.push_back(dt);
      errors.push_back(drop_error(integ, dt));
    }
    const double p = observed_order(dts, errors);
    std::printf("drop test       %-17s order %.2f (errors %.2e .. %.2e)\n", integrator_name(integ), p, errors.front(),
                errors.back());
    // Every fixed-step scheme integrates the dashpot's jump of ηv at
    // touch-down to O(h): error <= C·ζωh of the 1.6 m bounce, C = 10.
    if (integ != DemIntegrator::abm4_events) {
      for (std::size_t k = 0; k < dts.size(); ++k) EXPECT_LE(errors[k], 10 * 0.1 * 100.0 * dts[k] * 1.6);
    }
    switch (integ) {
      case DemIntegrator::abm4_events: EXPECT_NEAR(p, 4.0, 0.3); break;  // the formal order, recovered
      case DemIntegrator::abm4: EXPECT_NEAR(p, 1.0, 0.35); break;        // the paper's method drops to first
      // RK4 samples the jump at 0, h/2, h/2, h: its quadrature error is (θ − 1/6)h
      // for a jump at θh, so the O(h) term changes sign with where the jump
      // falls and the fitted slope wanders between 1 and 2: well below 4.
      case DemIntegrator::rk4: EXPECT_LT(p, 2.5); break;
      default: EXPECT_LT(p, 1.6) << integrator_name(integ); break;  // Verlet (formal 2), symplectic Euler (1)
    }
  }
}

}  // namespace
}  // namespace xfdem::testing
