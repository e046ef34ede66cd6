// Disks against a plate with a free crack across inclusions (cells cut by a
// crack and an inclusion: the crack's faces are contact surfaces, each with
// its side's functions, the inclusion's boundary is not, plate_boundary.hpp):
//  - a free plate whose two parts move apart across the crack, hit by
//    undamped frictionless disks, one coming down inside the opening crack
//    onto a face where it runs in the inclusion, one on the edge across the
//    inclusion: total momentum constant, the exchange's impulse and work
//    books balanced (it creates no energy), with the linear law and hertz;
//  - hertz: each segment's compliance is its material's at the segment;
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
#include "xfdem/xfem/level_set.hpp"

using namespace xfdem;
using xfdem::testing::disk;
using xfdem::testing::plate;
using xfdem::testing::total_momentum;

namespace {

constexpr DemIntegrator kIntegrators[] = {DemIntegrator::symplectic_euler, DemIntegrator::verlet,
                                          DemIntegrator::rk4, DemIntegrator::abm4};

/// A 1 m × 1 m plate (16 × 16 cells, h = 0.0625, E = 2e8 Pa) cut by a free
/// crack y = 0.53 from edge to edge (two free parts), through two inclusions
/// (E = 6e8 Pa, ν = 0.25, ρ = 3000 kg/m³): a circle about (−0.06, 0.47) of
/// radius 0.1, which crosses the left edge at y = 0.39 and 0.55 and the
/// crack at x = 0.02, both inside the cell (0, 8) = [0, 0.0625] × [0.5,
/// 0.5625], the edge's cell both cut; and a circle about (0.55, 0.5) of
/// radius 0.15 inside the plate. In the cell (0, 8) the inclusion's level
/// set, linear on the sub-triangle, is zero on the crack's line at x =
/// 0.0149 (the circle at 0.02): the faces are in the inclusion from the
/// mouth to there.
constexpr double kCrackY = 0.53;
constexpr std::size_t kEdgeCell = 8 * 16 + 0;

PlateDesc crack_across_inclusions_plate() {
  PlateDesc p = plate(2e8, 1, 1, 16, 16);
  PlateDiscontinuity crack;
  crack.name = "c1";
  crack.kind = PlateDiscontinuity::Kind::crack;
  crack.shape = PlateDiscontinuity::Shape::polyline;
  crack.points = {{-0.2, kCrackY}, {1.2, kCrackY}};
  p.discontinuities.push_back(crack);
  PlateDiscontinuity at_edge = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, -0.06, 0.47, 0.1, "at_edge");
  at_edge.material = {6e8, 0.25, 3000};
  p.discontinuities.push_back(at_edge);
  PlateDiscontinuity inner = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, 0.55, 0.5, 0.15, "inner");
  inner.material = {6e8, 0.25, 3000};
  p.discontinuities.push_back(inner);
  return p;
}

