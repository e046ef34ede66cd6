// What build_coupled refuses beyond its halves' own checks, and how: the
// memory budget counts the coupled window's copies of the particles' state,
// an allocation the system refuses (in either half) is a refusal, and a
// particle may not start inside the bar.
#include <gtest/gtest.h>

#include <string>

#include "support/coupled_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"

namespace xfdem::testing {
namespace {

/// Case II with its two particles on a grid whose pair list holds a million entries (24 MB a state).
CoupledDesc case2_with_a_large_pair_list() {
  CoupledDesc d = coupled_scene("case2_xfem.json");
  d.dem.all_pairs_up_to = 0;
  d.dem.capacities.max_pairs = 1'000'000;
  return d;
}

TEST(CoupledBuild, MemoryBudgetCountsTheWindowsCopiesOfTheParticleState) {
  CoupledDesc d = case2_with_a_large_pair_list();
  d.max_memory_bytes = 50'000'000;  // one state's 24 MB fits, five do not
  d.dem.max_memory_bytes = 0;
  CoupledWorld w;
  BuildResult r = w.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message),
            "dem.capacities.max_pairs: 1000000 pairs take 120 MB of the 120 MB the particles' arrays need (24 bytes a "
            "pair, in the state, the coupled window's 3 copies of it and its sensitivity to the force, counted as a "
            "fifth), more than the memory budget of 50 MB (max_memory_bytes)");
  EXPECT_EQ(w.model.bar.dofs, 0) << "refused before the bar was built";
  EXPECT_EQ(w.step(), StepStatus::not_built);
  // The coupled budget replaces the particles' own.
  d.max_memory_bytes = 130'000'000;
  d.dem.max_memory_bytes = 1;
  r = w.build(d);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(w.workspace.dem_start.pair_i.size(), 1'000'000u);
  EXPECT_EQ(w.workspace.dem_end.pair_i.size(), 1'000'000u);
  EXPECT_EQ(w.workspace.dem_first.pair_i.size(), 1'000'000u);
}

TEST(CoupledBuild, AnAllocationTheSystemRefusesIsARefusalNotAnException) {
  const CoupledDesc d = case2_with_a_large_pair_list();
  CoupledWorld w;
  BuildResult r;
  {
    platform::ScopedAllocationLimit limit(5'000'000);  // a state's pair_stiffness is 8 MB
    EXPECT_NO_THROW(r = w.build(d));
  }
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message),
            "dem.capacities.max_pairs: 1000000 pairs take 120 MB of the 120 MB the particles' arrays need (24 bytes a "
            "pair, in the state, the coupled window's 3 copies of it and its sensitivity to the force, counted as a "
            "fifth): the allocator could not provide them");
  EXPECT_EQ(w.step(), StepStatus::not_built);
  EXPECT_TRUE(w.state.dem.pair_i.empty());  // nothing is left allocated

  // The bar's arrays, sized by its elements.
  CoupledDesc fine = coupled_scene("case2_xfem.json");
  fine.bar.elements = 1'000'000;
  {
    platform::ScopedAllocationLimit limit(1'000'000);
    EXPECT_NO_THROW(r = w.build(fine));
  }
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message), "bar.elements: the allocator could not provide the arrays of 1000000 elements");
  {  // the bar alone
    BarModel model;
    BarState state;
    BarWorkspace workspace;
    platform::ScopedAllocationLimit limit(1'000'000);
    EXPECT_NO_THROW(r = build_bar(fine.bar, model, state, workspace));
    EXPECT_EQ(std::string(r.message), "elements: the allocator could not provide the arrays of 1000000 elements");
    EXPECT_FALSE(model.built);
  }
}

TEST(CoupledBuild, AParticleStartingInsideTheBarIsRefusedNamingIt) {
  CoupledDesc d = coupled_scene("case1_xfem.json");  // m = 100 kg, r = 0.5 m, k = 1e7 N/m; tip at 30 m
  d.dem.particles[0].position = {28.5};
  CoupledWorld w;
  BuildResult r = w.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::invalid_argument);
  // ω = √(k (1/m_top + 1/m)), m_top = 400 kg (the tip's share of the top element): 354 rad/s.
  EXPECT_EQ(std::string(r.message),
            "dem.particles[0].position: overlaps the bar's tip by 2 m at the start, more than its radius 0.5 m (its "
            "centre is inside the bar): its contact would throw it out at up to 707 m/s");
  EXPECT_EQ(w.step(), StepStatus::not_built);
  d.dem.particles[0].position = {30.0};  // centre on the tip: overlap = radius
  EXPECT_TRUE(w.build(d).ok());
  d.dem.particles[0].position = {30.25};  // resting at half its radius
  EXPECT_TRUE(w.build(d).ok());
  // Particle pairs as build_dem checks them.
  CoupledDesc two = coupled_scene("case2_xfem.json");
  two.dem.particles[1].position = {33.6};
  r = w.build(two);
  EXPECT_EQ(std::string(r.message),
            "dem.particles[1].position: overlaps particles[0] by 0.7 m at the start, more than the smaller radius 0.3 "
            "m: their contact would throw them apart at up to 271 m/s");
}

}  // namespace
}  // namespace xfdem::testing
