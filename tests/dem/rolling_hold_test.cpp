// Rolling resistance that holds (contact_law.hpp, rolling_torque): a disk or
// a sphere on a plane inclined at θ, with Coulomb μ and rolling μ_r (R* = r),
// against the closed forms the tests compute. With k = I/(m r²):
//   - tan θ ≤ μ and tan θ ≤ μ_r: at rest forever. The sticking contact carries
//     m g sin θ, whose torque m g sin θ r the rolling couple cancels while
//     it is at most μ_r r m g cos θ;
//   - μ_r < tan θ ≤ μ + (μ − μ_r)/k (needs μ > μ_r): rolls without slip,
//     a = g (sin θ − μ_r cos θ)/(1 + k) (the friction force this needs,
//     m g (k sin θ + μ_r cos θ)/(1 + k), is at most μ m g cos θ exactly up to
//     that bound);
//   - above it, with μ > μ_r: slides and spins up, a = g (sin θ − μ cos θ),
//     α = (μ − μ_r) m g cos θ r/I (the slip rate g (sin θ − μ cos θ) −
//     α r stays positive exactly above the bound);
//   - tan θ > μ with μ ≤ μ_r: slides without turning, a = g (sin θ − μ cos θ),
//     ω = 0 (the friction's torque μ m g cos θ r is within the rolling cap).
// And a particle resting on a held one (a pair, R* = r_i r_j/(r_i + r_j)).
// Every integrator that carries rotation; the energy check at every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/dem_scenes.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
constexpr DemIntegrator kRotating[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                       DemIntegrator::abm4, DemIntegrator::abm4_events};

template <int D>
double speed_of(const DemState<D>& s, int i) {
  double v2 = 0;
  for (int d = 0; d < D; ++d) v2 += s.v[d][i] * s.v[d][i];
  return std::sqrt(v2);
}
template <int D>
double spin_of(const DemState<D>& s, int i) {
  double w2 = 0;
  for (const auto& c : s.w) w2 += c[i] * c[i];
  return std::sqrt(w2);
}
template <int D>
double total_energy(const DemWorld<D>& w) {
  const DemEnergy e = dem_energy(w.model, w.state);
  return e.kinetic + e.elastic + e.potential;
}
/// Position and velocity down the slope, d = (−cos θ, −sin θ) (incline()'s plane rises to the right).
template <int D>
double downhill_x(const DemState<D>& s, double theta) {
  return -std::cos(theta) * s.x[0][0] - std::sin(theta) * s.x[1][0];
}
template <int D>
double downhill_v(const DemState<D>& s, double theta) {
  return -std::cos(theta) * s.v[0][0] - std::sin(theta) * s.v[1][0];
}

/// The incline with the energy check at every step: a step that finds the
/// books broken returns energy_growth, which the callers' ASSERT_EQ(ok) sees.
template <int D>
DemDesc<D> checked_incline(double theta, double mu, double mu_r, DemIntegrator integrator) {
  DemDesc<D> d = incline<D>(theta, mu, mu_r, 0.5, integrator);
  d.energy_check.interval = 1;
  return d;
}

