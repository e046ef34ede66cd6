// Two closed-form checks of the coupled step: a particle hitting the rod's end
// sees a dashpot before the stress wave returns, and the paper's cases
// converge as dt → 0.
#include <gtest/gtest.h>

#include <cstdio>

#include "support/coupled_scenes.hpp"

namespace xfdem::testing {
namespace {

// Before the stress wave comes back (t < 2L/c = 0.49 s) the end of a long rod
// is a dashpot Z = ρcA: with a linear spring k, ζ = 0 and no gravity, the
// overlap obeys δ'' + (k/Z)δ' + (k/m)δ = 0 with δ(0) = 0, δ'(0) = v0. The
// discrete end departs from an impedance at the contact frequency ω = √(k/m) by
// the lattice's dispersion, O((ωh/c)²); the time error (dt = 2e-5 s, ωdt =
// 0.006, trapezoidal Newmark, event-located particle steps) is far smaller.
double impact_force_error(int elements) {
  CoupledDesc d;
  d.bar.length = 30;
  d.bar.youngs_modulus = 3e7;
  d.bar.area = 0.4;
  d.bar.density = 2000;
  d.bar.elements = elements;
  d.bar.method = BarDesc::Method::fem;
  d.bar.beta = 0.25;
  d.bar.gamma = 0.5;
  d.bar.dt = 2e-5;
  d.dem.integrator = DemIntegrator::abm4_events;
  d.dem_substeps = 10;
  const double m = 100, k = 1e7, v0 = 2.0;
  d.dem.particles.push_back({m, 0.5, k, {30.5}, {-v0}});  // touching, moving down
  CoupledWorld w;
  EXPECT_TRUE(w.build(d).ok());
  const double Z = d.bar.density * std::sqrt(d.bar.youngs_modulus / d.bar.density) * d.bar.area;
  const double omega = std::sqrt(k / m), zeta = k / Z / (2 * omega), omega_d = omega * std::sqrt(1 - zeta * zeta);
  double worst = 0, peak = 0;
  while (w.state.time < 1.2 * M_PI / omega_d) {  // the contact and a little after
    EXPECT_EQ(w.step(), StepStatus::ok);
    const double t = w.state.time;
    const double exact = k * std::max(0.0, v0 / omega_d * std::exp(-zeta * omega * t) * std::sin(omega_d * t));
    worst = std::max(worst, std::fabs(coupled_top_force(w.model, w.state, 0) - exact));
    peak = std::max(peak, exact);
  }
  return worst / peak;
}

TEST(Impact, RodEndActsAsADashpotUntilTheWaveReturns) {
  const double c = std::sqrt(3e7 / 2000.0), omega = std::sqrt(1e7 / 100.0);
  const double e1 = impact_force_error(750), e2 = impact_force_error(1500);
  const double q1 = std::pow(omega * (30.0 / 750) / c, 2), q2 = std::pow(omega * (30.0 / 1500) / c, 2);
  std::printf("impact force vs closed form: %.2e of the peak (h = 0.04 m, (wh/c)^2 = %.1e), %.2e (h = 0.02 m); ratio %.2f\n",
              e1, q1, e2, e1 / e2);
  EXPECT_LT(e1, 0.1 * q1);
  EXPECT_LT(e2, 0.1 * q2);
  EXPECT_NEAR(e1 / e2, 4.0, 0.5);  // second order in h
}

// Case I (ζ = 0.1, β = 0.4, γ = 0.6) converges as dt → 0, with n = 10 and with
// n = 1, to a run of the same semi-discrete system at dt/128, over the first
// second (the drop and the first impact, before the sensitivity sets in).
// Expected order 1: Newmark with γ > ½ is first order, and so is the particle
// integrator across the dashpot's jump at touch-down.
TEST(Convergence, CaseOneConvergesAtFirstOrder) {
  for (int n : {10, 1}) {
    auto trace = [&](double dt) {
      CoupledDesc d = coupled_scene("case1_xfem.json");
      d.bar.dt = dt;
      d.dem_substeps = n;
      CoupledWorld w;
      EXPECT_TRUE(w.build(d).ok());
      std::vector<std::pair<double, double>> samples;  // (p1_y, tip_u) every 1 ms
      const long per_ms = std::lround(1e-3 / dt);
      for (long k = 1; k <= 1000 * per_ms; ++k) {
        EXPECT_EQ(w.step(), StepStatus::ok);
        if (k % per_ms == 0) samples.emplace_back(w.state.dem.x[0][0], bar_tip_displacement(w.model.bar, w.state.bar));
      }
      return samples;
    };
    const auto reference = trace(1e-3 / 128);
    std::vector<double> dts = {1e-3 / 2, 1e-3 / 4, 1e-3 / 8}, errors;
    for (double dt : dts) {
      const auto s = trace(dt);
      double worst = 0;
      for (std::size_t i = 0; i < s.size(); ++i)
        worst = std::max(worst, std::fabs(s[i].first - reference[i].first) + std::fabs(s[i].second - reference[i].second));
      errors.push_back(worst);
    }
    const double order = std::log(errors.front() / errors.back()) / std::log(dts.front() / dts.back());
    std::printf("Case I, n = %d: max error over 1 s %.2e, %.2e, %.2e m (dt = 5e-4, 2.5e-4, 1.25e-4): order %.2f\n", n,
                errors[0], errors[1], errors[2], order);
    EXPECT_NEAR(order, 1.0, 0.4);
  }
}

}  // namespace
}  // namespace xfdem::testing
