// The plate in time: Newmark (1/4, 1/2) conserves the energy of a free plate
// over 1e5 steps, the energy books balance with loads and dashpots, a column
// one cell wide on rollers with ν = 0 is the 1D bar, a step never allocates,
// and a copy of the state replays bit for bit.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/state_io.hpp"
#include "xfem/plate_fields.hpp"
#include "xfem/plate_free_vibration.hpp"
#include "xfem/reference.hpp"

using namespace xfdem;
using test::set_field;

namespace {

constexpr double kEps = DBL_EPSILON;

PlateDesc small_plate() {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 1.5, d.max[1] = 1.0;
  d.cells[0] = 3, d.cells[1] = 2;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.thickness = 1.0;
  d.dt = 1e-5;
  return d;
}

}  // namespace

// A plate vibrating freely (no loads), released from a deformed shape with a
// velocity that strains it: the trapezoidal rule conserves ½vᵀMv + ½uᵀKu of
// a linear system exactly, so over 1e5 steps it moves by round-off only.
// Clamped on the left edge, the displacements stay of the size of the
// vibration; unsupported, the plate also translates and rotates, and the
// round-off of K u grows with the rigid displacement (ε|K||u|, u reaching
// 0.1 m here against strains of 1e-5), which the momentum and energy show.
TEST(PlateDynamic, TrapezoidalRuleConservesEnergyOverAHundredThousandSteps) {
  for (const bool clamped : {true, false}) {
    PlateDesc d = small_plate();
    if (clamped) d.supports.push_back({PlateEdge::left, {true, true}, false});
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    ASSERT_TRUE(build_plate(d, m, st, ws).ok());
    set_field(m, st.u, [](double x, double y, int c) { return c == 0 ? 1e-5 * x * y : 1e-5 * (x * x - 0.5 * y); });
    set_field(m, st.v, [&](double x, double y, int c) {
      const double rigid = clamped ? 0.0 : (c == 0 ? 0.1 + 0.05 * y : -0.05 * x);
      return rigid + (c == 0 ? 0.02 * x * y : 0.03 * x * x);
    });
    ASSERT_EQ(plate_initial_acceleration(m, st, ws), StepStatus::ok);
    auto total = [&] {
      const PlateEnergy e = plate_energy(m, st);
      return e.kinetic + e.elastic;
    };
    const double e0 = total();
    const double p0[2] = {plate_momentum(m, st, 0), plate_momentum(m, st, 1)};
    const double p_scale = std::hypot(p0[0], p0[1]);
    double worst_e = 0.0, worst_p = 0.0, elastic_peak = 0.0;
    for (int step = 1; step <= 100000; ++step) {
      ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok) << step;
      if (step % 100 == 0) {
        worst_e = std::max(worst_e, std::fabs(total() - e0));
        elastic_peak = std::max(elastic_peak, plate_energy(m, st).elastic);
        for (int c = 0; c < 2; ++c) worst_p = std::max(worst_p, std::fabs(plate_momentum(m, st, c) - p0[c]));
      }
    }
    std::printf("%s plate, 1e5 steps of (1/4, 1/2): energy drift %.3g of E0 = %.6g J (%.3g relative), elastic "
                "peak %.3g J; momentum drift %.3g of %.3g kg m/s\n",
                clamped ? "clamped" : "free", worst_e, e0, worst_e / e0, elastic_peak, worst_p, p_scale);
    EXPECT_GT(elastic_peak, 0.05 * e0);  // energy really flows between the two forms
    EXPECT_EQ(st.energy.exceeded, 0);
    if (clamped) {
      EXPECT_LE(worst_e, 1e-12 * e0);
    } else {
      EXPECT_LE(worst_e, 1e-8 * e0);
      EXPECT_LE(worst_p, 1e-8 * p_scale);
    }
  }
}

// Loads of every kind (self weight, an edge traction, a point force) and an
// absorbing edge: Ê − Ê0 equals the booked work W to round-off for (1/4, 1/2),
// and stays below it for a dissipative (β, γ).
TEST(PlateDynamic, EnergyBooksBalanceWithLoadsAndDashpots) {
  for (const double gamma : {0.5, 0.6}) {
    PlateDesc d = small_plate();
    d.cells[0] = 6, d.cells[1] = 4;
    d.gamma = gamma;
    d.beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    d.dt = 2e-5;
    d.self_weight = true;
    d.gravity[1] = -9.81;
    d.supports.push_back({PlateEdge::left, {true, true}, false});
    d.supports.push_back({PlateEdge::bottom, {false, false}, true});
    PlateLoad traction;
    traction.edge = PlateEdge::top;
    traction.value[0] = 2e5, traction.value[1] = -1e6;
    traction.shape = PlateLoadShape::half_sine, traction.duration = 2e-4;
    PlateLoad point;
    point.kind = PlateLoad::Kind::point_force;
    point.at[0] = 1.2, point.at[1] = 0.6;
    point.value[0] = 1e4, point.value[1] = 3e4;
    d.loads = {traction, point};
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    ASSERT_TRUE(build_plate(d, m, st, ws).ok());
    EXPECT_FALSE(m.damper_dof.empty());
    double worst = 0.0, scale = 0.0, lowest = 0.0;
    for (int step = 1; step <= 3000; ++step) {
      ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok) << step;
      const double balance = plate_algorithmic_energy(m, st) - st.energy.reference - st.energy.work;
      scale = std::max(scale, std::fabs(st.energy.work) + plate_algorithmic_energy(m, st));
      worst = std::max(worst, balance);
      lowest = std::min(lowest, balance);
    }
    std::printf("energy books, gamma = %.2f: max (E - E0 - W) = %.3g, min %.3g, of a scale %.3g J\n", gamma, worst,
                lowest, scale);
    if (gamma == 0.5) {
      EXPECT_LE(std::fabs(worst), 1e-11 * scale);
      EXPECT_LE(std::fabs(lowest), 1e-11 * scale);
    } else {
      EXPECT_LE(worst, 1e-11 * scale);
      EXPECT_LT(lowest, -1e-4 * scale);  // the dissipation is real
    }
  }
}

