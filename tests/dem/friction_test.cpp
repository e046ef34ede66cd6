// Rotation and Coulomb friction (DemDesc::friction) against closed forms the
// tests compute: a disk and a sphere on an incline (rolling without slip,
// sliding with its spin-up, frictionless sliding), the gross-sliding oblique
// impact, a particle at rest on a slope, and the contact records' survival of
// pair-list rebuilds, snapshots, two workers and the allocation guard.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "xfdem/dem.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"
#include "support/dem_replay.hpp"
#include "support/dem_scenes.hpp"

namespace xfdem::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

/// Velocity down the slope, d = (−cos θ, −sin θ).
template <int D>
double downhill(const DemState<D>& s, double theta) {
  return -std::cos(theta) * s.v[0][0] - std::sin(theta) * s.v[1][0];
}

struct Slope {
  double acceleration, spin_rate, slip;  // between t1 and t2; slip = v − ω r at t2
};

/// Runs to t2, reading the downhill velocity and the spin at t1 and t2: the
/// slopes between them are past the tangential spring's start-up transient
/// (decay e^{−ζ ω_t t1}, ω_t ≈ 1e3 rad/s: e^{−100} at t1 = 0.2 s, ζ = 0.5).
template <int D>
Slope run_slope(const DemDesc<D>& d, double theta, double t1, double t2) {
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  const auto n1 = static_cast<std::int64_t>(std::llround(t1 / d.dt)), n2 = static_cast<std::int64_t>(std::llround(t2 / d.dt));
  double v1 = 0, w1 = 0;
  for (std::int64_t k = 1; k <= n2; ++k) {
    const StepStatus status = world.step();
    if (status != StepStatus::ok) {
      ADD_FAILURE() << "step " << k << ": " << static_cast<unsigned>(status);
      break;
    }
    if (k == n1) {
      v1 = downhill(world.state, theta);
      w1 = spin_z(world.state);
    }
  }
  const double v2 = downhill(world.state, theta), w2 = spin_z(world.state);
  const double span = static_cast<double>(n2 - n1) * d.dt;
  return {(v2 - v1) / span, (w2 - w1) / span, v2 - w2 * d.particles[0].radius};
}

// Below tan θ = μ (1 + m r²/I) (3μ disk, 3.5μ sphere) the particle rolls
// without slip: a = g sin θ / (1 + I/(m r²)), ω = v / r. After the start-up
// transient the motion is a constant acceleration, which every integrator
// that carries rotation (verlet, symplectic_euler, rk4, abm4) integrates
// exactly; what remains is the spring's stretch held by a growing force
// (none: the friction force is constant) and round-off over 1e5 steps.
constexpr DemIntegrator kRotating[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                       DemIntegrator::abm4, DemIntegrator::abm4_events};

template <int D>
void rolls_without_slip(DemIntegrator integrator) {
  const double theta = 20 * kPi / 180, mu = 0.5;
  ASSERT_LT(std::tan(theta), mu * (1 + 1 / inertia_factor<D>()));
  const Slope s = run_slope(incline<D>(theta, mu, 0, 0.5, integrator), theta, 0.2, 0.6);
  std::printf("%s ", integrator_name(integrator));
  const double a = kG * std::sin(theta) / (1 + inertia_factor<D>());
  std::printf("D=%d rolling: a %.12g (closed form %.12g), spin rate %.12g (a/r %.12g), slip %.3e m/s\n", D,
              s.acceleration, a, s.spin_rate, a / 0.05, s.slip);
  EXPECT_NEAR(s.acceleration, a, 1e-9 * a);
  EXPECT_NEAR(s.spin_rate, a / 0.05, 1e-9 * a / 0.05);
  // v = ω r up to the spring's stick-slip stretch rate (0 at constant force).
  EXPECT_LT(std::fabs(s.slip), 1e-9);
}
TEST(Incline, DiskRollsWithoutSlipBelowThreeMu) {
  for (DemIntegrator integrator : kRotating) rolls_without_slip<2>(integrator);
}
TEST(Incline, SphereRollsWithoutSlipBelowThreePointFiveMu) {
  for (DemIntegrator integrator : kRotating) rolls_without_slip<3>(integrator);
}

