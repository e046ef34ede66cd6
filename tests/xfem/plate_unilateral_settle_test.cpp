// Unilateral crack faces whose active set cycles (docs/xfem2d.md, "Unilateral
// faces"): a stiff penalty on a crack loaded across and along it, where the
// plain iteration (each solve with the set of the last one) flips between
// sets without end, ends on the exact solution through the damped iteration:
// the static solve and every dynamic step settle, and the test checks each
// result against the problem itself, with the set the test reads off the
// solution: a static K u + Σ w k_n min(g, 0) n = f, a dynamic
// M a + K u + Σ w k_n min(g, 0) n = f, to round-off of each row's terms;
// the steps allocate nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"

using namespace xfdem;

namespace {

/// The largest |row residual| over the size of the row's largest term, of
/// f − M a − K u − Σ_{g_p < 0} w k_n g_p n_p (M a left out when `a` is null),
/// f the loads of shape step at their amplitude plus the held nodes' push.
double relative_residual(const PlateModel& m, const std::vector<double>& u, const double* a, int* closing) {
  const int n = m.dofs;
  std::vector<double> r(m.held_force), scale(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) scale[i] = std::fabs(r[i]);
  for (std::size_t e = 0; e < m.load_dof.size(); ++e) {
    r[m.load_dof[e]] += m.load_value[e];
    scale[m.load_dof[e]] = std::max(scale[m.load_dof[e]], std::fabs(m.load_value[e]));
  }
  auto subtract = [&](const xfem::SymmetricBand& b, const double* x) {
    for (int i = 0; i < n; ++i)
      for (int j = b.first_column(i); j <= i; ++j) {
        const double v = b.get(i, j);
        r[i] -= v * x[j];
        scale[i] = std::max(scale[i], std::fabs(v * x[j]));
        if (j != i) {
          r[j] -= v * x[i];
          scale[j] = std::max(scale[j], std::fabs(v * x[i]));
        }
      }
  };
  subtract(m.stiffness, u.data());
  if (a != nullptr) subtract(m.mass, a);
  *closing = 0;
  for (const PlateModel::FacePoint& fp : m.face_points) {
    if (!fp.unilateral) continue;
    double g = 0.0;
    for (int k = 0; k < fp.terms; ++k)
      if (fp.dof[k] >= 0) g += fp.normal[k] * u[fp.dof[k]];
    if (!(g < 0.0)) continue;
    ++*closing;
    const double force = fp.weight * fp.k_normal * g;
    for (int k = 0; k < fp.terms; ++k)
      if (fp.dof[k] >= 0) {
        r[fp.dof[k]] -= force * fp.normal[k];
        scale[fp.dof[k]] = std::max(scale[fp.dof[k]], std::fabs(force * fp.normal[k]));
      }
  }
  double worst = 0.0;
  for (int i = 0; i < n; ++i)
    if (scale[i] > 0.0) worst = std::max(worst, std::fabs(r[i]) / scale[i]);
  return worst;
}

}  // namespace

