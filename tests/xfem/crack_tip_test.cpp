// The near-tip building blocks of tip enrichment: the tip frame,
// the four branch functions and the Williams near-tip fields, checked against
// closed forms and finite differences the tests compute. The plate does not
// use them yet.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "xfdem/xfem/level_set.hpp"

using namespace xfdem::xfem;

namespace {

constexpr double kPi = std::numbers::pi;

// Points around a tip at radii 0.01..0.3 and angles within (−π, π), avoiding the faces.
std::vector<Point2> ring_points(const TipFrame& f) {
  std::vector<Point2> pts;
  for (double r : {0.01, 0.07, 0.3})
    for (int k = -5; k <= 5; ++k) {
      const double t = 0.95 * kPi * k / 5.0;
      const double lx = r * std::cos(t), ly = r * std::sin(t);
      pts.push_back({f.origin[0] + f.cos_a * lx - f.sin_a * ly, f.origin[1] + f.sin_a * lx + f.cos_a * ly});
    }
  return pts;
}

const std::vector<Point2> kCrack = {{0.1, 0.2}, {0.5, 0.4}, {0.9, 0.5}};

}  // namespace

TEST(CrackTip, FrameLooksOutOfTheCrackAtBothEnds) {
  const TipFrame end = tip_frame(kCrack, true), start = tip_frame(kCrack, false);
  const double le = std::hypot(0.4, 0.1), ls = std::hypot(0.4, 0.2);
  EXPECT_DOUBLE_EQ(end.origin[0], 0.9);
  EXPECT_NEAR(end.cos_a, 0.4 / le, 1e-15);
  EXPECT_NEAR(end.sin_a, 0.1 / le, 1e-15);
  EXPECT_DOUBLE_EQ(start.origin[1], 0.2);
  EXPECT_NEAR(start.cos_a, -0.4 / ls, 1e-15);
  EXPECT_NEAR(start.sin_a, -0.2 / ls, 1e-15);
  // A point on the crack behind the end tip is at θ = ±π, one ahead at θ = 0.
  double r = 0, t = 0;
  tip_polar(end, {0.5 + 0.2 * 0.4, 0.4 + 0.2 * 0.1}, r, t);
  EXPECT_NEAR(std::abs(t), kPi, 1e-12);
  tip_polar(end, {0.9 + 0.4, 0.5 + 0.1}, r, t);
  EXPECT_NEAR(t, 0.0, 1e-12);
  EXPECT_NEAR(r, le, 1e-15);
}

TEST(CrackTip, BranchFunctionGradientsMatchFiniteDifferences) {
  for (bool at_end : {false, true}) {
    const TipFrame f = tip_frame(kCrack, at_end);
    for (const Point2& x : ring_points(f)) {
      double v[4], g[4][2];
      branch_functions(f, x, v, g);
      double r = 0, t = 0;
      tip_polar(f, x, r, t);
      const double expect[4] = {std::sqrt(r) * std::sin(t / 2), std::sqrt(r) * std::cos(t / 2),
                                std::sqrt(r) * std::sin(t / 2) * std::sin(t), std::sqrt(r) * std::cos(t / 2) * std::sin(t)};
      const double h = 1e-6 * r;
      for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(v[i], expect[i], 1e-15);
        for (int d = 0; d < 2; ++d) {
          Point2 xp = x, xm = x;
          xp[d] += h;
          xm[d] -= h;
          double vp[4], vm[4], dummy[4][2];
          branch_functions(f, xp, vp, dummy);
          branch_functions(f, xm, vm, dummy);
          const double fd = (vp[i] - vm[i]) / (2 * h);
          // Central differences: error O(h²|F'''|) ~ 1e-12/√r, plus round-off ε√r/h.
          EXPECT_NEAR(g[i][d], fd, 1e-7 / std::sqrt(r)) << "F" << i << " d" << d << " r " << r << " θ " << t;
        }
      }
    }
  }
}