// (1) tan θ < μ_r < μ: at rest. The disk starts at rest with the static
// overlap and no tangential stretch; the spring takes up m g sin θ with an
// overshoot of at most the static stretch m g sin θ/k_t (the held spin makes
// it a block's spring, ω_t = √(k_t/m)), and the start-up oscillation decays
// as e^{−ζ ω_t t} = e^{−267} over the 1 s run: what is left is round-off.
template <int D>
void held_on_a_slope(DemIntegrator integrator, int steps) {
  const double theta = 10 * kPi / 180, mu = 0.5, mu_r = 0.3;
  ASSERT_LT(std::tan(theta), mu_r);
  ASSERT_LT(mu_r, mu);
  DemWorld<D> world;
  ASSERT_TRUE(world.build(checked_incline<D>(theta, mu, mu_r, integrator)).ok());
  double start[D];
  for (int k = 0; k < D; ++k) start[k] = world.state.x[k][0];
  const double stretch = kG * std::sin(theta) / (kDefaultTangentialStiffnessRatio * 1e6);
  const double e0 = total_energy(world);
  double peak = 0, spin_peak = 0, energy_peak = -INFINITY;
  for (int s = 0; s < steps; ++s) {
    ASSERT_EQ(world.step(), StepStatus::ok) << integrator_name(integrator) << " step " << s;
    double r2 = 0;
    for (int k = 0; k < D; ++k) r2 += (world.state.x[k][0] - start[k]) * (world.state.x[k][0] - start[k]);
    peak = std::max(peak, std::sqrt(r2));
    spin_peak = std::max(spin_peak, spin_of(world.state, 0));
    energy_peak = std::max(energy_peak, total_energy(world));
  }
  const double speed = speed_of(world.state, 0), spin = spin_of(world.state, 0);
  std::printf("D=%d %s held on a 10 deg slope (mu_r 0.3), %d steps: speed %.3e m/s, spin %.3e rad/s (peak %.3e), "
              "peak displacement %.3e m (static stretch %.3e m), largest energy rise %.3e J\n",
              D, integrator_name(integrator), steps, speed, spin, spin_peak, peak, stretch, energy_peak - e0);
  EXPECT_LT(speed, 1e-12);
  EXPECT_LT(spin, 1e-12);
  EXPECT_LE(peak, 2 * stretch);
  // The books: at rest the disk has slid Δs down the slope without turning
  // and its spring carries m g sin θ, so E − E0 = −m g sin θ Δs + ½ (m g
  // sin θ)²/k_t: no other store and no gain, to round-off of the energies
  // (0.5 J) against 5e-6 J. Verlet and symplectic Euler advance ξ by the same
  // h v_t as x, so Δs is the static stretch x_s and E − E0 = −½ (m g sin θ)²/k_t,
  // the dashpot's share of the start-up; RK4 and ABM4 advance ξ by h v_t(y_n+1)
  // (first order) beside their x: Δs differs from x_s by 1e-11 m (printed).
  const double force = kG * std::sin(theta), kt = kDefaultTangentialStiffnessRatio * 1e6;
  double slid = 0;
  const double down[3] = {-std::cos(theta), -std::sin(theta), 0.0};
  for (int k = 0; k < D; ++k) slid += (world.state.x[k][0] - start[k]) * down[k];
  const double change = -force * slid + 0.5 * force * force / kt;
  std::printf("  slid %.6e m (x_s %.6e m), E - E0 %.12g J (books %.12g J)\n", slid, stretch, total_energy(world) - e0,
              change);
  EXPECT_NEAR(total_energy(world) - e0, change, 1e-9 * std::fabs(change));
  if (integrator == DemIntegrator::verlet || integrator == DemIntegrator::symplectic_euler) {
    EXPECT_NEAR(total_energy(world) - e0, -0.5 * force * force / kt, 1e-9 * std::fabs(change));
  }
}
TEST(RollingHold, DiskHeldOnASlopeBelowTheRollingAngle) {
  for (DemIntegrator integrator : kRotating) held_on_a_slope<2>(integrator, 100000);
}
TEST(RollingHold, SphereHeldOnASlopeBelowTheRollingAngle) {
  for (DemIntegrator integrator : kRotating) held_on_a_slope<3>(integrator, 100000);
}

/// The slack of the energy books' closed forms below: verlet, rk4 and ABM4
/// step a constant acceleration exactly, positions included, so the books
/// (m g y from the positions) match to round-off (1e-9 relative). Symplectic
/// Euler's positions x_n = x0 + h Σ v_k lead the exact ones by ½ a h t_n, so
/// over [t1, t2] its Δs, and with it the potential energy it books, is off by
/// ½ a h (t2 − t1) times a force along the slope of at most m g sin θ
/// (every net force and couple here is below the weight's downhill part).
double books_slack(DemIntegrator integrator, double theta, double a, double h, double span) {
  if (integrator != DemIntegrator::symplectic_euler) return 0.0;
  return kG * std::sin(theta) * 0.5 * a * h * span;
}

