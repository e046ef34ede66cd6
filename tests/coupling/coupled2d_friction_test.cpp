// Frictional disks against the plate (coupled2d.hpp): the DEM's particle–wall
// contact (Cundall–Strack spring, Coulomb cap, rolling resistance) between a
// disk and the plate's boundary, each against a closed form computed here.
//  - a disk thrown along a stiff plate's top slides, then rolls: deceleration
//    μ g and spin-up while sliding, then v = v0 / (1 + I/(m a²)) (2/3 v0 for
//    a disk, a = r − δ the arm to the contact point), with the linear law
//    and with hertz (the plate's material the second body); rolling
//    resistance slows a rolling disk at μ_r r m g a / (I + m a²);
//  - on an incline (gravity turned, the plate's flat top): below tan θ = 3μ
//    it rolls without slip at g sin θ / (1 + I/(m a²)) (2/3 g sin θ), its
//    static friction force steady across 100 edge joints (the spring is kept
//    from edge to edge); above it slides at g (sin θ − μ cos θ);
//  - a free plate hit by spinning frictional disks, no gravity: total linear
//    momentum constant to round-off; with no damping the energy at
//    contact-free instants never rises;
//  - no allocation in a step, the same bits on 1 and 2 workers and run after
//    run; refusals naming the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "support/coupled2d_scenes.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"

using namespace xfdem;
using xfdem::testing::circle;
using xfdem::testing::disk;
using xfdem::testing::plate;
using xfdem::testing::total_momentum;

namespace {

constexpr double kG = 9.81;

/// A disk (m = 1 kg, r = 0.05 m, k = 1e6 N/m) on the top (y = 0.5 m) of a
/// nearly rigid plate held at its bottom, of `cells` cells 0.1 m wide, with
/// gravity turned by θ (the top an incline rising to the left: the disk goes
/// towards +x), resting at the overlap m g cos θ / k, moving at v0 along x.
struct Incline {
  double m = 1.0, r = 0.05, k = 1e6, mu = 0.3, theta = 0.0;
  double delta() const { return m * kG * std::cos(theta) / k; }
  double arm() const { return r - delta(); }
  double inertia() const { return 0.5 * m * r * r; }
  DemIntegrator integrator = DemIntegrator::symplectic_euler;
  Coupled2dDesc desc(int cells, double v0, double w0) const {
    Coupled2dDesc d;
    // E = 2e15: the plate's deflection under the disk leaves < 1e-8 m g in
    // the normal force (coupled2d_test's sliding disk).
    d.plate = plate(2e15, 0.1 * cells, 0.5, cells, 2);
    d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
    d.dem.integrator = integrator;
    d.dem.damping_ratio = 0.3;
    d.dem.friction = mu;
    d.dem.tangential_stiffness_ratio = 0.8;
    d.dem.gravity = {kG * std::sin(theta), -kG * std::cos(theta)};
    ParticleDesc<2> p = disk(m, r, k, 0.3, 0.5 + r - delta(), v0, 0.0);
    p.angular_velocity = {w0};
    d.dem.particles.push_back(p);
    d.dem_substeps = 10;
    return d;
  }
};

/// A free plate 2 m × 1 m, 8 × 4 cells, cut by a free crack, and four
/// spinning disks coming at it from its four sides, no gravity, no damping.
Coupled2dDesc free_plate_hit(double friction, double rolling,
                             DemIntegrator integrator = DemIntegrator::symplectic_euler) {
  Coupled2dDesc d;
  d.plate = xfdem::testing::cracked_free_plate();
  d.dem.integrator = integrator;
  d.dem.friction = friction;
  d.dem.rolling_friction = rolling;
  d.dem.tangential_stiffness_ratio = 0.8;
  auto spinning = [](ParticleDesc<2> p, double w) {
    p.angular_velocity = {w};
    return p;
  };
  d.dem.particles.push_back(spinning(disk(2.0, 0.05, 1e6, -0.06, 0.37, 3.0, 0.4), 40.0));    // left
  d.dem.particles.push_back(spinning(disk(1.0, 0.05, 1e6, 2.07, 0.71, -2.0, 1.0), -60.0));   // right
  d.dem.particles.push_back(spinning(disk(1.5, 0.04, 2e6, 1.02, 1.05, 0.8, -2.5), 30.0));    // top, over the crack's mouth
  d.dem.particles.push_back(spinning(disk(3.0, 0.06, 1e6, 0.51, -0.07, -0.9, 1.5), -20.0));  // bottom
  d.dem_substeps = 10;
  return d;
}

/// Every integrator the coupled 2D stepper takes: symplectic Euler holds the
/// boundary's force and torque over a substep; the others evaluate the
/// boundary at their stages through the DEM's external contact hook, the
/// springs advanced and kept as the DEM's own planes' are.
constexpr DemIntegrator kIntegrators[] = {DemIntegrator::symplectic_euler, DemIntegrator::verlet, DemIntegrator::rk4,
                                          DemIntegrator::abm4};

/// The spin of disk i now less at the start (friction or rolling resistance acted).
double largest_spin_change(const Coupled2dWorld& w, const std::vector<double>& w0) {
  double change = 0;
  for (std::int32_t i = 0; i < w.model.dem.n; ++i)
    change = std::max(change, std::fabs(w.state.dem.w[0][static_cast<std::size_t>(i)] - w0[static_cast<std::size_t>(i)]));
  return change;
}

}  // namespace