TEST(CrackTip, WilliamsGradientMatchesFiniteDifferencesAndStressIsHookes) {
  const double E = 2e11, nu = 0.3, mu = E / (2 * (1 + nu));
  for (bool strain : {true, false}) {
    const double kappa = kolosov(nu, strain);
    // λ of the plane: λ in plane strain, 2μν/(1 − ν) in plane stress.
    const double lambda = strain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : 2 * mu * nu / (1 - nu);
    for (auto [k1, k2] : {std::pair{1e6, 0.0}, std::pair{0.0, 1e6}, std::pair{7e5, -4e5}})
      for (double r : {0.01, 0.2})
        for (int k = -5; k <= 5; ++k) {
          const double t = 0.95 * kPi * k / 5.0;
          const WilliamsField w = williams_field(k1, k2, mu, kappa, r, t);
          const double scale = std::hypot(k1, k2) / std::sqrt(2 * kPi * r);  // stress scale
          // ∂u/∂x_j by central differences in local Cartesian coordinates.
          const double x = r * std::cos(t), y = r * std::sin(t), h = 1e-6 * r;
          auto u_at = [&](double px, double py, int i) {
            return williams_field(k1, k2, mu, kappa, std::hypot(px, py), std::atan2(py, px)).u[i];
          };
          for (int i = 0; i < 2; ++i) {
            const double dx = (u_at(x + h, y, i) - u_at(x - h, y, i)) / (2 * h);
            const double dy = (u_at(x, y + h, i) - u_at(x, y - h, i)) / (2 * h);
            EXPECT_NEAR(w.grad_u[i][0], dx, 1e-6 * scale / mu);
            EXPECT_NEAR(w.grad_u[i][1], dy, 1e-6 * scale / mu);
          }
          // The closed-form stress is Hooke's law of the closed-form strain.
          const double exx = w.grad_u[0][0], eyy = w.grad_u[1][1], gxy = w.grad_u[0][1] + w.grad_u[1][0];
          EXPECT_NEAR(w.stress[0], lambda * (exx + eyy) + 2 * mu * exx, 1e-12 * scale);
          EXPECT_NEAR(w.stress[1], lambda * (exx + eyy) + 2 * mu * eyy, 1e-12 * scale);
          EXPECT_NEAR(w.stress[2], mu * gxy, 1e-12 * scale);
        }
  }
}

TEST(CrackTip, WilliamsFacesAreTractionFreeAndOpenByTheClosedForm) {
  const double mu = 8e10, kappa = kolosov(0.3, true), k1 = 1e6, k2 = 3e5, r = 0.04;
  for (double t : {kPi, -kPi}) {
    const WilliamsField w = williams_field(k1, k2, mu, kappa, r, t);
    const double scale = k1 / std::sqrt(2 * kPi * r);
    EXPECT_NEAR(w.stress[1], 0.0, 1e-14 * scale);
    EXPECT_NEAR(w.stress[2], 0.0, 1e-14 * scale);
  }
  // The jump upper minus lower face: Δu_y = (κ + 1) K_I/μ √(r/2π), Δu_x = (κ + 1) K_II/μ √(r/2π).
  const WilliamsField up = williams_field(k1, k2, mu, kappa, r, kPi), lo = williams_field(k1, k2, mu, kappa, r, -kPi);
  const double c = (kappa + 1) / mu * std::sqrt(r / (2 * kPi));
  EXPECT_NEAR(up.u[1] - lo.u[1], c * k1, 1e-14 * c * k1);
  EXPECT_NEAR(up.u[0] - lo.u[0], c * k2, 1e-14 * c * k1);
}

