// Disks against a plate with a crack from a void (cells cut by both: the
// void's boundary on each side of the crack and the crack's faces outside
// the void are contact surfaces, plate_boundary.hpp):
//  - disks resting under gravity on the void's floor on either side of the
//    crack, the plate held at its bottom: the boundary's force on each is
//    its weight, and the supports' reactions (their virtual work over the
//    bottom row of cells, computed here from the plate's stresses) sum to
//    the weights;
//  - a free plate hit by undamped frictionless disks, one inside the void
//    falling onto the crack's mouth: total momentum constant, the exchange's
//    impulse and work books balanced (it creates no energy);
//  - no allocation in a step, the same bits on 1 and 2 workers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/coupled2d_scenes.hpp"
#include "support/coupled2d_sweep.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/coupling/plate_boundary.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"

using namespace xfdem;
using xfdem::testing::disk;
using xfdem::testing::plate;
using xfdem::testing::total_momentum;

namespace {

constexpr DemIntegrator kIntegrators[] = {DemIntegrator::symplectic_euler, DemIntegrator::verlet,
                                          DemIntegrator::rk4, DemIntegrator::abm4};

/// A 1 m × 1 m plate (16 × 16 cells, h = 0.0625) with a circular void of
/// radius 0.2 about (0.52, 0.6) and a free crack from its centre straight
/// down to a tip at y = 0.2: the crack leaves the void at its lowest point
/// (0.52, 0.4), inside the cell (8, 6), the only cell both cut (the crack's
/// line off the cell's centre and edges), and the tip's branch functions
/// reach no cell the void cuts.
constexpr double kCrackX = 0.52, kVoidY = 0.6, kVoidR = 0.2, kFloor = kVoidY - kVoidR;

PlateDiscontinuity crack_down_from(double x, double y) {
  PlateDiscontinuity crack;
  crack.name = "c1";
  crack.kind = PlateDiscontinuity::Kind::crack;
  crack.shape = PlateDiscontinuity::Shape::polyline;
  crack.points = {{x, y}, {x, 0.2}};
  return crack;
}

PlateDesc crack_from_a_void_plate(double youngs_modulus) {
  PlateDesc p = plate(youngs_modulus, 1, 1, 16, 16);
  p.discontinuities.push_back(xfdem::testing::circle(PlateDiscontinuity::Kind::hole, kCrackX, kVoidY, kVoidR));
  p.discontinuities.push_back(crack_down_from(kCrackX, kVoidY));
  return p;
}

/// The disks' stiffness, 5e4 N/m: the exchange settles at dt = 1e-4 s on the
/// lightest node of the cut cells (the build's ω dt ≤ 1).
///
/// The free plate hit by three undamped frictionless disks (no gravity): one
/// in the void falling onto the crack's mouth (a little to its + side), one
/// at the plate's bottom under the crack's tip, one at its right side.
Coupled2dDesc free_plate_hit(DemIntegrator integrator) {
  Coupled2dDesc d;
  d.plate = crack_from_a_void_plate(2e9);
  d.dem.integrator = integrator;
  d.dem.particles.push_back(disk(1.0, 0.05, 5e4, kCrackX + 0.004, kFloor + 0.07, 0.1, -2.0));  // in the void
  d.dem.particles.push_back(disk(2.0, 0.05, 5e4, kCrackX - 0.03, -0.07, 0.2, 2.5));          // bottom
  d.dem.particles.push_back(disk(1.5, 0.04, 5e4, 1.06, 0.37, -3.0, 0.3));                     // right
  d.dem_substeps = 10;
  return d;
}

/// What a disk's contacts with the boundary touch in the cell (8, 6), cut by
/// the void and the crack along x = crack_x: the void's boundary on the +
/// and − side (bits 1, 2), a face's end where the crack leaves the void (bit 4).
unsigned touched_in_the_cut_cell(const Coupled2dWorld& w, std::int32_t i, double crack_x, std::vector<double>& positions) {
  const PlateBoundary& b = w.model.boundary;
  plate_boundary_positions(w.model.plate, b, w.state.plate.u.data(), w.state.plate.time, positions.data());
  const double centre[2] = {w.state.dem.x[0][i], w.state.dem.x[1][i]};
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  const int count = plate_boundary_contacts(b, positions.data(), centre, w.model.dem.radius[i], contacts);
  unsigned bits = 0;
  for (int c = 0; c < count; ++c) {
    const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(contacts[c].segment)];
    if (s.cell[0] != 8 || s.cell[1] != 6) continue;
    const PlateBoundaryVertex& va = b.vertices[static_cast<std::size_t>(s.a)];
    const PlateBoundaryVertex& vb = b.vertices[static_cast<std::size_t>(s.b)];
    const bool face = std::fabs(va.x[0] - crack_x) < 1e-12 && std::fabs(vb.x[0] - crack_x) < 1e-12;
    if (contacts[c].vertex >= 0) {
      // A vertex where a face and the void's boundary meet.
      const PlateBoundaryVertex& v = b.vertices[static_cast<std::size_t>(contacts[c].vertex)];
      if (std::fabs(v.x[0] - crack_x) < 1e-12) bits |= 4u;
    }
    if (!face) bits |= s.side > 0 ? 1u : 2u;
  }
  return bits;
}

}  // namespace

