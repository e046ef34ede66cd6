// Tied and unilateral faces on a crack that ends inside the plate (a tip):
// the penalty acts on the crack in every cell it cuts, the tip's cell and the
// blending cells included, on the jump of the Heaviside and of the branch
// function √r sin(θ/2). Against closed forms computed here: the uncracked
// plate in uniform tension (tied faces stiffening towards it as 1/k, closed
// unilateral faces under compression), Tada's edge-crack factor and the free
// crack (unilateral faces opening under tension), the opening σ/k_n of a
// compliant tied crack, and the energy of Newmark (¼, ½) with tied faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"

using namespace xfdem;

namespace {

constexpr double kEps = DBL_EPSILON;
constexpr double kE = 2e11, kNu = 0.3, kSigma = 1e6;

/// The strip [0, W] × [0, H] (plane stress), the top edge pulled by
/// `sigma`, a roller on the bottom edge and the lower-left corner held, with
/// an edge crack from the left edge to the tip (a, yc), faces `faces` of
/// stiffness k (both components), branch functions within `radius` of the tip.
PlateDesc edge_cracked_strip(int nx, int ny, double width, double height, double a, double yc, double sigma,
                             PlateDiscontinuity::Faces faces, double k, double radius) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::stress;
  d.youngs_modulus = kE, d.poisson_ratio = kNu, d.density = 7800, d.thickness = 1.0;
  d.analysis = PlateDesc::Analysis::statics;
  d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = width, d.max[1] = height;
  d.cells[0] = nx, d.cells[1] = ny;
  d.tip_radius = radius;
  PlateDiscontinuity c;
  c.name = "crack";
  c.points = {{-0.5 * width, yc}, {a, yc}};
  c.faces = faces;
  c.stiffness[0] = c.stiffness[1] = k;
  d.discontinuities.push_back(c);
  d.supports.push_back({PlateEdge::bottom, {false, true}, false});
  d.prescribed.push_back({{0.0, 0.0}, {0.0, 0.0}});
  PlateLoad pull;
  pull.edge = PlateEdge::top;
  pull.value[1] = sigma;
  d.loads.push_back(pull);
  return d;
}

struct Built {
  PlateModel m;
  PlateState s;
  PlateWorkspace w;
};

/// The largest displacement and stress differences from uniaxial tension
/// σ_yy = sigma (u_x = −ν σ x / E, u_y = σ y / E) at points of a grid that
/// avoids the crack line y = yc.
void uniform_error(const Built& p, double sigma, double yc, double& du, double& ds) {
  const PlateDesc& d = p.m.desc;
  du = ds = 0.0;
  for (int sj = 0; sj <= 30; ++sj)
    for (int si = 0; si <= 20; ++si) {
      const double x = d.max[0] * (si + 0.37) / 21.3, y = d.max[1] * (sj + 0.41) / 31.2;
      if (std::fabs(y - yc) < 1e-6) continue;
      du = std::max({du, std::fabs(plate_displacement(p.m, p.s, x, y, 0) + kNu * sigma * x / kE),
                     std::fabs(plate_displacement(p.m, p.s, x, y, 1) - sigma * y / kE)});
      ds = std::max({ds, std::fabs(plate_stress(p.m, p.s, x, y, 0)), std::fabs(plate_stress(p.m, p.s, x, y, 1) - sigma),
                     std::fabs(plate_stress(p.m, p.s, x, y, 2))});
    }
}

/// Tada's edge crack in a strip: K_I = σ √(πa) F(a/W).
double tada(double sigma, double a, double width) {
  const double al = a / width;
  const double f = 1.12 - 0.231 * al + 10.55 * al * al - 21.72 * std::pow(al, 3) + 30.39 * std::pow(al, 4);
  return sigma * std::sqrt(std::numbers::pi * a) * f;
}

// The strip and crack of the tests: W = 1, H = 3, 20 × 60 cells, the crack
// along the middle of a row of cells (yc = 1.525), tip at a = 0.4125 (a cell's
// middle), branch functions within 0.1 (blending cells cut by the crack).
constexpr int kNx = 20, kNy = 60;
constexpr double kW = 1.0, kH = 3.0, kA = 0.4125, kYc = 1.525, kRadius = 0.1;

}  // namespace

