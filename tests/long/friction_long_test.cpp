// Deep runs of the granular step (label `long`): a particle at rest on a slope
// below the friction angle stays at rest for 1e6 steps (issue: rotating the
// tangential history into the contact plane must not make it creep). The same
// set-up as tests/dem/friction_test.cpp's 1e5-step RestOnSlope, on a slope
// whose plane is not axis-aligned in 3D. And a disk and a sphere held by
// rolling resistance below tan θ = μ_r, as tests/dem/rolling_hold_test.cpp's
// 1e5-step RollingHold.*HeldOnASlope*, for 1e6 steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/dem_scenes.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

template <int D>
void stays_at_rest(DemIntegrator integrator) {
  const double theta = 20 * kPi / 180, mu = 0.5, g = 9.81;
  ASSERT_LT(std::tan(theta), mu);
  DemDesc<D> d;
  d.dt = 1e-5;
  d.damping_ratio = 0.5;
  d.friction = mu;
  d.integrator = integrator;
  d.gravity[1] = -g;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  p.inertia = 1e12;  // a block: it cannot roll, the sticking spring alone holds it
  // The slope's normal (−sin θ, cos θ) turned about y in 3D by 30°: no axis-aligned shortcut.
  double normal[3] = {-std::sin(theta), std::cos(theta), 0};
  if constexpr (D == 3) {
    const double phi = kPi / 6, nx = normal[0];
    normal[0] = std::cos(phi) * nx;
    normal[2] = -std::sin(phi) * nx;
  }
  const double height = p.radius - p.mass * g * std::cos(theta) / p.stiffness;
  PlaneDesc<D> plane;
  for (int k = 0; k < D; ++k) {
    p.position[k] = normal[k] * height;
    plane.normal[k] = normal[k];
  }
  d.particles.push_back(p);
  d.planes.push_back(plane);
  DemWorld<D> world;
  ASSERT_TRUE(world.build(d).ok());
  double start[D];
  for (int k = 0; k < D; ++k) start[k] = world.state.x[k][0];
  const double stretch = g * std::sin(theta) / (kDefaultTangentialStiffnessRatio * p.stiffness);
  double peak = 0;
  for (int s = 0; s < 1000000; ++s) {
    ASSERT_EQ(world.step(), StepStatus::ok);
    double r2 = 0;
    for (int k = 0; k < D; ++k) r2 += (world.state.x[k][0] - start[k]) * (world.state.x[k][0] - start[k]);
    peak = std::max(peak, std::sqrt(r2));
  }
  double v2 = 0;
  for (int k = 0; k < D; ++k) v2 += world.state.v[k][0] * world.state.v[k][0];
  std::printf("D=%d %s 1e6 steps at rest: peak displacement %.3e m (static stretch %.3e m), speed %.3e m/s\n", D,
              integrator_name(integrator), peak, stretch, std::sqrt(v2));
  EXPECT_LE(peak, 2 * stretch);  // a suddenly loaded spring overshoots by at most its static stretch
  EXPECT_LT(std::sqrt(v2), 1e-12);
}

TEST(FrictionLong, DiskBlockStaysAtRestOnASlopeForAMillionSteps) {
  stays_at_rest<2>(DemIntegrator::verlet);
  stays_at_rest<2>(DemIntegrator::abm4_events);
}
TEST(FrictionLong, SphereBlockStaysAtRestOnATiltedSlopeForAMillionSteps) {
  stays_at_rest<3>(DemIntegrator::verlet);
  stays_at_rest<3>(DemIntegrator::abm4_events);
}

// tan θ = 0.18 < μ_r = 0.3 < μ = 0.5: the rolling couple cancels the sticking
// contact's torque m g sin θ r, so the disk (sphere) neither creeps nor turns:
// speed and spin at round-off after 1e6 steps (the start-up oscillation of
// the tangential spring decays as e^{−ζ ω_t t} = e^{−2670} over 10 s), having
// slid at most twice the static stretch.
template <int D>
void held_by_rolling_resistance(DemIntegrator integrator) {
  const double theta = 10 * kPi / 180, mu = 0.5, mu_r = 0.3, g = 9.81;
  ASSERT_LT(std::tan(theta), mu_r);
  DemDesc<D> d = incline<D>(theta, mu, mu_r, 0.5, integrator);
  d.energy_check.interval = 1;
  DemWorld<D> world;
  ASSERT_TRUE(world.build(d).ok());
  double start[D];
  for (int k = 0; k < D; ++k) start[k] = world.state.x[k][0];
  const double stretch = g * std::sin(theta) / (kDefaultTangentialStiffnessRatio * 1e6);
  double peak = 0;
  for (int s = 0; s < 1000000; ++s) {
    ASSERT_EQ(world.step(), StepStatus::ok);
    double r2 = 0;
    for (int k = 0; k < D; ++k) r2 += (world.state.x[k][0] - start[k]) * (world.state.x[k][0] - start[k]);
    peak = std::max(peak, std::sqrt(r2));
  }
  double v2 = 0, w2 = 0;
  for (int k = 0; k < D; ++k) v2 += world.state.v[k][0] * world.state.v[k][0];
  for (const auto& c : world.state.w) w2 += c[0] * c[0];
  std::printf("D=%d %s 1e6 steps held by rolling resistance: peak displacement %.3e m (static stretch %.3e m), "
              "speed %.3e m/s, spin %.3e rad/s\n",
              D, integrator_name(integrator), peak, stretch, std::sqrt(v2), std::sqrt(w2));
  EXPECT_LE(peak, 2 * stretch);
  EXPECT_LT(std::sqrt(v2), 1e-12);
  EXPECT_LT(std::sqrt(w2), 1e-12);
}

TEST(FrictionLong, DiskHeldByRollingResistanceOnASlopeForAMillionSteps) {
  held_by_rolling_resistance<2>(DemIntegrator::verlet);
  held_by_rolling_resistance<2>(DemIntegrator::abm4_events);
}
TEST(FrictionLong, SphereHeldByRollingResistanceOnASlopeForAMillionSteps) {
  held_by_rolling_resistance<3>(DemIntegrator::verlet);
  held_by_rolling_resistance<3>(DemIntegrator::abm4_events);
}

}  // namespace
}  // namespace xfdem::testing
