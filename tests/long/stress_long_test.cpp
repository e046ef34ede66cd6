// Deep runs of the stability stress suite (label `long`, left out of the
// default presets: `ctest --preset release -L long`): 10⁶ steps each, with the
// bounds of docs/stability.md.
#include <gtest/gtest.h>

#include "stress/sweeps.hpp"
#include "support/coupled_scenes.hpp"

namespace xfdem::stress {
namespace {

constexpr std::int64_t kMillion = 1'000'000;

TEST(LongStress, DampedColumnForAMillionStepsAtNineTenthsOfTheNetworkLimit) {
  for (DemIntegrator integrator : {DemIntegrator::abm4, DemIntegrator::rk4, DemIntegrator::verlet}) {
    const DemDesc<1> d = column_scene(integrator, 0.1);
    const double dt = 0.9 * dem_stable_step_factor(integrator, 0.1) / column_network_omega(d);
    const Outcome o = run_dem_case(d, dt, kMillion);
    std::printf("%-8s: %lld steps, flags %s, max (E-E0)/A %.2e\n", integrator_name(integrator),
                static_cast<long long>(o.steps), flag_text(o.flags).c_str(), o.worst_excess);
    EXPECT_EQ(o.steps, kMillion);
    EXPECT_EQ(o.flags, StepStatus::ok);
    EXPECT_LE(o.worst_excess, 1e-12);
  }
}

TEST(LongStress, CaseOneForAMillionSteps) {
  CoupledDesc d = testing::coupled_scene("case1_xfem.json");
  d.bar.gamma = 0.6;
  d.bar.beta = 0.3025;
  d.dem.particles[0].position = {30.7};
  const Outcome o = run_coupled_case(d, kMillion, true);
  std::printf("case I: %lld steps, flags %s, max (E-E0)/A %.2e\n", static_cast<long long>(o.steps),
              flag_text(o.flags).c_str(), o.worst_excess);
  EXPECT_EQ(o.steps, kMillion);
  EXPECT_EQ(o.flags, StepStatus::ok);
  EXPECT_LE(o.worst_excess, 1e-12);
}

}  // namespace
}  // namespace xfdem::stress