struct Motion {
  double acceleration, spin_rate, slip;  // between t1 and t2; slip = v − ω r at t2
  double energy_drop, distance, turned;  // over [t1, t2]: E(t1) − E(t2), Δs, ∫|ω| dt
  double spin_peak;                      // max |ω| over the run
};

/// Runs to t2 and measures over [t1, t2], past the tangential spring's
/// start-up transient (e^{−ζ ω_t t1}, ω_t ≥ 534 rad/s: e^{−53} at t1 = 0.2 s).
/// ∫|ω| dt is the trapezoid over the window, exact for the constant angular
/// acceleration of every regime here.
template <int D>
Motion run_incline(const DemDesc<D>& d, double theta, double t1, double t2) {
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  const auto n1 = std::llround(t1 / d.dt), n2 = std::llround(t2 / d.dt);
  double v1 = 0, w1 = 0, s1 = 0, e1 = 0, peak = 0;
  for (long long k = 1; k <= n2; ++k) {
    const StepStatus status = world.step();
    if (status != StepStatus::ok) {
      ADD_FAILURE() << integrator_name(d.integrator) << " step " << k << ": " << static_cast<unsigned>(status);
      break;
    }
    peak = std::max(peak, spin_of(world.state, 0));
    if (k == n1) {
      v1 = downhill_v(world.state, theta);
      w1 = spin_z(world.state);
      s1 = downhill_x(world.state, theta);
      e1 = total_energy(world);
    }
  }
  const double v2 = downhill_v(world.state, theta), w2 = spin_z(world.state);
  const double span = static_cast<double>(n2 - n1) * d.dt;
  return {(v2 - v1) / span,
          (w2 - w1) / span,
          v2 - w2 * d.particles[0].radius,
          e1 - total_energy(world),
          downhill_x(world.state, theta) - s1,
          0.5 * (std::fabs(w1) + std::fabs(w2)) * span,
          peak};
}

// (2) Just above tan θ = μ_r (5 %): rolls without slip at the closed-form
// acceleration. The rolling couple is then its cap μ_r r m g cos θ, a
// constant, and the friction force constant too (the spring's stretch does
// not change): a constant acceleration, which every integrator here steps
// exactly, so what is left is round-off over 6e4 steps (1e-9 relative, as the
// incline tests). The energy goes only into the rolling couple's work:
// E(t1) − E(t2) = μ_r r m g cos θ ∫|ω| dt = μ_r m g cos θ Δs (no slip, the
// springs' energies constant), to round-off of the energies (1e-9 relative).
template <int D>
void rolls_just_above(DemIntegrator integrator) {
  const double mu = 0.5, mu_r = 0.3, theta = std::atan(1.05 * mu_r), k = inertia_factor<D>(), r = 0.05;
  ASSERT_GT(std::tan(theta), mu_r);
  ASSERT_LT(std::tan(theta), mu + (mu - mu_r) / k);
  const Motion m = run_incline(checked_incline<D>(theta, mu, mu_r, integrator), theta, 0.2, 0.6);
  const double a = kG * (std::sin(theta) - mu_r * std::cos(theta)) / (1 + k);
  const double drop = mu_r * kG * std::cos(theta) * m.distance;
  std::printf("D=%d %s rolling at tan = 1.05 mu_r: a %.12g (closed form %.12g), spin rate %.12g (a/r %.12g), slip "
              "%.3e m/s, energy drop %.12g J (mu_r m g cos th ds %.12g J)\n",
              D, integrator_name(integrator), m.acceleration, a, m.spin_rate, a / r, m.slip, m.energy_drop, drop);
  EXPECT_NEAR(m.acceleration, a, 1e-9 * a);
  EXPECT_NEAR(m.spin_rate, a / r, 1e-9 * a / r);
  EXPECT_LT(std::fabs(m.slip), 1e-9);
  const double slack = books_slack(integrator, theta, a, 1e-5, 0.4);
  EXPECT_NEAR(m.energy_drop, drop, 1e-9 * drop + slack);
  // The couple's work against the turning: the same number another way.
  EXPECT_NEAR(m.energy_drop, mu_r * r * kG * std::cos(theta) * m.turned, 1e-9 * drop + slack);
}
TEST(RollingHold, DiskRollsJustAboveTheRollingAngleAtTheClosedForm) {
  for (DemIntegrator integrator : kRotating) rolls_just_above<2>(integrator);
}
TEST(RollingHold, SphereRollsJustAboveTheRollingAngleAtTheClosedForm) {
  for (DemIntegrator integrator : kRotating) rolls_just_above<3>(integrator);
}

