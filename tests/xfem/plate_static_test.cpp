// The plate's static analysis: patch test (a linear field reproduced to
// round-off), uniaxial tension under an edge traction against the closed form
// in plane strain and plane stress, and bad descriptions named by field.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

#include "xfdem/plate.hpp"

using namespace xfdem;

namespace {

constexpr double kEps = DBL_EPSILON;

PlateDesc steel(PlateDesc::Plane plane) {
  PlateDesc d;
  d.plane = plane;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.thickness = 1.0;
  d.analysis = PlateDesc::Analysis::statics;
  return d;
}

double node_x(const PlateDesc& d, int i) { return i == d.cells[0] ? d.max[0] : d.min[0] + (d.max[0] - d.min[0]) * i / d.cells[0]; }
double node_y(const PlateDesc& d, int j) { return j == d.cells[1] ? d.max[1] : d.min[1] + (d.max[1] - d.min[1]) * j / d.cells[1]; }

}  // namespace

// u = a0 + a1 x + a2 y, v = b0 + b1 x + b2 y imposed on every boundary node:
// the interior nodes and the stresses everywhere must be exact to round-off.
TEST(PlateStatic, PatchTestReproducesALinearFieldToRoundOff) {
  for (auto plane : {PlateDesc::Plane::strain, PlateDesc::Plane::stress}) {
    PlateDesc d = steel(plane);
    d.min[0] = 0.3, d.min[1] = -0.5, d.max[0] = 2.3, d.max[1] = 0.7;
    d.cells[0] = 7, d.cells[1] = 5;
    const double a[3] = {1e-4, 2e-4, -3e-4}, b[3] = {-5e-5, 4e-4, 1e-4};
    auto ux = [&](double x, double y) { return a[0] + a[1] * x + a[2] * y; };
    auto uy = [&](double x, double y) { return b[0] + b[1] * x + b[2] * y; };
    for (int j = 0; j <= d.cells[1]; ++j)
      for (int i = 0; i <= d.cells[0]; ++i) {
        if (i != 0 && i != d.cells[0] && j != 0 && j != d.cells[1]) continue;
        const double x = node_x(d, i), y = node_y(d, j);
        d.prescribed.push_back({{x, y}, {ux(x, y), uy(x, y)}});
      }
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(m.dofs, 2 * (d.cells[0] - 1) * (d.cells[1] - 1));
    const double u_scale = 1e-3;  // |u| over the domain is below this
    double worst_u = 0.0;
    for (int j = 1; j < d.cells[1]; ++j)
      for (int i = 1; i < d.cells[0]; ++i) {
        const double x = node_x(d, i), y = node_y(d, j);
        worst_u = std::max(worst_u, std::fabs(plate_displacement(m, st, x, y, 0) - ux(x, y)));
        worst_u = std::max(worst_u, std::fabs(plate_displacement(m, st, x, y, 1) - uy(x, y)));
      }
    const double eps_exact[3] = {a[1], b[2], a[2] + b[1]};
    double sigma_exact[3], sigma_scale = 0.0;
    for (int c = 0; c < 3; ++c) {
      sigma_exact[c] = m.elasticity[c][0] * eps_exact[0] + m.elasticity[c][1] * eps_exact[1] +
                       m.elasticity[c][2] * eps_exact[2];
      sigma_scale = std::max(sigma_scale, std::fabs(sigma_exact[c]));
    }
    double worst_s = 0.0;
    for (double fx : {0.0, 0.13, 0.5, 0.77, 1.0})
      for (double fy : {0.0, 0.31, 0.5, 0.9, 1.0}) {
        const double x = d.min[0] + fx * (d.max[0] - d.min[0]), y = d.min[1] + fy * (d.max[1] - d.min[1]);
        for (int c = 0; c < 3; ++c) worst_s = std::max(worst_s, std::fabs(plate_stress(m, st, x, y, c) - sigma_exact[c]));
      }
    std::printf("patch test (%s): displacement error %.3g of %.3g (%.1f eps), stress error %.3g of %.3g Pa (%.1f eps)\n",
                plane == PlateDesc::Plane::strain ? "plane strain" : "plane stress", worst_u, u_scale,
                worst_u / (u_scale * kEps), worst_s, sigma_scale, worst_s / (sigma_scale * kEps));
    EXPECT_LE(worst_u, 64 * kEps * u_scale);
    EXPECT_LE(worst_s, 256 * kEps * sigma_scale);
  }
}

