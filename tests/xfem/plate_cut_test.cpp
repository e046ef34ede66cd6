// The plate cut by discontinuities: cut patch tests (a linear field through a
// tied crack and through an inclusion of the same material, a field linear on
// each side of a free crack), the tiny-cut rule, the bimaterial circular
// inclusion (Sukumar et al. 2001) and the plate with a circular hole (Kirsch)
// converging at the optimal rates, a tied crack across the one-cell column
// reproducing the 1D X-FEM bar, a step that never allocates, and the
// refusals named by field.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfem/reference.hpp"

using namespace xfdem;

namespace {

constexpr double kEps = DBL_EPSILON;
using Field = std::function<void(double x, double y, double u[2])>;

double node_x(const PlateDesc& d, int i) { return i == d.cells[0] ? d.max[0] : d.min[0] + (d.max[0] - d.min[0]) * i / d.cells[0]; }
double node_y(const PlateDesc& d, int j) { return j == d.cells[1] ? d.max[1] : d.min[1] + (d.max[1] - d.min[1]) * j / d.cells[1]; }

PlateDesc static_plate(double x0, double y0, double x1, double y1, int nx, int ny) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.analysis = PlateDesc::Analysis::statics;
  d.min[0] = x0, d.min[1] = y0, d.max[0] = x1, d.max[1] = y1;
  d.cells[0] = nx, d.cells[1] = ny;
  return d;
}

/// Every boundary node prescribed at field(x, y).
void prescribe_boundary(PlateDesc& d, const Field& field) {
  for (int j = 0; j <= d.cells[1]; ++j)
    for (int i = 0; i <= d.cells[0]; ++i) {
      if (i != 0 && i != d.cells[0] && j != 0 && j != d.cells[1]) continue;
      const double x = node_x(d, i), y = node_y(d, j);
      double u[2];
      field(x, y, u);
      d.prescribed.push_back({{x, y}, {u[0], u[1]}});
    }
}

PlateDiscontinuity crack(std::vector<std::array<double, 2>> points, PlateDiscontinuity::Faces faces, double k = 0.0) {
  PlateDiscontinuity q;
  q.name = "crack";
  q.kind = PlateDiscontinuity::Kind::crack;
  q.shape = PlateDiscontinuity::Shape::polyline;
  q.points = std::move(points);
  q.faces = faces;
  q.stiffness[0] = q.stiffness[1] = k;
  return q;
}

PlateDiscontinuity circle(PlateDiscontinuity::Kind kind, double cx, double cy, double r) {
  PlateDiscontinuity q;
  q.name = kind == PlateDiscontinuity::Kind::hole ? "hole" : "inclusion";
  q.kind = kind;
  q.shape = PlateDiscontinuity::Shape::circle;
  q.centre[0] = cx, q.centre[1] = cy;
  q.radius = r;
  return q;
}

void plane_strain_d(double e, double nu, double dm[3][3]) {
  const double f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
  dm[0][0] = dm[1][1] = f * (1.0 - nu);
  dm[0][1] = dm[1][0] = f * nu;
  dm[2][2] = f * 0.5 * (1.0 - 2.0 * nu);
  dm[0][2] = dm[2][0] = dm[1][2] = dm[2][1] = 0.0;
}

/// The enrichment of the boundary nodes is free (only their standard unknowns
/// are prescribed), so the field's traction σ·n must be applied on the edges:
/// the uniform stress of strain (ε_xx, ε_yy, γ_xy) in the plate's material.
void add_edge_tractions(PlateDesc& d, double exx, double eyy, double gxy) {
  double dm[3][3];
  plane_strain_d(d.youngs_modulus, d.poisson_ratio, dm);
  const double sxx = dm[0][0] * exx + dm[0][1] * eyy, syy = dm[1][0] * exx + dm[1][1] * eyy, sxy = dm[2][2] * gxy;
  auto load = [&](PlateEdge e, double tx, double ty) {
    PlateLoad l;
    l.kind = PlateLoad::Kind::edge_traction;
    l.edge = e;
    l.value[0] = tx, l.value[1] = ty;
    d.loads.push_back(l);
  };
  load(PlateEdge::left, -sxx, -sxy);
  load(PlateEdge::right, sxx, sxy);
  load(PlateEdge::bottom, -sxy, -syy);
  load(PlateEdge::top, sxy, syy);
}