// Held at its bottom (its 16 cells uncut), no self weight, E = 2e11 Pa: a
// rectangular void [0.28, 0.78] × [0.4, 0.78] and the crack from inside it
// (x = 0.535) down through its floor to a tip at y = 0.2. The floor's level
// set is linear in the cell both cut, (8, 6) = [0.5, 0.5625] × [0.375,
// 0.4375] (the floor is the nearest side there), so the traced floor is the
// line y = 0.4 on both sides of the crack: flat, it holds a frictionless
// disk where it lands (a curved floor lets it rock on, coupled2d_test.cpp).
// Two 0.5 kg disks (r = 8 mm) let go 2 mm above it, one on each side of the
// crack and both in that cell (2 cm and 1.5 cm from the crack's mouth, far
// beyond the √(2 r δ) = 1.3 mm at which the other side's lip would touch),
// come to rest (DEM damping 0.5, the plate's numerical damping γ = 0.6). At
// rest the boundary's force on each is its weight; the supports' reaction is
// the virtual work of the stresses over the bottom row of cells for w = the
// bottom nodes' shape functions (R_y = −(t/h_y) ∫ σ_yy dA, R_x = −(t/h_y)
// ∫ σ_xy dA, exact by 2 × 2 Gauss on the uncut cells): by the partition of
// unity the forces the disks put on the plate, spread through the cut
// cell's enriched functions of each side, plus the plate's inertia (0 at
// rest). Bounds as the disk resting in a void (coupled2d_test.cpp): 1e-6 of
// the weight.
TEST(Coupled2dCrackVoid, DisksRestingOnTheVoidsFloorEitherSideOfTheCrackCarryTheirWeightToTheSupports) {
  const double crack_x = 0.535, floor_y = 0.4;
  Coupled2dDesc d;
  d.plate = plate(2e11, 1, 1, 16, 16);
  PlateDesc& p = d.plate;
  PlateDiscontinuity hole;
  hole.name = "hole";
  hole.kind = PlateDiscontinuity::Kind::hole;
  hole.shape = PlateDiscontinuity::Shape::polygon;
  hole.points = {{0.28, floor_y}, {0.78, floor_y}, {0.78, 0.78}, {0.28, 0.78}};
  p.discontinuities.push_back(hole);
  p.discontinuities.push_back(crack_down_from(crack_x, 0.6));
  p.gamma = 0.6, p.beta = 0.3025;  // numerical damping: the plate's ringing after the drop dies out
  p.supports.push_back({PlateEdge::bottom, {true, true}, false});
  d.dem.integrator = DemIntegrator::symplectic_euler;
  d.dem.damping_ratio = 0.5;
  d.dem.gravity = {0.0, -9.81};
  const double m = 0.5, g = 9.81, r = 0.008;
  d.dem.particles.push_back(disk(m, r, 5e4, crack_x - 0.02, floor_y + r + 0.002, 0.0, 0.0));   // − side
  d.dem.particles.push_back(disk(m, r, 5e4, crack_x + 0.015, floor_y + r + 0.002, 0.0, 0.0));  // + side
  d.dem_substeps = 10;
  Coupled2dWorld w;
  const BuildResult built = w.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  ASSERT_GE(w.model.plate.cell_second_cut[6 * 16 + 8], 0);  // the cell both cut
  for (int step = 0; step < 10000; ++step) ASSERT_EQ(w.step(), StepStatus::ok) << step;
  std::vector<double> positions(2 * w.model.boundary.vertices.size());
  // The reactions: 2 × 2 Gauss over each cell of the bottom row.
  const double hx = 1.0 / 16, hy = 1.0 / 16, gp = 0.5 / std::sqrt(3.0);
  double reaction[2] = {0, 0};
  for (int i = 0; i < 16; ++i)
    for (int q = 0; q < 4; ++q) {
      const double x = (i + 0.5 + (q % 2 == 0 ? -gp : gp)) * hx, y = (0.5 + (q < 2 ? -gp : gp)) * hy;
      const double weight = 0.25 * hx * hy;
      reaction[0] -= p.thickness / hy * weight * plate_stress(w.model.plate, w.state.plate, x, y, 2);
      reaction[1] -= p.thickness / hy * weight * plate_stress(w.model.plate, w.state.plate, x, y, 1);
    }
  for (std::int32_t i = 0; i < 2; ++i) {
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, i, f));
    const unsigned touched = touched_in_the_cut_cell(w, i, crack_x, positions);
    const double speed = std::hypot(w.state.dem.v[0][i], w.state.dem.v[1][i]);
    std::printf("disk %d on the void's floor after 1 s: at (%.6f, %.9f), F_y - m g = %.3g N of %.4g N, F_x = %.3g N, "
                "speed %.3g m/s, on the floor's %s piece in the cell both cut\n",
                i, w.state.dem.x[0][i], w.state.dem.x[1][i], f[1] - m * g, m * g, f[0], speed,
                touched == 1u ? "+" : touched == 2u ? "-" : "(neither or both)");
    EXPECT_EQ(touched, i == 0 ? 2u : 1u);
    EXPECT_NEAR(w.state.dem.x[1][i], floor_y + r - m * g / 5e4, 1e-6);  // resting on the floor
    EXPECT_NEAR(f[1], m * g, 1e-6 * m * g);
    EXPECT_NEAR(f[0], 0.0, 1e-6 * m * g);
  }
  std::printf("- the supports' reactions: R_y - 2 m g = %.3g N of %.4g N, R_x = %.3g N\n", reaction[1] - 2 * m * g,
              2 * m * g, reaction[0]);
  EXPECT_NEAR(reaction[1], 2 * m * g, 1e-6 * 2 * m * g);
  EXPECT_NEAR(reaction[0], 0.0, 1e-6 * 2 * m * g);
}