// Thrown at v0 without spin on a flat top: sliding, friction −μ m g slows it
// and its torque (r − δ) μ m g spins it up; the slip would end at
// t* = v0 / (μ g (1 + m a²/I)). The sticking dashpot takes the contact below
// the cap once the trial force, the cap plus η_t times the slip's decrease
// over a substep less k_t h v_slip, falls under it: at v_slip = η_t s / k_t
// (s the slip's deceleration), η_t/k_t before t*. Then it rolls at
// v0 / (1 + I/(m a²)) (the angular momentum about the contact point is kept).
namespace {

/// Runs the thrown disk of Incline `c` (desc `d`) and checks it against the
/// closed forms; k_t: the tangential stiffness (hertz: S_t at rest), eta_t
/// its dashpot, delta the overlap at rest.
void slides_then_rolls(const char* what, const Incline& c, const Coupled2dDesc& d, double kt, double eta_t,
                       double delta) {
  const double v0 = d.dem.particles[0].velocity[0];
  Coupled2dWorld w;
  const BuildResult built = w.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  const double a = c.r - delta, ratio = c.m * a * a / c.inertia();
  const double t_stick = v0 / (c.mu * kG * (1.0 + ratio));
  const double v_roll = v0 / (1.0 + 1.0 / ratio);
  const double dt = w.model.dt;
  const double t_below_cap = t_stick - eta_t / kt;
  // Verlet: a window that starts with the disk touching re-evaluates the
  // acceleration it keeps (coupled2d.hpp) at (x_n, v_n), where verlet's own
  // evaluation was at (x_n, v_n−½): the slip rate is lower there by (h/2)
  // ds/dt, ds/dt = μ g (1 + m a²/I), so the sliding contact's trial force
  // falls under the cap by η_t (h/2) ds/dt for the window's first half kick.
  // Every window after the first loses that impulse, (h/2) η_t (h/2) ds/dt.
  const double h = dt / d.dem_substeps;
  const double shortfall = d.dem.integrator == DemIntegrator::verlet
                               ? 0.5 * h * eta_t * 0.5 * h * c.mu * kG * (1.0 + ratio)
                               : 0.0;
  double worst_v = 0, worst_w = 0, worst_cap = 0, stuck_at = -1;
  for (int step = 0; step < 4000; ++step) {
    ASSERT_EQ(w.step(), StepStatus::ok) << step;
    const double t = w.state.time;
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
    if (t < t_below_cap - 2 * dt) {
      // Sliding: the held force at the cap, the rates its closed forms.
      const double lost = step * shortfall;  // the restarted windows' (verlet)
      worst_cap = std::max(worst_cap, std::fabs(f[0] + c.mu * f[1]));
      worst_v = std::max(worst_v, std::fabs(w.state.dem.v[0][0] - (v0 - c.mu * kG * t + lost / c.m)));
      worst_w = std::max(worst_w,
                         std::fabs(w.state.dem.w[0][0] + c.mu * kG * t * a * c.m / c.inertia() - lost * a / c.inertia()));
    }
    if (stuck_at < 0 && std::fabs(f[0]) < (1.0 - 1e-6) * c.mu * f[1]) stuck_at = t;
  }
  const double v = w.state.dem.v[0][0], spin = w.state.dem.w[0][0];
  std::printf("slide then roll (%s): sliding |v - (v0 - mu g t)| <= %.3g m/s, |w - w(t)| <= %.3g rad/s "
              "(a restarted window's loss %.4g N s), |F_t + mu F_n| <= %.3g N; below the cap from %.5f s (closed form "
              "%.5f s, t* = %.5f s); v = %.9f m/s (closed form %.9f, 2/3 v0 = %.9f), v + w a = %.3g m/s\n",
              what, worst_v, worst_w, shortfall, worst_cap, stuck_at, t_below_cap, t_stick, v, v_roll, 2.0 / 3.0 * v0,
              v + spin * a);
  // The normal force is m g to 1e-8 (the plate's deflection): so are the rates.
  EXPECT_LT(worst_cap, 1e-8 * c.mu * c.m * kG);
  EXPECT_LT(worst_v, 1e-8 * v0);
  EXPECT_LT(worst_w, 1e-8 * v0 / c.r);
  EXPECT_NEAR(stuck_at, t_below_cap, 2 * dt);
  EXPECT_NEAR(v, v_roll, 1e-8 * v0);
  EXPECT_LT(std::fabs(v + spin * a), 1e-8 * v0);
}

}  // namespace

TEST(Coupled2dFriction, ADiskThrownAlongThePlateSlidesThenRolls) {
  for (const DemIntegrator integrator : kIntegrators) {
    SCOPED_TRACE(integrator_name(integrator));
    Incline c;
    c.integrator = integrator;
    const double kt = 0.8 * c.k;
    const std::string what = std::string("linear, ") + integrator_name(integrator);
    slides_then_rolls(what.c_str(), c, c.desc(20, 2.0, 0.0), kt, 2.0 * 0.3 * std::sqrt(kt * c.m), c.delta());
  }
}

// The same with the hertz law, the plate's material the second body: at rest
// δ = (3 m g / (4 E* √r))^{2/3}, S_t = 8 G* √(r δ), η_t = −2√(5/6) β √(S_t m).
TEST(Coupled2dFriction, AHertzDiskThrownAlongThePlateSlidesThenRolls) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Incline c;
  c.integrator = integrator;
  Coupled2dDesc d = c.desc(20, 2.0, 0.0);
  const double e = 1e8, nu = 0.3, restitution = 0.5;
  d.dem.law = ContactLaw::hertz;
  d.dem.damping_ratio = 0;
  d.dem.tangential_stiffness_ratio = 0;
  d.dem.restitution = restitution;
  const double inv_e = (1 - nu * nu) / e + (1 - d.plate.poisson_ratio * d.plate.poisson_ratio) / d.plate.youngs_modulus;
  const double inv_g = 2 * (2 - nu) * (1 + nu) / e +
                       2 * (2 - d.plate.poisson_ratio) * (1 + d.plate.poisson_ratio) / d.plate.youngs_modulus;
  const double delta = std::pow(3.0 * c.m * kG * inv_e / (4.0 * std::sqrt(c.r)), 2.0 / 3.0);
  ParticleDesc<2>& p = d.dem.particles[0];
  p.youngs_modulus = e, p.poisson_ratio = nu, p.stiffness = 0;
  p.position[1] = 0.5 + c.r - delta;
  const double st = 8.0 / inv_g * std::sqrt(c.r * delta);
  const double l = std::log(restitution);
  const double beta = l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  const std::string what = std::string("hertz, ") + integrator_name(integrator);
  slides_then_rolls(what.c_str(), c, d, st, -2.0 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(st * c.m), delta);
  }
}

