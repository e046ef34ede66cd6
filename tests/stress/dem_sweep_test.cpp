// Stability stress sweeps of the particle stepper (label `stress`; the deep
// runs are in tests/long). The scene is a column of three unequal spheres
// dropped on a plane (stress/sweeps.hpp): impacts, then resting contact in
// which one particle carries two contacts, so the frequency that limits the
// step is the contact network's, not a single contact's. docs/stability.md
// states the bounds asserted here.
#include <gtest/gtest.h>

#include <cstring>

#include "stress/sweeps.hpp"

namespace xfdem::stress {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::rk4,
                                  DemIntegrator::verlet, DemIntegrator::symplectic_euler};
constexpr double kFractions[] = {0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 1.01, 1.1, 1.5, 2.0};
constexpr std::int64_t kSteps = 20000;
// The kernel's energy check at every step, at its default tolerance: a case
// it lets through has gained at most that fraction of the largest energy in
// motion; one that gained more must say energy_growth.
constexpr EnergyCheck kCheck{1, EnergyCheck{}.tolerance};

/// The stated energy bound ε (E ≤ E0 + ε·A) inside 0.9 of the network limit,
/// or a negative value where none is stated (see docs/stability.md).
double stated_bound(DemIntegrator integrator, double zeta) {
  if (zeta > 0) {
    // The dashpot dissipates and these methods add nothing of their own below
    // 0.9 of the limit: the energy never rises above E0 but for round-off.
    if (integrator != DemIntegrator::symplectic_euler) return 1e-12;
    // First order: its impacts gain O(ωh)² of the exchanged energy; the
    // stated bound is that the column never gains what it has available.
    return 1.0;
  }
  // Undamped: every impact leaves an error of the method's order; the
  // fourth-order methods stay below the available energy, the second- and
  // first-order ones do not (their impact errors accumulate: not bounded).
  if (integrator == DemIntegrator::verlet || integrator == DemIntegrator::symplectic_euler) return -1;
  return 1.0;
}

/// What every case inside the stable step (at `fraction` of it) asserts of the
/// check: no false alarm where the energy cannot rise (the bound stated below
/// is round-off: dashpots, and a method that adds nothing of its own, inside
/// 0.9 of the limit), and no silent gain past the tolerance anywhere.
void expect_checked(DemIntegrator integrator, double zeta, double fraction, const Outcome& o) {
  EXPECT_EQ(without(o.flags, StepStatus::energy_growth), StepStatus::ok) << flag_text(o.flags);
  const double epsilon = stated_bound(integrator, zeta);
  if (epsilon >= 0 && epsilon <= 1e-12 && fraction <= 0.9) {
    EXPECT_EQ(o.flags, StepStatus::ok) << flag_text(o.flags);
  }
  if (!has(o.flags, StepStatus::energy_growth)) {
    EXPECT_LE(o.worst_excess, kCheck.tolerance * o.peak_motion * (1 + 1e-9)) << "a gain past the check, unreported";
  }
}

TEST(DemStress, TimeStepFromATenthToTwiceTheNetworkLimit) {
  for (DemIntegrator integrator : kAll)
    for (double zeta : {0.0, 0.1})
      for (double f : kFractions) {
        const DemDesc<1> d = column_scene(integrator, zeta);
        const double dt = f * dem_stable_step_factor(integrator, zeta) / column_network_omega(d);
        const Outcome o = run_dem_case(d, dt, kSteps, kCheck);
        std::printf("%-16s zeta %.1f dt/limit %4.2f: flags %-32s (first at step %5lld), max (E-E0)/A %.2e\n",
                    integrator_name(integrator), zeta, f, flag_text(o.flags).c_str(),
                    static_cast<long long>(o.first_flag_step), o.worst_excess);
        SCOPED_TRACE(std::string(integrator_name(integrator)) + " zeta " + std::to_string(zeta) + " dt/limit " +
                     std::to_string(f));
        ASSERT_TRUE(o.built) << o.build_message;
        if (f > 1) {
          // Past the limit the stepper says so as soon as the column's
          // contacts close (single-contact-only impacts come first).
          EXPECT_TRUE(has(o.flags, StepStatus::unstable_time_step));
          EXPECT_LE(o.first_flag_step, 500);
          continue;
        }
        expect_checked(integrator, zeta, f, o);
        EXPECT_TRUE(o.finite);
        const double epsilon = stated_bound(integrator, zeta);
        if (epsilon >= 0 && f <= 0.9) {
          EXPECT_LE(o.worst_excess, epsilon);
        }
      }
}

TEST(DemStress, ContactStiffnessOverSixDecadesAtOneTimeStep) {
  // dt fixed at half the network limit of the middle stiffness; k from 1e-3
  // to 1e3 times it. The soft columns must stay bounded; the stiff ones are
  // refused by the build (naming dt) or, when the check is off, flagged.
  for (DemIntegrator integrator : kAll) {
    const double zeta = 0.1;
    const double dt =
        0.5 * dem_stable_step_factor(integrator, zeta) / column_network_omega(column_scene(integrator, zeta));
    for (double scale : {1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3}) {
      DemDesc<1> d = column_scene(integrator, zeta, scale);
      const bool inside = dt * column_network_omega(d) <= dem_stable_step_factor(integrator, zeta);
      const Outcome o = run_dem_case(d, dt, kSteps, kCheck);
      std::printf("%-16s k x %-6g: %s; flags %-32s max (E-E0)/A %.2e\n", integrator_name(integrator), scale,
                  inside ? "inside " : "outside", flag_text(o.flags).c_str(), o.worst_excess);
      SCOPED_TRACE(std::string(integrator_name(integrator)) + " stiffness x " + std::to_string(scale));
      ASSERT_TRUE(o.built);
      if (inside) {
        expect_checked(integrator, zeta, dt * column_network_omega(d) / dem_stable_step_factor(integrator, zeta), o);
        EXPECT_LE(o.worst_excess, stated_bound(integrator, zeta));
      } else {
        EXPECT_TRUE(has(o.flags, StepStatus::unstable_time_step));
      }
      // With the check on, a single contact past its limit is refused at build.
      d.dt = dt;
      DemWorld<1> w;
      const BuildResult r = w.build(d);
      if (dt > w.model.stable_dt) {
        EXPECT_EQ(r.code, BuildResult::Code::unstable_time_step);
        EXPECT_EQ(std::strncmp(r.message, "dt:", 3), 0) << r.message;
      }
    }
  }
}

}  // namespace
}  // namespace xfdem::stress