// No supports, no gravity, no damping, no friction (E = 2e9 Pa); 600 steps
// with each integrator, every step ok (the coupled energy check, every 16
// steps, included). The bounds are the other free plates': the disks'
// impulse the plate's within 1e-12 of the exchange, the plate's work the
// disks' on the boundary it saw within 1e-9 of Σ|W| each step (not abm4: its
// corrector's books balance over the run) (coupled2d_test.cpp), and the
// total momentum within 1e-10 of Σ m|v| of the start (coupled2d_sweep_check.hpp:
// the plate's ∫ρv takes the round-off of its Newmark solves, here 16 × 16
// cells). The energy at contact-free instants is printed only: the disks'
// contacts close and open inside a substep, a kink none of the integrators
// follows to its order (the bouncing disk of coupled2d_test.cpp; the disk
// hitting the plate's plain right edge alone gains as much).
TEST(Coupled2dCrackVoid, FreePlateHitInsideTheVoidKeepsMomentumAndTheExchangeCreatesNoEnergy) {
  for (const DemIntegrator integrator : kIntegrators) {
    SCOPED_TRACE(integrator_name(integrator));
    Coupled2dWorld w;
    const BuildResult r = w.build(free_plate_hit(integrator));
    ASSERT_TRUE(r.ok()) << r.message;
    double scale = 0;
    for (std::int32_t i = 0; i < w.model.dem.n; ++i)
      scale += w.model.dem.mass[i] * std::hypot(w.state.dem.v[0][i], w.state.dem.v[1][i]);
    const double p0[2] = {total_momentum(w.model, w.state, 0), total_momentum(w.model, w.state, 1)};
    std::vector<double> positions(2 * w.model.boundary.vertices.size());
    bool touching = false;
    const double e0 = xfdem::testing::sweep_energy(w, positions, touching);
    double worst = 0, worst_books = 0, peak_exchange = 0, worst_work = 0, work_scale = 0, rise = -INFINITY;
    unsigned touched = 0;
    int free_instants = 0;
    for (int step = 0; step < 600; ++step) {
      const double before[2] = {w.state.work_on_plate, w.state.work_by_particles};
      ASSERT_EQ(w.step(), StepStatus::ok) << "step " << step;
      const double on_plate = w.state.work_on_plate - before[0], by_disks = w.state.work_by_particles - before[1];
      worst_work = std::max(worst_work, std::fabs(on_plate - by_disks));
      work_scale += std::fabs(on_plate);
      for (int axis = 0; axis < 2; ++axis) {
        worst = std::max(worst, std::fabs(total_momentum(w.model, w.state, axis) - p0[axis]));
        worst_books = std::max(worst_books,
                               std::fabs(w.state.impulse_to_particles[axis] + w.state.impulse_to_plate[axis]));
        peak_exchange = std::max(peak_exchange, std::fabs(w.state.impulse_to_particles[axis]));
      }
      touched |= touched_in_the_cut_cell(w, 0, kCrackX, positions);
      const double e = xfdem::testing::sweep_energy(w, positions, touching);
      if (!touching) rise = std::max(rise, e - e0), ++free_instants;
    }
    std::printf("%s, free plate with a crack from a void, 3 disks, 600 steps: momentum drift %.3g of %.3g kg m/s, "
                "books %.3g of %.3g N s, exchange work: worst step %.3g J of sum |W| %.3g J; the disk in the void "
                "touched the void's boundary on the%s%s side%s%s; energy at %d contact-free instants: largest rise "
                "%.3g J of E0 %.6g J\n",
                integrator_name(integrator), worst, scale, worst_books, peak_exchange, worst_work, work_scale,
                (touched & 1u) ? " +" : "", (touched & 2u) ? " -" : "", (touched & 3u) == 3u ? "s" : "",
                (touched & 4u) ? " and the faces' ends where the crack leaves it" : "", free_instants, rise, e0);
    EXPECT_EQ(touched, 7u);  // both sides' pieces and the faces' ends
    EXPECT_GT(peak_exchange, 0.5 * scale);  // the disks did hit and bounce
    EXPECT_LT(worst, 1e-10 * scale);
    EXPECT_LT(worst_books, 1e-12 * peak_exchange);
    EXPECT_GT(work_scale, 0.0);
    if (integrator != DemIntegrator::abm4) {
      EXPECT_LT(worst_work, 1e-9 * work_scale);
    }
  }
}