struct Built {
  PlateModel m;
  PlateState s;
  PlateWorkspace w;
};

}  // namespace

// u linear imposed on the boundary nodes (and its traction on the edges, for
// the boundary nodes' free enrichment). Cut by a straight slanted crack with
// tied faces of stiffness k, the exact solution is that field shifted by ∓j/2
// on each side, j = ((σn)·n/k_n) n + ((σn)·t/k_t) t the penalty's constant
// jump; cut by an inclusion of the plate's own material it is the field
// itself; and both at once. Interior displacements, stresses and the crack's
// opening are the closed form's to round-off.
TEST(PlateCut, PatchTestsReproduceALinearFieldToRoundOff) {
  const double a[3] = {1e-4, 2e-4, -3e-4}, b[3] = {-5e-5, 4e-4, 1e-4};
  const double p0[2] = {0.1, -0.61}, p1[2] = {2.5, 0.31}, kn = 4e13, kt = 1e13;
  const double len = std::hypot(p1[0] - p0[0], p1[1] - p0[1]);
  const double t[2] = {(p1[0] - p0[0]) / len, (p1[1] - p0[1]) / len}, n[2] = {-t[1], t[0]};
  for (int variant = 0; variant < 3; ++variant) {
    PlateDesc d = static_plate(0.3, -0.5, 2.3, 0.7, 9, 7);
    const bool cracked = variant != 1;
    if (cracked) d.discontinuities.push_back(crack({{p0[0], p0[1]}, {p1[0], p1[1]}}, PlateDiscontinuity::Faces::tied, kn));
    if (cracked) d.discontinuities.back().stiffness[1] = kt;
    if (variant != 0) {
      PlateDiscontinuity inc = variant == 1 ? circle(PlateDiscontinuity::Kind::inclusion, 1.6, -0.05, 0.33)
                                            : circle(PlateDiscontinuity::Kind::inclusion, 0.9, 0.4, 0.18);
      inc.material = {d.youngs_modulus, d.poisson_ratio, d.density};
      d.discontinuities.push_back(inc);
    }
    double dm[3][3];
    plane_strain_d(d.youngs_modulus, d.poisson_ratio, dm);
    const double eps_exact[3] = {a[1], b[2], a[2] + b[1]};
    double sigma[3], sigma_scale = 0.0;
    for (int c = 0; c < 3; ++c) {
      sigma[c] = dm[c][0] * eps_exact[0] + dm[c][1] * eps_exact[1] + dm[c][2] * eps_exact[2];
      sigma_scale = std::max(sigma_scale, std::fabs(sigma[c]));
    }
    const double tn[2] = {sigma[0] * n[0] + sigma[2] * n[1], sigma[2] * n[0] + sigma[1] * n[1]};
    const double jn = cracked ? (tn[0] * n[0] + tn[1] * n[1]) / kn : 0.0;
    const double jt = cracked ? (tn[0] * t[0] + tn[1] * t[1]) / kt : 0.0;
    const double jump[2] = {jn * n[0] + jt * t[0], jn * n[1] + jt * t[1]};
    const Field exact = [&](double x, double y, double u[2]) {
      const double half = n[0] * (x - p0[0]) + n[1] * (y - p0[1]) >= 0.0 ? 0.5 : -0.5;
      u[0] = a[0] + a[1] * x + a[2] * y + half * jump[0];
      u[1] = b[0] + b[1] * x + b[2] * y + half * jump[1];
    };
    prescribe_boundary(d, exact);
    add_edge_tractions(d, a[1], b[2], a[2] + b[1]);
    Built p;
    const BuildResult r = build_plate(d, p.m, p.s, p.w);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_GT(p.m.enriched_dofs, 0);
    double worst_u = 0.0, worst_s = 0.0, worst_open = 0.0;
    for (int sj = 0; sj <= 40; ++sj)
      for (int si = 0; si <= 40; ++si) {
        const double x = 0.3 + 2.0 * (si + 0.37) / 41.5, y = -0.5 + 1.2 * (sj + 0.41) / 41.5;
        if (plate_point_region(d, x, y, 1e-9) != 0) continue;
        double u[2];
        exact(x, y, u);
        for (int c = 0; c < 2; ++c) worst_u = std::max(worst_u, std::fabs(plate_displacement(p.m, p.s, x, y, c) - u[c]));
        for (int c = 0; c < 3; ++c) worst_s = std::max(worst_s, std::fabs(plate_stress(p.m, p.s, x, y, c) - sigma[c]));
      }
    if (cracked)
      for (double f : {0.15, 0.4, 0.5, 0.77}) {
        const double x = p0[0] + f * (p1[0] - p0[0]), y = p0[1] + f * (p1[1] - p0[1]);
        worst_open = std::max({worst_open, std::fabs(plate_crack_opening(p.m, p.s, 0, x, y, 0) - jn),
                               std::fabs(plate_crack_opening(p.m, p.s, 0, x, y, 1) - jt)});
      }
    std::printf("cut patch test (%s): %d enriched unknowns; displacement error %.3g (%.1f eps of 1e-3), stress error "
                "%.3g of %.3g Pa (%.1f eps), opening error %.3g of (%.3g, %.3g) m\n",
                variant == 0 ? "tied crack" : variant == 1 ? "inclusion, same material" : "both", p.m.enriched_dofs,
                worst_u, worst_u / (1e-3 * kEps), worst_s, sigma_scale, worst_s / (sigma_scale * kEps), worst_open, jn, jt);
    EXPECT_LE(worst_u, 100 * kEps * 1e-3);
    EXPECT_LE(worst_s, 1e4 * kEps * sigma_scale);
    EXPECT_LE(worst_open, 100 * kEps * 1e-3);
  }
}

