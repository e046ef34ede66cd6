// The grid broad phase finds exactly the contacts an all-pairs search finds,
// and every capacity overflow is a status with the state left untouched.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

/// A loose random cloud of n spheres in a box, falling under gravity onto the
/// floor: contacts form, break and the list is rebuilt many times. No pair
/// starts deeper than the smaller radius (the build refuses that).
template <int D>
DemDesc<D> cloud(int n, std::uint32_t seed) {
  DemDesc<D> d;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  d.gravity[D - 1] = -9.81;
  d.damping_ratio = 0.2;
  d.integrator = DemIntegrator::verlet;
  d.dt = 2e-5;
  const double side = 0.25 * std::pow(static_cast<double>(n), 1.0 / D) * 0.05;
  for (int i = 0; i < n; ++i) {
    ParticleDesc<D> p;
    p.mass = 0.01 * (1 + u(rng));
    p.radius = 0.004 * (1 + 0.5 * u(rng));
    p.stiffness = 1e4 * (1 + u(rng));
    for (int k = 0; k < D; ++k) p.velocity[k] = u(rng) - 0.5;
    do {
      for (int k = 0; k < D; ++k) p.position[k] = side * u(rng);
    } while (starts_too_deep(d.particles, p));
    d.particles.push_back(p);
  }
  for (int k = 0; k < D; ++k) {
    PlaneDesc<D> lo, hi;
    lo.normal[k] = 1;
    hi.normal[k] = -1;
    hi.point[k] = side;
    d.planes.push_back(lo);
    d.planes.push_back(hi);
  }
  return d;
}

template <int D>
void grid_matches_all_pairs(int n) {
  DemDesc<D> desc = cloud<D>(n, 7);
  DemDesc<D> brute = desc;
  desc.all_pairs_up_to = 0;  // force the grid
  brute.all_pairs_up_to = n;  // every pair, never rebuilt
  DemWorld<D> grid, all;
  ASSERT_TRUE(grid.build(desc).ok());
  ASSERT_TRUE(all.build(brute).ok());
  ASSERT_EQ(grid.model.features.broad_phase, BroadPhase::grid);
  ASSERT_EQ(all.model.features.broad_phase, BroadPhase::all_pairs);
  for (int s = 0; s < 3000; ++s) {
    ASSERT_EQ(grid.step(), StepStatus::ok);
    ASSERT_EQ(all.step(), StepStatus::ok);
  }
  // Both lists are sorted by (i, j) and pairs out of reach add nothing, so the
  // forces are summed in the same order: the trajectories agree to the bit.
  for (int k = 0; k < D; ++k)
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(grid.state.x[k][i], all.state.x[k][i]) << "particle " << i;
      ASSERT_EQ(grid.state.v[k][i], all.state.v[k][i]) << "particle " << i;
    }
  EXPECT_GT(grid.state.list_builds, 3);  // the test exercised rebuilds
  EXPECT_GT(grid.state.peak_pairs, 0);
}

TEST(BroadPhase, GridEqualsAllPairsBitwise2D) { grid_matches_all_pairs<2>(300); }
TEST(BroadPhase, GridEqualsAllPairsBitwise3D) { grid_matches_all_pairs<3>(400); }
TEST(BroadPhase, GridEqualsAllPairsBitwise1D) { grid_matches_all_pairs<1>(60); }

TEST(BroadPhase, OneParticleSkipsTheBroadPhase) {
  DemWorld<1> w;
  ASSERT_TRUE(w.build(drop_scene({}, DemIntegrator::abm4, 1e-4)).ok());
  EXPECT_EQ(w.model.features.broad_phase, BroadPhase::none);
  EXPECT_TRUE(w.model.features.gravity);
  EXPECT_TRUE(w.model.features.damped);
}

template <int D>
void expect_untouched_after(DemWorld<D>& w, StepStatus flag) {
  const DemState<D> before = w.state;
  const StepStatus status = w.step();
  EXPECT_TRUE(has(status, flag)) << "got " << static_cast<unsigned>(status);
  EXPECT_EQ(w.state.time, before.time);
  EXPECT_EQ(w.state.step, before.step);
  for (int k = 0; k < D; ++k) {
    EXPECT_EQ(w.state.x[k], before.x[k]);
    EXPECT_EQ(w.state.v[k], before.v[k]);
  }
}