// Rolling at v0 with rolling resistance μ_r: the torque μ_r r m g against the
// spin slows it at μ_r r m g a / (I + m a²), still without slip.
TEST(Coupled2dFriction, RollingResistanceSlowsARollingDisk) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Incline c;
  c.integrator = integrator;
  const double v0 = 2.0, mu_r = 0.01;
  Coupled2dDesc d = c.desc(20, v0, -v0 / c.arm());
  d.dem.rolling_friction = mu_r;
  Coupled2dWorld w;
  const BuildResult built = w.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  const double a = c.arm();
  const double decel = mu_r * c.r * c.m * kG * a / (c.inertia() + c.m * a * a);
  double v1 = 0, t1 = 0, worst_slip = 0;
  for (int step = 0; step < 3000; ++step) {
    ASSERT_EQ(w.step(), StepStatus::ok) << step;
    if (step == 500) v1 = w.state.dem.v[0][0], t1 = w.state.time;
    if (step > 500) worst_slip = std::max(worst_slip, std::fabs(w.state.dem.v[0][0] + w.state.dem.w[0][0] * a));
  }
  const double measured = (v1 - w.state.dem.v[0][0]) / (w.state.time - t1);
  std::printf("rolling resistance mu_r %.2f (%s): deceleration %.9f m/s^2 (closed form %.9f), slip <= %.3g m/s\n",
              mu_r, integrator_name(integrator), measured, decel, worst_slip);
  EXPECT_NEAR(measured, decel, 1e-8 * decel);
  EXPECT_LT(worst_slip, 1e-8 * v0);
  }
}

// On an incline below tan θ = 3μ (here μ = 0.3, tan 20° = 0.36 < 0.9), a
// disk rolling from 18 m/s keeps rolling without slip: a = g sin θ / (1 +
// I/(m a²)), the friction force m g sin θ − m a. It crosses about 100 edge
// joints of the plate's top: the static spring is kept from edge to edge
// (the history key is the boundary chain), so the force has no bump there
// and the disk's normal velocity stays at round-off.
TEST(Coupled2dFriction, ADiskRollsDownAnInclineAcross100JointsWithoutABump) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Incline c;
  c.integrator = integrator;
  c.theta = 20.0 * std::numbers::pi / 180.0;
  const double v0 = 18.0;
  const double a = c.arm(), ratio = c.m * a * a / c.inertia();
  const double accel = kG * std::sin(c.theta) / (1.0 + 1.0 / ratio);
  const double friction_force = c.m * kG * std::sin(c.theta) - c.m * accel;
  Coupled2dWorld w;
  const BuildResult built = w.build(c.desc(120, v0, -v0 / a));
  ASSERT_TRUE(built.ok()) << built.message;
  // The spring starts at 0 and takes its load in a damped oscillation
  // (ω ≈ √(k_t (1/m + a²/I)) ≈ 1.5e3 rad/s); from 0.05 s on it is steady.
  double worst_force = 0, worst_slip = 0, worst_vy = 0, worst_jump = 0, v1 = 0, t1 = 0;
  double previous = 0;
  const double x_start = 0.3;
  double x_steady = 0;
  for (int step = 0; step < 6000; ++step) {
    ASSERT_EQ(w.step(), StepStatus::ok) << step;
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
    if (step == 500) {
      v1 = w.state.dem.v[0][0], t1 = w.state.time, x_steady = w.state.dem.x[0][0];
    } else if (step > 500) {
      worst_force = std::max(worst_force, std::fabs(-f[0] - friction_force));
      worst_jump = std::max(worst_jump, std::fabs(f[0] - previous));
      worst_slip = std::max(worst_slip, std::fabs(w.state.dem.v[0][0] + w.state.dem.w[0][0] * a));
      worst_vy = std::max(worst_vy, std::fabs(w.state.dem.v[1][0]));
    }
    previous = f[0];
  }
  const double measured = (w.state.dem.v[0][0] - v1) / (w.state.time - t1);
  const double joints = std::floor(w.state.dem.x[0][0] / 0.1) - std::floor(x_steady / 0.1);
  std::printf("%s: rolling down 20 deg from x = %.2f m, steady from %.2f to %.2f m (%g joints): a = %.9f m/s^2 "
              "(closed form %.9f, 2/3 g sin = %.9f), |F_t - F| <= %.3g N of %.4f N, step-to-step |dF_t| <= %.3g N, "
              "slip <= %.3g m/s, |v_y| <= %.3g m/s\n",
              integrator_name(integrator), x_start, x_steady, w.state.dem.x[0][0], joints, measured, accel, 2.0 / 3.0 * kG * std::sin(c.theta),
              worst_force, friction_force, worst_jump, worst_slip, worst_vy);
  EXPECT_GE(joints, 100.0);
  EXPECT_NEAR(measured, accel, 1e-8 * accel);
  // What is left is the plate's deflection under the moving load (1e-8 of
  // the normal force); a spring lost at a joint would drop the force by
  // all of it (keyed by segment instead of chain: 1.1 N bumps).
  EXPECT_LT(worst_force, 1e-7 * friction_force);
  EXPECT_LT(worst_jump, 1e-7 * friction_force);
  EXPECT_LT(worst_slip, 1e-8 * v0);
  EXPECT_LT(worst_vy, 1e-9);
  }
}