// The disk in the void 1 mm above the crack's mouth (it lands within the
// first steps), the disks in two parts: no allocation in a step, and one and
// two workers give the same bits, with every integrator.
TEST(Coupled2dCrackVoid, StepNeverAllocatesAndTwoWorkersGiveTheSameBits) {
  for (const DemIntegrator integrator : kIntegrators) {
    SCOPED_TRACE(integrator_name(integrator));
    Coupled2dDesc d = free_plate_hit(integrator);
    d.dem.split_from = 2;  // two parts of disks, so that a pool runs them on two workers
    d.dem.particles[0].position = {kCrackX + 0.004, kFloor + 0.051};
    Coupled2dWorld one, two;
    ASSERT_TRUE(one.build(d).ok());
    ASSERT_TRUE(two.build(d).ok());
    platform::TwoWorkerPool pool;
    two.workspace.dem.parallel = pool.parallel_for();
    {
      platform::AllocationCounter counter;
      for (int step = 0; step < 15; ++step) ASSERT_EQ(one.step(), StepStatus::ok);
      EXPECT_EQ(counter.allocations(), 0u);
    }
    for (int step = 0; step < 15; ++step) ASSERT_EQ(two.step(), StepStatus::ok);
    EXPECT_GT(std::fabs(one.state.impulse_to_particles[1]), 0.0);  // the disk in the void has landed by then
    for (std::int32_t i = 0; i < one.model.dem.n; ++i)
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_EQ(one.state.dem.x[axis][i], two.state.dem.x[axis][i]);
        EXPECT_EQ(one.state.dem.v[axis][i], two.state.dem.v[axis][i]);
      }
    EXPECT_EQ(one.state.plate.u, two.state.plate.u);
    EXPECT_EQ(one.state.plate.v, two.state.plate.v);
  }
}

// The crack's line inside the void has no material either side: a disk
// centred on it there is in the void and builds; centred on the crack's line
// below the void (in the plate) it is refused, naming the key.
TEST(Coupled2dCrackVoid, ADiskCentredOnTheCracksLineIsInTheVoidOnlyInsideIt) {
  Coupled2dDesc d = free_plate_hit(DemIntegrator::symplectic_euler);
  d.dem.particles[0].position = {kCrackX, kVoidY - 0.1};
  Coupled2dWorld in_void;
  const BuildResult r = in_void.build(d);
  EXPECT_TRUE(r.ok()) << r.message;
  d.dem.particles[0].position = {kCrackX, 0.3};
  Coupled2dWorld in_plate;
  const BuildResult refused = in_plate.build(d);
  EXPECT_FALSE(refused.ok());
  EXPECT_EQ(std::string(refused.message).rfind("dem.particles[0].position: its centre (0.52, 0.3) is inside the plate's material", 0), 0u)
      << refused.message;
}