// Above it the contact slides: a = g (sin θ − μ cos θ), and the friction
// torque μ m g cos θ r spins it up at α = μ m g cos θ r / I.
template <int D>
void slides_and_spins_up(DemIntegrator integrator) {
  const double theta = 40 * kPi / 180, mu = 0.2;
  ASSERT_GT(std::tan(theta), mu * (1 + 1 / inertia_factor<D>()));
  const Slope s = run_slope(incline<D>(theta, mu, 0, 0.5, integrator), theta, 0.2, 0.6);
  std::printf("%s ", integrator_name(integrator));
  const double a = kG * (std::sin(theta) - mu * std::cos(theta));
  const double alpha = mu * kG * std::cos(theta) * 0.05 / (inertia_factor<D>() * 0.05 * 0.05);
  std::printf("D=%d sliding: a %.12g (closed form %.12g), spin-up %.12g (closed form %.12g)\n", D, s.acceleration, a,
              s.spin_rate, alpha);
  EXPECT_NEAR(s.acceleration, a, 1e-9 * a);
  EXPECT_NEAR(s.spin_rate, alpha, 1e-9 * alpha);
  EXPECT_GT(s.slip, 0.0);  // still sliding
}
TEST(Incline, DiskSlidesAboveThreeMuWithTheClosedFormSpinUp) {
  for (DemIntegrator integrator : kRotating) slides_and_spins_up<2>(integrator);
}
TEST(Incline, SphereSlidesAboveThreePointFiveMuWithTheClosedFormSpinUp) {
  for (DemIntegrator integrator : kRotating) slides_and_spins_up<3>(integrator);
}

// μ = 0 with rolling resistance on (so the particles rotate): no tangential
// force, so the particle slides at g sin θ and never spins.
template <int D>
void frictionless_slides_without_spin() {
  const double theta = 20 * kPi / 180;
  const Slope s = run_slope(incline<D>(theta, 0.0, 0.1, 0.5), theta, 0.2, 0.6);
  const double a = kG * std::sin(theta);
  EXPECT_NEAR(s.acceleration, a, 1e-9 * a);
  EXPECT_EQ(s.spin_rate, 0.0);
}
TEST(Incline, WithoutFrictionBothSlideWithoutSpin) {
  frictionless_slides_without_spin<2>();
  frictionless_slides_without_spin<3>();
}

/// A particle (m = 1, R = 0.05, k = 1e6, undamped: e = 1 up to Verlet's
/// energy error) hitting the plane y = 0 at (v_t, −v_n), no gravity.
template <int D>
struct Impact {
  double vt_before, vt_after, vn_after, spin;
  double kinetic_before, kinetic_after;
};
template <int D>
Impact<D> oblique_impact(double vt, double vn, double mu, double dt, DemIntegrator integrator) {
  DemDesc<D> d;
  d.dt = dt;
  d.friction = mu;
  d.integrator = integrator;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  p.position[1] = p.radius + 1e-4;
  p.velocity[0] = vt;
  p.velocity[1] = -vn;
  d.particles.push_back(p);
  PlaneDesc<D> floor;
  floor.normal[1] = 1;
  d.planes.push_back(floor);
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  const double inertia = inertia_factor<D>() * p.mass * p.radius * p.radius;
  auto kinetic = [&] {
    double sum = 0;
    for (int k = 0; k < D; ++k) sum += 0.5 * p.mass * world.state.v[k][0] * world.state.v[k][0];
    for (const auto& c : world.state.w) sum += 0.5 * inertia * c[0] * c[0];
    return sum;
  };
  Impact<D> r{vt, 0, 0, 0, kinetic(), 0};
  bool touched = false;
  for (int k = 0; k < 1000000; ++k) {
    EXPECT_EQ(world.step(), StepStatus::ok);
    const bool touching = world.state.x[1][0] < p.radius;
    touched |= touching;
    if (touched && !touching) break;
  }
  EXPECT_TRUE(touched);
  r.vt_after = world.state.v[0][0];
  r.vn_after = world.state.v[1][0];
  r.spin = spin_z(world.state);
  r.kinetic_after = kinetic();
  return r;
}