/// The disks' stiffness (linear law), 5e4 N/m, as the crack-from-a-void
/// scene's: the exchange settles at dt = 1e-4 s (the build's ω dt ≤ 1).
/// The moduli are a tenth of that scene's: the parts' rigid motion carries
/// u up to 6 cm, and the round-off of K u, which moves the plate's momentum,
/// grows with E (at E = 2e9 Pa and 6e9 Pa in the inclusions the drift was
/// 5.5e-9 to 7.2e-9 kg m/s, the same at a tenth of the density).
///
/// The free plate, its two parts moving apart at 1 m/s each (pull_apart),
/// hit by four undamped frictionless disks (no gravity): a 0.1 kg disk (r =
/// 1 cm) that enters the opening crack at its mouth (0.5 mm clear of the
/// lower lip's corner) and comes down onto the lower part's face inside the
/// inclusion (at x ≈ 0.008 m, 1.1 m/s down against the part's 1 m/s); one on
/// the left edge across the inclusion below the crack; one at the plate's
/// right side; one on its top. The boundary may move 0.1 m (the parts move
/// 0.06 m in the 600 steps). Hertz: soft disks (E = 1e7 Pa, ν = 0.3).
Coupled2dDesc free_plate_hit(DemIntegrator integrator, bool hertz) {
  Coupled2dDesc d;
  d.plate = crack_across_inclusions_plate();
  d.dem.integrator = integrator;
  d.boundary_allowance = 0.1;
  d.dem.particles.push_back(disk(0.1, 0.01, 5e4, -0.032, kCrackY + 0.0125, 1.6, -1.1));  // into the crack
  d.dem.particles.push_back(disk(1.5, 0.04, 5e4, -0.05, 0.43, 2.5, 0.2));       // the edge across the inclusion
  d.dem.particles.push_back(disk(1.5, 0.04, 5e4, 1.06, 0.37, -3.0, 0.3));       // right
  d.dem.particles.push_back(disk(2.0, 0.05, 5e4, 0.4, 1.07, 0.1, -2.0));        // top
  if (hertz) {
    d.dem.law = ContactLaw::hertz;
    for (ParticleDesc<2>& p : d.dem.particles) p.stiffness = 0.0, p.youngs_modulus = 1e7, p.poisson_ratio = 0.3;
  }
  d.dem_substeps = 10;
  return d;
}

/// Sets the plate moving apart at `speed` (m/s) across the crack: its part
/// above (the crack's + side) at +speed in y, its part below at −speed, a
/// rigid motion of each (no stress): the field speed·H(x) ŷ, H = ±1 the
/// side, is Σ N_a speed H(x_a) + Σ N_a (H(x) − H(x_a)) speed over the
/// crack's Heaviside functions (the ridge's unknowns 0).
void pull_apart(Coupled2dWorld& w, double speed) {
  const PlateModel& m = w.model.plate;
  for (int n = 0; n < m.nodes; ++n) {
    const double h = xfem::side_of(m.node_phi[static_cast<std::size_t>(n)]);  // the crack is discontinuity 0
    const int dof = m.node_dof[static_cast<std::size_t>(2 * n + 1)];
    if (dof >= 0) w.state.plate.v[static_cast<std::size_t>(dof)] = speed * h;
    for (int s = 0; s < 2; ++s) {
      if (m.node_enrichment[static_cast<std::size_t>(2 * n + s)] != 0) continue;
      const int e = m.enriched_dof[static_cast<std::size_t>(2 * (2 * n + s) + 1)];
      if (e >= 0) w.state.plate.v[static_cast<std::size_t>(e)] = speed;
    }
  }
  coupled2d_restart_energy_ledger(w.model, w.state, w.workspace);  // the state was edited
}

/// What a disk's contacts touch: the crack's + and − face (bits 1, 2; a
/// segment on the crack's line), a face in the inclusion's material (bit
/// 4), the left edge in the inclusion's material (bit 8).
unsigned touched(const Coupled2dWorld& w, std::int32_t i, std::vector<double>& positions) {
  const PlateBoundary& b = w.model.boundary;
  plate_boundary_positions(w.model.plate, b, w.state.plate.u.data(), w.state.plate.time, positions.data());
  const double centre[2] = {w.state.dem.x[0][i], w.state.dem.x[1][i]};
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  const int count = plate_boundary_contacts(b, positions.data(), centre, w.model.dem.radius[i], contacts);
  unsigned bits = 0;
  for (int c = 0; c < count; ++c) {
    const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(contacts[c].segment)];
    const double* xa = b.vertices[static_cast<std::size_t>(s.a)].x;
    const double* xb = b.vertices[static_cast<std::size_t>(s.b)].x;
    const bool inclusion = plate_boundary_segment_material(w.model.plate, s) > 0;
    if (std::fabs(xa[1] - kCrackY) < 1e-12 && std::fabs(xb[1] - kCrackY) < 1e-12)
      bits |= (s.side > 0 ? 1u : 2u) | (inclusion ? 4u : 0u);
    else if (xa[0] == 0.0 && xb[0] == 0.0 && inclusion)
      bits |= 8u;
  }
  return bits;
}

}  // namespace

