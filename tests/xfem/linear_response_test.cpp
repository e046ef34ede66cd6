// The bar's step is linear in its tip force when no active set can change
// (tied interface or none): the coupled step takes it once per window and moves
// it to the settled force along BarModel::tip_response_* (bar_adjust_step_input).
// Here that correction is compared with the step taken with the settled force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfem/reference.hpp"

using namespace xfdem;

namespace {

double max_abs(const std::vector<double>& x) {
  double m = 0;
  for (double v : x) m = std::max(m, std::fabs(v));
  return m;
}

double max_difference(const std::vector<double>& x, const std::vector<double>& y) {
  double m = 0;
  for (std::size_t i = 0; i < x.size(); ++i) m = std::max(m, std::fabs(x[i] - y[i]));
  return m;
}

struct Variant {
  BarDesc::Method method;
  BarDesc::Base base;
  bool interface;
  double position;
};

}  // namespace

TEST(BarLinearResponse, CorrectedStepIsTheStepTakenWithTheOtherForce) {
  const double h = 1.0;  // the element length of v2_rod(30)
  const Variant variants[] = {
      {BarDesc::Method::xfem, BarDesc::Base::fixed, true, 14.5},
      {BarDesc::Method::xfem, BarDesc::Base::absorbing, true, 14.5},
      {BarDesc::Method::xfem, BarDesc::Base::fixed, true, 14.0 + 1e-9 * h},  // a sliver cut
      {BarDesc::Method::xfem, BarDesc::Base::fixed, true, 15.0 - 1e-12 * h},
      {BarDesc::Method::fem, BarDesc::Base::absorbing, true, 14.5},
      {BarDesc::Method::fem, BarDesc::Base::fixed, false, 0.0},
  };
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  double worst = 0;
  for (const Variant& v : variants) {
    BarDesc d = test::v2_rod(30);
    d.method = v.method;
    d.base = v.base;
    if (v.interface) d.interface = BarInterfaceDesc{v.position, 1.2e9, BarInterfaceDesc::Behaviour::tied};
    BarModel m;
    BarState st;
    BarWorkspace ws;
    ASSERT_TRUE(build_bar(d, m, st, ws).ok());
    ASSERT_TRUE(m.linear_in_tip_force);
    // Warm up under a load and a varying input, so that u, v, a are all far from zero.
    for (int k = 0; k < 200; ++k) {
      const BarInput in{-3e3 * std::sin(0.07 * k)};
      ASSERT_EQ(bar_resolve_acceleration(m, st, ws, in), StepStatus::ok);
      ASSERT_EQ(bar_step(m, st, ws, in), StepStatus::ok);
    }
    for (const double f1 : {-2e3, 0.0, 150.0}) {
      for (const double f2 : {-2.5e3, -2e3 + 1e-6, 40.0, 7e3}) {
        BarState corrected = st, direct = st;
        BarWorkspace ws_corrected = ws, ws_direct = ws;
        ASSERT_EQ(bar_resolve_acceleration(m, corrected, ws_corrected, BarInput{f1}), StepStatus::ok);
        ASSERT_EQ(bar_step(m, corrected, ws_corrected, BarInput{f1}), StepStatus::ok);
        ASSERT_EQ(bar_adjust_step_input(m, corrected, ws_corrected, f2), StepStatus::ok);
        ASSERT_EQ(bar_resolve_acceleration(m, direct, ws_direct, BarInput{f2}), StepStatus::ok);
        ASSERT_EQ(bar_step(m, direct, ws_direct, BarInput{f2}), StepStatus::ok);
        // Two roundings of one affine map. u: within a few dozen roundings of
        // the size of what it adds up (the state, and the response times the
        // change of force). v and a are tied to u by Newmark's update
        // (u = u_pred + βΔt² a, v = v_pred + γΔt a), so a difference δu allows
        // δa = δu/(βΔt²) and δv = γΔt δa: a and v come out of the solve with
        // the round-off of the elastic forces, far larger than themselves.
        const double df = std::fabs(f2 - f1);
        const auto bound = [&](const std::vector<double>& x, const std::vector<double>& r) {
          return 64 * kEps * (max_abs(x) + df * max_abs(r));
        };
        const double fac0 = m.scheme.fac0(), fac1 = m.scheme.fac1();
        const double bound_u = bound(direct.u, m.tip_response_u);
        const double bound_a = bound_u / fac0 + bound(direct.a, m.tip_response_a);
        const double bound_v = fac1 * bound_u / fac0 + bound(direct.v, m.tip_response_v);
        const double du = max_difference(corrected.u, direct.u), dv = max_difference(corrected.v, direct.v),
                     da = max_difference(corrected.a, direct.a);
        EXPECT_LE(du, bound_u) << v.position << " " << f1 << " -> " << f2;
        EXPECT_LE(dv, bound_v) << v.position << " " << f1 << " -> " << f2;
        EXPECT_LE(da, bound_a) << v.position << " " << f1 << " -> " << f2;
        worst = std::max({worst, du / bound_u, dv / bound_v, da / bound_a});
        EXPECT_EQ(corrected.tip_input, direct.tip_input);
        EXPECT_EQ(corrected.step, direct.step);
        EXPECT_EQ(corrected.time, direct.time);
        // The books: re-booked as if f2 had acted throughout.
        const double work_scale = std::fabs(direct.energy.work) + std::fabs(direct.input_work) + 1.0;
        EXPECT_NEAR(corrected.energy.work, direct.energy.work, 64 * kEps * work_scale);
        EXPECT_NEAR(corrected.input_work, direct.input_work, 64 * kEps * work_scale);
        EXPECT_NEAR(ws_corrected.last_external_impulse, ws_direct.last_external_impulse,
                    64 * kEps * (std::fabs(ws_direct.last_external_impulse) + df * m.scheme.dt));
      }
    }
    // The tip's share is the tip unknown's.
    EXPECT_EQ(m.tip_response_displacement, m.tip_response_u[static_cast<std::size_t>(m.tip_dof)]);
  }
  std::printf("worst difference, corrected vs direct step: %.3g of the bound\n", worst);
}

TEST(BarLinearResponse, UnilateralInterfaceIsNotLinear) {
  BarDesc d = test::v2_rod(30);
  d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::unilateral};
  BarModel m;
  BarState st;
  BarWorkspace ws;
  ASSERT_TRUE(build_bar(d, m, st, ws).ok());
  EXPECT_FALSE(m.linear_in_tip_force);
  EXPECT_TRUE(m.tip_response_u.empty());
  ASSERT_EQ(bar_step(m, st, ws, BarInput{1.0}), StepStatus::ok);
  const BarState before = st;
  EXPECT_EQ(bar_adjust_step_input(m, st, ws, 2.0), StepStatus::not_built);
  EXPECT_EQ(st.u, before.u);
}