// Above tan θ = 3μ (μ = 0.2, tan 40° = 0.84 > 0.6) the disk slides: its
// centre accelerates at g (sin θ − μ cos θ) and it spins up at μ g cos θ a m/I.
TEST(Coupled2dFriction, ADiskSlidesDownASteeperIncline) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Incline c;
  c.integrator = integrator;
  c.mu = 0.2;
  c.theta = 40.0 * std::numbers::pi / 180.0;
  ASSERT_GT(std::tan(c.theta), 3 * c.mu);
  Coupled2dWorld w;
  const BuildResult built = w.build(c.desc(20, 0.0, 0.0));
  ASSERT_TRUE(built.ok()) << built.message;
  const double accel = kG * (std::sin(c.theta) - c.mu * std::cos(c.theta));
  const double spin_up = c.mu * kG * std::cos(c.theta) * c.arm() * c.m / c.inertia();
  double v1 = 0, w1 = 0, t1 = 0;
  for (int step = 0; step < 3000; ++step) {
    ASSERT_EQ(w.step(), StepStatus::ok) << step;
    if (step == 500) v1 = w.state.dem.v[0][0], w1 = w.state.dem.w[0][0], t1 = w.state.time;
  }
  const double span = w.state.time - t1;
  const double a_measured = (w.state.dem.v[0][0] - v1) / span;
  const double alpha_measured = (w.state.dem.w[0][0] - w1) / span;
  const double slip = w.state.dem.v[0][0] + w.state.dem.w[0][0] * c.arm();
  std::printf("%s: sliding down 40 deg, mu 0.2: a = %.9f m/s^2 (closed form %.9f), alpha = %.6f rad/s^2 (closed form "
              "%.6f), slip %.4f m/s\n",
              integrator_name(integrator), a_measured, accel, alpha_measured, -spin_up, slip);
  EXPECT_NEAR(a_measured, accel, 1e-8 * accel);
  EXPECT_NEAR(alpha_measured, -spin_up, 1e-8 * spin_up);
  EXPECT_GT(slip, 0.1);
  }
}

// A disk with friction and rolling resistance resting on the soft plate's
// top off its centre (over a node and between nodes): the plate bends under
// it, so the contact's normal tilts by φ and the sticking contact holds a
// tangential force m g sin φ, whose torque about the centre a couple has to
// balance. Rolling resistance was the torque that stops the relative rolling
// within a step, −I ω/h: it holds that torque only while the disk rolls at
// ω = h τ_t / I, so the disk crept, the plate following it (the 2D scene
// variants' `rest` case: 12 of 23 scenes not at rest). It now stops the
// relative rolling within h together with the contact's own tangential
// torque, so the disk rests: after 6.4 s (the disk's dashpot's e-folding time
// 1/(ζ √(k/m)) is 0.022 s) its speed, and its spin times the arm, are below
// 1e-3 of the clamp's creep h a² |F_t| / I (which the test computes from the
// force and normal it finds), the plate's displacement still by 1e-9 of
// itself over the last 100 steps, the force m g, every window after the
// first settled (the first, where the top starts to bend under a disk over a
// node, may be taken at its smallest residual, 1.2e-9 … 1.1e-8 here). With
// the plane's clamp the disk crept at that speed under symplectic Euler, and
// under the other integrators the window's re-evaluation at h = 0 (uncapped
// rolling torque) left hundreds of windows at a jump and F off m g by 3e-2 N.
TEST(Coupled2dFriction, AStuckDiskOnTheBentTopComesToRestWithEveryIntegrator) {
  const double L = 1.8352577124736102;
  for (const double at : {0.25, 0.37}) {  // a node of the top (every L/4), and between two
    for (const DemIntegrator integrator : kIntegrators) {
      Coupled2dDesc d = xfdem::testing::disk_resting_on_soft_plate(integrator, at * L);
      d.dem.friction = 0.5;
      d.dem.rolling_friction = 0.05;
      d.dem.tangential_stiffness_ratio = 0.8;
      const double m = d.dem.particles[0].mass, r = d.dem.particles[0].radius, g = 9.81;
      const double h = d.plate.dt / d.dem_substeps, inertia = 0.5 * m * r * r;
      Coupled2dWorld w;
      const BuildResult built = w.build(d);
      ASSERT_TRUE(built.ok()) << built.message;
      const int steps = 4000;
      std::vector<double> u_before;
      std::int64_t first_unsettled = 0;  // the first window, in which the top starts to bend under the disk
      for (int step = 0; step < steps; ++step) {
        if (step == steps - 100) u_before = w.state.plate.u;
        ASSERT_EQ(w.step(), StepStatus::ok) << integrator_name(integrator) << " at " << at << " L, step " << step;
        if (step == 0) first_unsettled = w.state.unsettled_windows;
      }
      double f[2];
      ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
      std::vector<double> positions(2 * w.model.boundary.vertices.size());
      plate_boundary_positions(w.model.plate, w.model.boundary, w.state.plate.u.data(), w.state.plate.time, positions.data());
      const double centre[2] = {w.state.dem.x[0][0], w.state.dem.x[1][0]};
      PlateBoundaryContact c[kPlateBoundaryMaxContacts];
      ASSERT_EQ(plate_boundary_contacts(w.model.boundary, positions.data(), centre, r, c), 1);
      const double tangential = std::fabs(f[0] * c[0].normal[1] - f[1] * c[0].normal[0]);
      const double arm = std::hypot(centre[0] - c[0].point[0], centre[1] - c[0].point[1]);
      const double creep = h * arm * arm * tangential / inertia;  // the clamp's rolling speed ω a
      const double speed = std::hypot(w.state.dem.v[0][0], w.state.dem.v[1][0]);
      const double rolling = std::fabs(w.state.dem.w[0][0]) * arm;
      double moved = 0, size = 0;
      for (std::size_t j = 0; j < u_before.size(); ++j) {
        moved = std::max(moved, std::fabs(w.state.plate.u[j] - u_before[j]));
        size = std::max(size, std::fabs(w.state.plate.u[j]));
      }
      std::printf("%s, disk at %.2f L: |F_t| = %.3g N (%.3g of mu m g), the clamp's creep %.3g m/s; speed %.3g m/s, "
                  "omega a %.3g m/s; the plate moved %.3g of its %.3g m over 100 steps; F - m g = (%.3g, %.3g) N; "
                  "windows blended %lld, at their smallest residual %lld (worst %.3g)\n",
                  integrator_name(integrator), at, tangential, tangential / (d.dem.friction * m * g), creep, speed,
                  rolling, moved / size, size, f[0], f[1] - m * g, static_cast<long long>(w.state.blended_windows),
                  static_cast<long long>(w.state.unsettled_windows), w.state.worst_unsettled);
      EXPECT_GT(tangential, 1e-6 * m * g);  // the top is bent under the disk: the contact needs a couple
      EXPECT_LT(speed, 1e-3 * creep);
      EXPECT_LT(rolling, 1e-3 * creep);
      EXPECT_LT(moved, 1e-9 * size);
      EXPECT_NEAR(f[0], 0.0, 1e-6 * m * g);
      EXPECT_NEAR(f[1], m * g, 1e-6 * m * g);
      EXPECT_EQ(w.state.unsettled_windows, first_unsettled);
      EXPECT_LT(w.state.worst_unsettled, 1e-6);
    }
  }
}