// No supports, no gravity, no damping, no friction, the plate's parts
// moving apart; 600 steps with each integrator (linear law) and with
// symplectic Euler under hertz, every step ok (the coupled energy check,
// every 16 steps, included). The bounds are the other free plates'
// (coupled2d_crack_void_test.cpp): the disks' impulse the plate's within
// 1e-12 of the exchange, the plate's work the disks' on the boundary it saw
// within 1e-9 of Σ|W| each step (not abm4: its corrector's books balance
// over the run), and the total momentum within 1e-10 of the disks' Σ m|v|
// at the start (the plate's parts' own momentum, about 3500 and 4000 kg m/s,
// not counted in it). The disk in the crack touches the lower part's face
// in the inclusion's material; the edge's disk the edge in it. The energy at
// contact-free instants is printed only (as there).
TEST(Coupled2dCrackInclusion, FreePlateHitOnACrackFaceAndAcrossTheInclusionKeepsMomentumAndTheExchangeCreatesNoEnergy) {
  struct Case {
    DemIntegrator integrator;
    bool hertz;
  };
  const Case cases[] = {{DemIntegrator::symplectic_euler, false}, {DemIntegrator::verlet, false},
                        {DemIntegrator::rk4, false}, {DemIntegrator::abm4, false},
                        {DemIntegrator::symplectic_euler, true}};
  for (const Case& k : cases) {
    SCOPED_TRACE(std::string(integrator_name(k.integrator)) + (k.hertz ? " hertz" : " linear"));
    Coupled2dWorld w;
    const BuildResult r = w.build(free_plate_hit(k.integrator, k.hertz));
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_GE(w.model.plate.cell_second_cut[kEdgeCell], 0);  // the edge's cell both cut
    pull_apart(w, 1.0);
    double scale = 0;
    for (std::int32_t i = 0; i < w.model.dem.n; ++i)
      scale += w.model.dem.mass[i] * std::hypot(w.state.dem.v[0][i], w.state.dem.v[1][i]);
    const double p0[2] = {total_momentum(w.model, w.state, 0), total_momentum(w.model, w.state, 1)};
    std::vector<double> positions(2 * w.model.boundary.vertices.size());
    bool touching = false;
    const double e0 = xfdem::testing::sweep_energy(w, positions, touching);
    double worst = 0, worst_books = 0, peak_exchange = 0, worst_work = 0, work_scale = 0, rise = -INFINITY;
    unsigned seen[2] = {0, 0};
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
      for (std::int32_t i = 0; i < 2; ++i) seen[i] |= touched(w, i, positions);
      const double e = xfdem::testing::sweep_energy(w, positions, touching);
      if (!touching) rise = std::max(rise, e - e0), ++free_instants;
    }
    std::printf("%s %s, free plate with a crack across inclusions, 4 disks, 600 steps: momentum drift %.3g of %.3g "
                "kg m/s, books %.3g of %.3g N s, exchange work: worst step %.3g J of sum |W| %.3g J; the "
                "disk in the crack touched bits %u (1, 2: the + and - face; 4: a face in the inclusion; 8: the "
                "left edge in the inclusion), the edge's disk %u; energy at %d contact-free instants: largest rise %.3g J of "
                "E0 %.6g J\n",
                integrator_name(k.integrator), k.hertz ? "hertz" : "linear", worst, scale, worst_books, peak_exchange,
                worst_work, work_scale, seen[0], seen[1], free_instants, rise, e0);
    EXPECT_EQ(seen[0] & 6u, 6u);  // the lower part's face, in the inclusion
    EXPECT_NE(seen[1] & 8u, 0u);  // the edge in the inclusion's material
    EXPECT_GT(peak_exchange, 0.5 * scale);  // the disks did hit and bounce
    EXPECT_LT(worst, 1e-10 * scale);
    EXPECT_LT(worst_books, 1e-12 * peak_exchange);
    EXPECT_GT(work_scale, 0.0);
    if (k.integrator != DemIntegrator::abm4) {
      EXPECT_LT(worst_work, 1e-9 * work_scale);
    }
  }
}