// (a) Tied faces with a tip, uniform tension across them: as k grows, the
// plate tends to the uncracked one (σ_yy = σ everywhere) as 1/k. For k_n =
// 10 … 10⁶ E/h the displacement differs by at most 2.5 σ/k_n (the faces'
// opening, ≈ σ/k_n, is the departure; near the tip the field bends by about
// twice it), the stress by at most 0.3 σ E/(k_n h) (that bend over a cell),
// and the displacement difference falls by 10 ± 0.5 per decade of k, over
// all six decades (the cells with branch functions are integrated exactly
// enough that no floor is left; with the former collapsed rule the
// difference stopped falling at 1.1e-6 σH/E and 1.8e-4 σ from 10⁴ E/h on).
TEST(PlateTipFaces, StiffTiedFacesWithATipGiveTheUncrackedPlate) {
  double last_du = 0.0;
  const double h = kW / kNx;
  for (const double scale : {1e1, 1e2, 1e3, 1e4, 1e5, 1e6}) {
    const double kn = scale * kE / h;
    Built p;
    const BuildResult r = build_plate(
        edge_cracked_strip(kNx, kNy, kW, kH, kA, kYc, kSigma, PlateDiscontinuity::Faces::tied, kn, kRadius), p.m, p.s,
        p.w);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(p.m.tips.size(), 1u);
    EXPECT_GT(p.m.face_points.size(), 0u);
    double du = 0.0, ds = 0.0;
    uniform_error(p, kSigma, kYc, du, ds);
    const double opening = plate_crack_opening(p.m, p.s, 0, 0.5 * kA, kYc, 0);
    std::printf("tied faces with a tip, k_n = %.0e E/h: displacement error %.3e m (%.3f sigma/k_n), stress error %.3e "
                "of sigma (%.3f E/(k_n h)), opening %.4e m (%.4f sigma/k_n)\n",
                scale, du, du * kn / kSigma, ds / kSigma, ds / kSigma * scale, opening, opening * kn / kSigma);
    EXPECT_GT(opening, 0.0);
    EXPECT_LE(opening, 1.0 * kSigma / kn);
    EXPECT_LE(du, 2.5 * kSigma / kn);
    EXPECT_LE(ds, 0.3 * kSigma / scale);
    if (last_du > 0.0) {
      std::printf("  displacement error ratio to the previous k: %.3f\n", last_du / du);
      EXPECT_NEAR(last_du / du, 10.0, 0.5);
    }
    last_du = du;
  }
}