// A heavy hertz disk (89 kg) with rolling resistance exactly over a node of
// a light, soft plate (the 2D variants' rest14 scene, its numbers as drawn):
// the torque that stops the relative rolling within a substep, taken with
// the disk's I alone (I/h = 1.7e3 N m s), made the window's map so steep in
// the boundary's spin that from pass to pass the couple left and rejoined its
// cap (33, 0, 33, 9, 21 of 33 evaluations capped), and rk4 stopped at step 5
// with coupling_unstable (a window left at 6.7e-3 of the force). With the
// segment's own turning under the couple (1/I + 1/I_wall, as a pair's), every
// window settles, under every integrator, and the disk comes to rest.
TEST(Coupled2dFriction, AHeavyDiskOverANodeOfALightPlateSettlesEveryWindow) {
  for (const DemIntegrator integrator : kIntegrators) {
    Coupled2dDesc d;
    d.plate = plate(17414798.081581157, 1, 1, 7, 5);
    d.plate.min[0] = -0.7596155685440884, d.plate.min[1] = -1.3866948935452443;
    d.plate.max[0] = -0.21885120927774204, d.plate.max[1] = -1.0997063441649662;
    d.plate.poisson_ratio = 0.23994904563190073;
    d.plate.density = 5889.339071340372;
    d.plate.plane = PlateDesc::Plane::stress;
    d.plate.thickness = 0.7666976092911267;
    d.plate.beta = 0.35717106049547737, d.plate.gamma = 0.6952758016382284;
    d.plate.dt = 0.003629701273285315;
    d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
    d.plate.supports.push_back({PlateEdge::left, {true, false}, false});
    d.dem.integrator = integrator;
    d.dem.gravity = {0.0, -kG};
    d.dem.law = ContactLaw::hertz;
    d.dem.restitution = 0.09040959642209974;
    d.dem.friction = 0.6469191634373623;
    d.dem.rolling_friction = 0.037218093491207825;
    ParticleDesc<2> p = disk(89.0726010256705, 0.13286748102897902, 0.0, -0.2961032606015058, -0.9820213678190001,
                             0.0, 0.0);
    p.youngs_modulus = 823246.6216258717, p.poisson_ratio = 0.43352875307294636;
    d.dem.particles.push_back(p);
    d.dem_substeps = 8;
    const double m = p.mass;
    Coupled2dWorld w;
    const BuildResult built = w.build(d);
    ASSERT_TRUE(built.ok()) << built.message;
    for (int step = 0; step < 3000; ++step)
      ASSERT_EQ(w.step(), StepStatus::ok) << integrator_name(integrator) << " step " << step;
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
    const double speed = std::hypot(w.state.dem.v[0][0], w.state.dem.v[1][0]);
    std::printf("%s, heavy disk over a node of a light plate, 3000 steps: peak passes %d, windows blended %lld, at "
                "their smallest residual %lld; speed %.3g m/s, omega r %.3g m/s, F - m g = (%.3g, %.3g) N\n",
                integrator_name(integrator), w.state.peak_passes, static_cast<long long>(w.state.blended_windows),
                static_cast<long long>(w.state.unsettled_windows), speed, w.state.dem.w[0][0] * p.radius, f[0],
                f[1] - m * kG);
    EXPECT_EQ(w.state.unsettled_windows, 0);
    EXPECT_LT(speed, 1e-9);
    EXPECT_LT(std::fabs(w.state.dem.w[0][0]) * p.radius, 1e-9);
    EXPECT_NEAR(f[0], 0.0, 1e-6 * m * kG);
    EXPECT_NEAR(f[1], m * kG, 1e-6 * m * kG);
  }
}