// Gross sliding (v_t / v_n > (1 + m R²/I) μ (1 + e): the contact point never
// stops): the tangential impulse is μ times the normal one at every force
// evaluation, so Δv_t = μ (1 + e) v_n and ω = μ (1 + e) v_n m R / I
// (5 μ (1 + e) v_n / (2R) for a sphere, 2 μ (1 + e) v_n / R for a disk), with
// e the measured rebound; the two kicks weigh both forces alike, so the
// relation holds to round-off (every integrator weighs both forces alike at
// each evaluation). e itself is 1 up to the integrator's energy error over
// the contact: O((ω h)²) = 1e-6 for verlet, rk4 and abm4 (the contact's onset
// is a kink of the force: at most second order there), O(ω h) = 1e-3 for
// symplectic Euler (ω = 1e3 rad/s, h = 1e-6 s).
double energy_bound(DemIntegrator integrator) { return integrator == DemIntegrator::symplectic_euler ? 1e-3 : 1e-6; }

template <int D>
void gross_sliding_impact(DemIntegrator integrator) {
  const double vn = 1.0, vt = 5.0, mu = 0.3;
  const Impact<D> r = oblique_impact<D>(vt, vn, mu, 1e-6, integrator);
  std::printf("%s ", integrator_name(integrator));
  const double e = r.vn_after / vn;
  const double dvt = r.vt_before - r.vt_after;
  const double omega = mu * (1 + e) * vn * 0.05 / (inertia_factor<D>() * 0.05 * 0.05);
  std::printf("D=%d oblique impact: e %.12f, dv_t %.12g (mu (1+e) v_n = %.12g), spin %.12g (closed form %.12g)\n", D,
              e, dvt, mu * (1 + e) * vn, r.spin, -omega);
  EXPECT_NEAR(e, 1.0, energy_bound(integrator));
  EXPECT_NEAR(dvt, mu * (1 + e) * vn, 1e-12);
  EXPECT_NEAR(r.spin, -omega, 1e-12 * omega);  // clockwise: the spin of rolling in +x
}
TEST(ObliqueImpact, SphereGrossSlidingMatchesMuOnePlusEVn) {
  for (DemIntegrator integrator : kRotating) gross_sliding_impact<3>(integrator);
}
TEST(ObliqueImpact, DiskGrossSlidingMatchesMuOnePlusEVn) {
  for (DemIntegrator integrator : kRotating) gross_sliding_impact<2>(integrator);
}

// e = 1 over incidence angles from grazing to head-on, through sticking and
// sliding: the impact never ends with more kinetic energy (translation and
// rotation) than it started with. The undamped normal spring returns its
// energy up to the integrator's error (energy_bound, the bound allowed); the
// tangential spring only stores or dissipates.
template <int D>
void impact_never_gains_energy(DemIntegrator integrator) {
  for (double angle_deg = 5; angle_deg < 90; angle_deg += 10) {
    const double angle = angle_deg * kPi / 180;  // from the plane
    const Impact<D> r = oblique_impact<D>(std::cos(angle), std::sin(angle), 0.3, 1e-6, integrator);
    EXPECT_LE(r.kinetic_after, r.kinetic_before * (1 + energy_bound(integrator)))
        << "D=" << D << " angle " << angle_deg << " " << integrator_name(integrator);
  }
}
TEST(ObliqueImpact, SweepNeverGainsEnergy) {
  for (DemIntegrator integrator : kRotating) {
    impact_never_gains_energy<2>(integrator);
    impact_never_gains_energy<3>(integrator);
  }
}

