// The stable step each integrator states (dem_stable_step_factor) measured on
// the real stepper: a sphere resting in contact on a plane, slightly displaced,
// so that the contact is the linear oscillator the statement is about.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4,
                                  DemIntegrator::verlet, DemIntegrator::symplectic_euler};

/// Growth of the free response per undamped period, measured between periods
/// 100–110 and 190–200 (late enough for the dominant mode of the step map to
/// have taken over, whichever root it is).
double measured_growth_per_period(DemIntegrator integrator, double zeta, double wh) {
  const double m = 1.0, k = 1e4, r = 0.1, g = 9.81;
  const double w = std::sqrt(k / m), ds = m * g / k, y_eq = r - ds;
  DemDesc<1> d;
  d.gravity = {-g};
  d.damping_ratio = zeta;
  d.integrator = integrator;
  d.dt = wh / w;
  d.reject_unstable_dt = false;
  // A displacement of 1e-9 of the static overlap: the response is read only
  // while it stays below 1e-3 of it, so that neither the state nor any
  // intermediate stage of a step (which reaches a few ωh times further) can
  // leave the contact: the oscillator stays exactly linear.
  const double start = 1e-9 * ds, ceiling = 1e-3 * ds;
  d.particles.push_back({m, r, k, {y_eq - start}, {0.0}});
  d.planes.push_back({{0.0}, {1.0}});
  DemWorld<1> world;
  EXPECT_TRUE(world.build(d).ok());
  const double period = 2 * M_PI / wh;  // steps
  const auto window = [&](double from, double to) -> double {
    double amplitude = 0;
    while (static_cast<double>(world.state.step) < to * period) {
      world.step();
      const double a = std::fabs(world.state.x[0][0] - y_eq);
      // Past the ceiling the response grew by 1e6 within 200 periods, i.e. by
      // more than 7 % per period: unstable by the 1 % criterion.
      if (!std::isfinite(a) || a > ceiling) return INFINITY;
      if (static_cast<double>(world.state.step) >= from * period) amplitude = std::max(amplitude, a);
    }
    return amplitude;
  };
  const double early = window(100, 110);
  const double late = window(190, 200);
  if (!std::isfinite(late) || !std::isfinite(early)) return INFINITY;
  return std::pow(late / early, 1.0 / 90.0);
}

TEST(StableStep, MeasuredLimitMatchesTheStatedOneWithinFivePercent) {
  for (double zeta : {0.0, 0.1}) {
    for (DemIntegrator integ : kAll) {
      const double stated = dem_stable_step_factor(integ, zeta);
      // Bisection on ωh for the 1 %-per-period growth the statement uses.
      double lo = 0.5 * stated, hi = 1.5 * stated;
      ASSERT_LE(measured_growth_per_period(integ, zeta, lo), 1.01) << integrator_name(integ);
      ASSERT_GT(measured_growth_per_period(integ, zeta, hi), 1.01) << integrator_name(integ);
      for (int it = 0; it < 14; ++it) {
        const double mid = 0.5 * (lo + hi);
        (measured_growth_per_period(integ, zeta, mid) <= 1.01 ? lo : hi) = mid;
      }
      const double measured = 0.5 * (lo + hi);
      std::printf("zeta=%.1f %-17s stated omega*dt %.4f measured %.4f (%+.2f %%); eq 21 would say %.4f\n", zeta,
                  integrator_name(integ), stated, measured, 100 * (measured / stated - 1), std::sqrt(2.0));
      EXPECT_NEAR(measured / stated, 1.0, 0.05) << integrator_name(integ) << " zeta " << zeta;
    }
  }
}

// The stated values against the classical strict limits where those exist.
TEST(StableStep, OneStepMethodsSitAtTheirClassicalLimits) {
  // Undamped: Verlet and symplectic Euler are stable up to ωh = 2, RK4 up to
  // 2√2; the 1 %-per-period criterion moves that by well under 1 %.
  EXPECT_NEAR(dem_stable_step_factor(DemIntegrator::verlet, 0.0), 2.0, 0.01);
  EXPECT_NEAR(dem_stable_step_factor(DemIntegrator::symplectic_euler, 0.0), 2.0, 0.01);
  EXPECT_NEAR(dem_stable_step_factor(DemIntegrator::rk4, 0.0), 2 * std::sqrt(2.0), 0.02);
  // PECE ABM4 is weakly unstable on the imaginary axis: ρ = 1 + 0.16(ωh)^6 + …
  const double y = 0.1, rho = dem_amplification(DemIntegrator::abm4, 0.0, y);
  EXPECT_GT(rho, 1.0);
  EXPECT_NEAR((rho - 1) / std::pow(y, 6), 0.16, 0.01);
}

TEST(StableStep, BuildRejectsAStepPastTheLimitAndNamesIt) {
  DropParameters p;
  p.stiffness = 1e6;
  DemDesc<1> d = drop_scene(p, DemIntegrator::abm4, 1.0);
  DemWorld<1> world;
  const double limit = dem_stable_step_factor(DemIntegrator::abm4, p.zeta) / std::sqrt(p.stiffness / p.mass);
  d.dt = 1.05 * limit;
  const BuildResult bad = world.build(d);
  EXPECT_EQ(bad.code, BuildResult::Code::unstable_time_step);
  EXPECT_NE(std::strstr(bad.message, "dt"), nullptr) << bad.message;
  EXPECT_NE(std::strstr(bad.message, "abm4"), nullptr) << bad.message;
  d.dt = 0.95 * limit;
  EXPECT_TRUE(world.build(d).ok());
  EXPECT_NEAR(world.model.stable_dt, limit, 1e-12 * limit);
}

}  // namespace
}  // namespace xfdem::testing