// A column one cell wide on rollers (x held on the left and right edges, y on
// the bottom) with ν = 0, under the V2 rod's half-sine tip load split between
// the two top nodes, is the 1D bar: with ν = 0 and the nodes of a level moving
// together, the consistent Q4 mass and stiffness summed over a level are the
// bar's ρAh/6 [2 1; 1 2] and EA/h [1 −1; −1 1], A = width × thickness.
// With an absorbing bottom (Lysmer: ρ c_p per unit area, lumped to the two
// bottom nodes, c_p = √(E/ρ) for ν = 0) it is the bar on its absorbing base.
TEST(PlateDynamic, ColumnOnRollersWithZeroPoissonRatioIsTheBar) {
  for (const bool absorbing : {false, true})
  for (const double gamma : {0.5, 0.6}) {
    BarDesc bd = test::v2_rod(30, 1e-3);
    if (absorbing) bd.base = BarDesc::Base::absorbing;
    bd.gamma = gamma;
    bd.beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    BarModel bm;
    BarState bs;
    BarWorkspace bw;
    ASSERT_TRUE(build_bar(bd, bm, bs, bw).ok());

    const PlateDesc d = test::column_of(bd);
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    ASSERT_TRUE(build_plate(d, m, st, ws).ok());
    ASSERT_EQ(m.dofs, 2 * bd.elements + (absorbing ? 2 : 0));
    double worst_u = 0.0, worst_v = 0.0, worst_lr = 0.0, u_scale = 0.0, v_scale = 0.0;
    double worst_e = 0.0, e_peak = 0.0, bar_e_end = 0.0;
    for (int step = 1; step <= 3000; ++step) {
      ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok);
      ASSERT_EQ(bar_step(bm, bs, bw), StepStatus::ok);
      for (int j = 0; j <= bd.elements; ++j) {
        const double y = j == bd.elements ? bd.length : bd.length * j / bd.elements;
        const double ub = bar_displacement(bm, bs, y), vb = bar_velocity(bm, bs, y);
        const double ul = plate_displacement(m, st, 0.0, y, 1), ur = plate_displacement(m, st, 1.0, y, 1);
        u_scale = std::max(u_scale, std::fabs(ub));
        v_scale = std::max(v_scale, std::fabs(vb));
        worst_u = std::max({worst_u, std::fabs(ul - ub), std::fabs(ur - ub)});
        worst_lr = std::max(worst_lr, std::fabs(ul - ur));
        worst_v = std::max(worst_v, std::fabs(plate_velocity(m, st, 0.5, y, 1) - vb));
        EXPECT_EQ(plate_displacement(m, st, 0.5, y, 0), 0.0);
      }
      const PlateEnergy pe = plate_energy(m, st);
      const BarEnergy be = bar_energy(bm, bs);
      bar_e_end = be.kinetic + be.elastic;
      e_peak = std::max(e_peak, bar_e_end);
      worst_e = std::max({worst_e, std::fabs(pe.kinetic - be.kinetic), std::fabs(pe.elastic - be.elastic)});
    }
    std::printf("column vs bar (%s base), (beta, gamma) = (%.4g, %.2g), 3000 steps: displacement %.3g of %.3g m "
                "(%.1f eps), velocity %.3g of %.3g m/s (%.1f eps); left vs right node %.3g m\n",
                absorbing ? "absorbing" : "fixed", bd.beta, gamma, worst_u, u_scale, worst_u / (u_scale * kEps), worst_v, v_scale,
                worst_v / (v_scale * kEps), worst_lr);
    EXPECT_LE(worst_u, 1e-12 * u_scale);
    EXPECT_LE(worst_v, 1e-12 * v_scale);
    // Their energies are the same too, and an absorbing base lets the pulse out.
    std::printf("  energy: largest difference %.3g of a peak %.3g J; left at the end %.3g J\n", worst_e, e_peak,
                bar_e_end);
    EXPECT_LE(worst_e, 1e-12 * e_peak);
    if (absorbing) {
      EXPECT_LE(bar_e_end, 1e-6 * e_peak);  // (1/4, 1/2): 2.7e-7 left in the mesh's undamped modes
    }
  }
}