// A particle at rest on a slope below the friction angle (tan θ < μ) stays at
// rest: it settles where the tangential spring carries m g sin θ (stretch
// m g sin θ / k_t) and moves no further. Its inertia is made large (a block
// rather than a disk) so that it cannot roll: what holds it is the sticking
// spring alone. Verlet (the incline's default) and abm4_events; tests/long
// repeats it for 1e6 steps (Verlet).
void stays_at_rest_below_the_friction_angle(DemIntegrator integrator) {
  const double theta = 20 * kPi / 180, mu = 0.5;
  ASSERT_LT(std::tan(theta), mu);
  DemDesc<2> d = incline<2>(theta, mu, 0.0, 0.5);
  d.particles[0].inertia = 1e12;
  d.integrator = integrator;
  DemWorld<2> world;
  ASSERT_TRUE(world.build(d).ok());
  const double x0 = world.state.x[0][0], y0 = world.state.x[1][0];
  const double stretch = kG * std::sin(theta) / (kDefaultTangentialStiffnessRatio * 1e6);
  double peak = 0;
  for (int k = 0; k < 100000; ++k) {
    ASSERT_EQ(world.step(), StepStatus::ok);
    peak = std::max(peak, std::hypot(world.state.x[0][0] - x0, world.state.x[1][0] - y0));
  }
  const double speed = std::hypot(world.state.v[0][0], world.state.v[1][0]);
  std::printf("rest on slope, %s: peak displacement %.3e m (static stretch %.3e m), speed %.3e m/s\n",
              integrator_name(integrator), peak, stretch, speed);
  // At most twice the static stretch (a suddenly loaded spring's overshoot),
  // and at rest: the start-up oscillation (1e-2 m/s at most) decays as
  // e^{−ζ ω_t t} = e^{−500} in 1 s; 1e-12 m/s is round-off of the forces.
  EXPECT_LE(peak, 2 * stretch);
  EXPECT_LT(speed, 1e-12);
}
TEST(RestOnSlope, BlockStaysAtRestBelowTheFrictionAngle) {
  stays_at_rest_below_the_friction_angle(DemIntegrator::verlet);
  stays_at_rest_below_the_friction_angle(DemIntegrator::abm4_events);
}

// Rolling resistance on a flat floor: a disk rolling without slip at v0
// decelerates at μ_r g / (1 + I/(m r²)) (the torque μ_r r m g against the
// roll, the friction force keeping v = ω r), stops, and stays stopped: the
// torque never reverses the rolling.
// A disk thrown along a flat floor with a sticking dashpot (ζ = 0.3): while
// it slides, the law keeps in its spring ξ the cap and the dashpot's share
// (contact_law.hpp), k_t|ξ| ≈ η_t v_slip, far above the cap μ k δ. The
// books count the spring's energy up to the cap (tangential_energy): the
// elastic energy at every step at most ½ k δ² + (μ k δ)²/(2 k_t), and the
// energy check at every step, at its default tolerance, stays silent over
// the slide and the roll after it. Counted whole, the spring showed about a
// third of the disk's kinetic energy as a rise.
TEST(EnergyBooks, ASlidingContactsSpringCountsUpToItsCap) {
  DemDesc<2> d = incline<2>(0.0, 0.3, 0.0, 0.3);
  d.particles[0].velocity[0] = 2.0;
  d.energy_check.interval = 1;
  DemWorld<2> w;
  ASSERT_TRUE(w.build(d).ok());
  const double k = d.particles[0].stiffness, kt = w.model.tangential_ratio * k, mu = d.friction;
  const double delta = d.particles[0].mass * 9.81 / k;
  double worst = 0, raw_peak = 0;
  for (int step = 0; step < 40000; ++step) {
    ASSERT_EQ(w.step(), StepStatus::ok) << step;
    const double xi2 = w.state.plane_xi[0][0] * w.state.plane_xi[0][0];
    raw_peak = std::max(raw_peak, 0.5 * kt * xi2);
    // The overlap now (the normal oscillation is damped, not absent).
    const double overlap = d.particles[0].radius - w.state.x[1][0];
    const double bound = 0.5 * k * overlap * overlap + 0.5 * (mu * k * overlap) * (mu * k * overlap) / kt;
    worst = std::max(worst, dem_energy(w.model, w.state).elastic - bound);
  }
  const double cap_energy = 0.5 * (mu * k * delta) * (mu * k * delta) / kt;
  std::printf("elastic energy above its bound by at most %.3g J; the raw ½ k_t |ξ|² peaked at %.4g J, %.3g times "
              "the cap's (μ m g)²/(2 k_t) = %.3g J; v = %.6f m/s at the end\n",
              worst, raw_peak, raw_peak / cap_energy, cap_energy, w.state.v[0][0]);
  EXPECT_LE(worst, 1e-15);
  EXPECT_GT(raw_peak, 100 * cap_energy);  // the slide did put the dashpot's share into ξ
  EXPECT_NEAR(w.state.v[0][0], 2.0 / 3.0 * 2.0, 1e-3);  // it rolls at the end
}

