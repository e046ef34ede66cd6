// The paper's V1 drop test against its closed form (tests/support/drop_closed_form.hpp).
#include <gtest/gtest.h>

#include <cstdio>

#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

struct DropErrors {
  int bounces = 0;
  double apex = 0, overlap = 0, duration = 0, impact_time = 0;  // worst relative (time: absolute, s)
};

DropErrors drop_errors(double k, DemIntegrator integrator, double dt, int max_bounces) {
  DropParameters p;
  p.stiffness = k;
  const auto exact = drop_bounces(p, 6.0);
  DemWorld<1> world;
  const BuildResult built = world.build(drop_scene(p, integrator, dt));
  EXPECT_TRUE(built.ok()) << built.message;
  const auto measured = measure_drop(world, p.radius, 6.0);
  DropErrors e;
  for (std::size_t b = 0; b < exact.size() && b < measured.size() && e.bounces < max_bounces; ++b) {
    if (!exact[b].duration || std::isnan(measured[b].apex_after) || std::isnan(measured[b].t_release)) break;
    // Apex heights of the centre above the plane; relative to the height itself.
    e.apex = std::max(e.apex, std::fabs(measured[b].apex_after / exact[b].apex - 1));
    e.overlap = std::max(e.overlap, std::fabs(measured[b].max_overlap / exact[b].max_overlap - 1));
    const double duration = measured[b].t_release - measured[b].t_impact;
    e.duration = std::max(e.duration, std::fabs(duration / *exact[b].duration - 1));
    e.impact_time = std::max(e.impact_time, std::fabs(measured[b].t_impact - exact[b].t_impact));
    ++e.bounces;
  }
  return e;
}

// Tolerances, with ω = √(k/m), h = dt, ζ = 0.1:
// - abm4 (the paper's integrator): at touch-down the dashpot force jumps by
//   η v, and a multistep formula that spans the jump integrates it to O(h): the
//   exit speed is off by O(η h / m) = O(2ζωh) relative, and every later apex
//   inherits it. Bound: 10 ζωh (observed 1.6–3.2 ζωh for k = 1e3…1e5).
// - abm4_events: the contact start and end are located to 2^-48 of a step and
//   each piece is integrated with a smooth right-hand side, so the 4th order
//   holds: error ≈ c (ωh)^4 with c of order 0.1 per bounce (observed 0.16–0.18
//   over six bounces). Bound: (ωh)^4 on the apex heights, which the measurement
//   reads exactly (parabola through samples in free flight).
// - Maximum overlap and contact duration are read from samples and carry their
//   own measurement error: the parabola through the deepest three samples is
//   off by O((ωh)^3) relative; the Hermite crossing at touch-down by
//   h²Δa/(8v) with Δa = ηv/m, i.e. ζ(ωh)²/(4π) of the duration. Bounds for
//   abm4_events: those measurement errors (the simulation error is below them).
class DropTest : public ::testing::TestWithParam<double> {};

TEST_P(DropTest, Abm4IsFirstOrderAcrossImpactsWithinTheDashpotJumpBound) {
  const double k = GetParam(), dt = 1e-4, zeta = 0.1;
  const double wh = std::sqrt(k) * dt;  // m = 1
  const DropErrors e = drop_errors(k, DemIntegrator::abm4, dt, 6);
  std::printf("k=%g abm4: %d bounces, apex %.3e, max overlap %.3e, duration %.3e (relative)\n", k, e.bounces, e.apex,
              e.overlap, e.duration);
  EXPECT_GE(e.bounces, 6);
  EXPECT_LE(e.apex, 10 * zeta * wh);
  EXPECT_LE(e.overlap, 10 * zeta * wh);
  EXPECT_LE(e.duration, 10 * zeta * wh);
}

TEST_P(DropTest, Abm4WithEventsIsFourthOrderAccurate) {
  const double k = GetParam(), dt = 1e-4, zeta = 0.1;
  const double wh = std::sqrt(k) * dt;
  const DropErrors e = drop_errors(k, DemIntegrator::abm4_events, dt, 6);
  std::printf("k=%g abm4_events: %d bounces, apex %.3e, max overlap %.3e, duration %.3e (relative)\n", k, e.bounces,
              e.apex, e.overlap, e.duration);
  EXPECT_GE(e.bounces, 6);
  EXPECT_LE(e.apex, std::pow(wh, 4));
  EXPECT_LE(e.overlap, std::pow(wh, 3));
  EXPECT_LE(e.duration, zeta * wh * wh / (4 * M_PI) + std::pow(wh, 4));
}

// What event location buys, in one number: the apex error of the paper's run.
TEST(DropTest, EventLocationCutsTheApexErrorByOrdersOfMagnitude) {
  const DropErrors plain = drop_errors(1e4, DemIntegrator::abm4, 1e-4, 6);
  const DropErrors located = drop_errors(1e4, DemIntegrator::abm4_events, 1e-4, 6);
  std::printf("k=1e4, dt=1e-4: apex error abm4 %.3e, abm4_events %.3e, ratio %.3g\n", plain.apex, located.apex,
              plain.apex / located.apex);
  EXPECT_GT(plain.apex / located.apex, 1e5);
}

// The same closed form over the whole run: the trajectory, not only the events.
TEST(DropTest, TrajectoryFollowsTheClosedFormThroughAllBounces) {
  DropParameters p;
  p.stiffness = 1e4;
  const auto exact = drop_bounces(p, 6.0);
  DemWorld<1> world;
  ASSERT_TRUE(world.build(drop_scene(p, DemIntegrator::abm4_events, 1e-4)).ok());
  double worst = 0;
  while (world.state.time < 6.0 - 1e-9) {
    ASSERT_EQ(world.step(), StepStatus::ok);
    worst = std::max(worst, std::fabs(world.state.x[0][0] - drop_height(p, exact, world.state.time)));
  }
  // (ωh)^4 = 1e-8 relative of a 3 m drop (see the tolerances above).
  EXPECT_LE(worst, 3.0 * 1e-8);
  std::printf("max |y - y_exact| over 6 s: %.3e m\n", worst);
}

INSTANTIATE_TEST_SUITE_P(V1, DropTest, ::testing::Values(1e3, 1e4, 1e5),
                         [](const auto& param_info) { return "k" + std::to_string(static_cast<int>(param_info.param)); });

}  // namespace
}  // namespace xfdem::testing
