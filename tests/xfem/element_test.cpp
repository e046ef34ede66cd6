// Element matrices against hand-derived values, and the enriched patch test.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "xfdem/bar.hpp"
#include "xfdem/xfem/element.hpp"
#include "xfem/reference.hpp"

using namespace xfdem;

namespace {
// Entries come from a handful of flops each: a few ulps.
constexpr double kElementTol = 1e-14;

void expect_rel(double got, double want, double scale, const char* what) {
  EXPECT_NEAR(got, want, kElementTol * scale) << what;
}
}  // namespace

TEST(Element, StandardBarElement) {
  const double ea = 1.2e7, rho_a = 800.0, x0 = 2.0, x1 = 3.5, h = 1.5;
  const auto pm = xfem::bar_piece_matrices(ea, rho_a, x0, x1, x0, x1);
  // eq 25-26 for a 2-node bar: EA/h [1 −1; −1 1], ρAh/6 [2 1; 1 2].
  expect_rel(pm.stiffness(0, 0), ea / h, ea / h, "k00");
  expect_rel(pm.stiffness(0, 1), -ea / h, ea / h, "k01");
  expect_rel(pm.stiffness(1, 1), ea / h, ea / h, "k11");
  expect_rel(pm.mass(0, 0), rho_a * h / 3.0, rho_a * h, "m00");
  expect_rel(pm.mass(0, 1), rho_a * h / 6.0, rho_a * h, "m01");
  expect_rel(pm.mass(1, 1), rho_a * h / 3.0, rho_a * h, "m11");
}

TEST(Element, EnrichedElementAgainstHandDerivation) {
  // Element [0, h] cut at s·h. Below: enriched functions (0, −N1); above: (N0, 0).
  // Hand integration (t = x/h):
  //   K_u0a0 = EA(1−s)/h, K_u0a1 = EA s/h, K_u1a0 = −EA(1−s)/h, K_u1a1 = −EA s/h,
  //   K_a0a0 = EA(1−s)/h, K_a1a1 = EA s/h, K_a0a1 = 0;
  //   M_u0a0 = M_a0a0 = ρAh(1−s)³/3, M_u1a0 = ρAh(1/6 − s²/2 + s³/3),
  //   M_u0a1 = −ρAh(s²/2 − s³/3), M_u1a1 = −ρAh s³/3, M_a1a1 = ρAh s³/3, M_a0a1 = 0;
  //   jump = (0, 1−s, 0, s).
  const double ea = 3e6, rho_a = 500.0, h = 2.0;
  for (double s : {0.5, 0.3, 0.9, 1e-3}) {
    const auto em = xfem::enriched_element_matrices(ea, rho_a, 0.0, h, s * h);
    const double k = ea / h, m = rho_a * h;
    enum { u0, a0, u1, a1 };
    expect_rel(em.stiffness(u0, u0), k, k, "Ku0u0");
    expect_rel(em.stiffness(u0, u1), -k, k, "Ku0u1");
    expect_rel(em.stiffness(u0, a0), k * (1 - s), k, "Ku0a0");
    expect_rel(em.stiffness(u0, a1), k * s, k, "Ku0a1");
    expect_rel(em.stiffness(u1, a0), -k * (1 - s), k, "Ku1a0");
    expect_rel(em.stiffness(u1, a1), -k * s, k, "Ku1a1");
    expect_rel(em.stiffness(a0, a0), k * (1 - s), k, "Ka0a0");
    expect_rel(em.stiffness(a1, a1), k * s, k, "Ka1a1");
    expect_rel(em.stiffness(a0, a1), 0.0, k, "Ka0a1");
    expect_rel(em.mass(u0, u0), m / 3, m, "Mu0u0");
    expect_rel(em.mass(u0, u1), m / 6, m, "Mu0u1");
    expect_rel(em.mass(u0, a0), m * std::pow(1 - s, 3) / 3, m, "Mu0a0");
    expect_rel(em.mass(a0, a0), m * std::pow(1 - s, 3) / 3, m, "Ma0a0");
    expect_rel(em.mass(u1, a0), m * (1.0 / 6 - s * s / 2 + s * s * s / 3), m, "Mu1a0");
    expect_rel(em.mass(u0, a1), -m * (s * s / 2 - s * s * s / 3), m, "Mu0a1");
    expect_rel(em.mass(u1, a1), -m * s * s * s / 3, m, "Mu1a1");
    expect_rel(em.mass(a1, a1), m * s * s * s / 3, m, "Ma1a1");
    expect_rel(em.mass(a0, a1), 0.0, m, "Ma0a1");
    expect_rel(em.jump(a0), 1 - s, 1, "jump a0");
    expect_rel(em.jump(a1), s, 1, "jump a1");
    EXPECT_TRUE(em.stiffness.isApprox(em.stiffness.transpose(), 0.0));
  }
}