// A bar of plate under a uniform traction σ0 on its right edge, on rollers
// on the left (x held) and bottom (y held): the exact solution is linear, so
// the Q4 mesh reproduces it. Plane stress: ε_xx = σ0/E, ε_yy = −ν σ0/E;
// plane strain: ε_xx = (1 − ν²)σ0/E, ε_yy = −ν(1 + ν)σ0/E.
TEST(PlateStatic, UniaxialTensionMatchesTheClosedForm) {
  for (auto plane : {PlateDesc::Plane::strain, PlateDesc::Plane::stress}) {
    PlateDesc d = steel(plane);
    d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 2.0, d.max[1] = 1.0;
    d.cells[0] = 8, d.cells[1] = 4;
    d.thickness = 0.02;
    const double sigma0 = 1e6;
    d.supports.push_back({PlateEdge::left, {true, false}, false});
    d.supports.push_back({PlateEdge::bottom, {false, true}, false});
    PlateLoad load;
    load.kind = PlateLoad::Kind::edge_traction;
    load.edge = PlateEdge::right;
    load.value[0] = sigma0;
    load.shape = PlateLoadShape::step;
    d.loads.push_back(load);
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    const double e = d.youngs_modulus, nu = d.poisson_ratio;
    const bool strain = plane == PlateDesc::Plane::strain;
    const double exx = strain ? (1 - nu * nu) * sigma0 / e : sigma0 / e;
    const double eyy = strain ? -nu * (1 + nu) * sigma0 / e : -nu * sigma0 / e;
    const double u_scale = exx * d.max[0];
    double worst_u = 0.0, worst_s = 0.0;
    for (int j = 0; j <= d.cells[1]; ++j)
      for (int i = 0; i <= d.cells[0]; ++i) {
        const double x = node_x(d, i), y = node_y(d, j);
        worst_u = std::max(worst_u, std::fabs(plate_displacement(m, st, x, y, 0) - exx * x));
        worst_u = std::max(worst_u, std::fabs(plate_displacement(m, st, x, y, 1) - eyy * y));
        const double xm = std::min(x + 0.1, 2.0), ym = std::min(y + 0.07, 1.0);
        worst_s = std::max(worst_s, std::fabs(plate_stress(m, st, xm, ym, 0) - sigma0));
        worst_s = std::max(worst_s, std::fabs(plate_stress(m, st, xm, ym, 1)));
        worst_s = std::max(worst_s, std::fabs(plate_stress(m, st, xm, ym, 2)));
      }
    std::printf("uniaxial tension (%s): displacement error %.3g of %.3g m (%.1f eps), stress error %.3g of %.3g Pa "
                "(%.1f eps)\n",
                strain ? "plane strain" : "plane stress", worst_u, u_scale, worst_u / (u_scale * kEps), worst_s, sigma0,
                worst_s / (sigma0 * kEps));
    EXPECT_LE(worst_u, 64 * kEps * u_scale);
    EXPECT_LE(worst_s, 256 * kEps * sigma0);
    // The elastic energy equals the work of the traction, ½ F·u (static, linear).
    const double f = sigma0 * d.thickness * d.max[1];
    EXPECT_NEAR(plate_energy(m, st).elastic, 0.5 * f * exx * d.max[0], 1e-12 * f * exx * d.max[0]);
  }
}

namespace {
void expect_rejected(const PlateDesc& d, const char* field) {
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  const BuildResult r = build_plate(d, m, st, ws);
  EXPECT_FALSE(r.ok()) << field;
  EXPECT_EQ(std::string(r.message).rfind(std::string(field) + ":", 0), 0u) << "message: " << r.message;
  EXPECT_EQ(plate_step(m, st, ws), StepStatus::not_built);
}
}  // namespace