// (2b) Slip and roll together: μ = 0.2, μ_r = 0.1, θ = 40° (tan θ = 0.84,
// above μ + (μ − μ_r)/k = 0.4 disk, 0.45 sphere). The friction force is its
// cap μ m g cos θ, the rolling couple its cap μ_r r m g cos θ against the
// spin: a = g (sin θ − μ cos θ), α = (μ − μ_r) m g cos θ r/I. Energy: the
// friction's work on the slip and the couple's on the spin,
// E(t1) − E(t2) = μ m g cos θ (Δs − r ∫ω dt) + μ_r r m g cos θ ∫ω dt.
template <int D>
void slides_and_rolls(DemIntegrator integrator) {
  const double mu = 0.2, mu_r = 0.1, theta = 40 * kPi / 180, k = inertia_factor<D>(), r = 0.05;
  ASSERT_GT(std::tan(theta), mu + (mu - mu_r) / k);
  const Motion m = run_incline(checked_incline<D>(theta, mu, mu_r, integrator), theta, 0.2, 0.6);
  const double a = kG * (std::sin(theta) - mu * std::cos(theta));
  const double alpha = (mu - mu_r) * kG * std::cos(theta) * r / (k * r * r);
  const double fn = kG * std::cos(theta);
  const double drop = mu * fn * (m.distance - r * m.turned) + mu_r * r * fn * m.turned;
  std::printf("D=%d %s slip and roll: a %.12g (closed form %.12g), spin-up %.12g (closed form %.12g), energy drop "
              "%.12g J (closed form %.12g J)\n",
              D, integrator_name(integrator), m.acceleration, a, m.spin_rate, alpha, m.energy_drop, drop);
  EXPECT_NEAR(m.acceleration, a, 1e-9 * a);
  EXPECT_NEAR(m.spin_rate, alpha, 1e-9 * alpha);
  EXPECT_GT(m.slip, 0.0);
  EXPECT_NEAR(m.energy_drop, drop, 1e-9 * drop + books_slack(integrator, theta, a, 1e-5, 0.4));
}
TEST(RollingHold, DiskSlipsAndRollsAboveTheRollingBound) {
  for (DemIntegrator integrator : kRotating) slides_and_rolls<2>(integrator);
}
TEST(RollingHold, SphereSlipsAndRollsAboveTheRollingBound) {
  for (DemIntegrator integrator : kRotating) slides_and_rolls<3>(integrator);
}