TEST(Element, PhantomFormSpansTheEnrichedSpace) {
  // Tᵀ K_enr T must be the two side pieces assembled on (u0, p0, u1, p1): lower
  // piece on (u0, p1), upper on (p0, u1). Cancellation in Tᵀ K T costs a few ulps
  // of the largest entry.
  const double ea = 3e6, rho_a = 500.0, h = 2.0, s = 0.37;
  const auto em = xfem::enriched_element_matrices(ea, rho_a, 0.0, h, s * h);
  const xfem::Mat4 t = xfem::phantom_transform();
  EXPECT_DOUBLE_EQ(std::abs(t.determinant()), 1.0);
  const auto lo = xfem::bar_piece_matrices(ea, rho_a, 0.0, h, 0.0, s * h);
  const auto up = xfem::bar_piece_matrices(ea, rho_a, 0.0, h, s * h, h);
  xfem::Mat4 k = xfem::Mat4::Zero(), m = xfem::Mat4::Zero();
  const int lo_dofs[2] = {0, 3}, up_dofs[2] = {1, 2};
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      k(lo_dofs[r], lo_dofs[c]) += lo.stiffness(r, c);
      m(lo_dofs[r], lo_dofs[c]) += lo.mass(r, c);
      k(up_dofs[r], up_dofs[c]) += up.stiffness(r, c);
      m(up_dofs[r], up_dofs[c]) += up.mass(r, c);
    }
  EXPECT_LT((t.transpose() * em.stiffness * t - k).cwiseAbs().maxCoeff(), 8 * kElementTol * ea / h);
  EXPECT_LT((t.transpose() * em.mass * t - m).cwiseAbs().maxCoeff(), 8 * kElementTol * rho_a * h);
}

TEST(Element, EnrichedPatchTestInterpolation) {
  // Any field linear on each side of the interface, with any jump, is in the
  // enriched space: set the unknowns from it and read it back everywhere.
  BarDesc d = test::v2_rod(10, 1e-3);
  d.interface = BarInterfaceDesc{13.7, 1e8, BarInterfaceDesc::Behaviour::tied};
  BarModel m;
  BarState st;
  BarWorkspace ws;
  ASSERT_TRUE(build_bar(d, m, st, ws).ok());
  const double xi = 13.7;
  auto lower = [](double x) { return 2e-3 * x; };          // through 0: fixed base
  auto upper = [](double x) { return -1e-3 * x + 0.05; };  // other slope, jump at ξ
  const int e = m.cut_element;
  const double xe = d.length * e / d.elements, xe1 = d.length * (e + 1) / d.elements;
  // Enriched unknowns by hand: u_i is the field at node i on its own side,
  // a_e = upper(x_e) − lower(x_e), a_{e+1} = upper(x_{e+1}) − lower(x_{e+1}).
  const double a_e = upper(xe) - lower(xe), a_e1 = upper(xe1) - lower(xe1);
  // Unknowns of the cut element: cell (u_e, p_{e+1}) then (p_e, u_{e+1}); p = T⁻¹ (u, a).
  const BarCell& lo = m.cells[m.element_cell[e]];
  const BarCell& up = m.cells[m.element_cell[e] + 1];
  for (int i = 0; i <= d.elements; ++i) {
    const double x = d.length * i / d.elements;
    const double value = x < xi ? lower(x) : upper(x);
    for (const BarCell& c : m.cells) {
      if (c.dof[0] >= 0 && c.x0 == x && &c != &up) st.u[c.dof[0]] = value;
      if (c.dof[1] >= 0 && c.x1 == x && &c != &lo) st.u[c.dof[1]] = value;
    }
  }
  st.u[up.dof[0]] = lower(xe) + a_e;   // p_e = u_e + a_e
  st.u[lo.dof[1]] = upper(xe1) - a_e1; // p_{e+1} = u_{e+1} − a_{e+1}
  // Evaluation is a couple of products of O(1) numbers: ulps of 0.05.
  for (int k = 0; k <= 3000; ++k) {
    const double x = d.length * k / 3000.0;
    const double want = x <= xi ? lower(x) : upper(x);
    EXPECT_NEAR(bar_displacement(m, st, x), want, 1e-16 * 64) << "x = " << x;
  }
  EXPECT_NEAR(bar_interface_gap(m, st), upper(xi) - lower(xi), 1e-16 * 64);
}

TEST(Element, EnrichedPatchTestStatic) {
  // A static tip force F on a fixed-free bar with a tied interface: the exact
  // solution, u = F x/(EA) below ξ and F x/(EA) + F/k above, lies in the
  // enriched space, so the Galerkin solution must equal it at every x (not only
  // at nodes). Solved here with a dense LDLᵀ of the model's assembled K.
  for (auto method : {BarDesc::Method::xfem, BarDesc::Method::fem}) {
    BarDesc d = test::v2_rod(10, 1e-3);
    d.method = method;
    const double xi = 13.7, k_if = 4e8, f = -1e4;
    d.interface = BarInterfaceDesc{xi, k_if, BarInterfaceDesc::Behaviour::tied};
    BarModel m;
    BarState st;
    BarWorkspace ws;
    ASSERT_TRUE(build_bar(d, m, st, ws).ok());
    const Eigen::MatrixXd k = test::dense_stiffness(m);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m.dofs);
    rhs(m.tip_dof) = f;
    const Eigen::VectorXd u = k.ldlt().solve(rhs);
    for (int i = 0; i < m.dofs; ++i) st.u[i] = u(i);
    const double ea = d.youngs_modulus * d.area;
    const double scale = std::abs(f) * (d.length / ea + 1.0 / k_if);
    // cond(K) ~ (L/h)² · (1 + EA/(k h)) ≈ 1e3: round-off well under 1e-12 of the tip value.
    for (int j = 0; j <= 600; ++j) {
      const double x = d.length * j / 600.0;
      const double want = f * x / ea + (x > xi ? f / k_if : 0.0);
      EXPECT_NEAR(bar_displacement(m, st, x), want, 1e-12 * scale) << "x = " << x;
    }
    EXPECT_NEAR(bar_interface_gap(m, st), f / k_if, 1e-12 * scale);
  }
}