TEST(PlateStatic, BadDescriptionsNameTheField) {
  PlateDesc good = steel(PlateDesc::Plane::strain);
  good.max[0] = 2.0, good.max[1] = 1.0;
  good.cells[0] = 4, good.cells[1] = 2;
  good.supports.push_back({PlateEdge::left, {true, true}, false});
  {
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    ASSERT_TRUE(build_plate(good, m, st, ws).ok());
    EXPECT_EQ(plate_step(m, st, ws), StepStatus::not_built);  // a static model has nothing to step
  }
  PlateDesc d = good;
  d.poisson_ratio = 0.5;
  expect_rejected(d, "material.poisson_ratio");
  d.plane = PlateDesc::Plane::stress;
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  EXPECT_TRUE(build_plate(d, m, st, ws).ok());  // ν = 1/2 is a plane-stress sheet
  d = good, d.cells[1] = 0;
  expect_rejected(d, "cells");
  d = good, d.max[0] = 0.0;
  expect_rejected(d, "domain.max");
  d = good, d.thickness = -1.0;
  expect_rejected(d, "thickness");
  d = good, d.youngs_modulus = 0.0;
  expect_rejected(d, "material.youngs_modulus");
  d = good, d.density = NAN;
  expect_rejected(d, "material.density");
  d = good, d.prescribed.push_back({{0.25, 0.0}, {0.0, 0.0}});
  expect_rejected(d, "prescribed.0.at");
  d = good, d.prescribed.push_back({{0.0, 0.5}, {1e-3, 0.0}});
  expect_rejected(d, "prescribed.0.displacement");  // held at 0 by the left support
  d = good, d.supports.clear();
  expect_rejected(d, "supports");  // static and free: singular
  d = good, d.supports[0].fix[1] = false;
  expect_rejected(d, "supports");  // free to slide in y
  d = good, d.loads.push_back(PlateLoad{});
  d.loads[0].shape = PlateLoadShape::half_sine, d.loads[0].duration = 0.1;
  expect_rejected(d, "loads.0.shape");  // static: no time
  d = good, d.loads.push_back(PlateLoad{});
  d.loads[0].kind = PlateLoad::Kind::point_force, d.loads[0].at[0] = 3.0;
  expect_rejected(d, "loads.0.at");
  d = good, d.max_dofs = 3;
  expect_rejected(d, "max_dofs");
  d = good, d.analysis = PlateDesc::Analysis::dynamic;
  expect_rejected(d, "dt");
  d.dt = 1e-3, d.beta = 0.2;
  expect_rejected(d, "newmark.beta");
  d.beta = 0.25, d.gamma = 0.4;
  expect_rejected(d, "newmark.gamma");
}

// Cantilever under an end shear, plane stress, against the elasticity solution
// of Timoshenko & Goodier (beam [0, L] × [−D/2, D/2], I = D³/12):
//   u_x = −P y / (6EI) [(6L − 3x) x + (2 + ν)(y² − D²/4)]
//   u_y =  P / (6EI) [3ν y² (L − x) + (4 + 5ν) D² x / 4 + (3L − x) x²]
//   σ_xx = −P (L − x) y / I,  σ_yy = 0,  σ_xy = P / (2I) (D²/4 − y²)
// The exact displacements are prescribed on the left edge, the parabolic
// shear is the right edge's traction (consistent nodal forces, point forces at
// the nodes: Simpson's rule is exact for the cubic N·τ), top and bottom free.
// Q4 locks in bending, so coarse meshes are stiff; the tip deflection error
// falls at second order.
TEST(PlateStatic, CantileverConvergesToTheElasticitySolution) {
  const double length = 4.0, depth = 1.0, e = 1e7, nu = 0.3, p = 100.0;
  const double inertia = depth * depth * depth / 12.0;
  auto exact_ux = [&](double x, double y) {
    return -p * y / (6 * e * inertia) * ((6 * length - 3 * x) * x + (2 + nu) * (y * y - 0.25 * depth * depth));
  };
  auto exact_uy = [&](double x, double y) {
    return p / (6 * e * inertia) *
           (3 * nu * y * y * (length - x) + (4 + 5 * nu) * depth * depth * x / 4 + (3 * length - x) * x * x);
  };
  auto shear = [&](double y) { return p / (2 * inertia) * (0.25 * depth * depth - y * y); };
  const double tip_exact = exact_uy(length, 0.0);
  std::vector<double> errors;
  std::vector<double> sizes;
  for (int ny : {2, 4, 8, 16, 32}) {
    PlateDesc d = steel(PlateDesc::Plane::stress);
    d.youngs_modulus = e;
    d.poisson_ratio = nu;
    d.min[0] = 0.0, d.min[1] = -0.5 * depth, d.max[0] = length, d.max[1] = 0.5 * depth;
    d.cells[0] = 4 * ny, d.cells[1] = ny;
    for (int j = 0; j <= ny; ++j) {
      const double y = node_y(d, j);
      d.prescribed.push_back({{0.0, y}, {exact_ux(0.0, y), exact_uy(0.0, y)}});
    }
    for (int j = 0; j < ny; ++j) {
      const double y0 = node_y(d, j), y1 = node_y(d, j + 1), h = y1 - y0;
      const double tm = shear(0.5 * (y0 + y1));
      for (int k = 0; k < 2; ++k) {
        PlateLoad f;
        f.kind = PlateLoad::Kind::point_force;
        f.at[0] = length, f.at[1] = k == 0 ? y0 : y1;
        f.value[1] = d.thickness * h / 6.0 * ((k == 0 ? shear(y0) : shear(y1)) + 2.0 * tm);
        d.loads.push_back(f);
      }
    }
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    const double tip = plate_displacement(m, st, length, 0.0, 1);
    errors.push_back(std::fabs(tip - tip_exact) / tip_exact);
    sizes.push_back(depth / ny);
    std::printf("cantilever %3d x %2d: tip deflection %.10g (exact %.10g), relative error %.3e", d.cells[0], ny, tip,
                tip_exact, errors.back());
    if (errors.size() > 1)
      std::printf(", order %.3f", std::log(errors[errors.size() - 2] / errors.back()) / std::log(2.0));
    std::printf("\n");
    EXPECT_LT(tip, tip_exact);  // Q4 is too stiff in bending
  }
  const std::size_t n = errors.size();
  const double order = std::log(errors[n - 2] / errors[n - 1]) / std::log(2.0);
  EXPECT_GT(order, 1.9);
  EXPECT_LT(order, 2.1);
  EXPECT_LT(errors[n - 1], 1e-3);
}