TEST(RollingResistance, DiskDeceleratesAtTheClosedFormAndStops) {
  const double mu_r = 0.02, v0 = 0.1;
  DemDesc<2> d = incline<2>(0.0, 0.5, mu_r, 0.5);
  d.particles[0].velocity = {v0, 0};
  d.particles[0].angular_velocity = {-v0 / d.particles[0].radius};
  const double a = mu_r * kG / 1.5;
  const double t_stop = v0 / a;
  DemWorld<2> world;
  ASSERT_TRUE(world.build(d).ok());
  const auto steps = static_cast<int>(0.5 * t_stop / d.dt);
  for (int k = 0; k < steps; ++k) ASSERT_EQ(world.step(), StepStatus::ok);
  const double v_half = world.state.v[0][0];
  std::printf("rolling resistance: v(t_stop/2) %.12g (closed form %.12g)\n", v_half, v0 - a * steps * d.dt);
  // The tangential spring's start-up transient (the roll starts exact) is
  // absent; Verlet integrates the constant deceleration exactly.
  EXPECT_NEAR(v_half, v0 - a * steps * d.dt, 1e-9 * v0);
  for (int k = 0; k < 3 * steps; ++k) ASSERT_EQ(world.step(), StepStatus::ok);
  EXPECT_LT(std::fabs(world.state.v[0][0]), 1e-9);
  EXPECT_LT(std::fabs(world.state.w[0][0]), 1e-9 / d.particles[0].radius);
}

/// Disks dropped into a box, with friction and rolling resistance.
DemDesc<2> box_of_disks(int n, std::int32_t all_pairs_up_to, DemIntegrator integrator = DemIntegrator::verlet) {
  DemDesc<2> d;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  d.dt = 2e-5;
  d.gravity = {0, -9.81};
  d.damping_ratio = 0.2;
  d.friction = 0.5;
  d.rolling_friction = 0.05;
  d.integrator = integrator;
  d.all_pairs_up_to = all_pairs_up_to;
  d.split_from = 100;
  const int columns = 10;
  for (int i = 0; i < n; ++i) {
    ParticleDesc<2> p;
    p.mass = 0.01 * (1 + 0.2 * u(rng));
    p.radius = 0.01 * (1 + 0.2 * u(rng));
    p.stiffness = 1e4;
    p.position = {0.025 * (i % columns) + 0.015, 0.025 * (i / columns) + 0.015};
    p.velocity = {0.2 * (u(rng) - 0.5), 0.2 * (u(rng) - 0.5)};
    p.angular_velocity = {2 * (u(rng) - 0.5)};
    d.particles.push_back(p);
  }
  PlaneDesc<2> floor, left, right;
  floor.normal = {0, 1};
  left.normal = {1, 0};
  right.normal = {-1, 0};
  right.point = {0.25, 0};
  d.planes = {floor, left, right};
  return d;
}

// The grid's pair list is rebuilt as the disks fall; each rebuild carries
// the tangential springs over by (i, j). A list of every pair (all_pairs,
// never rebuilt) visits the touching pairs in the same order, so the two runs
// agree bit for bit only if no record was lost or misplaced.
// (rk4 rebuilds at its stages too, from the stored springs.)
class ContactRecords : public ::testing::TestWithParam<DemIntegrator> {};

TEST_P(ContactRecords, SurvivePairListRebuildsBitForBit) {
  DemWorld<2> grid, all;
  ASSERT_TRUE(grid.build(box_of_disks(60, 0, GetParam())).ok());
  ASSERT_TRUE(all.build(box_of_disks(60, 64, GetParam())).ok());
  ASSERT_EQ(grid.model.features.broad_phase, BroadPhase::grid);
  ASSERT_EQ(all.model.features.broad_phase, BroadPhase::all_pairs);
  for (int k = 0; k < 20000; ++k) {
    ASSERT_FALSE(has(grid.step(), kStepNotTaken));
    ASSERT_FALSE(has(all.step(), kStepNotTaken));
  }
  EXPECT_GT(grid.state.list_builds, 5);
  int sticking = 0;
  for (std::int32_t c = 0; c < all.state.pair_count; ++c) sticking += all.state.pair_xi[0][c] != 0.0 ? 1 : 0;
  EXPECT_GT(sticking, 10);  // contacts that carried a spring across the rebuilds
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(grid.state.x[k], all.state.x[k]);
    EXPECT_EQ(grid.state.v[k], all.state.v[k]);
  }
  EXPECT_EQ(grid.state.w[0], all.state.w[0]);
  EXPECT_EQ(grid.state.angle[0], all.state.angle[0]);
}