// Hertz: every segment's compliances are its material's at the segment (the
// plate's or the inclusion's, by plate_boundary_segment_material, which the
// boundary test checks against the circles), and in the edge's cell both
// cut the inclusion's and the plate's both occur.
TEST(Coupled2dCrackInclusion, HertzTakesTheMaterialAtTheSegment) {
  Coupled2dWorld w;
  const BuildResult r = w.build(free_plate_hit(DemIntegrator::symplectic_euler, true));
  ASSERT_TRUE(r.ok()) << r.message;
  const PlateBoundary& b = w.model.boundary;
  ASSERT_EQ(w.model.segment_inv_e.size(), b.segments.size());
  const double plate_inv_e = (1.0 - 0.3 * 0.3) / 2e8, inclusion_inv_e = (1.0 - 0.25 * 0.25) / 6e8;
  const double plate_inv_g = 2.0 * (2.0 - 0.3) * (1.0 + 0.3) / 2e8;
  const double inclusion_inv_g = 2.0 * (2.0 - 0.25) * (1.0 + 0.25) / 6e8;
  int in_cell[2] = {0, 0};
  for (std::size_t k = 0; k < b.segments.size(); ++k) {
    const PlateBoundarySegment& s = b.segments[k];
    const bool inclusion = plate_boundary_segment_material(w.model.plate, s) > 0;
    EXPECT_EQ(w.model.segment_inv_e[k], inclusion ? inclusion_inv_e : plate_inv_e) << "segment " << k;
    EXPECT_EQ(w.model.segment_inv_g[k], inclusion ? inclusion_inv_g : plate_inv_g) << "segment " << k;
    if (s.cell[0] == 0 && s.cell[1] == 8) ++in_cell[inclusion ? 1 : 0];
  }
  std::printf("edge's cell both cut: %d segments of the plate's material, %d of the inclusion's\n", in_cell[0],
              in_cell[1]);
  EXPECT_GT(in_cell[0], 0);
  EXPECT_GT(in_cell[1], 0);
}

// The plate's parts moving apart, the disk on the edge across the inclusion
// 1 mm off it (it lands within the first steps), the disks in two parts: no allocation in a step, and one and two workers give
// the same bits, with every integrator.
TEST(Coupled2dCrackInclusion, StepNeverAllocatesAndTwoWorkersGiveTheSameBits) {
  for (const DemIntegrator integrator : kIntegrators) {
    SCOPED_TRACE(integrator_name(integrator));
    Coupled2dDesc d = free_plate_hit(integrator, false);
    d.dem.split_from = 2;  // two parts of disks, so that a pool runs them on two workers
    d.dem.particles[1].position = {-0.041, 0.43};
    Coupled2dWorld one, two;
    ASSERT_TRUE(one.build(d).ok());
    ASSERT_TRUE(two.build(d).ok());
    pull_apart(one, 1.0);
    pull_apart(two, 1.0);
    platform::TwoWorkerPool pool;
    two.workspace.dem.parallel = pool.parallel_for();
    {
      platform::AllocationCounter counter;
      for (int step = 0; step < 15; ++step) ASSERT_EQ(one.step(), StepStatus::ok);
      EXPECT_EQ(counter.allocations(), 0u);
    }
    for (int step = 0; step < 15; ++step) ASSERT_EQ(two.step(), StepStatus::ok);
    EXPECT_GT(std::fabs(one.state.impulse_to_particles[0]), 0.0);  // the edge's disk has landed by then
    for (std::int32_t i = 0; i < one.model.dem.n; ++i)
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_EQ(one.state.dem.x[axis][i], two.state.dem.x[axis][i]);
        EXPECT_EQ(one.state.dem.v[axis][i], two.state.dem.v[axis][i]);
      }
    EXPECT_EQ(one.state.plate.u, two.state.plate.u);
    EXPECT_EQ(one.state.plate.v, two.state.plate.v);
  }
}
