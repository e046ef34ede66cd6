// What build_coupled refuses beyond its halves' own checks, and how: the
// memory budget counts the coupled window's copies of the particles' state,
// and an allocation the system refuses (in either half) is a refusal.
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
  d.max_memory_bytes = 50'000'000;  // one state's 24 MB fits, three do not
  d.dem.max_memory_bytes = 0;
  CoupledWorld w;
  BuildResult r = w.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message),
            "dem.capacities.max_pairs: 1000000 pairs take 72 MB of the 72 MB the particles' arrays need (24 bytes a "
            "pair, in the state and the coupled window's 2 copies of it), more than the memory budget of 50 MB "
            "(max_memory_bytes)");
  EXPECT_EQ(w.model.bar.dofs, 0) << "refused before the bar was built";
  EXPECT_EQ(w.step(), StepStatus::not_built);
  // The coupled budget replaces the particles' own.
  d.max_memory_bytes = 80'000'000;
  d.dem.max_memory_bytes = 1;
  r = w.build(d);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(w.workspace.dem_start.pair_i.size(), 1'000'000u);
  EXPECT_EQ(w.workspace.dem_end.pair_i.size(), 1'000'000u);
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
            "dem.capacities.max_pairs: 1000000 pairs take 72 MB of the 72 MB the particles' arrays need (24 bytes a "
            "pair, in the state and the coupled window's 2 copies of it): the allocator could not provide them");
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

}  // namespace
}  // namespace xfdem::testing
