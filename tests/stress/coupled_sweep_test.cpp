// Stability stress sweeps of the coupled stepper (label `stress`): a particle
// dropped on the top of the Case I rod (tied X-FEM interface, fixed base),
// over six decades of the mass ratio between the particle and the rod's top
// node, and with the interface cut down to 1e-9 of an element.
#include <gtest/gtest.h>

#include <cstring>

#include "stress/sweeps.hpp"
#include "support/coupled_scenes.hpp"

namespace xfdem::stress {
namespace {

constexpr std::int64_t kSteps = 5000;  // 5 s: the impacts and the rest

/// Case I with the particle's mass at `ratio` times the top node's lumped mass,
/// damped contact (ζ = 0.1) and a dissipative Newmark (γ = 0.6, β = 0.3025).
CoupledDesc dropped(double ratio) {
  CoupledDesc d = testing::coupled_scene("case1_xfem.json");
  d.bar.gamma = 0.6;
  d.bar.beta = (d.bar.gamma + 0.5) * (d.bar.gamma + 0.5) / 4;
  const double m_top = d.bar.density * d.bar.area * d.bar.length / d.bar.elements / 2;
  d.dem.particles[0].mass = ratio * m_top;
  d.dem.particles[0].position = {d.bar.length + d.dem.particles[0].radius + 0.2};
  return d;
}

double omega_c(const CoupledDesc& d) {
  const double m_top = d.bar.density * d.bar.area * d.bar.length / d.bar.elements / 2;
  return std::sqrt(d.dem.particles[0].stiffness * (1 / m_top + 1 / d.dem.particles[0].mass));
}

// Both dissipate (contact dashpot, γ > 1/2) and the exchange conserves energy
// at its fixed point: the energy never rises above E0 but for round-off.
constexpr double kEpsilon = 1e-12;
// The kernel's own check at every step, at the same bound: it must never trip
// where the energy stays within it.
constexpr EnergyCheck kTightCheck{1, kEpsilon};

TEST(CoupledStress, MassRatioOverSixDecadesAtTheScenesStep) {
  for (double ratio : {1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3}) {
    const CoupledDesc d = dropped(ratio);
    const Outcome checked = run_coupled_case(d, kSteps, true, kTightCheck);
    const Outcome o = run_coupled_case(d, kSteps, false);
    std::printf("m_p/m_top %-6g omega_c*dt %.3f: build %s; flags %-40s max (E-E0)/A %.2e\n", ratio,
                omega_c(d) * d.bar.dt, checked.built ? "ok     " : "refused", flag_text(o.flags).c_str(),
                o.worst_excess);
    SCOPED_TRACE("mass ratio " + std::to_string(ratio));
    ASSERT_TRUE(o.built);
    if (checked.built) {
      EXPECT_EQ(checked.flags, StepStatus::ok) << flag_text(checked.flags);
      EXPECT_TRUE(checked.finite);
      EXPECT_LE(checked.worst_excess, kEpsilon);
    } else {
      // Refused naming the step; built anyway, every step says so.
      EXPECT_EQ(checked.build_message.rfind("time.dt", 0), 0u) << checked.build_message;
      EXPECT_TRUE(has(o.flags, StepStatus::unstable_time_step));
      EXPECT_EQ(o.first_flag_step, 1);
    }
  }
}

TEST(CoupledStress, MassRatioOverSixDecadesAtAStableStep) {
  // The same ratios with dt chosen at ω_c·dt = 0.5: each one inside the region.
  for (double ratio : {1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3}) {
    CoupledDesc d = dropped(ratio);
    d.bar.dt = 0.5 / omega_c(d);
    const Outcome o = run_coupled_case(d, kSteps, true, kTightCheck);
    std::printf("m_p/m_top %-6g dt %.3g: flags %-20s max (E-E0)/A %.2e\n", ratio, d.bar.dt, flag_text(o.flags).c_str(),
                o.worst_excess);
    SCOPED_TRACE("mass ratio " + std::to_string(ratio));
    ASSERT_TRUE(o.built) << o.build_message;
    // Found by this sweep: with the particle as heavy as the top node or
    // heavier, some windows at ω_c·dt = 0.5 do not settle in kCoupledMaxPasses
    // passes. They are reported (coupling_unstable; the residual is carried,
    // so the books still close) and the energy stays bounded all the same.
    EXPECT_EQ(without(o.flags, StepStatus::coupling_unstable), StepStatus::ok) << flag_text(o.flags);
    EXPECT_TRUE(o.finite);
    EXPECT_LE(o.worst_excess, kEpsilon);
  }
}

TEST(CoupledStress, InterfaceCutDownToATrillionthOfAnElement) {
  // Both sides of a node, down to 1e-12 of an element: the exchange changes
  // the bar's acceleration by M⁻¹e_tip·Δf (bar_resolve_acceleration), so no
  // round-off is divided by the sliver's phantom mass.
  for (double cut : {1e-1, 1e-3, 1e-5, 1e-7, 1e-9, 1e-12, 1 - 1e-9, 1 - 1e-12}) {
    CoupledDesc d = dropped(0.25);  // Case I's 100 kg
    const double h = d.bar.length / d.bar.elements;
    d.bar.interface->position = 14 * h + cut * h;
    const Outcome o = run_coupled_case(d, kSteps, true, kTightCheck);
    std::printf("cut fraction %-9g: flags %-20s max (E-E0)/A %.2e\n", cut, flag_text(o.flags).c_str(), o.worst_excess);
    SCOPED_TRACE("cut fraction " + std::to_string(cut));
    ASSERT_TRUE(o.built) << o.build_message;
    EXPECT_EQ(o.flags, StepStatus::ok) << flag_text(o.flags);
    EXPECT_LE(o.worst_excess, kEpsilon);
  }
}

}  // namespace
}  // namespace xfdem::stress