// (b) Unilateral faces with a tip. Pushed (traction −σ across the crack,
// k_n = 1000 E/h) the faces close and the plate is the uncracked one within
// the bounds of (a). Pulled, every face point opens: the plate is the free crack's,
// K_I and the opening the same to round-off (the tip as the polyline's last
// or first point), K_I within 1 % of Tada's edge crack (a/W = 0.4, the strip
// 6W long, 40 × 240 cells as PlateTip.EdgeCrackInAStripFollowsTada).
TEST(PlateTipFaces, UnilateralFacesWithATipCloseUnderCompressionAndOpenAsAFreeCrack) {
  {
    const double kn = 1e3 * kE / (kW / kNx);
    Built p;
    const BuildResult r = build_plate(
        edge_cracked_strip(kNx, kNy, kW, kH, kA, kYc, -kSigma, PlateDiscontinuity::Faces::unilateral, kn, kRadius),
        p.m, p.s, p.w);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_GT(p.m.unilateral_points, 0);
    double du = 0.0, ds = 0.0;
    uniform_error(p, -kSigma, kYc, du, ds);
    const double opening = plate_crack_opening(p.m, p.s, 0, 0.5 * kA, kYc, 0);
    std::printf("unilateral faces with a tip, pushed: displacement error %.3e m (%.3f sigma/k_n), stress error %.3e of "
                "sigma, opening %.4e m (%.4f sigma/k_n)\n",
                du, du * kn / kSigma, ds / kSigma, opening, opening * kn / kSigma);
    EXPECT_LE(du, 2.5 * kSigma / kn);
    EXPECT_LE(ds, 0.3 * kSigma / 1e3);
    EXPECT_LT(opening, 0.0);
    EXPECT_GE(opening, -1.0 * kSigma / kn);
  }
  const double width = 1.0, height = 6.0, h = width / 40, yc = 3.0 + 0.5 * h, a = 0.4;
  const double exact = tada(kSigma, a, width);
  for (bool tip_last : {true, false}) {
    double k_free[2] = {0, 0}, k_uni[2] = {0, 0}, open_free[3] = {}, open_uni[3] = {};
    const double at[3] = {a - 0.01, a - 0.05, 0.5 * a};  // within the radius (F₁ carries the jump) and beyond
    for (const auto faces : {PlateDiscontinuity::Faces::free, PlateDiscontinuity::Faces::unilateral}) {
      PlateDesc d = edge_cracked_strip(40, 240, width, height, a, yc, kSigma, faces, 1e4 * kE / h, 0.1);
      if (!tip_last) std::swap(d.discontinuities[0].points[0], d.discontinuities[0].points[1]);
      Built p;
      const BuildResult r = build_plate(d, p.m, p.s, p.w);
      ASSERT_TRUE(r.ok()) << r.message;
      const bool free = faces == PlateDiscontinuity::Faces::free;
      plate_stress_intensity(p.m, p.s, 0, tip_last, 0.15, free ? k_free : k_uni);
      for (int q = 0; q < 3; ++q) (free ? open_free : open_uni)[q] = plate_crack_opening(p.m, p.s, 0, at[q], yc, 0);
    }
    std::printf("unilateral faces with a tip (%s point), pulled: K_I %.8g (free crack %.8g, Tada %.6g, error %.3e); "
                "openings %.6e %.6e %.6e m (free %.6e %.6e %.6e)\n",
                tip_last ? "last" : "first", k_uni[0], k_free[0], exact, (k_uni[0] - exact) / exact, open_uni[0],
                open_uni[1], open_uni[2], open_free[0], open_free[1], open_free[2]);
    EXPECT_NEAR(k_uni[0], k_free[0], 1e-12 * exact);
    EXPECT_NEAR(k_uni[1], k_free[1], 1e-12 * exact);
    EXPECT_NEAR(k_uni[0], exact, 0.01 * exact);
    for (int q = 0; q < 3; ++q) {
      EXPECT_GT(open_uni[q], 0.0);
      EXPECT_NEAR(open_uni[q], open_free[q], 1e-12 * open_free[2]);
    }
  }
}

// (c) A compliant tied crack with a tip, k_n = c E / a: uniform tension σ
// across it is carried by the faces' springs, the opening σ/k_n far from the
// tip (at mid-crack) up to the crack's own compliance, a relative O(1/c)
// (the opening σ/k_n spread over the crack's length a changes the stress by
// O(E σ/(k_n a))), and the mesh's own departure at mid-crack, which (a)
// shows at stiff k as an opening of 0.9994 σ/k_n: asserted |opening k_n/σ −
// 1| ≤ 0.15/c + 1e-3 for c = 10, 100, 1000, and no sliding (≤ 1e-6 of the
// opening).
TEST(PlateTipFaces, CompliantTiedFacesWithATipOpenBySigmaOverTheirStiffness) {
  for (const double c : {10.0, 100.0, 1000.0}) {
    const double kn = c * kE / kA;
    Built p;
    const BuildResult r = build_plate(
        edge_cracked_strip(kNx, kNy, kW, kH, kA, kYc, kSigma, PlateDiscontinuity::Faces::tied, kn, kRadius), p.m, p.s,
        p.w);
    ASSERT_TRUE(r.ok()) << r.message;
    const double opening = plate_crack_opening(p.m, p.s, 0, 0.5 * kA, kYc, 0);
    const double sliding = plate_crack_opening(p.m, p.s, 0, 0.5 * kA, kYc, 1);
    const double departure = opening * kn / kSigma - 1.0;
    std::printf("compliant tied faces with a tip, k_n = %.0f E/a: opening %.6e m, sigma/k_n %.6e m, relative "
                "departure %.4e (%.3f / c), sliding %.3e m\n",
                c, opening, kSigma / kn, departure, departure * c, sliding);
    EXPECT_LE(std::fabs(departure), 0.15 / c + 1e-3);
    EXPECT_LE(std::fabs(sliding), 1e-6 * opening);
  }
}