// Two workers, a snapshot taken half-way and restored into a fresh world, and
// no allocation in any step: the same bits.
TEST_P(ContactRecords, TwoWorkersSnapshotsAndNoAllocation) {
  DemWorld<2> one;
  xfdem::testing::expect_same_bits_on_two_workers_and_after_a_snapshot(box_of_disks(200, 0, GetParam()), one);
  EXPECT_GT(one.state.list_builds, 1);
}

// Spheres in a box, Coulomb friction without rolling resistance, split in two
// parts (split_from): the 3D pair kernel that evaluates two contacts at once,
// and part 0's contributions to part 1's particles and torques through the
// cross buffers.
DemDesc<3> box_of_spheres(ContactLaw law, DemIntegrator integrator) {
  DemDesc<3> d;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  d.dt = 2e-5;
  d.gravity = {0, 0, -9.81};
  d.damping_ratio = 0.2;
  d.friction = 0.5;
  d.law = law;
  d.integrator = integrator;
  d.all_pairs_up_to = 0;
  d.split_from = 100;
  const int side = 7;
  for (int i = 0; i < side * side * 5; ++i) {
    ParticleDesc<3> p;
    p.mass = 0.01 * (1 + 0.2 * u(rng));
    p.radius = 0.01 * (1 + 0.2 * u(rng));
    p.stiffness = 1e4;
    p.position = {0.022 * (i % side) + 0.015, 0.022 * ((i / side) % side) + 0.015, 0.022 * (i / (side * side)) + 0.015};
    p.velocity = {0.2 * (u(rng) - 0.5), 0.2 * (u(rng) - 0.5), 0.2 * (u(rng) - 0.5)};
    p.angular_velocity = {2 * (u(rng) - 0.5), 2 * (u(rng) - 0.5), 2 * (u(rng) - 0.5)};
    d.particles.push_back(p);
  }
  const double wall = 0.022 * side + 0.01;
  d.planes = {{.point = {0, 0, 0}, .normal = {0, 0, 1}},    {.point = {0, 0, 0}, .normal = {1, 0, 0}},
              {.point = {wall, 0, 0}, .normal = {-1, 0, 0}}, {.point = {0, 0, 0}, .normal = {0, 1, 0}},
              {.point = {0, wall, 0}, .normal = {0, -1, 0}}};
  return d;
}

TEST(ContactRecords, SpheresOnTwoPartsTwoWorkersSnapshotsAndNoAllocation) {
  for (ContactLaw law : {ContactLaw::linear, ContactLaw::linear_nontensile})
    for (DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::rk4}) {
      SCOPED_TRACE(integrator_name(integrator));
      DemWorld<3> one;
      expect_same_bits_on_two_workers_and_after_a_snapshot(box_of_spheres(law, integrator), one, 3000);
      EXPECT_EQ(one.model.parts, 2);
      int loaded = 0;
      for (std::int32_t c = 0; c < one.state.pair_count; ++c) loaded += one.state.pair_xi[0][c] != 0.0 ? 1 : 0;
      EXPECT_GT(loaded, 50);  // sticking contacts carry a spring
    }
}