// A free crack, slanted, through the plate; a uniform stress along the crack
// (its faces carry no traction) and on each side its own rigid motion,
// imposed on the boundary nodes of that side (with the edges' tractions for
// their free enrichment): the solution is that field on each side to
// round-off, and the crack opens and slides by the difference.
TEST(PlateCut, FreeCrackReproducesAFieldLinearOnEachSide) {
  PlateDesc d = static_plate(0.0, 0.0, 2.0, 1.0, 10, 6);
  const double p0[2] = {-0.1, 0.23}, p1[2] = {2.1, 0.71};
  d.discontinuities.push_back(crack({{p0[0], p0[1]}, {p1[0], p1[1]}}, PlateDiscontinuity::Faces::free));
  const double len = std::hypot(p1[0] - p0[0], p1[1] - p0[1]);
  const double t[2] = {(p1[0] - p0[0]) / len, (p1[1] - p0[1]) / len}, n[2] = {-t[1], t[0]};
  double dm[3][3];
  plane_strain_d(d.youngs_modulus, d.poisson_ratio, dm);
  // ε = D⁻¹σ for σ = s t⊗t.
  auto strain_of = [&](double s, double eps[3]) {
    const double sig[3] = {s * t[0] * t[0], s * t[1] * t[1], s * t[0] * t[1]};
    const double det = dm[0][0] * dm[1][1] - dm[0][1] * dm[1][0];
    eps[0] = (dm[1][1] * sig[0] - dm[0][1] * sig[1]) / det;
    eps[1] = (dm[0][0] * sig[1] - dm[1][0] * sig[0]) / det;
    eps[2] = sig[2] / dm[2][2];
  };
  // The same stress on both sides (the edges' tractions are then one per
  // edge), different rigid motions: the crack opens and slides.
  const double s_side[2] = {-1.1e8, -1.1e8};
  const double rigid[2][3] = {{1e-5, -2e-5, 3e-5}, {-4e-5, 6e-5, -1e-5}};  // (u0, v0, rotation)
  auto side_of = [&](double x, double y) { return n[0] * (x - p0[0]) + n[1] * (y - p0[1]) >= 0.0 ? 1 : 0; };
  const Field field = [&](double x, double y, double u[2]) {
    const int s = side_of(x, y);
    double e[3];
    strain_of(s_side[s], e);
    u[0] = rigid[s][0] + e[0] * x + 0.5 * e[2] * y - rigid[s][2] * y;
    u[1] = rigid[s][1] + e[1] * y + 0.5 * e[2] * x + rigid[s][2] * x;
  };
  prescribe_boundary(d, field);
  {
    double e[3];
    strain_of(s_side[0], e);
    add_edge_tractions(d, e[0], e[1], e[2]);
  }
  Built p;
  const BuildResult r = build_plate(d, p.m, p.s, p.w);
  ASSERT_TRUE(r.ok()) << r.message;
  double worst_u = 0.0, worst_s = 0.0, worst_open = 0.0, open_scale = 0.0;
  for (int sj = 0; sj <= 30; ++sj)
    for (int si = 0; si <= 30; ++si) {
      const double x = 2.0 * (si + 0.29) / 31.3, y = (sj + 0.43) / 31.3;
      if (plate_point_region(d, x, y, 1e-9) != 0) continue;
      double u[2];
      field(x, y, u);
      for (int c = 0; c < 2; ++c) worst_u = std::max(worst_u, std::fabs(plate_displacement(p.m, p.s, x, y, c) - u[c]));
      const double s = s_side[side_of(x, y)];
      const double sig[3] = {s * t[0] * t[0], s * t[1] * t[1], s * t[0] * t[1]};
      for (int c = 0; c < 3; ++c) worst_s = std::max(worst_s, std::fabs(plate_stress(p.m, p.s, x, y, c) - sig[c]));
    }
  for (double f : {0.1, 0.37, 0.5, 0.83}) {
    const double x = p0[0] + f * (p1[0] - p0[0]), y = p0[1] + f * (p1[1] - p0[1]);
    double up[2], um[2];
    field(x + 1e-9 * n[0], y + 1e-9 * n[1], up);
    field(x - 1e-9 * n[0], y - 1e-9 * n[1], um);
    // Exact jump at the point itself (each side's field evaluated there).
    double e0[3], e1[3];
    strain_of(s_side[0], e0);
    strain_of(s_side[1], e1);
    double ju[2];
    for (int sd = 0; sd < 2; ++sd) {
      const double* e = sd ? e1 : e0;
      const double ux = rigid[sd][0] + e[0] * x + 0.5 * e[2] * y - rigid[sd][2] * y;
      const double uy = rigid[sd][1] + e[1] * y + 0.5 * e[2] * x + rigid[sd][2] * x;
      ju[0] = sd ? ju[0] + ux : -ux;
      ju[1] = sd ? ju[1] + uy : -uy;
    }
    const double exact[2] = {n[0] * ju[0] + n[1] * ju[1], t[0] * ju[0] + t[1] * ju[1]};
    for (int c = 0; c < 2; ++c) {
      open_scale = std::max(open_scale, std::fabs(exact[c]));
      worst_open = std::max(worst_open, std::fabs(plate_crack_opening(p.m, p.s, 0, x, y, c) - exact[c]));
    }
  }
  std::printf("free crack, linear on each side: displacement error %.3g (%.1f eps of 1e-4), stress error %.3g Pa (%.1f "
              "eps of 1.1e8), opening error %.3g of %.3g m\n",
              worst_u, worst_u / (1e-4 * kEps), worst_s, worst_s / (1.1e8 * kEps), worst_open, open_scale);
  EXPECT_GT(open_scale, 1e-5);
  EXPECT_LE(worst_u, 100 * kEps * 1e-4);
  EXPECT_LE(worst_s, 1e4 * kEps * 1.1e8);
  EXPECT_LE(worst_open, 100 * kEps * 1e-4);
}