TEST(Capacities, PairOverflowIsAStatusAndTheStepIsNotTaken) {
  DemDesc<3> d = cloud<3>(200, 3);
  d.all_pairs_up_to = 0;
  DemWorld<3> w;
  ASSERT_TRUE(w.build(d).ok());
  // Squeeze every particle into one spot: far more pairs than capacity.
  const int cap = w.model.capacities.max_pairs;
  ASSERT_GT(cap, 0);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 200; ++i) w.state.x[k][i] = 0.05 + 1e-4 * i * (k + 1);
  expect_untouched_after(w, StepStatus::pair_capacity);
}

TEST(Capacities, NeighbourOverflowIsAStatus) {
  DemDesc<2> d = cloud<2>(100, 4);
  d.all_pairs_up_to = 0;
  d.capacities.max_neighbors_per_particle = 2;
  d.capacities.max_pairs = 100000;
  for (auto& p : d.particles) p.position = {0.01, 0.01};  // all on one spot
  for (int i = 0; i < 100; ++i) d.particles[i].position[0] += 1e-5 * i;
  DemWorld<2> w;
  const BuildResult r = w.build(d);
  // The initial configuration already needs more: the build says which capacity.
  EXPECT_EQ(r.code, BuildResult::Code::capacity);
  EXPECT_NE(std::strstr(r.message, "neighbor_capacity"), nullptr) << r.message;
}

TEST(Capacities, GridOverflowWhenParticlesSpreadTooFar) {
  DemDesc<2> d = cloud<2>(50, 5);
  d.all_pairs_up_to = 0;
  d.capacities.max_grid_cells = 100000;
  DemWorld<2> w;
  ASSERT_TRUE(w.build(d).ok());
  w.state.x[0][7] = 1e6;  // one particle thrown very far: the bounding box needs ~1e16 cells
  w.state.x[1][7] = 1e6;
  expect_untouched_after(w, StepStatus::grid_capacity);
}

TEST(Capacities, NonFiniteStateIsReportedWithinOneStep) {
  DemDesc<2> d = cloud<2>(50, 6);
  d.all_pairs_up_to = 0;
  DemWorld<2> w;
  ASSERT_TRUE(w.build(d).ok());
  w.state.v[0][3] = NAN;
  EXPECT_TRUE(has(w.step(), StepStatus::non_finite));
}

TEST(ContactLaw, NonTensileForceNeverPulls) {
  DropParameters p;
  p.zeta = 0.5;  // a strong dashpot would pull hard at the end of a linear contact
  DemDesc<1> d = drop_scene(p, DemIntegrator::abm4_events, 1e-4);
  DemDesc<1> n = d;
  n.law = ContactLaw::linear_nontensile;
  DemWorld<1> lin, non;
  ASSERT_TRUE(lin.build(d).ok());
  ASSERT_TRUE(non.build(n).ok());
  double min_linear = 0, min_nontensile = 0, apex_linear = 0, apex_nontensile = 0;
  for (int s = 0; s < 15000; ++s) {  // the first bounce: impact at 0.77 s, apex near 1.3 s
    ASSERT_EQ(lin.step(), StepStatus::ok);
    ASSERT_EQ(non.step(), StepStatus::ok);
    min_linear = std::min(min_linear, dem_plane_force(lin.model, lin.state, 0, 0));
    min_nontensile = std::min(min_nontensile, dem_plane_force(non.model, non.state, 0, 0));
    if (lin.state.time > 0.9) {
      apex_linear = std::max(apex_linear, lin.state.x[0][0]);
      apex_nontensile = std::max(apex_nontensile, non.state.x[0][0]);
    }
  }
  EXPECT_LT(min_linear, -1.0);  // the linear law pulls before the overlap closes
  EXPECT_EQ(min_nontensile, 0.0);
  // Without the pull the sphere leaves earlier and faster: it bounces higher.
  EXPECT_GT(apex_nontensile, apex_linear);
}

}  // namespace
}  // namespace xfdem::testing
