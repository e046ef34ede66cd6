// A particle given a spin in a frictionless model keeps it (docs/dem.md,
// "Rotation and friction": the rotation feature is on when the law turns the
// particles or a particle is given a non-zero angular velocity).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "xfdem/dem.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kAll[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                  DemIntegrator::abm4, DemIntegrator::abm4_events};

/// Two particles (m 1, r 0.05, k 1e6) without gravity or friction, each given
/// a spin: p0 falls at 1 m/s onto a floor (normal (0, 1)) and bounces off it
/// (a damped contact of about 3 ms), p1 flies free with an inertia of its own.
template <int D>
DemDesc<D> spinning_pair(DemIntegrator integrator, ContactLaw law) {
  DemDesc<D> d;
  d.dt = 1e-4;
  d.law = law;
  d.damping_ratio = 0.1;
  d.integrator = integrator;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  p.position[1] = 0.2;
  p.velocity[1] = -1.0;
  if constexpr (D == 2) p.angular_velocity = {7.0};
  if constexpr (D == 3) p.angular_velocity = {1.5, -2.0, 7.0};
  d.particles.push_back(p);
  p.position[0] = 1.0;
  p.velocity[0] = 0.3;
  p.inertia = 0.003;
  if constexpr (D == 2) p.angular_velocity = {-3.0};
  if constexpr (D == 3) p.angular_velocity = {0.0, 4.0, -3.0};
  d.particles.push_back(p);
  d.planes.push_back({});
  d.planes.back().normal[1] = 1.0;
  return d;
}

/// Σ ½ m v² + ½ I ω², I the particle's own or ½ m r² (disk), 2/5 m r² (sphere).
template <int D>
double kinetic(const DemDesc<D>& d, const DemState<D>& s) {
  double sum = 0;
  for (std::size_t i = 0; i < d.particles.size(); ++i) {
    const auto& p = d.particles[i];
    const double inertia = p.inertia > 0 ? p.inertia : (D == 2 ? 0.5 : 0.4) * p.mass * p.radius * p.radius;
    double v2 = 0, w2 = 0;
    for (int c = 0; c < D; ++c) v2 += s.v[c][i] * s.v[c][i];
    for (double w : p.angular_velocity) w2 += w * w;
    sum += 0.5 * p.mass * v2 + 0.5 * inertia * w2;
  }
  return sum;
}

template <int D>
void keeps_its_spin(DemIntegrator integrator, ContactLaw law) {
  SCOPED_TRACE(integrator_name(integrator));
  SCOPED_TRACE(contact_law_name(law));
  const DemDesc<D> d = spinning_pair<D>(integrator, law);
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  ASSERT_TRUE(world.model.features.rotation);
  const auto check = [&](std::int64_t step) {
    SCOPED_TRACE(step);
    for (std::int32_t i = 0; i < 2; ++i)
      for (int k = 0; k < spin_components(D); ++k)
        EXPECT_EQ(dem_angular_velocity(world.model, world.state, i, k),
                  d.particles[static_cast<std::size_t>(i)].angular_velocity[static_cast<std::size_t>(k)]);
    if constexpr (D == 2)
      for (std::int32_t i = 0; i < 2; ++i) {
        const double turned = d.particles[static_cast<std::size_t>(i)].angular_velocity[0] * world.state.time;
        EXPECT_NEAR(dem_rotation(world.model, world.state, i), turned, 1e-12 * std::fabs(turned) + 1e-300);
      }
    const double expected = kinetic(d, world.state);
    EXPECT_NEAR(dem_energy(world.model, world.state).kinetic, expected, 1e-14 * expected);
  };
  check(0);
  // 0.3 s: p0 lands at 0.15 s and leaves the floor 3 ms later.
  double lowest = 1;
  for (std::int64_t k = 1; k <= 3000; ++k) {
    const StepStatus status = world.step();
    ASSERT_EQ(status, StepStatus::ok) << "step " << k;
    lowest = std::min(lowest, world.state.x[1][0]);
    if (k % 250 == 0) check(k);
  }
  EXPECT_LT(lowest, 0.05);               // it touched the floor
  EXPECT_GT(world.state.v[1][0], 0.5);  // and bounced off it
  std::printf("D=%d %s %s: omega %.17g, angle %.17g (omega t %.17g), kinetic %.17g J\n", D, integrator_name(integrator),
              contact_law_name(law), dem_angular_velocity(world.model, world.state, 0, spin_components(D) - 1),
              D == 2 ? dem_rotation(world.model, world.state, 0) : 0.0, 7.0 * world.state.time,
              dem_energy(world.model, world.state).kinetic);
}

TEST(SpinWithoutFriction, KeptBitForBitAndCountedIn2D) {
  for (DemIntegrator integrator : kAll)
    for (ContactLaw law : {ContactLaw::linear, ContactLaw::linear_nontensile}) keeps_its_spin<2>(integrator, law);
}

TEST(SpinWithoutFriction, KeptBitForBitAndCountedIn3D) {
  for (DemIntegrator integrator : kAll)
    for (ContactLaw law : {ContactLaw::linear, ContactLaw::linear_nontensile}) keeps_its_spin<3>(integrator, law);
}

// The scene of the report: one disk, ω 7, no gravity, verlet, linear, ζ 0.1:
// ½ I ω² = ½ · ½ · 0.05² · 49 = 0.030625 J from t = 0; the snapshot's hash
// carries the spin; without spin the model does not rotate (the frictionless
// step, whose golden hashes are tests/determinism/scene_hash_test.cpp's).
TEST(SpinWithoutFriction, ReportedDiskAndTheFeatureRule) {
  DemDesc<2> d;
  d.dt = 1e-4;
  d.damping_ratio = 0.1;
  d.integrator = DemIntegrator::verlet;
  d.particles.push_back({1, 0.05, 1e6, {0, 1}, {0, 0}});
  d.particles[0].angular_velocity = {7.0};
  DemWorld<2> world;
  ASSERT_TRUE(world.build(d).ok());
  EXPECT_NEAR(dem_energy(world.model, world.state).kinetic, 0.030625, 1e-17);
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(world.step(), StepStatus::ok);
  EXPECT_EQ(dem_angular_velocity(world.model, world.state, 0, 0), 7.0);
  EXPECT_NEAR(dem_rotation(world.model, world.state, 0), 0.7, 1e-13);
  EXPECT_NEAR(dem_energy(world.model, world.state).kinetic, 0.030625, 1e-17);

  DemDesc<2> other = d;
  other.particles[0].angular_velocity = {8.0};
  DemWorld<2> faster;
  ASSERT_TRUE(faster.build(other).ok());
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(faster.step(), StepStatus::ok);
  EXPECT_NE(state_hash(world.state), state_hash(faster.state));

  DemDesc<2> still = d;
  still.particles[0].angular_velocity = {0.0};
  DemWorld<2> plain;
  ASSERT_TRUE(plain.build(still).ok());
  EXPECT_FALSE(plain.model.features.rotation);
  EXPECT_TRUE(plain.state.w[0].empty());
  EXPECT_EQ(dem_angular_velocity(plain.model, plain.state, 0, 0), 0.0);
}

}  // namespace
}  // namespace xfdem::testing
