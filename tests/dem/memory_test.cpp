// What a build costs in memory: dem_memory() counts exactly the arrays
// build_dem() sizes, a description past DemDesc::max_memory_bytes is refused
// before a byte is allocated, naming the capacity (or the particle count) that
// takes the most, and an allocation the system refuses is a refusal, not an
// exception.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/dem_scenes.hpp"
#include "xfdem/platform/alloc_guard.hpp"

namespace xfdem::testing {
namespace {

template <class T>
std::uint64_t bytes(const std::vector<T>& v) {
  return v.size() * sizeof(T);
}
template <class T, std::size_t N>
std::uint64_t bytes(const std::array<std::vector<T>, N>& columns) {
  std::uint64_t sum = 0;
  for (const auto& c : columns) sum += bytes(c);
  return sum;
}

template <int D>
std::uint64_t model_bytes(const DemModel<D>& m) {
  return bytes(m.mass) + bytes(m.inv_mass) + bytes(m.radius) + bytes(m.stiffness) + bytes(m.plane_eta) +
         bytes(m.plane_point) + bytes(m.plane_normal) + bytes(m.inv_inertia) + bytes(m.hertz_inv_e) +
         bytes(m.hertz_inv_g) + bytes(m.plane_inv_e) + bytes(m.plane_inv_g);
}

template <int D>
std::uint64_t state_bytes(const DemState<D>& s) {
  std::uint64_t sum = bytes(s.x) + bytes(s.v) + bytes(s.external_force) + bytes(s.x_ref) + bytes(s.pair_i) +
                      bytes(s.pair_j) + bytes(s.pair_stiffness) + bytes(s.pair_eta) + bytes(s.plane_offset) +
                      bytes(s.plane_speed) + bytes(s.plane_impulse) + bytes(s.w) + bytes(s.angle) +
                      bytes(s.pair_xi) + bytes(s.plane_xi);
  for (int k = 0; k < 4; ++k)
    sum += bytes(s.hist_v[k]) + bytes(s.hist_a[k]) + bytes(s.hist_plane_force[k]) + bytes(s.hist_w[k]) +
           bytes(s.hist_alpha[k]);
  return sum;
}

template <int D>
std::uint64_t workspace_bytes(const DemWorkspace<D>& w) {
  return bytes(w.xs) + bytes(w.vs) + bytes(w.as) + bytes(w.sum_x) + bytes(w.sum_v) + bytes(w.x0) + bytes(w.v0) +
         bytes(w.a0) + bytes(w.x1) + bytes(w.v1) + bytes(w.cell_start) + bytes(w.cell_particles) +
         bytes(w.particle_cell) + bytes(w.cross) + bytes(w.plane_force_part) + bytes(w.plane_force) +
         bytes(w.plane_force0) + bytes(w.plane_weighted) + bytes(w.plane_step_impulse) + bytes(w.network_row) +
         bytes(w.w1) + bytes(w.alpha1) + bytes(w.angle1) + bytes(w.old_pair_i) + bytes(w.old_pair_j) +
         bytes(w.old_pair_xi) + bytes(w.ws) + bytes(w.alphas) + bytes(w.sum_w) + bytes(w.angle_s) +
         bytes(w.sum_angle) + bytes(w.cross_spin);
}

/// n particles on a lattice 3 radii apart (no two touch) above a floor, in D dimensions.
template <int D>
DemDesc<D> lattice(int n) {
  DemDesc<D> d;
  d.gravity[D - 1] = -9.81;
  d.damping_ratio = 0.1;
  d.dt = 1e-4;
  for (int i = 0; i < n; ++i) {
    ParticleDesc<D> p{0.01, 0.01, 1e4, {}, {}};
    for (int k = 0; k < D; ++k) p.position[k] = 0.05 + 0.03 * ((i >> (3 * k)) & 7);
    d.particles.push_back(p);
  }
  PlaneDesc<D> floor;
  floor.normal[D - 1] = 1;
  d.planes.push_back(floor);
  return d;
}

template <int D>
void expect_counted_exactly(const DemDesc<D>& d, BroadPhase expected) {
  DemWorld<D> w;
  const BuildResult r = w.build(d);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(w.model.features.broad_phase, expected);
  const DemMemory m = dem_memory(d);
  EXPECT_EQ(m.model, model_bytes(w.model));
  EXPECT_EQ(m.state, state_bytes(w.state));
  EXPECT_EQ(m.workspace, workspace_bytes(w.workspace));
  EXPECT_EQ(m.pairs, w.model.capacities.max_pairs);
  EXPECT_EQ(m.grid_cells, w.model.capacities.max_grid_cells);
}

TEST(Memory, DemMemoryCountsEveryArrayTheBuildSizes) {
  DemDesc<3> grid = lattice<3>(40);
  grid.all_pairs_up_to = 0;
  grid.split_from = 20;  // two parts: the cross buffer is sized
  grid.external_forces = true;
  grid.capacities.max_pairs = 5000;
  expect_counted_exactly(grid, BroadPhase::grid);
  expect_counted_exactly(lattice<2>(6), BroadPhase::all_pairs);
  expect_counted_exactly(lattice<1>(1), BroadPhase::none);
  EXPECT_EQ(dem_memory(grid).total(3), dem_memory(grid).total() + 2 * dem_memory(grid).state);
  // Rotating particles: their angular columns and the contact records
  // (tangential springs of the pair list and of each particle–plane contact).
  for (DemDesc<3> rotating : {grid, lattice<3>(6)}) {
    rotating.friction = 0.4;
    rotating.integrator = DemIntegrator::verlet;
    expect_counted_exactly(rotating, rotating.particles.size() > 8 ? BroadPhase::grid : BroadPhase::all_pairs);
    EXPECT_EQ(dem_memory(rotating).bytes_per_pair, DemMemory::kBytesPerPair + 3 * sizeof(double));
  }
  DemDesc<2> disks = lattice<2>(6);
  disks.rolling_friction = 0.1;
  disks.integrator = DemIntegrator::symplectic_euler;
  expect_counted_exactly(disks, BroadPhase::all_pairs);
}

TEST(Memory, PastTheBudgetIsRefusedBeforeAnythingIsAllocatedNamingTheCapacity) {
  DemDesc<3> d = lattice<3>(20);
  d.all_pairs_up_to = 0;
  d.capacities.max_pairs = 1'000'000;  // 24 MB of pair list
  d.max_memory_bytes = 10'000'000;
  DemWorld<3> w;
  BuildResult r;
  {
    platform::AllocationCounter counter;
    r = w.build(d);
    EXPECT_EQ(counter.allocations(), 0u) << "refused before allocating";
  }
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message),
            "capacities.max_pairs: 1000000 pairs take 24 MB of the 24 MB the particles' arrays need (24 bytes a pair), "
            "more than the memory budget of 10 MB (max_memory_bytes)");
  EXPECT_EQ(w.step(), StepStatus::not_built);