// A strip 1 × 0.5 clamped on the left, a unilateral crack across its lower
// left corner (k_n = 1e14 Pa/m, 10^5.5 E/h), pulled and sheared on the right:
// the plain iteration does not settle in its 64 solves.
TEST(PlateUnilateralSettle, AStaticSetThatCyclesEndsOnTheExactSolution) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.thickness = 0.01;
  d.max[0] = 1.0, d.max[1] = 0.5;
  d.cells[0] = 17, d.cells[1] = 27;
  d.youngs_modulus = 1e9, d.poisson_ratio = 0.28, d.density = 1000.0;
  d.analysis = PlateDesc::Analysis::statics;
  d.supports.push_back({PlateEdge::left, {true, true}, false});
  PlateLoad load;
  load.edge = PlateEdge::right;
  load.value[0] = 4e5, load.value[1] = -9.4e5;
  load.shape = PlateLoadShape::step;
  d.loads.push_back(load);
  PlateDiscontinuity c;
  c.name = "c0";
  c.points = {{0.5985, 0.1154}, {0.0794, 0.5363}};
  c.faces = PlateDiscontinuity::Faces::unilateral;
  c.stiffness[0] = 1e14, c.stiffness[1] = 1e12;
  d.discontinuities.push_back(c);
  PlateModel m;
  PlateState s;
  PlateWorkspace w;
  const BuildResult r = build_plate(d, m, s, w);
  ASSERT_TRUE(r.ok()) << r.message;
  int closing = 0;
  const double residual = relative_residual(m, s.u, nullptr, &closing);
  std::printf("static: damped iteration used %lld, %d of %d unilateral points closing, residual %.2e of each row's "
              "largest term\n",
              static_cast<long long>(w.damped_solves), closing, m.unilateral_points, residual);
  EXPECT_EQ(w.damped_solves, 1);  // the plain iteration cycled: the case is the one this test is for
  EXPECT_LE(residual, 1e-9);
}

// A strip 3 × 0.5 clamped on the left, a unilateral crack from its bottom to
// a tip 0.011 below the top edge (k_n = 1e14 Pa/m, branch functions within
// 0.3), a step traction pressing and shearing the right edge; 40 steps at
// Δt = h/c (the set first cycles at the fourth).
TEST(PlateUnilateralSettle, DynamicStepsWhoseSetCyclesEndOnTheExactSolution) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.max[0] = 3.0, d.max[1] = 0.5;
  d.cells[0] = 27, d.cells[1] = 15;
  d.youngs_modulus = 1e9, d.poisson_ratio = 0.16, d.density = 7800.0;
  d.analysis = PlateDesc::Analysis::dynamic;
  d.dt = (0.5 / 15) / std::sqrt(d.youngs_modulus / d.density);
  d.tip_radius = 0.3;
  d.supports.push_back({PlateEdge::left, {true, true}, false});
  PlateLoad load;
  load.edge = PlateEdge::right;
  load.value[0] = -9.3e5, load.value[1] = 8.2e5;
  load.shape = PlateLoadShape::step;
  d.loads.push_back(load);
  PlateDiscontinuity c;
  c.name = "c0";
  c.points = {{0.9413, 0.4890}, {-0.1502, -1.8504}, {0.9221, -0.8083}};
  c.faces = PlateDiscontinuity::Faces::unilateral;
  c.stiffness[0] = 1e14, c.stiffness[1] = 1e13;
  d.discontinuities.push_back(c);
  PlateModel m;
  PlateState s;
  PlateWorkspace w;
  const BuildResult r = build_plate(d, m, s, w);
  ASSERT_TRUE(r.ok()) << r.message;
  int bad = 0, worst_closing = 0;
  double worst = 0.0;
  std::int64_t held = 0;
  std::size_t allocations = 0;
  for (int step = 0; step < 40; ++step) {
    {
      platform::AllocationCounter counter;
      if (plate_step(m, s, w) != StepStatus::ok) ++bad;
      allocations += counter.allocations();
    }
    // A step redone with its openings held (the energy rule) ends with the
    // acceleration of the set of u_{n+1} too, so every step is checked.
    int closing = 0;
    const double res = relative_residual(m, s.u, s.a.data(), &closing);
    worst = std::max(worst, res);
    worst_closing = std::max(worst_closing, closing);
    held = w.held_steps;
  }
  std::printf("dynamic: %lld solves needed the damped iteration, %lld steps held; up to %d of %d points closing; "
              "worst residual %.2e of each row's largest term\n",
              static_cast<long long>(w.damped_solves), static_cast<long long>(held), worst_closing,
              m.unilateral_points, worst);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(w.damped_solves, 0);  // the plain iteration cycled in some steps
  EXPECT_GT(worst_closing, 0);
  EXPECT_LE(worst, 1e-9);
}