// A snapshot names its model by a fingerprint that covers the tangential law:
// restored into a model that differs only in μ, μ_r, k_t/k_n or an inertia, it
// is refused (the springs it carries were built under the other law).
TEST(ContactRecords, SnapshotOfAnotherTangentialLawIsRefused) {
  const DemDesc<2> d = box_of_disks(20, 0);
  DemWorld<2> source;
  ASSERT_TRUE(source.build(d).ok());
  for (int k = 0; k < 100; ++k) ASSERT_FALSE(has(source.step(), kStepNotTaken));
  std::vector<std::byte> buffer(snapshot_size(source.state));
  ASSERT_EQ(save_snapshot(source.state, buffer, model_fingerprint(source.model)).status, SnapshotStatus::ok);
  auto restore_into = [&](DemDesc<2> other) {
    DemWorld<2> world;
    EXPECT_TRUE(world.build(other).ok());
    return restore_snapshot(world.state, buffer, model_fingerprint(world.model)).status;
  };
  EXPECT_EQ(restore_into(d), SnapshotStatus::ok);
  DemDesc<2> other = d;
  other.friction = 0.4;
  EXPECT_EQ(restore_into(other), SnapshotStatus::other_model);
  other = d;
  other.rolling_friction = 0.04;
  EXPECT_EQ(restore_into(other), SnapshotStatus::other_model);
  other = d;
  other.tangential_stiffness_ratio = 0.5;
  EXPECT_EQ(restore_into(other), SnapshotStatus::other_model);
  other = d;
  other.particles[3].inertia = 1e-6;
  EXPECT_EQ(restore_into(other), SnapshotStatus::other_model);
}

// abm4_events takes no grid with rotation (build_dem refuses it): its own test below.
constexpr DemIntegrator kGridRotating[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                           DemIntegrator::abm4};
INSTANTIATE_TEST_SUITE_P(Integrators, ContactRecords, ::testing::ValuesIn(kGridRotating),
                         [](const auto& param_info) { return std::string(integrator_name(param_info.param)); });

// abm4_events with friction and rolling resistance: a dozen disks falling
// into the box (two parts, all pairs), every impact a located event; the
// same bits on two workers and after a snapshot, no allocation.
TEST(ContactRecords, Abm4EventsTwoWorkersSnapshotsAndNoAllocation) {
  DemDesc<2> d = box_of_disks(12, 16, DemIntegrator::abm4_events);
  d.split_from = 6;
  DemWorld<2> one;
  xfdem::testing::expect_same_bits_on_two_workers_and_after_a_snapshot(d, one, 6000);
  ASSERT_EQ(one.model.parts, 2);
  EXPECT_GT(one.state.events_located, 10);
  int sticking = 0;
  for (std::int32_t c = 0; c < one.state.pair_count; ++c) sticking += one.state.pair_xi[0][c] != 0.0 ? 1 : 0;
  for (std::size_t c = 0; c < one.state.plane_xi[0].size(); ++c) sticking += one.state.plane_xi[0][c] != 0.0 ? 1 : 0;
  EXPECT_GT(sticking, 0);
}

// Bad input is refused naming the key.
TEST(FrictionInputs, RefusedNamingTheKey) {
  auto refused = [](DemDesc<2> d, const char* key) {
    DemWorld<2> world;
    const BuildResult r = world.build(d);
    EXPECT_FALSE(r.ok()) << key;
    EXPECT_EQ(std::string(r.message).rfind(key, 0), 0u) << r.message;
  };
  const DemDesc<2> good = incline<2>(0.1, 0.5, 0.0, 0.1);
  DemDesc<2> d = good;
  d.friction = -0.1;
  refused(d, "friction:");
  d.friction = NAN;
  refused(d, "friction:");
  d = good;
  d.rolling_friction = -1;
  refused(d, "rolling_friction:");
  d = good;
  d.tangential_stiffness_ratio = NAN;
  refused(d, "tangential_stiffness_ratio:");
  d = good;
  d.particles[0].inertia = -1;
  refused(d, "particles[0].inertia:");
  d = good;
  d.particles[0].angular_velocity = {INFINITY};
  refused(d, "particles[0].angular_velocity:");
  // abm4_events keeps each located piece's springs before the step is done:
  // it takes no grid, whose rebuild could still refuse the step.
  d = good;
  d.integrator = DemIntegrator::abm4_events;
  d.all_pairs_up_to = 0;
  d.particles.push_back(d.particles[0]);
  d.particles.back().position[1] += 1.0;
  refused(d, "integrator: abm4_events with friction, rolling friction, the hertz law or a spinning particle takes the "
             "pairs of broad phase "
             "none or all_pairs");
  DemDesc<1> line;
  line.dt = 1e-5;
  line.friction = 0.3;
  line.particles.push_back({1, 0.05, 1e6, {0}, {0}});
  DemWorld<1> world;
  const BuildResult r = world.build(line);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(std::string(r.message).rfind("friction:", 0), 0u) << r.message;
}

}  // namespace
}  // namespace xfdem::testing
