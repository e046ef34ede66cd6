// External forces as step inputs (a control loop sets them between steps).
#include <gtest/gtest.h>

#include "support/dem_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"

namespace xfdem::testing {
namespace {

// A free particle pushed by a force the host switches every 100 steps: its
// path is a chain of parabolas, which RK4, ABM4 (restarted at each switch) and
// Verlet integrate exactly, so they follow it to round-off.
TEST(Inputs, ExternalForceSwitchedBetweenStepsIsFollowedExactly) {
  for (DemIntegrator integ : {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4, DemIntegrator::verlet}) {
    DemDesc<2> d;
    d.dt = 1e-3;
    d.integrator = integ;
    d.external_forces = true;
    d.particles.push_back({2.0, 0.1, 1e3, {0.0, 0.0}, {0.5, 0.0}});
    DemWorld<2> w;
    ASSERT_TRUE(w.build(d).ok());
    double x = 0, y = 0, vx = 0.5, vy = 0;
    platform::AllocationCounter counter;
    for (int window = 0; window < 10; ++window) {
      const double fx = (window % 3) - 1.0, fy = 0.5 * (window % 2);
      w.state.external_force[0][0] = fx;
      w.state.external_force[1][0] = fy;
      dem_inputs_changed(w.state);
      const double T = 100 * d.dt;
      for (int k = 0; k < 100; ++k) ASSERT_EQ(w.step(), StepStatus::ok);
      x += vx * T + 0.5 * fx / 2.0 * T * T;
      y += vy * T + 0.5 * fy / 2.0 * T * T;
      vx += fx / 2.0 * T;
      vy += fy / 2.0 * T;
    }
    EXPECT_EQ(counter.allocations(), 0u);
    EXPECT_NEAR(w.state.x[0][0], x, 1e-13) << integrator_name(integ);
    EXPECT_NEAR(w.state.x[1][0], y, 1e-13) << integrator_name(integ);
    EXPECT_NEAR(w.state.v[0][0], vx, 1e-13) << integrator_name(integ);
  }
}

TEST(Inputs, WithoutTheFeatureThereIsNoInputTerm) {
  DemDesc<1> d;
  d.dt = 1e-3;
  d.particles.push_back({1.0, 0.1, 1e3, {0.0}, {0.0}});
  DemWorld<1> w;
  ASSERT_TRUE(w.build(d).ok());
  EXPECT_FALSE(w.model.features.external_forces);
  EXPECT_TRUE(w.state.external_force[0].empty());
}

}  // namespace
}  // namespace xfdem::testing