// A free cracked plate hit by four spinning disks with friction and rolling
// resistance, no gravity, no damping: the exchange is of impulses (normal
// and tangential force, and the rolling couple as two opposite forces), so
// the total linear momentum stays at its start to round-off. Energy at the
// instants no disk touches the plate (when it is all kinetic and the
// plate's) never rises: friction only takes it out.
TEST(Coupled2dFriction, FreePlateHitBySpinningDisksKeepsMomentumAndLosesEnergy) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Coupled2dWorld w;
  const BuildResult r = w.build(free_plate_hit(0.5, 0.02, integrator));
  ASSERT_TRUE(r.ok()) << r.message;
  double scale = 0;
  for (std::int32_t i = 0; i < w.model.dem.n; ++i)
    scale += w.model.dem.mass[i] * std::hypot(w.state.dem.v[0][i], w.state.dem.v[1][i]);
  auto energy = [&] {
    double e = plate_algorithmic_energy(w.model.plate, w.state.plate);
    for (std::int32_t i = 0; i < w.model.dem.n; ++i)
      e += 0.5 * w.model.dem.mass[i] * (w.state.dem.v[0][i] * w.state.dem.v[0][i] + w.state.dem.v[1][i] * w.state.dem.v[1][i]) +
           0.5 * w.state.dem.w[0][i] * w.state.dem.w[0][i] / w.model.dem.inv_inertia[i];
    return e;
  };
  const double p0[2] = {total_momentum(w.model, w.state, 0), total_momentum(w.model, w.state, 1)};
  const double e0 = energy();
  const std::vector<double> w0 = w.state.dem.w[0];
  double worst = 0, last_free = e0, worst_rise = 0, worst_work = 0, work_scale = 0;
  int free_instants = 0;
  for (int step = 0; step < 600; ++step) {
    const double before[2] = {w.state.work_on_plate, w.state.work_by_particles};
    ASSERT_EQ(w.step(), StepStatus::ok) << "step " << step;
    // The exchange's work, the rolling couple's included: what the plate
    // received against what the disks did on the boundary it saw.
    const double on_plate = w.state.work_on_plate - before[0], by_disks = w.state.work_by_particles - before[1];
    worst_work = std::max(worst_work, std::fabs(on_plate - by_disks));
    work_scale += std::fabs(on_plate);
    for (int axis = 0; axis < 2; ++axis)
      worst = std::max(worst, std::fabs(total_momentum(w.model, w.state, axis) - p0[axis]));
    bool touching = false;
    for (std::int32_t i = 0; i < w.model.dem.n; ++i) {
      double f[2];
      ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, i, f));
      touching = touching || f[0] != 0 || f[1] != 0;
    }
    // Touching at the end of a step's last substep or not: whether it still
    // touches is seen at the next substep's start, so a free instant is one
    // between two steps that both end free.
    if (!touching) {
      const double e = energy();
      worst_rise = std::max(worst_rise, e - last_free);
      last_free = e;
      ++free_instants;
    }
  }
  const double spin_change = largest_spin_change(w, w0);
  std::printf("free plate, 4 spinning frictional disks, 600 steps (%s): momentum drift %.3g of %.3g kg m/s; energy "
              "at %d contact-free instants: worst rise %.3g J, from %.6f J to %.6f J; largest spin change %.3g rad/s; "
              "exchange work: worst step %.3g J of sum |W| %.3g J\n",
              integrator_name(integrator), worst, scale, free_instants, worst_rise, e0, last_free, spin_change,
              worst_work, work_scale);
  EXPECT_GT(spin_change, 1.0);  // the boundary's friction turned the disks
  EXPECT_LT(worst, 1e-12 * scale);
  EXPECT_GT(free_instants, 10);
  EXPECT_LT(last_free, e0);
  EXPECT_LE(worst_rise, 1e-12 * e0);
  EXPECT_GT(work_scale, 0.0);
  EXPECT_LT(worst_work, 1e-9 * work_scale);  // coupled2d_test's bound: the fixed point's tolerance
  }
}

TEST(Coupled2dFriction, StepNeverAllocatesAndGivesTheSameBitsOnTwoWorkersAndRunAfterRun) {
  for (const DemIntegrator integrator : kIntegrators) {
  SCOPED_TRACE(integrator_name(integrator));
  Coupled2dDesc d = free_plate_hit(0.5, 0.02, integrator);
  d.dem.damping_ratio = 0.05;
  d.dem.split_from = 2;  // two parts of disks, so that a pool runs them on two workers
  d.dem.particles[0].position = {-0.051, 0.37};  // 1 mm from the plate
  Coupled2dWorld one, again, two;
  ASSERT_TRUE(one.build(d).ok());
  ASSERT_TRUE(again.build(d).ok());
  ASSERT_TRUE(two.build(d).ok());
  platform::TwoWorkerPool pool;
  two.workspace.dem.parallel = pool.parallel_for();
  {
    platform::AllocationCounter counter;
    for (int step = 0; step < 30; ++step) ASSERT_EQ(one.step(), StepStatus::ok);
    EXPECT_EQ(counter.allocations(), 0u);
  }
  for (int step = 0; step < 30; ++step) ASSERT_EQ(again.step(), StepStatus::ok);
  for (int step = 0; step < 30; ++step) ASSERT_EQ(two.step(), StepStatus::ok);
  // The left disk touches with friction by then: its springs are loaded.
  EXPECT_TRUE(std::any_of(one.state.springs.xi.begin(), one.state.springs.xi.end(), [](double x) { return x != 0.0; }));
  for (const Coupled2dWorld* other : {&again, &two}) {
    for (std::int32_t i = 0; i < one.model.dem.n; ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_EQ(one.state.dem.x[axis][i], other->state.dem.x[axis][i]);
        EXPECT_EQ(one.state.dem.v[axis][i], other->state.dem.v[axis][i]);
      }
      EXPECT_EQ(one.state.dem.w[0][i], other->state.dem.w[0][i]);
    }
    EXPECT_EQ(one.state.springs.xi, other->state.springs.xi);
    EXPECT_EQ(one.state.springs.chain, other->state.springs.chain);
    EXPECT_EQ(one.state.plate.u, other->state.plate.u);
    EXPECT_EQ(one.state.plate.v, other->state.plate.v);
  }
  }
}

