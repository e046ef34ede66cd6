// The bar's energy balance check (BarDesc::energy_check, BarState::energy):
// its books against the closed forms of a constant tip force, and its report
// when the state gains energy nothing did work for.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>

#include "xfdem/bar.hpp"
#include "xfem/reference.hpp"

namespace xfdem {
namespace {

/// ½vᵀMv + ½uᵀKu from dense copies of the operators (the kernel sums the
/// elastic part cell by cell instead).
double dense_energy(const BarModel& m, const BarState& st) {
  const Eigen::Map<const Eigen::VectorXd> u(st.u.data(), m.dofs), v(st.v.data(), m.dofs);
  return 0.5 * v.dot(test::dense(m.mass) * v) + 0.5 * u.dot(test::dense_stiffness(m) * u);
}

BarDesc step_loaded(double beta, double gamma) {
  BarDesc d = test::v2_rod(30, 1e-3);
  d.tip_load = BarDesc::TipLoad::step;
  d.tip_amplitude = -1e4;
  d.tip_duration = 0.0;
  d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::tied};
  d.beta = beta;
  d.gamma = gamma;
  return d;
}

// Under a constant force F the scheme's weighted work Σ[u_tip]·F_γ is F·u_tip
// whatever γ, and the energy it booked is the energy the bar holds: exactly
// (to round-off) for the trapezoidal rule, less the numerical dissipation for
// γ > ½. Neither is ever reported, even at a tolerance of 1e-12.
TEST(EnergyCheck, BooksTheWorkOfAConstantTipForce) {
  for (const auto& [beta, gamma] : {std::pair{0.25, 0.5}, std::pair{0.3025, 0.6}}) {
    BarDesc d = step_loaded(beta, gamma);
    d.energy_check = EnergyCheck{1, 1e-12};
    BarModel m;
    BarState st;
    BarWorkspace ws;
    ASSERT_TRUE(build_bar(d, m, st, ws).ok());
    // Ê0: at rest, but a₀ ≠ 0 under the step load, so ½Δt²(β − γ/2)a₀ᵀMa₀ (0 at β = γ/2).
    const Eigen::Map<const Eigen::VectorXd> a0(st.a.data(), m.dofs);
    const double ehat0 = 0.5 * d.dt * d.dt * (beta - 0.5 * gamma) * a0.dot(test::dense(m.mass) * a0);
    EXPECT_NEAR(st.energy.reference, ehat0, 1e-12 * ehat0);
    double peak = 0, worst_work = 0, worst_balance = 0, lowest_balance = 0;
    for (int k = 0; k < 4000; ++k) {
      ASSERT_EQ(bar_step(m, st, ws), StepStatus::ok) << "gamma " << gamma << ", step " << k + 1;
      const double work = d.tip_amplitude * bar_tip_displacement(m, st);
      const double energy = dense_energy(m, st);
      peak = std::max(peak, std::fabs(work));
      worst_work = std::max(worst_work, std::fabs(st.energy.work - work));
      // E ≤ Ê ≤ Ê0 + W: the books' bound on the true energy.
      worst_balance = std::max(worst_balance, energy - ehat0 - work);
      lowest_balance = std::min(lowest_balance, energy - ehat0 - work);
    }
    SCOPED_TRACE("gamma " + std::to_string(gamma));
    EXPECT_GT(peak, 0.0);
    EXPECT_LE(worst_work, 1e-12 * peak);
    EXPECT_LE(worst_balance, 1e-11 * peak);
    if (gamma == 0.5) {
      EXPECT_GE(lowest_balance, -1e-11 * peak);
    } else {
      EXPECT_LT(lowest_balance, -1e-3 * peak);  // γ > ½ dissipates
    }
  }
}

/// A bar kicked into free vibration (no load), its books restarted by
/// bar_initial_acceleration, with the check every `interval` steps.
struct Kicked {
  BarModel m;
  BarState st;
  BarWorkspace ws;
  explicit Kicked(int interval, double tolerance = 0.05) {
    BarDesc d = test::v2_rod(30, 1e-3);
    d.tip_load = BarDesc::TipLoad::none;
    d.tip_amplitude = 0.0;
    d.tip_duration = 0.0;
    d.energy_check = EnergyCheck{interval, tolerance};
    EXPECT_TRUE(build_bar(d, m, st, ws).ok());
    for (std::size_t i = 0; i < st.v.size(); ++i) st.v[i] = 0.01 * static_cast<double>(i) / static_cast<double>(st.v.size());
    bar_initial_acceleration(m, st, ws);
  }
  /// What a defect would do: energy from nowhere (the speeds scaled by 1.1,
  /// 21 % more kinetic energy), with the books left as they were.
  void gain() {
    for (double& v : st.v) v *= 1.1;
  }
};

TEST(EnergyCheck, ReportsAGainAtTheNextCheckAndOnEveryStepAfter) {
  constexpr int kInterval = 8;
  Kicked k(kInterval);
  EXPECT_GT(k.st.energy.reference, 0.0);
  for (int s = 0; s < 21; ++s) ASSERT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::ok) << "step " << s + 1;
  k.gain();
  // Steps 22, 23: no check yet; step 24 is the next multiple of the interval.
  EXPECT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::ok);
  EXPECT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::ok);
  EXPECT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::energy_growth);
  EXPECT_EQ(k.st.step % kInterval, 0);
  for (int s = 0; s < 50; ++s) ASSERT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::energy_growth);
  // New books from the state as it is: nothing to report.
  bar_restart_energy_ledger(k.m, k.st);
  for (int s = 0; s < 200; ++s) ASSERT_EQ(bar_step(k.m, k.st, k.ws), StepStatus::ok);
}

TEST(EnergyCheck, AGainBelowTheToleranceIsNotReportedAndIntervalZeroChecksNothing) {
  Kicked loose(1, 0.5);  // 21 % of the energy in motion is below 50 %
  loose.gain();
  for (int s = 0; s < 100; ++s) ASSERT_EQ(bar_step(loose.m, loose.st, loose.ws), StepStatus::ok);
  Kicked off(0);
  off.gain();
  for (int s = 0; s < 100; ++s) ASSERT_EQ(bar_step(off.m, off.st, off.ws), StepStatus::ok);
  EXPECT_EQ(off.st.energy.exceeded, 0);
}

TEST(EnergyCheck, BadSettingsAreRefusedNamingTheField) {
  struct Case {
    int interval;
    double tolerance;
    const char* field;
  };
  const Case cases[] = {{-1, 0.05, "energy_check.interval"},
                        {16, 0.0, "energy_check.tolerance"},
                        {16, -0.1, "energy_check.tolerance"},
                        {16, std::nan(""), "energy_check.tolerance"},
                        {16, HUGE_VAL, "energy_check.tolerance"}};
  for (const Case& c : cases) {
    BarDesc d = test::v2_rod();
    d.energy_check = EnergyCheck{c.interval, c.tolerance};
    BarModel m;
    BarState st;
    BarWorkspace ws;
    const BuildResult r = build_bar(d, m, st, ws);
    EXPECT_EQ(r.code, BuildResult::Code::invalid_argument) << c.field;
    EXPECT_EQ(std::strncmp(r.message, c.field, std::strlen(c.field)), 0) << r.message;
  }
}

}  // namespace
}  // namespace xfdem
