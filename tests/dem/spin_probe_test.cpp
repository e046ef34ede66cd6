// A particle given a spin in a frictionless model keeps it (docs/dem.md,
// "Rotation and friction": the rotation feature is on when the law turns the
// particles or a particle is given a non-zero angular velocity), and the
// force probes read the force the step applied (Verlet evaluates the law at
// the kicked velocity v_n+1/2: the probes take v − h/2 a).
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

/// A disk (2D) or sphere (3D), m 1, r 0.05, k 1e6, thrown at 2 m/s along a
/// floor (normal (0, 1)) from its static overlap, μ 0.5, ratio 2/7, dt 4e-4 s.
template <int D>
DemDesc<D> thrown(DemIntegrator integrator, double zeta) {
  DemDesc<D> d;
  d.dt = 4e-4;
  d.gravity[1] = -9.81;
  d.damping_ratio = zeta;
  d.friction = 0.5;
  d.integrator = integrator;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  p.position[1] = 0.05 - 9.81 / 1e6;
  p.velocity[0] = 2.0;
  d.particles.push_back(p);
  d.planes.push_back({});
  d.planes.back().normal[1] = 1.0;
  return d;
}

/// The probes' force on the particle: F_n along n = (0, 1), and the tangential
/// part along t = (−n_y, n_x) = (−1, 0) (2D; 3D its magnitude, against the
/// slip along x).
struct Force {
  double x, y;
};
template <int D>
Force probed(const DemWorld<D>& world) {
  const double fn = dem_plane_force(world.model, world.state, 0, 0);
  const double ft = dem_plane_tangential_force(world.model, world.state, 0, 0);
  return {-ft, fn};
}

// While the contact slides the tangential probe is the cap μ F_n of the
// normal probe, to round-off, and the probes' forces are the ones the step
// applied: Verlet's v_n+1 − v_n = h/2 (a_n + a_n+1), symplectic Euler's
// h a_n (both parts, F = m a with the weight added). The probe once
// evaluated the law at v_n+1 instead of Verlet's v_n+1/2: 3.9611 N for
// 4.905 at ζ 0.3, −0.994 at ζ 0.9.
template <int D>
void probe_reads_the_applied_force(DemIntegrator integrator, double zeta) {
  SCOPED_TRACE(integrator_name(integrator));
  SCOPED_TRACE(zeta);
  const DemDesc<D> d = thrown<D>(integrator, zeta);
  const double h = d.dt, mu = 0.5, g = 9.81;
  DemWorld<D> world;
  ASSERT_TRUE(world.build(d).ok());
  Force before = probed(world);
  int sliding = 0, rolling = 0;
  // Whether this step and the one before it slid (both forces in Verlet's mean at the cap).
  double last_slip = 1.0;
  auto sliding_steps_in_a_row = [&](double slip) {
    const bool both = slip > 0.1 && last_slip > 0.1;
    last_slip = slip;
    return both;
  };
  double worst_cap = 0, worst_ma = 0;
  for (int k = 1; k <= 750; ++k) {  // 0.3 s: slides until 2/(3 μ g) = 0.136 s (disk), then rolls
    const double vx = world.state.v[0][0], vy = world.state.v[1][0];
    const double slip = vx + world.state.w[spin_components(D) - 1][0] * 0.05;
    ASSERT_EQ(world.step(), StepStatus::ok) << "step " << k;
    const Force after = probed(world);
    const double fn = after.y;
    // Sliding: slip 0.1 m/s is ~15 steps (3 μ g h = 5.9e-3 m/s of slip each,
    // 3.5 μ g h a sphere) before the end, where the dashpot η_t v_t falls
    // below the cap and the contact starts to stick.
    if (slip > 0.1) {
      ++sliding;
      worst_cap = std::max(worst_cap, std::fabs(-after.x - mu * fn) / (mu * fn));
      EXPECT_NEAR(-after.x, mu * fn, 1e-12 * mu * fn) << "step " << k;
    } else {
      ++rolling;
    }
    const double ax = (world.state.v[0][0] - vx) / h, ay = (world.state.v[1][0] - vy) / h;
    const bool verlet = integrator == DemIntegrator::verlet;
    const double fx = verlet ? 0.5 * (before.x + after.x) : before.x;
    const double fy = (verlet ? 0.5 * (before.y + after.y) : before.y) - g;
    // 3D reads the tangential part's magnitude, against the slip while it
    // slides; past that its sign is not the probe's: the normal part only.
    const bool signed_tangential = D == 2 || sliding_steps_in_a_row(slip);
    worst_ma = std::max({worst_ma, signed_tangential ? std::fabs(ax - fx) : 0.0, std::fabs(ay - fy)});
    if (signed_tangential) {
      EXPECT_NEAR(ax, fx, 1e-9) << "step " << k;
    }
    EXPECT_NEAR(ay, fy, 1e-9) << "step " << k;
    before = after;
  }
  EXPECT_GT(sliding, 250);
  EXPECT_GT(rolling, 300);
  std::printf("D=%d %s zeta %.2f: %d steps sliding, |Ft - mu Fn|/(mu Fn) <= %.2e; %d rolling; |m a - F| <= %.2e N\n",
              D, integrator_name(integrator), zeta, sliding, worst_cap, rolling, worst_ma);
}

