// A particle that starts deeper in a plane than its radius, or deeper in
// another particle than the smaller radius, is refused at build, naming it:
// its contact would throw it out at a speed no scene means. Moderate overlaps
// are legal, and only the initial state is checked: V1 with k = 1e3 goes
// deeper than the radius during its run, and a host may move particles after
// build.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

DropParameters v1(double stiffness) {
  DropParameters p;
  p.stiffness = stiffness;
  return p;
}

TEST(InitialOverlap, DeeperInAPlaneThanTheRadiusIsRefusedNamingTheParticle) {
  DemDesc<1> d = drop_scene(v1(1e4), DemIntegrator::abm4, 1e-4);  // m = 1 kg, r = 0.1 m, plane at 0
  d.particles[0].position = {-0.05};
  DemWorld<1> w;
  BuildResult r = w.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::invalid_argument);
  EXPECT_EQ(std::string(r.message),
            "particles[0].position: overlaps planes[0] by 0.15 m at the start, more than its radius 0.1 m (its centre "
            "is on the plane's solid side): its contact would throw it out at up to 15 m/s");
  EXPECT_EQ(w.step(), StepStatus::not_built);
  d.particles[0].position = {0.0};  // centre on the plane: overlap = radius
  EXPECT_TRUE(w.build(d).ok());
  d.particles[0].position = {0.05};  // half the radius
  EXPECT_TRUE(w.build(d).ok());

  // A plane's normal need not be of unit length; the second particle is named.
  DemDesc<2> d2;
  d2.dt = 1e-4;
  d2.particles.push_back({1.0, 0.1, 1e4, {0.0, 1.0}, {0.0, 0.0}});
  d2.particles.push_back({1.0, 0.1, 1e4, {3.0, -0.2}, {0.0, 0.0}});
  d2.planes.push_back({{0.0, 0.0}, {0.0, 2.0}});
  DemWorld<2> w2;
  r = w2.build(d2);
  EXPECT_EQ(std::string(r.message),
            "particles[1].position: overlaps planes[0] by 0.3 m at the start, more than its radius 0.1 m (its centre "
            "is on the plane's solid side): its contact would throw it out at up to 30 m/s");
}

TEST(InitialOverlap, DeeperInAnotherParticleThanTheSmallerRadiusIsRefused) {
  for (const std::int32_t all_pairs_up_to : {8, 0}) {  // the all-pairs list, then the grid's
    DemDesc<1> d;
    d.dt = 1e-5;
    d.all_pairs_up_to = all_pairs_up_to;
    d.particles.push_back({4.0, 0.1, 1e4, {0.0}, {0.0}});
    d.particles.push_back({1.0, 0.1, 1e4, {2.0}, {0.0}});
    d.particles.push_back({1.0, 0.05, 1e4, {2.04}, {0.0}});  // 0.11 into the second, more than 0.05
    DemWorld<1> w;
    const BuildResult r = w.build(d);
    EXPECT_EQ(r.code, BuildResult::Code::invalid_argument);
    // K = 5e3 N/m in series, 1/m_eff = 2 per kg: ω = 100 rad/s.
    EXPECT_EQ(std::string(r.message),
              "particles[2].position: overlaps particles[1] by 0.11 m at the start, more than the smaller radius 0.05 "
              "m: their contact would throw them apart at up to 11 m/s")
        << "all_pairs_up_to " << all_pairs_up_to;
    EXPECT_EQ(w.step(), StepStatus::not_built);
    d.particles[2].position = {2.1};  // exactly the smaller radius: legal
    EXPECT_TRUE(w.build(d).ok()) << "all_pairs_up_to " << all_pairs_up_to;
  }
}

TEST(InitialOverlap, OnlyTheInitialStateIsChecked) {
  // V1 with k = 1e3: the centre passes below the plane during the run, and the sphere rebounds.
  DemWorld<1> w;
  ASSERT_TRUE(w.build(drop_scene(v1(1e3), DemIntegrator::abm4, 1e-4)).ok());
  double lowest = w.state.x[0][0];
  for (int k = 0; k < 15000; ++k) {  // 1.5 s: the first contact, and up towards the apex
    ASSERT_EQ(w.step(), StepStatus::ok);
    lowest = std::min(lowest, w.state.x[0][0]);
  }
  EXPECT_LT(lowest, 0.0) << "deeper than the radius";
  EXPECT_GT(w.state.x[0][0], 1.0) << "and out again";
  // A host moves a built particle as deep as it likes: its business.
  w.state.x[0][0] = -0.05;
  dem_restart_energy_ledger(w.model, w.state);
  dem_inputs_changed(w.state);
  EXPECT_EQ(w.step(), StepStatus::ok);
}

}  // namespace
}  // namespace xfdem::testing