// (d) Newmark (¼, ½) with tied faces on a crack with a tip: free vibration
// from a velocity on every unknown conserves the algorithmic energy (the
// faces' penalty in the elastic energy) to round-off over 500 steps, without
// allocating; the step's cell-by-cell K x equals the assembled K's.
TEST(PlateTipFaces, TiedFacesWithATipConserveNewmarkEnergyWithoutAllocating) {
  PlateDesc d = edge_cracked_strip(10, 20, kW, 2.0, 0.43, 1.025, 0.0, PlateDiscontinuity::Faces::tied,
                                   100.0 * kE / (kW / 10), 0.2);
  d.analysis = PlateDesc::Analysis::dynamic;
  d.dt = 2e-6;
  d.loads.clear();
  Built p;
  ASSERT_TRUE(build_plate(d, p.m, p.s, p.w).ok());
  ASSERT_EQ(p.m.tips.size(), 1u);
  ASSERT_GT(p.m.tip_nodes, 4);
  // Face points with branch unknowns only (the tip's cell) and with both
  // kinds (blending cells cut by the crack).
  std::vector<char> is_branch(static_cast<std::size_t>(p.m.dofs), 0);
  for (int dof : p.m.tip_dof)
    if (dof >= 0) is_branch[static_cast<std::size_t>(dof)] = 1;
  int branch_only = 0, both = 0;
  for (const auto& fp : p.m.face_points) {
    int nb = 0, nh = 0;
    for (int t = 0; t < fp.terms; ++t)
      if (fp.dof[t] >= 0) (is_branch[static_cast<std::size_t>(fp.dof[t])] ? nb : nh) += 1;
    branch_only += nb > 0 && nh == 0;
    both += nb > 0 && nh > 0;
  }
  std::printf("tied faces with a tip: %zu face points, %d with branch unknowns only, %d with both kinds\n",
              p.m.face_points.size(), branch_only, both);
  EXPECT_GT(branch_only, 0);
  EXPECT_GT(both, 0);
  std::vector<double> x(static_cast<std::size_t>(p.m.dofs)), y1(x.size(), 0.0), y2(x.size(), 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::cos(1.3 * static_cast<double>(i));
  p.m.stiffness.subtract_product(x.data(), y1.data());
  plate_subtract_stiffness_product(p.m, x.data(), y2.data());
  double diff = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) diff = std::max(diff, std::fabs(y1[i] - y2[i])), norm = std::max(norm, std::fabs(y1[i]));
  EXPECT_LE(diff, 1e-12 * norm);
  for (std::size_t i = 0; i < p.s.v.size(); ++i) p.s.v[i] = 1e-3 * std::sin(0.7 * static_cast<double>(i));
  ASSERT_EQ(plate_initial_acceleration(p.m, p.s, p.w), StepStatus::ok);
  const double e0 = plate_algorithmic_energy(p.m, p.s);
  platform::AllocationCounter counter;
  double worst = 0.0;
  for (int i = 0; i < 500; ++i) {
    ASSERT_EQ(plate_step(p.m, p.s, p.w), StepStatus::ok);
    worst = std::max(worst, std::fabs(plate_algorithmic_energy(p.m, p.s) - e0));
  }
  EXPECT_EQ(counter.allocations(), 0u);
  std::printf("tied faces with a tip, 500 steps: |E - E0| <= %.3e of E0 = %.6g J; K x cell by cell vs assembled %.2e of "
              "%.3g\n",
              worst / e0, e0, diff, norm);
  EXPECT_LE(worst, 1e-10 * e0);
}
