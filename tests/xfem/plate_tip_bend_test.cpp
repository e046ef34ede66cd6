// A crack that bends just beyond its tip's cell (docs/xfem2d.md, "A bend near
// a tip"). The branch functions jump (θ = ±π) along the tip's straight line
// behind it; past the bend that line leaves the crack and runs through
// material, and a cut cell with branch functions that it crossed was
// integrated across the jump: its element mass was no Gram matrix (a negative
// diagonal), and a legal dynamic scene was refused with "the mass matrix is
// not positive definite". The scene that showed it: [−0.5, 0.5] × [−1, 1],
// 20 × 10 cells (0.05 × 0.2), plane strain, bottom clamped, 1 MPa step on
// the top, the crack from a tip at (−0.25, −0.7) (on a node column) bending
// at (−0.175, −0.6) (on a node row) and leaving through the top edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "xfdem/plate.hpp"

using namespace xfdem;

namespace {

constexpr double kHx = 0.05, kHy = 0.2;

struct Outcome {
  bool built = false;
  double energy = 0.0;  ///< elastic, J: static, or after the dynamic steps
  bool steps_ok = true;
};

/// The scene with the tip at `tip` and the bend at `bend`, each moved by
/// (δ h_x, δ h_y); static or 10 dynamic steps of 1e-5 s.
Outcome run(std::array<double, 2> tip, std::array<double, 2> bend, double delta, bool dynamic) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.youngs_modulus = 1e9, d.poisson_ratio = 0.3, d.density = 1000.0, d.thickness = 1.0;
  d.analysis = dynamic ? PlateDesc::Analysis::dynamic : PlateDesc::Analysis::statics;
  d.dt = 1e-5;
  d.min[0] = -0.5, d.min[1] = -1.0, d.max[0] = 0.5, d.max[1] = 1.0;
  d.cells[0] = 20, d.cells[1] = 10;
  PlateDiscontinuity c;
  c.name = "c";
  c.points = {{tip[0] + delta * kHx, tip[1] + delta * kHy}, {bend[0] + delta * kHx, bend[1] + delta * kHy}, {-0.325, 1.2}};
  d.discontinuities.push_back(c);
  PlateSupport s;
  s.edge = PlateEdge::bottom;
  s.fix[0] = s.fix[1] = true;
  d.supports.push_back(s);
  PlateLoad l;
  l.edge = PlateEdge::top;
  l.value[0] = 0.0, l.value[1] = 1e6;
  d.loads.push_back(l);
  PlateModel m;
  PlateState st;
  PlateWorkspace w;
  const BuildResult r = build_plate(d, m, st, w);
  Outcome out;
  out.built = r.ok();
  EXPECT_TRUE(r.ok()) << r.message << " (tip (" << tip[0] << ", " << tip[1] << "), delta " << delta << ")";
  if (!r.ok()) return out;
  if (dynamic)
    for (int k = 0; k < 10; ++k) {
      const StepStatus status = plate_step(m, st, w);
      if (status != StepStatus::ok) out.steps_ok = false;
    }
  out.energy = plate_energy(m, st).elastic;
  return out;
}

}  // namespace

TEST(PlateTipBend, BendBeyondTheTipCellBuildsRunsAndMovesTheAnswerContinuously) {
  struct Case {
    const char* what;
    std::array<double, 2> tip, bend;
  };
  const Case cases[] = {
      {"tip on a node column, bend on a node row (the reported scene)", {-0.25, -0.7}, {-0.175, -0.6}},
      {"tip and bend on nodes", {-0.25, -0.8}, {-0.15, -0.6}},
  };
  for (const Case& c : cases) {
    for (const bool dynamic : {false, true}) {
      const Outcome ref = run(c.tip, c.bend, 0.0, dynamic);
      ASSERT_TRUE(ref.built);
      EXPECT_TRUE(ref.steps_ok) << c.what;
      EXPECT_GT(ref.energy, 0.0);
      double worst = 0.0;
      for (const double delta : {1e-12, -1e-12, 1e-9, -1e-9}) {
        const Outcome r = run(c.tip, c.bend, delta, dynamic);
        ASSERT_TRUE(r.built) << c.what << ", delta " << delta;
        EXPECT_TRUE(r.steps_ok) << c.what << ", delta " << delta;
        const double change = std::fabs(r.energy - ref.energy) / ref.energy;
        worst = std::max(worst, change / std::fabs(delta));
        EXPECT_LE(change, 10.0 * std::fabs(delta)) << c.what << (dynamic ? ", dynamic" : ", static") << ", delta " << delta;
      }
      std::printf("%s, %s: elastic energy %.10g J; largest relative change over the moves %.3g x delta\n", c.what,
                  dynamic ? "dynamic (10 steps of 1e-5 s)" : "static", ref.energy, worst);
    }
  }
  // The reported scene with its start moved by 1e-4 m along x (δ = 2e-3 of a
  // cell's width), which was built before too: the tip leaves the node column
  // (its branch nodes change), and the answer still moves within 10 δ.
  for (const bool dynamic : {false, true}) {
    const Outcome a = run({-0.25, -0.7}, {-0.175, -0.6}, 0.0, dynamic);
    const Outcome b = run({-0.25 + 1e-4, -0.7}, {-0.175, -0.6}, 0.0, dynamic);
    ASSERT_TRUE(b.built);
    EXPECT_TRUE(b.steps_ok);
    EXPECT_LE(std::fabs(b.energy - a.energy) / a.energy, 10.0 * (1e-4 / kHx));
    std::printf("start moved by 1e-4 m, %s: %.10g J against %.10g J (%.3g relative)\n", dynamic ? "dynamic" : "static",
                b.energy, a.energy, (b.energy - a.energy) / a.energy);
  }
}