TEST(PlateDynamic, StepNeverAllocates) {
  PlateDesc d = small_plate();
  d.cells[0] = 8, d.cells[1] = 5;
  d.self_weight = true;
  d.gravity[1] = -9.81;
  d.supports.push_back({PlateEdge::left, {true, true}, false});
  d.supports.push_back({PlateEdge::right, {false, false}, true});
  d.prescribed.push_back({{0.75, 0.0}, {1e-6, 0.0}});
  PlateLoad traction;
  traction.edge = PlateEdge::top;
  traction.value[1] = -1e6;
  traction.shape = PlateLoadShape::half_sine, traction.duration = 1e-4;
  d.loads = {traction};
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  platform::AllocationCounter counter;
  double sink = 0.0;
  for (int i = 0; i < 2000; ++i) {
    EXPECT_EQ(plate_step(m, st, ws), StepStatus::ok);
    sink += plate_displacement(m, st, 1.0, 0.5, 0) + plate_velocity(m, st, 0.3, 0.2, 1) +
            plate_acceleration(m, st, 1.5, 1.0, 1) + plate_stress(m, st, 0.7, 0.7, 2) + plate_energy(m, st).elastic +
            plate_momentum(m, st, 1);
  }
  plate_initial_acceleration(m, st, ws);
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
  // The held node stays where it was put.
  EXPECT_EQ(plate_displacement(m, st, 0.75, 0.0, 0), 1e-6);
}

TEST(PlateDynamic, ACopyOfTheStateReplaysBitForBit) {
  PlateDesc d = small_plate();
  d.supports.push_back({PlateEdge::bottom, {true, true}, false});
  PlateLoad point;
  point.kind = PlateLoad::Kind::point_force;
  point.at[0] = 1.5, point.at[1] = 1.0;
  point.value[0] = 1e5;
  d.loads = {point};
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  for (int i = 0; i < 100; ++i) plate_step(m, st, ws);
  PlateState copy = st;
  PlateWorkspace ws2 = ws;
  for (int i = 0; i < 500; ++i) {
    plate_step(m, st, ws);
    plate_step(m, copy, ws2);
  }
  std::vector<const void*> a_ptrs;
  std::vector<std::size_t> bytes;
  st.for_each_field([&](const char*, const auto* data, std::size_t count) {
    a_ptrs.push_back(data);
    bytes.push_back(count * sizeof(*data));
  });
  std::size_t k = 0;
  copy.for_each_field([&](const char* name, const auto* data, std::size_t count) {
    ASSERT_EQ(count * sizeof(*data), bytes[k]) << name;
    EXPECT_EQ(std::memcmp(data, a_ptrs[k], bytes[k]), 0) << name;
    ++k;
  });
  EXPECT_EQ(k, 9u);
}

// The state's field manifest drives the state hash and snapshots: a restored
// snapshot replays bit for bit, and a snapshot of another plate is refused.
TEST(PlateDynamic, SnapshotRestoresAndReplaysBitForBit) {
  PlateDesc d = small_plate();
  d.supports.push_back({PlateEdge::left, {true, true}, false});
  PlateLoad traction;
  traction.edge = PlateEdge::right;
  traction.value[1] = -1e6;
  traction.shape = PlateLoadShape::half_sine, traction.duration = 3e-4;
  d.loads = {traction};
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  for (int i = 0; i < 100; ++i) plate_step(m, st, ws);
  std::vector<std::byte> buffer(snapshot_size(st));
  ASSERT_TRUE(save_snapshot(st, buffer, model_fingerprint(m)).ok());
  const std::uint64_t at_save = state_hash(st);
  for (int i = 0; i < 200; ++i) plate_step(m, st, ws);
  const std::uint64_t later = state_hash(st);
  EXPECT_NE(later, at_save);
  ASSERT_TRUE(restore_snapshot(st, buffer, model_fingerprint(m)).ok());
  EXPECT_EQ(state_hash(st), at_save);
  for (int i = 0; i < 200; ++i) plate_step(m, st, ws);
  EXPECT_EQ(state_hash(st), later);
  EXPECT_EQ(field_count(st), 9u);

  PlateDesc other = d;
  other.loads[0].value[1] = -2e6;  // same sizes, another model
  PlateModel m2;
  PlateState st2;
  PlateWorkspace ws2;
  ASSERT_TRUE(build_plate(other, m2, st2, ws2).ok());
  EXPECT_EQ(restore_snapshot(st2, buffer, model_fingerprint(m2)).status, SnapshotStatus::other_model);
}

// A plate with an edge crack (a tip) and a void, kicked and then unloaded:
// Newmark (1/4, 1/2) keeps its energy to round-off (the 1e5-step run is
// PlateLong.CrackedPlateWithAVoidKeepsItsEnergyOverAHundredThousandSteps,
// label `long`).
TEST(PlateDynamic, CrackedPlateWithAVoidKeepsItsEnergy) {
  const test::FreeVibration r = test::run_free_vibration(1000);
  ASSERT_TRUE(r.built);
  test::expect_energy_kept(r);  // drift printed: 1000 steps: 3.0e-14 of E0
}
