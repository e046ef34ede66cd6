// The same model and state give the same bits whether the step's two parts run
// on the calling thread one after the other or on the two workers of
// platform::TwoWorkerPool, for every integrator, with pair-list rebuilds.
#include <gtest/gtest.h>

#include <random>

#include "support/dem_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"

namespace xfdem::testing {
namespace {

DemDesc<3> stirred_box(int n) {
  DemDesc<3> d;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  d.gravity = {0, 0, -9.81};
  d.damping_ratio = 0.1;
  d.dt = 1e-5;
  d.split_from = 1000;
  const double side = 0.12;
  for (int i = 0; i < n; ++i) {
    ParticleDesc<3> p{0.001 * (1 + u(rng)), 0.002 * (1 + 0.3 * u(rng)), 2e3, {},
                      {4 * (u(rng) - 0.5), 4 * (u(rng) - 0.5), 4 * (u(rng) - 0.5)}};
    do {  // no pair starts deeper than the smaller radius (the build refuses that)
      p.position = {side * u(rng), side * u(rng), side * u(rng)};
    } while (starts_too_deep(d.particles, p));
    d.particles.push_back(p);
  }
  for (int k = 0; k < 3; ++k) {
    PlaneDesc<3> lo, hi;
    lo.normal[k] = 1;
    hi.normal[k] = -1;
    hi.point[k] = side;
    d.planes.push_back(lo);
    d.planes.push_back(hi);
  }
  return d;
}

TEST(TwoWorkers, SameBitsAsOneWorkerForEveryIntegrator) {
  platform::TwoWorkerPool pool;
  for (DemIntegrator integ : {DemIntegrator::abm4, DemIntegrator::rk4, DemIntegrator::verlet,
                              DemIntegrator::symplectic_euler, DemIntegrator::abm4_events}) {
    // abm4_events locates every contact event of the box (its frozen-set
    // evaluations run on one thread; its plain ones are split): fewer particles.
    DemDesc<3> d = stirred_box(integ == DemIntegrator::abm4_events ? 1200 : 3000);
    d.integrator = integ;
    DemWorld<3> one, two;
    ASSERT_TRUE(one.build(d).ok());
    ASSERT_TRUE(two.build(d).ok());
    ASSERT_EQ(one.model.parts, 2);
    two.workspace.parallel = pool.parallel_for();
    const bool events = integ == DemIntegrator::abm4_events;
    const int steps = events ? 5 : 150;
    platform::AllocationCounter counter;
    for (int k = 0; k < steps; ++k) {
      ASSERT_EQ(one.step(), StepStatus::ok);
      ASSERT_EQ(two.step(), StepStatus::ok);
    }
    EXPECT_EQ(counter.allocations(), 0u) << integrator_name(integ);
    if (!events) {
      EXPECT_GT(one.state.list_builds, 1) << integrator_name(integ);  // rebuilds were exercised
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(one.state.x[k], two.state.x[k]) << integrator_name(integ);
      EXPECT_EQ(one.state.v[k], two.state.v[k]) << integrator_name(integ);
    }
    EXPECT_EQ(one.state.plane_impulse, two.state.plane_impulse);
  }
}

// The split changes only where the work runs and in which order a particle's
// contributions are added: the trajectories agree with the unsplit model to
// round-off, not to the bit.
TEST(TwoWorkers, SplitModelAgreesWithUnsplitToRoundOff) {
  DemDesc<3> d = stirred_box(3000);
  DemDesc<3> whole = d;
  whole.split_from = 0;
  DemWorld<3> split, unsplit;
  ASSERT_TRUE(split.build(d).ok());
  ASSERT_TRUE(unsplit.build(whole).ok());
  ASSERT_EQ(unsplit.model.parts, 1);
  for (int k = 0; k < 50; ++k) {
    ASSERT_EQ(split.step(), StepStatus::ok);
    ASSERT_EQ(unsplit.step(), StepStatus::ok);
  }
  double worst = 0;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3000; ++i) worst = std::max(worst, std::fabs(split.state.x[k][i] - unsplit.state.x[k][i]));
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace xfdem::testing
