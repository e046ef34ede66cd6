// Per-stage profiles: filled only while the host installs a clock, consistent
// with each other, and without any effect on the results.
#include <gtest/gtest.h>

#include "support/coupled_scenes.hpp"
#include "xfdem/platform/clock.hpp"

namespace xfdem::testing {
namespace {

std::int64_t host_clock() { return platform::monotonic_ns(); }

TEST(Profile, CoupledStagesAddUpAndTimingChangesNoBits) {
  CoupledWorld timed, plain;
  ASSERT_TRUE(timed.build(coupled_scene("case2_xfem.json")).ok());
  ASSERT_TRUE(plain.build(coupled_scene("case2_xfem.json")).ok());
  timed.workspace.clock_ns = &host_clock;
  for (int k = 0; k < 3000; ++k) {  // free flight, impacts and contact: every stage runs
    ASSERT_EQ(timed.step(), StepStatus::ok);
    ASSERT_EQ(plain.step(), StepStatus::ok);
  }
  const CoupledProfile& p = timed.workspace.profile;
  EXPECT_EQ(p.steps, 3000);
  EXPECT_GT(p.passes, p.steps);  // the contact windows took more than one pass
  EXPECT_GT(p.continuum_ns, 0);
  EXPECT_GT(p.particles_ns, 0);
  EXPECT_GE(p.coupling_ns(), 0);
  const DemProfile& d = timed.workspace.dem.profile;
  EXPECT_EQ(d.steps, 10 * p.passes);  // one per substep of every pass
  EXPECT_GT(d.contacts_ns, 0);
  EXPECT_GE(d.integration_ns(), 0);
  EXPECT_EQ(plain.workspace.profile.steps, 0);  // no clock, no timing
  EXPECT_EQ(timed.state.dem.x[0], plain.state.dem.x[0]);
  EXPECT_EQ(timed.state.bar.u, plain.state.bar.u);
}

TEST(Profile, BroadPhaseIsTimedApart) {
  DemDesc<2> d;
  d.dt = 1e-5;
  d.all_pairs_up_to = 0;
  for (int i = 0; i < 400; ++i)
    d.particles.push_back({0.01, 0.004, 1e4, {0.01 * (i % 20), 0.01 * (i / 20)}, {(i % 7) - 3.0, (i % 5) - 2.0}});
  DemWorld<2> w;
  ASSERT_TRUE(w.build(d).ok());
  w.workspace.clock_ns = &host_clock;
  for (int k = 0; k < 2000; ++k) ASSERT_EQ(w.step(), StepStatus::ok);
  ASSERT_GT(w.state.list_builds, 2);
  EXPECT_GT(w.workspace.profile.broad_phase_ns, 0);
  EXPECT_GE(w.workspace.profile.integration_ns(), 0);
}

}  // namespace
}  // namespace xfdem::testing