TEST(ContactForceProbe, ThrownDiskReadsTheAppliedForce) {
  for (double zeta : {0.1, 0.3, 0.6, 0.9})
    for (DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::symplectic_euler})
      probe_reads_the_applied_force<2>(integrator, zeta);
}

TEST(ContactForceProbe, ThrownSphereReadsTheAppliedForce) {
  for (double zeta : {0.3, 0.9})
    for (DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::symplectic_euler})
      probe_reads_the_applied_force<3>(integrator, zeta);
}

// Between particles: two disks meet head-on and slide past each other (μ
// 0.3, ζ 0.5; frictionless too, the plain step): the pair probes' force on
// p1, F_n n + F_t t (n from p0 to p1), is the one Verlet applied.
TEST(ContactForceProbe, PairReadsTheAppliedForceWithVerlet) {
  for (double mu : {0.0, 0.3}) {
    SCOPED_TRACE(mu);
    DemDesc<2> d;
    d.dt = 1e-4;
    d.damping_ratio = 0.5;
    d.friction = mu;
    d.integrator = DemIntegrator::verlet;
    d.particles.push_back({1, 0.05, 1e6, {0, 0}, {1, 0}});
    d.particles.push_back({1, 0.05, 1e6, {0.11, 0.02}, {-1, 0.5}});
    DemWorld<2> world;
    ASSERT_TRUE(world.build(d).ok());
    auto force_on_1 = [&] {
      const double dx = world.state.x[0][1] - world.state.x[0][0], dy = world.state.x[1][1] - world.state.x[1][0];
      const double len = std::sqrt(dx * dx + dy * dy), nx = dx / len, ny = dy / len;
      const double fn = dem_pair_force(world.model, world.state, 0, 1);
      const double ft = dem_pair_tangential_force(world.model, world.state, 0, 1);
      return Force{fn * nx - ft * ny, fn * ny + ft * nx};
    };
    Force before = force_on_1();
    int touching = 0;
    double worst = 0;
    for (int k = 1; k <= 600; ++k) {
      const double vx = world.state.v[0][1], vy = world.state.v[1][1];
      ASSERT_EQ(world.step(), StepStatus::ok) << "step " << k;
      const Force after = force_on_1();
      if (after.x != 0 || before.x != 0) ++touching;
      const double ax = (world.state.v[0][1] - vx) / d.dt, ay = (world.state.v[1][1] - vy) / d.dt;
      worst = std::max({worst, std::fabs(ax - 0.5 * (before.x + after.x)), std::fabs(ay - 0.5 * (before.y + after.y))});
      EXPECT_NEAR(ax, 0.5 * (before.x + after.x), 1e-8) << "step " << k;
      EXPECT_NEAR(ay, 0.5 * (before.y + after.y), 1e-8) << "step " << k;
      before = after;
    }
    EXPECT_GT(touching, 10);
    std::printf("pair, mu %.1f: %d steps touching, |m a - F| <= %.2e N\n", mu, touching, worst);
  }
}

}  // namespace
}  // namespace xfdem::testing