// (2c) μ < tan θ with μ ≤ μ_r: slides at g (sin θ − μ cos θ) without
// turning: the friction's torque, at most μ r m g cos θ, stays within the
// rolling cap μ_r r m g cos θ, so the couple holds the spin at 0 from the
// first step (round-off: |ω| < 1e-12 throughout). Energy: the friction's
// work alone, μ m g cos θ Δs.
template <int D>
void slides_without_turning(DemIntegrator integrator) {
  const double mu = 0.2, mu_r = 0.3, theta = 20 * kPi / 180;
  ASSERT_GT(std::tan(theta), mu);
  const Motion m = run_incline(checked_incline<D>(theta, mu, mu_r, integrator), theta, 0.2, 0.6);
  const double a = kG * (std::sin(theta) - mu * std::cos(theta));
  const double drop = mu * kG * std::cos(theta) * m.distance;
  std::printf("D=%d %s sliding held from turning: a %.12g (closed form %.12g), peak spin %.3e rad/s, energy drop "
              "%.12g J (closed form %.12g J)\n",
              D, integrator_name(integrator), m.acceleration, a, m.spin_peak, m.energy_drop, drop);
  EXPECT_NEAR(m.acceleration, a, 1e-9 * a);
  EXPECT_LT(m.spin_peak, 1e-12);
  EXPECT_NEAR(m.energy_drop, drop, 1e-9 * drop + books_slack(integrator, theta, a, 1e-5, 0.4));
}
TEST(RollingHold, DiskSlidesWithoutTurningWhenMuIsBelowMuR) {
  for (DemIntegrator integrator : kRotating) slides_without_turning<2>(integrator);
}
TEST(RollingHold, SphereSlidesWithoutTurningWhenMuIsBelowMuR) {
  for (DemIntegrator integrator : kRotating) slides_without_turning<3>(integrator);
}

/// A particle (m = 1, r = 0.05, k = 1e6) on a held one (the same radius and
/// stiffness, m = 1e30: its motion under the contact, 1e-29 m/s², is below
/// every bound here), no gravity: the upper particle's external force
/// m g (0, −1) plays its weight, and the line of centres is tilted by θ from
/// it, n = (−sin θ, cos θ), as on incline()'s slope. Pressed in by the static
/// overlap m g cos θ/K (K = k/2, the springs in series).
template <int D>
DemDesc<D> on_a_held_particle(double theta, double mu, double mu_r, DemIntegrator integrator) {
  DemDesc<D> d;
  d.dt = 1e-5;
  d.damping_ratio = 0.5;
  d.friction = mu;
  d.rolling_friction = mu_r;
  d.integrator = integrator;
  d.external_forces = true;
  d.energy_check.interval = 1;
  ParticleDesc<D> held, upper;
  held.mass = 1e30;
  held.radius = upper.radius = 0.05;
  held.stiffness = upper.stiffness = 1e6;
  upper.mass = 1;
  const double distance = 2 * upper.radius - upper.mass * kG * std::cos(theta) / (0.5 * upper.stiffness);
  upper.position[0] = -std::sin(theta) * distance;
  upper.position[1] = std::cos(theta) * distance;
  d.particles = {held, upper};
  return d;
}

// (1b) A pair: the upper particle held at rest while tan θ ≤ μ_r R*/r
// (= μ_r/2 for equal radii) and tan θ ≤ μ: its sticking contact carries
// m g sin θ, the couple m g sin θ r, and the cap is μ_r R* m g cos θ.
// tan θ = 0.14 < μ_r/2 = 0.2 < μ = 0.5. As on the slope: at rest to round-off
// relative to the held particle, which moves at 1e-29 m/s.
template <int D>
void held_on_a_particle(DemIntegrator integrator) {
  const double theta = 8 * kPi / 180, mu = 0.5, mu_r = 0.4;
  ASSERT_LT(std::tan(theta), mu_r * 0.5);
  DemWorld<D> world;
  ASSERT_TRUE(world.build(on_a_held_particle<D>(theta, mu, mu_r, integrator)).ok());
  world.state.external_force[1][1] = -kG;
  dem_inputs_changed(world.state);
  for (int s = 0; s < 100000; ++s)
    ASSERT_EQ(world.step(), StepStatus::ok) << integrator_name(integrator) << " step " << s;
  double relative2 = 0;
  for (int d = 0; d < D; ++d)
    relative2 += (world.state.v[d][1] - world.state.v[d][0]) * (world.state.v[d][1] - world.state.v[d][0]);
  const double spin = spin_of(world.state, 1), held_spin = spin_of(world.state, 0);
  std::printf("D=%d %s on a held particle, tan = 0.14 < mu_r R*/r = 0.2: relative speed %.3e m/s, spin %.3e rad/s "
              "(the held one's %.3e)\n",
              D, integrator_name(integrator), std::sqrt(relative2), spin, held_spin);
  EXPECT_LT(std::sqrt(relative2), 1e-12);
  EXPECT_LT(spin, 1e-12);
}
TEST(RollingHold, DiskHeldOnAHeldDisk) {
  for (DemIntegrator integrator : kRotating) held_on_a_particle<2>(integrator);
}
TEST(RollingHold, SphereHeldOnAHeldSphere) {
  for (DemIntegrator integrator : kRotating) held_on_a_particle<3>(integrator);
}