TEST(Coupled2dFriction, BadInputIsRefusedNamingTheKey) {
  {
    // abm4_events' event location does not see the boundary's contacts.
    Coupled2dDesc d = free_plate_hit(0.5, 0.0, DemIntegrator::abm4_events);
    Coupled2dWorld w;
    const BuildResult r = w.build(d);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(std::strstr(r.message, "dem.integrator"), nullptr) << r.message;
  }
  {
    // The DEM's torque input needs particles that rotate.
    DemDesc<2> d;
    d.integrator = DemIntegrator::symplectic_euler;
    d.dt = 1e-5;
    d.particles.push_back(disk(1.0, 0.05, 1e6, 0.0, 0.0, 0.0, 0.0));
    d.external_torques = true;
    DemWorld<2> w;
    const BuildResult r = w.build(d);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(std::strstr(r.message, "external_torques"), nullptr) << r.message;
  }
}

// The torque input is a field of the DEM's state (hashes, snapshots) only
// when on: frictionless coupled scenes keep their layout; frictional ones
// carry the torques and the springs.
TEST(Coupled2dFriction, TheTorqueInputAndTheSpringsAreStateOnlyWhenOn) {
  Coupled2dWorld frictionless, frictional;
  Coupled2dDesc d = free_plate_hit(0.0, 0.0);
  ASSERT_TRUE(frictionless.build(d).ok());
  EXPECT_TRUE(frictionless.state.dem.external_torque[0].empty());
  EXPECT_TRUE(frictionless.state.springs.chain.empty());
  d.dem.friction = 0.5;
  ASSERT_TRUE(frictional.build(d).ok());
  EXPECT_EQ(frictional.state.dem.external_torque[0].size(), 4u);
  EXPECT_EQ(frictional.state.springs.chain.size(), 4u * kPlateBoundaryMaxContacts);
  // The integrators that evaluate the boundary at their stages take its
  // torque there (the DEM's hook), not as an input held over the substep.
  Coupled2dWorld staged;
  d.dem.integrator = DemIntegrator::rk4;
  ASSERT_TRUE(staged.build(d).ok());
  EXPECT_TRUE(staged.state.dem.external_torque[0].empty());
  EXPECT_EQ(staged.state.springs.chain.size(), 4u * kPlateBoundaryMaxContacts);
  d.dem.integrator = DemIntegrator::symplectic_euler;
  // The same rotating DEM with and without the input: one field more.
  DemDesc<2> dem = d.dem;
  dem.dt = 1e-5;
  DemWorld<2> with, without;
  ASSERT_TRUE(without.build(dem).ok());
  dem.external_torques = true;
  ASSERT_TRUE(with.build(dem).ok());
  EXPECT_EQ(field_count(with.state), field_count(without.state) + 1);
  EXPECT_NE(layout_hash(with.state), layout_hash(without.state));
}

// The boundary contact is the DEM's plane contact under the same integrator:
// the thrown disk of the first test on the plate's top and on a DEM plane at
// the same height, the same substep and integrator, the plane's DEM
// restarted where the coupled stepper restarts its disks (each window while
// they touch the plate: dem_inputs_changed; verlet's restarts then cost the
// two the impulse of slides_then_rolls, each at its arm). While it slides, its
// velocity and the friction force agree to the plate's deflection (1e-8 of
// m g), and its spin to the arm's ratio: the plate's contact turns the disk
// about the contact point (arm r − δ), the plane about r (the DEM's plane
// contact), so ω_plate r/(r − δ) is the plane's ω. Each then rolls at its
// own closed form v0 / (1 + I/(m a²)).
TEST(Coupled2dFriction, ADiskOnThePlateTopSlidesAsOnADemPlaneUnderEachIntegrator) {
  for (const DemIntegrator integrator : kIntegrators) {
    SCOPED_TRACE(integrator_name(integrator));
    Incline c;
    c.integrator = integrator;
    const double v0 = 2.0;
    const Coupled2dDesc d = c.desc(20, v0, 0.0);
    Coupled2dWorld coupled;
    ASSERT_TRUE(coupled.build(d).ok());
    DemDesc<2> alone = d.dem;
    alone.dt = d.plate.dt / d.dem_substeps;
    alone.planes = {{{0.0, 0.5}, {0.0, 1.0}}};
    DemWorld<2> plane;
    const BuildResult built = plane.build(alone);
    ASSERT_TRUE(built.ok()) << built.message;
    const double a = c.arm();
    const double t_stick = v0 / (c.mu * kG * (1.0 + c.m * a * a / c.inertia()));
    // Verlet's restarts cost each the impulse of slides_then_rolls, whose
    // slip deceleration μ g (1 + m arm²/I) has the arm a on the plate, r on
    // the plane: the two differ by that much per window.
    const double h = alone.dt, eta_t = 2.0 * 0.3 * std::sqrt(0.8 * c.k * c.m);
    auto shortfall = [&](double arm) {
      return integrator == DemIntegrator::verlet
                 ? 0.5 * h * eta_t * 0.5 * h * c.mu * kG * (1.0 + c.m * arm * arm / c.inertia())
                 : 0.0;
    };
    const double extra = shortfall(a) - shortfall(c.r);  // the plate's less the plane's, per window
    double worst_v = 0, worst_w = 0;
    for (int step = 0; step < 4000; ++step) {
      ASSERT_EQ(coupled.step(), StepStatus::ok) << step;
      // The coupled stepper re-evaluates the kept acceleration (and restarts
      // abm4's history) at each window the disk starts touching: the plane
      // the same.
      if (step > 0) dem_inputs_changed(plane.state);
      for (int k = 0; k < d.dem_substeps; ++k) ASSERT_EQ(plane.step(), StepStatus::ok) << step;
      if (coupled.state.time < 0.9 * t_stick) {
        worst_v = std::max(worst_v, std::fabs(coupled.state.dem.v[0][0] - plane.state.v[0][0] - step * extra / c.m));
        worst_w = std::max(worst_w, std::fabs(coupled.state.dem.w[0][0] * c.r / a - plane.state.w[0][0] -
                                              step * extra * c.r / c.inertia()));
      }
    }
    const double v_plate = coupled.state.dem.v[0][0], v_plane = plane.state.v[0][0];
    const double roll_plate = v0 / (1.0 + c.inertia() / (c.m * a * a));
    const double roll_plane = v0 / (1.0 + c.inertia() / (c.m * c.r * c.r));
    std::printf("%s: plate top against a DEM plane while sliding: |dv| <= %.3g m/s, |w r/a - w_plane| <= %.3g rad/s; "
                "rolling v = %.9f (closed form %.9f) and on the plane %.9f (closed form %.9f)\n",
                integrator_name(integrator), worst_v, worst_w, v_plate, roll_plate, v_plane, roll_plane);
    EXPECT_LT(worst_v, 1e-8 * v0);
    EXPECT_LT(worst_w, 1e-8 * v0 / c.r);
    EXPECT_NEAR(v_plate, roll_plate, 1e-8 * v0);
    EXPECT_NEAR(v_plane, roll_plane, 1e-8 * v0);
  }
}