  // The grid's index, when it is the capacity that takes the most.
  d.capacities.max_pairs = 0;
  d.capacities.max_grid_cells = 5'000'000;  // 20 MB
  r = w.build(d);
  EXPECT_EQ(std::string(r.message),
            "capacities.max_grid_cells: 5000000 grid cells take 20 MB of the 20 MB the particles' arrays need (4 bytes "
            "a cell), more than the memory budget of 10 MB (max_memory_bytes)");

  // No capacity given: the particles (with their default capacities) answer for it.
  d.capacities.max_grid_cells = 0;
  const std::uint64_t total = dem_memory(d).total();
  d.max_memory_bytes = total - 1;
  r = w.build(d);
  char expected[320];
  std::snprintf(expected, sizeof(expected),
                "particles: 20 particles take %.3g kB of the %.3g kB the particles' arrays need (%.3g kB a particle), "
                "more than the memory budget of %.3g kB (max_memory_bytes)",
                static_cast<double>(total) / 1e3, static_cast<double>(total) / 1e3,
                static_cast<double>(total) / 20 / 1e3, static_cast<double>(total - 1) / 1e3);
  EXPECT_EQ(std::string(r.message), expected);
  // Exactly the budget: built.
  d.max_memory_bytes = total;
  EXPECT_TRUE(w.build(d).ok());
  d.max_memory_bytes = 0;  // no budget
  EXPECT_TRUE(w.build(d).ok());
}

TEST(Memory, AnAllocationTheSystemRefusesIsARefusalNotAnException) {
  DemDesc<3> d = lattice<3>(20);
  d.all_pairs_up_to = 0;
  d.capacities.max_pairs = 1'000'000;  // pair_i alone is 4 MB
  DemWorld<3> w;
  BuildResult r;
  {
    platform::ScopedAllocationLimit limit(1'000'000);
    EXPECT_NO_THROW(r = w.build(d));
  }
  EXPECT_EQ(r.code, BuildResult::Code::memory);
  EXPECT_EQ(std::string(r.message),
            "capacities.max_pairs: 1000000 pairs take 24 MB of the 24 MB the particles' arrays need (24 bytes a pair): "
            "the allocator could not provide them");
  EXPECT_EQ(w.step(), StepStatus::not_built);
  EXPECT_TRUE(w.state.pair_i.empty());  // nothing is left allocated
  EXPECT_TRUE(w.build(d).ok());         // and the same description builds where memory allows
}

TEST(Memory, CapacityBoundsAreTheIndexTypes) {
  DemDesc<3> d = lattice<3>(20);
  d.all_pairs_up_to = 0;
  d.capacities.max_grid_cells = 2147483647;
  DemWorld<3> w;
  const BuildResult r = w.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::capacity);
  EXPECT_EQ(std::string(r.message), "capacities.max_grid_cells: 2147483647 is more than this build can index (2147483646)");
  // All with all: n(n−1)/2 entries past an int32.
  DemDesc<1> many;
  many.dt = 1e-4;
  many.all_pairs_up_to = 70'000;
  for (int i = 0; i < 70'000; ++i) many.particles.push_back({1.0, 0.1, 1e3, {i * 1.0}, {0.0}});
  DemWorld<1> all;
  const BuildResult r1 = all.build(many);
  EXPECT_EQ(r1.code, BuildResult::Code::capacity);
  EXPECT_EQ(std::string(r1.message),
            "particles: 70000 particles paired all with all need 2449965000 pairs, more than this build can index "
            "(2147483647); lower all_pairs_up_to");
}

}  // namespace
}  // namespace xfdem::testing