// Above the pair's bound (tan θ = 1.05 μ_r R*/r) the couple is at its cap
// and the upper particle rolls off: at t = 0.1 s, past the spring's start-up,
// it turns the way it rolls (ω_z > 0 for n = (−sin θ, cos θ)), and below the
// bound, the same scene stays (1b). The geometry turns as it rolls, and the
// spring's start-up overshoot (above the cap's 5 % margin) spins it up too,
// so no closed-form acceleration is asserted here (the slope's is, above).
template <int D>
void rolls_off_a_particle(DemIntegrator integrator) {
  const double mu = 0.5, mu_r = 0.4, theta = std::atan(1.05 * 0.5 * mu_r);
  DemWorld<D> world;
  ASSERT_TRUE(world.build(on_a_held_particle<D>(theta, mu, mu_r, integrator)).ok());
  world.state.external_force[1][1] = -kG;
  dem_inputs_changed(world.state);
  for (int s = 0; s < 10000; ++s)
    ASSERT_EQ(world.step(), StepStatus::ok) << integrator_name(integrator) << " step " << s;
  const double w = world.state.w[D == 2 ? 0 : 2][1];
  std::printf("D=%d %s rolling off a held particle: spin %.6g rad/s, speed %.6g m/s at 0.1 s\n", D,
              integrator_name(integrator), w, speed_of(world.state, 1));
  EXPECT_GT(w, 0.0);
  EXPECT_GT(speed_of(world.state, 1), 1e-6);
}
TEST(RollingHold, DiskRollsOffAHeldDiskAboveTheBound) {
  for (DemIntegrator integrator : kRotating) rolls_off_a_particle<2>(integrator);
}
TEST(RollingHold, SphereRollsOffAHeldSphereAboveTheBound) {
  for (DemIntegrator integrator : kRotating) rolls_off_a_particle<3>(integrator);
}