// Why the four branch functions: every Williams displacement, mode I, II or
// mixed, is a combination of them (least squares residual at round-off).
TEST(CrackTip, BranchFunctionsSpanTheWilliamsDisplacements) {
  const TipFrame f{{0.0, 0.0}, 1.0, 0.0};
  const std::vector<Point2> pts = ring_points(f);
  const int n = static_cast<int>(pts.size());
  Eigen::MatrixXd a(n, 4);
  for (int p = 0; p < n; ++p) {
    double v[4], g[4][2];
    branch_functions(f, pts[p], v, g);
    for (int i = 0; i < 4; ++i) a(p, i) = v[i];
  }
  for (auto [k1, k2] : {std::pair{1e6, 0.0}, std::pair{0.0, 1e6}, std::pair{7e5, -4e5}})
    for (int comp = 0; comp < 2; ++comp) {
      Eigen::VectorXd b(n);
      for (int p = 0; p < n; ++p) {
        double r = 0, t = 0;
        tip_polar(f, pts[p], r, t);
        b(p) = williams_field(k1, k2, 8e10, kolosov(0.3, true), r, t).u[comp];
      }
      const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(b);
      EXPECT_LE((a * coef - b).norm(), 1e-12 * b.norm()) << "K_I " << k1 << " K_II " << k2 << " comp " << comp;
    }
  // And the four are independent (a tip-enriched node adds four unknowns, not fewer).
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
  EXPECT_GT(svd.singularValues()(3), 1e-3 * svd.singularValues()(0));
}

// The domain interaction integral of the exact Williams field (K_I, K_II)
// recovers K_I and K_II: integrated on a polar Gauss grid over an annulus
// r1 < r < r2 with q = (r2 − r)/(r2 − r1) (q = 1 inside r1 contributes
// nothing: ∇q = 0), for two annuli (the integral is domain independent).
TEST(CrackTip, InteractionIntegralOfTheWilliamsFieldGivesItsK) {
  // Gauss-Legendre, 8 points on [−1, 1].
  const double gx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                        0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  const double gw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                        0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  const double E = 2e11, nu = 0.3, mu = E / (2 * (1 + nu));
  for (bool strain : {true, false}) {
    const double kappa = kolosov(nu, strain), e_star = strain ? E / (1 - nu * nu) : E;
    for (auto [k1, k2] : {std::pair{1e6, 0.0}, std::pair{0.0, 1e6}, std::pair{7e5, -4e5}})
      for (auto [r1, r2] : {std::pair{0.02, 0.1}, std::pair{0.05, 0.4}}) {
        double i_mode[2] = {0, 0};
        const int n_theta = 16;  // panels in θ, 8 points each
        for (int mode = 0; mode < 2; ++mode)
          for (int a = 0; a < 8; ++a) {
            const double r = 0.5 * (r1 + r2) + 0.5 * (r2 - r1) * gx[a];
            for (int p = 0; p < n_theta; ++p)
              for (int b = 0; b < 8; ++b) {
                const double t0 = -kPi + 2 * kPi * p / n_theta, t1 = -kPi + 2 * kPi * (p + 1) / n_theta;
                const double t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gx[b];
                const double weight = 0.5 * (r2 - r1) * gw[a] * 0.5 * (t1 - t0) * gw[b] * r;
                const WilliamsField act = williams_field(k1, k2, mu, kappa, r, t);
                const WilliamsField aux = williams_field(mode == 0 ? 1.0 : 0.0, mode == 1 ? 1.0 : 0.0, mu, kappa, r, t);
                const double dq_dr = -1.0 / (r2 - r1);
                const double gq[2] = {dq_dr * std::cos(t), dq_dr * std::sin(t)};
                i_mode[mode] += weight * interaction_integrand(act.stress, act.grad_u, aux, gq);
              }
          }
        const double scale = std::hypot(k1, k2);
        EXPECT_NEAR(0.5 * e_star * i_mode[0], k1, 1e-10 * scale) << "strain " << strain << " r1 " << r1;
        EXPECT_NEAR(0.5 * e_star * i_mode[1], k2, 1e-10 * scale) << "strain " << strain << " r1 " << r1;
      }
  }
}