// Hertz against a plate with an inclusion: a disk on the plate's top where
// the top runs through a circular inclusion meets the inclusion's material,
// E* = 1/((1 − ν_d²)/E_d + (1 − ν_i²)/E_i). Undamped (e = 1), at every
// evaluation of the integrators that evaluate the boundary at their stages
// the normal force is 4/3 E* √r δ^{3/2} at the overlap δ the test measures
// itself on the deformed boundary (the last evaluation's: the end state, the
// plate where it is now); the plate's own E* is twice the inclusion's.
TEST(Coupled2dFriction, HertzAgainstAnInclusionTakesTheInclusionsMaterial) {
  for (const DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::rk4, DemIntegrator::abm4}) {
    SCOPED_TRACE(integrator_name(integrator));
    Coupled2dDesc d;
    d.plate = plate(2e9, 2.0, 0.5, 20, 2);
    d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
    PlateDiscontinuity inclusion = circle(PlateDiscontinuity::Kind::inclusion, 1.0, 0.5, 0.2, "soft");
    inclusion.material = {5e8, 0.25, 2000};
    d.plate.discontinuities.push_back(inclusion);
    d.dem.integrator = integrator;
    d.dem.law = ContactLaw::hertz;
    d.dem.restitution = 1.0;
    d.dem.friction = 0.3;
    d.dem.gravity = {0.0, -kG};
    const double m = 1.0, r = 0.05, e = 1e9, nu = 0.3;
    const double e_star = 1.0 / ((1 - nu * nu) / e + (1 - 0.25 * 0.25) / 5e8);
    const double e_plate = 1.0 / ((1 - nu * nu) / e + (1 - d.plate.poisson_ratio * d.plate.poisson_ratio) / 2e9);
    const double delta = std::pow(3.0 * m * kG / (4.0 * e_star * std::sqrt(r)), 2.0 / 3.0);
    ParticleDesc<2> p = disk(m, r, 0.0, 1.03, 0.5 + r - delta, 0.0, 0.0);
    p.youngs_modulus = e, p.poisson_ratio = nu;
    d.dem.particles.push_back(p);
    d.dem_substeps = 10;
    Coupled2dWorld w;
    const BuildResult built = w.build(d);
    ASSERT_TRUE(built.ok()) << built.message;
    std::vector<double> positions(2 * w.model.boundary.vertices.size());
    double worst = 0, peak = 0;
    for (int step = 0; step < 400; ++step) {
      ASSERT_EQ(w.step(), StepStatus::ok) << step;
      plate_boundary_positions(w.model.plate, w.model.boundary, w.state.plate.u.data(), w.state.plate.time, positions.data());
      const double centre[2] = {w.state.dem.x[0][0], w.state.dem.x[1][0]};
      PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
      ASSERT_EQ(plate_boundary_contacts(w.model.boundary, positions.data(), centre, r, contacts), 1);
      const double fn = 4.0 / 3.0 * e_star * std::sqrt(r) * std::pow(contacts[0].overlap, 1.5);
      double f[2];
      ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
      const double normal = f[0] * contacts[0].normal[0] + f[1] * contacts[0].normal[1];
      worst = std::max(worst, std::fabs(normal - fn));
      peak = std::max(peak, normal);
    }
    std::printf("%s: hertz on an inclusion (E* = %.4g Pa, the plate's %.4g Pa): |F_n - 4/3 E* sqrt(r) d^1.5| <= %.3g N, "
                "peak F_n %.4f N (m g = %.4f N)\n",
                integrator_name(integrator), e_star, e_plate, worst, peak, m * kG);
    EXPECT_GT(e_plate / e_star, 1.9);
    EXPECT_GT(peak, 0.5 * m * kG);
    EXPECT_LT(worst, 1e-9 * m * kG);
  }
}