// plate_support_reaction: a wall held along its base (x and y) under two
// point forces balances them, component by component, in the plain plate and
// with a free crack and a void in the cells on the support (their rows come
// from the cut cells' own stiffnesses, enrichments and tip functions
// included). Statics: R + Σ F = 0 to the static solve's round-off (below).
TEST(PlateStatic, SupportReactionBalancesTheLoads) {
  for (int variant = 0; variant < 2; ++variant) {
    PlateDesc d = steel(PlateDesc::Plane::strain);
    d.youngs_modulus = 3e10, d.poisson_ratio = 0.2, d.density = 2400.0;
    d.max[0] = 0.4, d.max[1] = 1.6;
    d.cells[0] = 16, d.cells[1] = 64;
    d.supports.push_back({PlateEdge::bottom, {true, true}, false});
    if (variant == 1) {
      // A crack with two tips in the first row of cells (its nodes held below
      // it), and a void cutting cells of the second row.
      PlateDiscontinuity crack;
      crack.name = "crack";
      crack.points = {{0.14, 0.011}, {0.29, 0.011}};
      d.discontinuities.push_back(crack);
      PlateDiscontinuity hole;
      hole.name = "hole";
      hole.kind = PlateDiscontinuity::Kind::hole;
      hole.shape = PlateDiscontinuity::Shape::circle;
      hole.centre[0] = 0.2, hole.centre[1] = 0.06, hole.radius = 0.02;
      d.discontinuities.push_back(hole);
    }
    const double f[2][2] = {{3.0e3, -1.0e3}, {-0.5e3, -2.0e3}};
    const double at[2][2] = {{0.4, 1.2}, {0.1, 0.7}};
    for (int k = 0; k < 2; ++k) {
      PlateLoad load;
      load.kind = PlateLoad::Kind::point_force;
      load.at[0] = at[k][0], load.at[1] = at[k][1];
      load.value[0] = f[k][0], load.value[1] = f[k][1];
      d.loads.push_back(load);
    }
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    double reaction[2];
    plate_support_reaction(m, st, reaction);
    // R + Σ F is the sum of the static solve's residuals on the free rows
    // (Σ_all (K u) = 0 for a translation, Σ_free (K u − f) the rest): each
    // row's residual is a few ε of its terms, at most 2 × 4 cells' entries
    // (a cut cell's up to 2 kPlateMaxPointFunctions) times |u|. The bound:
    // ε × the rows × 64 × max |K_ab| × max |u|.
    double kmax = 0.0, umax = 0.0;
    for (double x : m.element_stiffness) kmax = std::max(kmax, std::fabs(x));
    for (double x : m.other_cell_matrix) kmax = std::max(kmax, std::fabs(x));
    for (double x : st.u) umax = std::max(umax, std::fabs(x));
    const double scale = static_cast<double>(m.dofs) * 64.0 * kmax * umax;
    for (int c = 0; c < 2; ++c) {
      const double total = f[0][c] + f[1][c];
      std::printf("%s: reaction %c %.12g N against the loads' %.12g N: off by %.3g N (bound ε × %.3g N, %.2g of it)\n",
                  variant == 0 ? "plain wall" : "crack and void at the base", c == 0 ? 'x' : 'y', reaction[c], total,
                  reaction[c] + total, scale, std::fabs(reaction[c] + total) / (scale * kEps));
      EXPECT_LE(std::fabs(reaction[c] + total), kEps * scale);
    }
  }
}