/// Two equal disks (m = 1, r = 0.05, k = 1e6) pressed together along x by
/// external forces ±P (no gravity), at the static overlap P/K, with external
/// torques +T on the right disk and −T on the left: by symmetry they turn
/// opposite ways, ω_i = −ω_j, so their surfaces move together at the
/// contact (r ω_i + r ω_j = 0): no slip, no tangential force, the line of
/// centres fixed, and the relative rolling w = ω_j − ω_i = 2 ω_j meets only
/// the rolling couple, whose cap is μ_r R* P (R* = r/2).
struct PairTurn {
  double spin_rate, spin, mirror_gap, tangential_speed;
};
PairTurn counter_rotating_pair(double torque, double mu_r, DemIntegrator integrator, int steps, int from) {
  const double P = kG, r = 0.05, k = 1e6, K = 0.5 * k;
  DemDesc<2> d;
  d.dt = 1e-5;
  d.damping_ratio = 0.5;
  d.friction = 0.5;
  d.rolling_friction = mu_r;
  d.integrator = integrator;
  d.external_forces = true;
  d.external_torques = true;
  d.energy_check.interval = 1;
  ParticleDesc<2> left, right;
  left.mass = right.mass = 1;
  left.radius = right.radius = r;
  left.stiffness = right.stiffness = k;
  const double distance = 2 * r - P / K;
  left.position = {-0.5 * distance, 0};
  right.position = {0.5 * distance, 0};
  d.particles = {left, right};
  DemWorld<2> world;
  EXPECT_TRUE(world.build(d).ok());
  world.state.external_force[0][0] = P;
  world.state.external_force[0][1] = -P;
  world.state.external_torque[0][0] = -torque;
  world.state.external_torque[0][1] = torque;
  dem_inputs_changed(world.state);
  double w0 = 0, gap = 0, vy = 0;
  for (int s = 1; s <= steps; ++s) {
    const StepStatus status = world.step();
    if (status != StepStatus::ok) {
      ADD_FAILURE() << integrator_name(integrator) << " step " << s << ": " << static_cast<unsigned>(status);
      break;
    }
    if (s == from) w0 = world.state.w[0][1];
    gap = std::max(gap, std::fabs(world.state.w[0][0] + world.state.w[0][1]));
    vy = std::max({vy, std::fabs(world.state.v[1][0]), std::fabs(world.state.v[1][1])});
  }
  return {(world.state.w[0][1] - w0) / ((steps - from) * d.dt), world.state.w[0][1], gap, vy};
}

// (1c, 2d) A pair's couple against the relative rolling alone (no
// tangential force), 2D. Above the cap, T = 1.5 μ_r R* P: the couple is the
// cap from the second evaluation on (the first sees w = 0 and no tangential
// torque: no couple), so each disk spins up at (T − μ_r R* P)/I, a constant
// every integrator steps exactly (1e-9 relative, as above).
// Below the cap, T = μ_r R* P/2, the known limit of a contact-local hold:
// the couple cancels this contact's own tangential torques, not a torque
// from elsewhere (an external torque here; another contact's net couple in a
// packing). That torque is balanced only by the clamp −w/(Δt K), at the
// creep w = Δt K T (K = 2/I), ω_j = Δt T/I: a closed form, asserted to
// 1e-9 relative after the clamp's decay (a factor ≤ 1/2 a step).
void pair_couple(DemIntegrator integrator) {
  const double mu_r = 0.3, r = 0.05, inertia = 0.5 * r * r, cap = mu_r * 0.5 * r * kG;
  const PairTurn above = counter_rotating_pair(1.5 * cap, mu_r, integrator, 20000, 100);
  const double alpha = (1.5 * cap - cap) / inertia;
  const PairTurn below = counter_rotating_pair(0.5 * cap, mu_r, integrator, 2000, 1000);
  const double creep = 1e-5 * 0.5 * cap / inertia;
  std::printf("%s pair couple: above the cap spin-up %.12g rad/s^2 (closed form %.12g); below it the spin %.12g "
              "rad/s (creep dt T/I %.12g); |w_i + w_j| <= %.1e, |v_y| <= %.1e\n",
              integrator_name(integrator), above.spin_rate, alpha, below.spin, creep,
              std::max(above.mirror_gap, below.mirror_gap), std::max(above.tangential_speed, below.tangential_speed));
  EXPECT_NEAR(above.spin_rate, alpha, 1e-9 * alpha);
  EXPECT_NEAR(below.spin, creep, 1e-9 * creep);
  EXPECT_NEAR(below.spin_rate, 0.0, 1e-9 * alpha);
  EXPECT_EQ(above.mirror_gap, 0.0);  // ω_i = −ω_j to the bit: no slip, no tangential force
  EXPECT_EQ(above.tangential_speed, 0.0);
}
TEST(RollingHold, PairCoupleAtTheCapAndTheCreepOfATorqueFromElsewhere) {
  for (DemIntegrator integrator : kRotating) pair_couple(integrator);
}

}  // namespace
}  // namespace xfdem::testing