// The tip cell's quadrature: sub-triangles fanned from the tip and a 5 × 5
// Gauss rule collapsed at the tip (the rule of the cut cells) integrate
// |∇F_1|² = 1/(4r) over a cell against the closed form
// ∫∫ dA/r = Σ_edges d [ln(sec φ + tan φ)] (d the edge's distance from the tip,
// φ the angle from its foot), where the cell's four sub-triangles from its
// centre (the tip not a vertex) do much worse.
TEST(CrackTip, FanFromTheTipIntegratesTheSingularGradient) {
  const double gx[5] = {0.5 * (1.0 - 0.9061798459386640), 0.5 * (1.0 - 0.5384693101056831), 0.5,
                        0.5 * (1.0 + 0.5384693101056831), 0.5 * (1.0 + 0.9061798459386640)};
  const double gw[5] = {0.5 * 0.2369268850561891, 0.5 * 0.4786286704993665, 0.5 * 0.5688888888888889,
                        0.5 * 0.4786286704993665, 0.5 * 0.2369268850561891};
  const Point2 cell[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const TipFrame f{{0.3, 0.45}, std::cos(0.4), std::sin(0.4)};
  auto collapsed = [&](const TrianglePiece* t, int count) {
    double sum = 0.0;
    for (int k = 0; k < count; ++k) {
      const Point2* v = t[k].v;
      const double e1x = v[1][0] - v[0][0], e1y = v[1][1] - v[0][1], e2x = v[2][0] - v[1][0], e2y = v[2][1] - v[1][1];
      const double jac = std::fabs(e1x * e2y - e1y * e2x);
      for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b) {
          const Point2 x{v[0][0] + gx[a] * e1x + gx[a] * gx[b] * e2x, v[0][1] + gx[a] * e1y + gx[a] * gx[b] * e2y};
          double val[4], g[4][2];
          branch_functions(f, x, val, g);
          sum += gw[a] * gw[b] * gx[a] * jac * (g[0][0] * g[0][0] + g[0][1] * g[0][1]);
        }
    }
    return sum;
  };
  // Closed form: Σ over the cell's edges of d/4 [ln(sec φ + tan φ)]_{φ_a}^{φ_b}.
  double exact = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Point2 a = cell[i], b = cell[(i + 1) % 4];
    const double tx = b[0] - a[0], ty = b[1] - a[1], len = std::hypot(tx, ty);
    const double ux = tx / len, uy = ty / len;
    const double sa = (a[0] - f.origin[0]) * ux + (a[1] - f.origin[1]) * uy;  // along the edge from the foot
    const double sb = (b[0] - f.origin[0]) * ux + (b[1] - f.origin[1]) * uy;
    const double d = std::fabs((a[0] - f.origin[0]) * uy - (a[1] - f.origin[1]) * ux);
    auto prim = [&](double s) { return std::asinh(s / d); };  // ln(sec φ + tan φ) with tan φ = s/d
    exact += 0.25 * d * (prim(sb) - prim(sa));
  }
  TrianglePiece fan[16];
  double fan_err[4] = {};
  for (int splits = 1; splits <= 3; ++splits) {
    const int nf = fan_from_tip(cell, 4, f.origin, splits, 1, fan);
    ASSERT_EQ(nf, 4 * splits);
    fan_err[splits] = std::fabs(collapsed(fan, nf) - exact) / exact;
  }
  // The cell's own sub-triangles from its centre, collapsed at the centre.
  TrianglePiece centre[4];
  for (int i = 0; i < 4; ++i) centre[i] = TrianglePiece{{{0.5, 0.5}, cell[i], cell[(i + 1) % 4]}, 1};
  const double centre_err = std::fabs(collapsed(centre, 4) - exact) / exact;
  std::printf("int |grad F1|^2 over the tip cell: exact %.12g; rel. error, fan from the tip with 1, 2, 3 splits "
              "per edge: %.2e %.2e %.2e; centre fan %.2e\n",
              exact, fan_err[1], fan_err[2], fan_err[3], centre_err);
  // The collapsed rule is exact in r here (the integrand times the Jacobian
  // does not depend on it); what is left is the angular 5-point rule, which
  // converges fast as the angles narrow.
  EXPECT_LT(fan_err[3], 1e-8);
  EXPECT_LT(fan_err[2], 1e-2 * fan_err[1]);
  EXPECT_GT(centre_err, 100 * fan_err[1]);
  // A tip on an edge: the degenerate triangle is skipped, the rest cover the cell.
  EXPECT_EQ(fan_from_tip(cell, 4, {0.5, 0.0}, 1, -1, fan), 3);
  EXPECT_EQ(fan[0].side, -1);
}
