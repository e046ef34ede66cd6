// Planes driven by the host (as the coupled stepper drives the rod's top end):
// the kernel's impulse ledger equals the momentum the particles received from
// the plane, to round-off, for every integrator; and a plane moving at a
// constant speed is the same physics as a resting one seen from a moving frame.
#include <gtest/gtest.h>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4,
                                  DemIntegrator::verlet, DemIntegrator::symplectic_euler};

TEST(MovingPlane, ImpulseLedgerEqualsMomentumReceived) {
  for (DemIntegrator integ : kAll) {
    // Two spheres stacked on a plane that the host moves up and down.
    DemDesc<1> d;
    d.gravity = {-9.81};
    d.damping_ratio = 0.1;
    d.integrator = integ;
    d.dt = 1e-4;
    d.particles = {{1.0, 0.1, 1e5, {0.3}, {0.0}}, {0.5, 0.05, 1e5, {0.6}, {0.0}}};
    d.planes = {{{0.0}, {1.0}}};
    DemWorld<1> w;
    ASSERT_TRUE(w.build(d).ok());
    const double p0 = 1.0 * w.state.v[0][0] + 0.5 * w.state.v[0][1];
    double gravity_impulse = 0;
    for (int window = 0; window < 200; ++window) {
      // Every 10 steps, as a continuum step would: new position and speed.
      dem_drive_plane(w.model, w.state, 0, 0.02 * std::sin(0.3 * window), 0.5 * std::cos(0.7 * window));
      for (int k = 0; k < 10; ++k) {
        ASSERT_EQ(w.step(), StepStatus::ok);
        gravity_impulse += 1.5 * -9.81 * d.dt;
      }
    }
    const double p1 = 1.0 * w.state.v[0][0] + 0.5 * w.state.v[0][1];
    const double from_plane = p1 - p0 - gravity_impulse;
    EXPECT_GT(std::fabs(from_plane), 1.0) << integrator_name(integ);  // the plane did push
    // Round-off of 2000 steps of O(10) N·s sums.
    EXPECT_NEAR(w.state.plane_impulse[0], from_plane, 1e-11 * std::fabs(from_plane)) << integrator_name(integ);
  }
}

// A sphere resting on a plane that moves at a constant speed u: in the plane's
// frame nothing changes, so the overlap and relative velocity follow the
// resting case exactly (up to the round-off of the frame shift).
TEST(MovingPlane, ConstantSpeedIsAMovingFrame) {
  for (DemIntegrator integ : kAll) {
    const double u = 0.7;
    DemDesc<1> rest;
    rest.gravity = {-9.81};
    rest.damping_ratio = 0.2;
    rest.integrator = integ;
    rest.dt = 1e-4;
    rest.particles = {{1.0, 0.1, 1e4, {0.095}, {0.0}}};
    rest.planes = {{{0.0}, {1.0}}};
    DemDesc<1> moving = rest;
    moving.particles[0].velocity = {u};
    DemWorld<1> a, b;
    ASSERT_TRUE(a.build(rest).ok());
    ASSERT_TRUE(b.build(moving).ok());
    dem_drive_plane(b.model, b.state, 0, 0.0, u);
    for (int k = 0; k < 3000; ++k) {
      ASSERT_EQ(a.step(), StepStatus::ok);
      ASSERT_EQ(b.step(), StepStatus::ok);
    }
    const double shift = u * b.state.time;
    EXPECT_NEAR(b.state.x[0][0] - shift, a.state.x[0][0], 1e-12) << integrator_name(integ);
    EXPECT_NEAR(b.state.v[0][0] - u, a.state.v[0][0], 1e-11) << integrator_name(integ);
  }
}

}  // namespace
}  // namespace xfdem::testing
