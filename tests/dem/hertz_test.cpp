// The hertz law (DemDesc::law = hertz) against closed forms and independent
// solutions the tests compute: the particle-level benchmarks of Chung & Ooi
// (2011), elastic normal impact sphere–wall and sphere–sphere (Hertz contact
// duration and peak force), normal impact with restitution, oblique impact
// (gross sliding, and the Mindlin regime at small incidence), and the bits on
// one and two workers, snapshots, no allocation, bad input.
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

namespace xfdem::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Glass-like spheres (Chung & Ooi's test 1 material scale): R = 0.01 m,
// ρ = 2500 kg/m³, E = 4.8e10 Pa, ν = 0.2.
constexpr double kRadius = 0.01, kE = 4.8e10, kNu = 0.2;
const double kMass = 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius * 2500;

/// ∫₀¹ dx / √(1 − x^{5/2}) = (2/5) B(2/5, 1/2): the Hertz duration is
/// 2 (δ_max / v) times it.
double hertz_integral() { return 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9); }

/// Maximum overlap of an elastic Hertz impact: m* v²/2 = 8/15 E* √R* δ^{5/2}.
double delta_max(double m_star, double r_star, double e_star, double v) {
  return std::pow(15.0 * m_star * v * v / (16.0 * e_star * std::sqrt(r_star)), 0.4);
}

template <int D>
ParticleDesc<D> sphere(double e = kE, double nu = kNu) {
  ParticleDesc<D> p;
  p.mass = kMass;
  p.radius = kRadius;
  p.youngs_modulus = e;
  p.poisson_ratio = nu;
  return p;
}

struct Measured {
  double duration, peak_force, rebound;  // rebound: the normal speed after / before
  double vt_after, spin;                 // oblique impacts
};

/// A sphere hitting the floor y = 0 (rigid, or of the sphere's material) at
/// normal speed vn (and tangential vt), no gravity; the contact duration from
/// the touch-down and lift-off instants, each interpolated linearly between
/// the steps around it (free flight on either side: exact up to round-off).
template <int D>
Measured wall_impact(double vn, double vt, double restitution, double mu, bool rigid, double dt,
                     DemIntegrator integrator = DemIntegrator::verlet) {
  DemDesc<D> d;
  d.law = ContactLaw::hertz;
  d.restitution = restitution;
  d.friction = mu;
  d.dt = dt;
  d.integrator = integrator;
  ParticleDesc<D> p = sphere<D>();
  p.position[1] = kRadius + 2 * vn * dt + 1e-12;
  p.velocity[0] = vt;
  p.velocity[1] = -vn;
  d.particles.push_back(p);
  PlaneDesc<D> floor;
  floor.normal[1] = 1;
  if (!rigid) {
    floor.youngs_modulus = kE;
    floor.poisson_ratio = kNu;
  }
  d.planes.push_back(floor);
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  Measured r{};
  double on = -1, off = -1;
  double gap_before = world.state.x[1][0] - kRadius;
  for (int k = 0; k < 10000000 && off < 0; ++k) {
    EXPECT_EQ(world.step(), StepStatus::ok);
    const double gap = world.state.x[1][0] - kRadius;
    const double t = world.state.time;
    if (on < 0 && gap < 0) on = t - dt * (-gap) / (gap_before - gap);
    if (on >= 0 && gap < 0) r.peak_force = std::max(r.peak_force, dem_plane_force(world.model, world.state, 0, 0));
    if (on >= 0 && gap >= 0 && gap_before < 0) off = t - dt * gap / (gap - gap_before);
    gap_before = gap;
  }
  r.duration = off - on;
  r.rebound = world.state.v[1][0] / vn;
  r.vt_after = world.state.v[0][0];
  r.spin = world.state.w[D == 2 ? 0 : 2][0];
  return r;
}

double star(double a, double b) { return 1.0 / (1.0 / a + 1.0 / b); }

// Elastic normal impact on a wall (Chung & Ooi test 1): contact duration
// t_c = 2 ∫ (δ_max/v) = 2.87 (m*²/(R* E*² v))^{1/5} and peak force
// 4/3 E* √R* δ_max^{3/2}, rigid wall (1/E_wall = 0) and a wall of the
// sphere's material (E* halved), disks and spheres alike (the law is the
// same at each contact). Step: t_c/2000. Verlet's error over the contact is
// O((ω h)²) ≈ 1e-6 on the rebound; the duration and peak are read from
// interpolated crossings and sampled steps: bound 1e-4 relative.
template <int D>
void elastic_wall_impact(bool rigid) {
  const double v = 0.2;
  const double e_star = rigid ? kE / (1 - kNu * kNu) : star(kE / (1 - kNu * kNu), kE / (1 - kNu * kNu));
  const double dm = delta_max(kMass, kRadius, e_star, v);
  const double tc = 2 * hertz_integral() * dm / v;
  const double peak = 4.0 / 3.0 * e_star * std::sqrt(kRadius) * std::pow(dm, 1.5);
  const Measured r = wall_impact<D>(v, 0, 1.0, 0.0, rigid, tc / 2000);
  std::printf("D=%d %s wall: t_c %.6e s (closed form %.6e, 2.87 (m*^2/(R* E*^2 v))^(1/5) = %.6e), peak %.6e N "
              "(closed form %.6e), e %.9f\n",
              D, rigid ? "rigid" : "elastic", r.duration, tc,
              2.87 * std::pow(kMass * kMass / (kRadius * e_star * e_star * v), 0.2), r.peak_force, peak, r.rebound);
  EXPECT_NEAR(r.duration / tc, 1.0, 1e-4);
  EXPECT_NEAR(r.peak_force / peak, 1.0, 1e-4);
  EXPECT_NEAR(r.rebound, 1.0, 1e-5);
}
TEST(HertzImpact, ElasticSphereOnRigidWall) { elastic_wall_impact<3>(true); }
TEST(HertzImpact, ElasticSphereOnElasticWall) { elastic_wall_impact<3>(false); }
TEST(HertzImpact, ElasticDiskOnRigidWall) { elastic_wall_impact<2>(true); }

// Sphere–sphere (Chung & Ooi test 2): equal spheres head-on at ±v/2, so
// m* = m/2, R* = R/2, E* = E/(2(1 − ν²)); same closed forms and bounds.
TEST(HertzImpact, ElasticSphereOnSphere) {
  const double v = 0.2;
  const double e_star = kE / (2 * (1 - kNu * kNu)), m_star = kMass / 2, r_star = kRadius / 2;
  const double dm = delta_max(m_star, r_star, e_star, v);
  const double tc = 2 * hertz_integral() * dm / v;
  const double peak = 4.0 / 3.0 * e_star * std::sqrt(r_star) * std::pow(dm, 1.5);
  const double dt = tc / 2000;
  DemDesc<3> d;
  d.law = ContactLaw::hertz;
  d.dt = dt;
  d.integrator = DemIntegrator::verlet;
  ParticleDesc<3> a = sphere<3>(), b = sphere<3>();
  a.position[0] = -kRadius - dt * v - 1e-12;
  b.position[0] = kRadius + dt * v + 1e-12;
  a.velocity[0] = v / 2;
  b.velocity[0] = -v / 2;
  d.particles = {a, b};
  DemWorld<3> world;
  ASSERT_TRUE(world.build(d).ok());
  double on = -1, off = -1, peak_force = 0;
  auto gap = [&] { return world.state.x[0][1] - world.state.x[0][0] - 2 * kRadius; };
  double before = gap();
  for (int k = 0; k < 100000 && off < 0; ++k) {
    ASSERT_EQ(world.step(), StepStatus::ok);
    const double g = gap(), t = world.state.time;
    if (on < 0 && g < 0) on = t - dt * (-g) / (before - g);
    if (on >= 0 && g < 0) peak_force = std::max(peak_force, dem_pair_force(world.model, world.state, 0, 1));
    if (on >= 0 && g >= 0 && before < 0) off = t - dt * g / (g - before);
    before = g;
  }
  const double rebound = (world.state.v[0][1] - world.state.v[0][0]) / v;
  std::printf("sphere-sphere: t_c %.6e s (closed form %.6e), peak %.6e N (closed form %.6e), e %.9f\n", off - on, tc,
              peak_force, peak, rebound);
  EXPECT_NEAR((off - on) / tc, 1.0, 1e-4);
  EXPECT_NEAR(peak_force / peak, 1.0, 1e-4);
  EXPECT_NEAR(rebound, 1.0, 1e-5);
}

// An independent solution of one damped Hertz impact: the test integrates
// m* δ'' = −4/3 E* √R* δ^{3/2} − η(δ) δ',  η = 2√(5/6) |β| √(2 E* √(R* δ) m*)
// with RK4 at 1/200000 of the duration, from δ = 0, δ' = v until δ returns
// to 0, and returns −δ'/v there: the restitution the spec's damping gives.
struct ModelImpact {
  double e;       ///< −δ'/v when δ returns to 0
  double tensile; ///< ∫ max(−F_n, 0) dt / (m* v): the dashpot's pull at the end of the contact
};
ModelImpact model_impact(double e, double m_star, double r_star, double e_star, double v) {
  const double l = std::log(e);
  const double beta = l / std::sqrt(l * l + kPi * kPi);
  auto acc = [&](double x, double u) {
    if (x <= 0) return 0.0;
    const double sn = 2 * e_star * std::sqrt(r_star * x);
    const double eta = -2 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(sn * m_star);
    return -(2.0 / 3.0 * sn * x + eta * u) / m_star;
  };
  const double tc = 2 * hertz_integral() * delta_max(m_star, r_star, e_star, v) / v;
  const double h = tc / 200000;
  double x = 0, u = v, pull = 0;
  for (int k = 0; k < 10000000; ++k) {
    const double k1x = u, k1u = acc(x, u);
    pull += h * std::max(k1u, 0.0) / v;  // a > 0: the net force pulls (rectangle rule, h = t_c/200000)
    const double k2x = u + 0.5 * h * k1u, k2u = acc(x + 0.5 * h * k1x, u + 0.5 * h * k1u);
    const double k3x = u + 0.5 * h * k2u, k3u = acc(x + 0.5 * h * k2x, u + 0.5 * h * k2u);
    const double k4x = u + h * k3u, k4u = acc(x + h * k3x, u + h * k3u);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
    if (k > 10 && xn <= 0) return {-un / v, pull};  // free flight past δ = 0: the speed is constant
    x = xn;
    u = un;
  }
  return {NAN, NAN};
}

// Normal impact with restitution (Chung & Ooi test 3): the spec's damping
// (−2√(5/6) β √(S_n m*), LIGGGHTS's hertz) is the linear spring's exact
// damping transplanted onto the Hertz spring; the restitution it gives is
// exactly e a priori. The test measures it on the stepper and compares it
// with the model's own restitution, computed above by an independent fine RK4
// solution (bound ζ π/2000: the stepper's h is t_c/2000), at two speeds (the
// model's e does not depend on v: the equation is scale-free), and prints
// the input e beside it.
TEST(HertzImpact, RestitutionIsTheModelsAndIndependentOfSpeed) {
  const double e_star = kE / (1 - kNu * kNu);
  for (double e : {0.9, 0.7, 0.5, 0.3}) {
    const ModelImpact mi = model_impact(e, kMass, kRadius, e_star, 0.2);
    const double model = mi.e;
    const double l = std::log(e), zeta = std::sqrt(5.0 / 6.0) * std::fabs(l) / std::sqrt(l * l + kPi * kPi);
    for (double v : {0.2, 2.0}) {
      const double tc = 2 * hertz_integral() * delta_max(kMass, kRadius, e_star, v) / v;
      const Measured r = wall_impact<3>(v, 0, e, 0.0, true, tc / 2000);
      std::printf("input e %.2f: measured %.7f at v = %.1f m/s, independent solution %.9f (%+.1e off the input), "
                  "tensile dashpot impulse %.2e m* v\n",
                  e, r.rebound, v, model, (model - e) / e, mi.tensile);
      // Verlet's dashpot reads the half-step velocity: an O(ζ ω h) error,
      // ω h ≈ π / 2000 at 2000 steps a contact.
      EXPECT_NEAR(r.rebound, model, zeta * kPi / 2000);
    }
  }
}

/// The Mindlin–Coulomb contact of one sphere (disk: D = 2) on a rigid wall in
/// continuous time, solved by the test (RK4 at 1/100000 of the duration):
/// normal m δ'' = −F_n, F_n = 4/3 E* √R* δ^{3/2} + η_n δ'; the tangential
/// spring force F_s with dF_s/dt = −S_t(δ) u', u' = v_t + ω R the contact
/// point's slip velocity, the force F = F_s − η_t u' capped at μ|F_n| (then
/// F_s is reset to give the cap, as the model does); F acts on the centre
/// and, at the arm −R ŷ, on the spin (torque R F ẑ). The dashpots as the
/// spec (−2√(5/6) β √(S m*)). Returns the tangential velocity and spin after.
struct Rebound {
  double vt, spin;
};
template <int D>
Rebound mindlin_coulomb(double vn, double vt, double mu, double restitution, double e_star, double g_star) {
  const double inertia = (D == 2 ? 0.5 : 0.4) * kMass * kRadius * kRadius;
  const double tc = 2 * hertz_integral() * delta_max(kMass, kRadius, e_star, vn) / vn;
  const double h = tc / 100000;
  const double l = std::log(restitution);
  const double damping = -2 * std::sqrt(5.0 / 6.0) * l / std::sqrt(l * l + kPi * kPi);
  struct Y {  // δ, δ', v_t, ω, F_s
    double x, u, v, w, f;
  };
  struct Law {
    double fn, st, eta_t, slip, force;
  };
  auto law = [&](const Y& y) {
    const double x = std::max(y.x, 0.0);
    const double sn = 2 * e_star * std::sqrt(kRadius * x), st = 8 * g_star * std::sqrt(kRadius * x);
    Law c{};
    c.fn = 2.0 / 3.0 * sn * x + damping * std::sqrt(sn * kMass) * y.u;
    c.st = st;
    c.eta_t = damping * std::sqrt(st * kMass);
    c.slip = y.v + y.w * kRadius;
    c.force = y.f - c.eta_t * c.slip;
    const double cap = mu * std::fabs(c.fn);
    if (std::fabs(c.force) > cap) c.force = std::copysign(cap, c.force);
    return c;
  };
  auto rate = [&](const Y& y) {
    const Law c = law(y);
    return Y{y.u, -c.fn / kMass, c.force / kMass, c.force * kRadius / inertia, -c.st * c.slip};
  };
  auto add = [](const Y& a, const Y& b, double s) {
    return Y{a.x + s * b.x, a.u + s * b.u, a.v + s * b.v, a.w + s * b.w, a.f + s * b.f};
  };
  Y y{0, vn, vt, 0, 0};
  for (int k = 0; k < 10000000; ++k) {
    const Y k1 = rate(y), k2 = rate(add(y, k1, h / 2)), k3 = rate(add(y, k2, h / 2)), k4 = rate(add(y, k3, h));
    Y n = add(y,
              Y{k1.x + 2 * k2.x + 2 * k3.x + k4.x, k1.u + 2 * k2.u + 2 * k3.u + k4.u, k1.v + 2 * k2.v + 2 * k3.v + k4.v,
                k1.w + 2 * k2.w + 2 * k3.w + k4.w, k1.f + 2 * k2.f + 2 * k3.f + k4.f},
              h / 6);
    const Law c = law(n);
    if (std::fabs(n.f - c.eta_t * c.slip) > mu * std::fabs(c.fn)) n.f = c.force + c.eta_t * c.slip;
    if (k > 10 && n.x <= 0) return {n.v, n.w};
    y = n;
  }
  return {NAN, NAN};
}

// Oblique impact, gross sliding (Chung & Ooi test 4 / 6 at large angles): the
// contact point slides throughout, the tangential force is μ|F_n| at every
// evaluation. Undamped (e = 1) F_n ≥ 0 throughout and Δv_t = μ (1 + e) v_n,
// ω = 5 μ (1 + e) v_n / (2R) (sphere; 2 μ (1 + e) v_n / R for a disk) hold to
// round-off. Damped, the closed form does not hold for this model: at the
// touch-down the dashpot (∝ δ^{1/4} δ') dominates F_n while Mindlin's spring
// (∝ δ^{1/2}) starts from zero, so the contact sticks below the cap at first,
// and at lift-off the dashpot pulls (F_n < 0) with the cap μ|F_n| still on.
// The stepper is then compared with the continuous Mindlin–Coulomb solution
// (mindlin_coulomb, the same dashpots), bound 2e-3 (the once-per-step spring
// update and cap are first order in h = t_c/2000), and the closed form's
// shortfall is printed.
template <int D>
void gross_sliding(double restitution) {
  const double vn = 0.2, vt = 1.0, mu = 0.3;
  const double e_star = kE / (1 - kNu * kNu);
  const double tc = 2 * hertz_integral() * delta_max(kMass, kRadius, e_star, vn) / vn;
  for (DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::rk4, DemIntegrator::abm4_events}) {
    const Measured r = wall_impact<D>(vn, vt, restitution, mu, true, tc / 2000, integrator);
    const double e = r.rebound;
    const double dvt = vt - r.vt_after;
    const double omega = mu * (1 + e) * vn / ((D == 2 ? 0.5 : 0.4) * kRadius);
    std::printf("D=%d %s e_in %.1f gross sliding: e %.9f, dv_t %.12g (mu (1+e) v_n = %.12g), spin %.12g (%.12g)\n", D,
                integrator_name(integrator), restitution, e, dvt, mu * (1 + e) * vn, r.spin, -omega);
    if (restitution == 1.0) {
      EXPECT_NEAR(dvt, mu * (1 + e) * vn, 1e-12);
      EXPECT_NEAR(r.spin, -omega, 1e-11 * omega);
    } else {
      const Rebound ref = mindlin_coulomb<D>(vn, vt, mu, restitution, e_star, kE / (2 * (2 - kNu) * (1 + kNu)));
      std::printf("  Mindlin-Coulomb solution: dv_t %.9f, spin %.6f: the closed form is short by %.2f %%\n",
                  vt - ref.vt, ref.spin, 100 * (vt - ref.vt - mu * (1 + e) * vn) / (vt - ref.vt));
      EXPECT_NEAR(dvt, vt - ref.vt, 2e-3 * dvt);
      EXPECT_NEAR(r.spin, ref.spin, 2e-3 * omega);
    }
  }
}
TEST(HertzOblique, SphereGrossSliding) {
  gross_sliding<3>(1.0);
  gross_sliding<3>(0.7);
  gross_sliding<3>(0.3);
}
TEST(HertzOblique, DiskGrossSliding) {
  gross_sliding<2>(1.0);
  gross_sliding<2>(0.7);
}

// Oblique impact over incidence angles, e = 1 (Chung & Ooi test 6): the
// stepper's rebound tangential velocity and spin against the continuous
// Mindlin–Coulomb solution above, from the sticking (Mindlin) regime at small
// angles, where the contact point's tangential velocity reverses, through
// partial slip to gross sliding. Bound: 2e-3 of v_t (the stepper's h is
// t_c/4000; the once-per-step spring update and cap are first order in h).
// No impact ends with more kinetic energy than it began with.
TEST(HertzOblique, SweepAgainstMindlinCoulombAndNeverGainsEnergy) {
  const double vn = 0.2, mu = 0.3;
  const double e_star = kE / (1 - kNu * kNu), g_star = kE / (2 * (2 - kNu) * (1 + kNu));
  const double tc = 2 * hertz_integral() * delta_max(kMass, kRadius, e_star, vn) / vn;
  for (double ratio : {0.05, 0.2, 0.5, 1.0, 2.0, 5.0}) {  // v_t / v_n
    const double vt = ratio * vn;
    const Measured r = wall_impact<3>(vn, vt, 1.0, mu, true, tc / 4000);
    const Rebound ref = mindlin_coulomb<3>(vn, vt, mu, 1.0, e_star, g_star);
    const double inertia = 0.4 * kMass * kRadius * kRadius;
    const double before = 0.5 * kMass * (vn * vn + vt * vt);
    const double after =
        0.5 * kMass * (r.rebound * r.rebound * vn * vn + r.vt_after * r.vt_after) + 0.5 * inertia * r.spin * r.spin;
    std::printf("v_t/v_n %.2f: contact point's v_t after/before %+.5f (Mindlin-Coulomb %+.5f), v_t %.6f (%.6f), "
                "spin %.4f (%.4f) rad/s, KE after/before %.8f\n",
                ratio, (r.vt_after + r.spin * kRadius) / vt, (ref.vt + ref.spin * kRadius) / vt, r.vt_after, ref.vt,
                r.spin, ref.spin, after / before);
    EXPECT_NEAR(r.vt_after, ref.vt, 2e-3 * vt);
    EXPECT_NEAR(r.spin * kRadius, ref.spin * kRadius, 2e-3 * vt);
    EXPECT_LE(after, before * (1 + 1e-6));
  }
}

/// A box of 200 hertz disks with friction and rolling resistance poured on
/// a floor between two elastic walls.
DemDesc<2> hertz_box(DemIntegrator integrator) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  DemDesc<2> d;
  d.law = ContactLaw::hertz;
  d.restitution = 0.5;
  d.friction = 0.5;
  d.rolling_friction = 0.05;
  d.gravity = {0, -9.81};
  d.integrator = integrator;
  d.dt = 2e-6;
  d.split_from = 100;
  for (int i = 0; i < 200; ++i) {
    ParticleDesc<2> p;
    p.radius = 0.01 * (1 + 0.2 * u(rng));
    p.mass = 2500 * kPi * p.radius * p.radius * 0.01;
    p.youngs_modulus = 1e8;
    p.poisson_ratio = 0.3;
    p.position = {0.025 * (i % 10) + 0.015, 0.025 * (i / 10) + 0.015};
    p.velocity = {0.2 * (u(rng) - 0.5), 0.2 * (u(rng) - 0.5)};
    d.particles.push_back(p);
  }
  PlaneDesc<2> floor, left, right;
  floor.normal = {0, 1};
  floor.youngs_modulus = 2e8;
  floor.poisson_ratio = 0.25;
  left.normal = {1, 0};
  right.normal = {-1, 0};
  right.point = {0.25, 0};
  d.planes = {floor, left, right};
  return d;
}

class HertzRecords : public ::testing::TestWithParam<DemIntegrator> {};

// Two workers, a snapshot half-way restored into a fresh world, no
// allocation in any step: the same bits; the springs carry force.
TEST_P(HertzRecords, TwoWorkersSnapshotsAndNoAllocation) {
  DemWorld<2> one;
  xfdem::testing::expect_same_bits_on_two_workers_and_after_a_snapshot(hertz_box(GetParam()), one);
  int loaded = 0;
  for (std::int32_t c = 0; c < one.state.pair_count; ++c) loaded += one.state.pair_xi[0][c] != 0.0 ? 1 : 0;
  EXPECT_GT(loaded, 10);
}
INSTANTIATE_TEST_SUITE_P(Integrators, HertzRecords,
                         ::testing::Values(DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                           DemIntegrator::abm4),
                         [](const auto& param_info) { return std::string(integrator_name(param_info.param)); });

// The stable-step rule: dt past the stable step of the stiffest contact at
// the reference overlap (kHertzReferenceOverlap R*) is refused; the step's
// network bound reads the actual overlap and flags a contact pressed deeper
// than dt allows.
TEST(HertzStability, ReferenceOverlapAndNetworkBound) {
  DemDesc<3> d;
  d.law = ContactLaw::hertz;
  d.integrator = DemIntegrator::verlet;
  d.particles = {sphere<3>()};
  d.particles[0].position[1] = kRadius;
  PlaneDesc<3> floor;
  floor.normal[1] = 1;
  d.planes = {floor};
  const double e_star = kE / (1 - kNu * kNu);
  const double omega = std::sqrt(2 * e_star * kRadius * std::sqrt(kHertzReferenceOverlap) / kMass);
  d.dt = 2.0 / omega * 1.001;  // verlet's stable ωh is 2 (undamped)
  DemWorld<3> world;
  BuildResult r = world.build(d);
  EXPECT_EQ(r.code, BuildResult::Code::unstable_time_step) << r.message;
  d.dt = 2.0 / omega * 0.999;
  ASSERT_TRUE(world.build(d).ok());
  EXPECT_NEAR(world.model.max_contact_omega / omega, 1.0, 1e-12);
  // Pressed in to 4 % of R: S_n (and ω²) twice the reference's, ωh = 2√√2 > 2.
  world.state.x[1][0] = kRadius * (1 - 0.04);
  EXPECT_TRUE(has(world.step(), StepStatus::unstable_time_step));
}

// Bad input is refused naming the key.
TEST(HertzInputs, RefusedNamingTheKey) {
  auto refused = [](DemDesc<2> d, const char* key) {
    DemWorld<2> world;
    const BuildResult r = world.build(d);
    EXPECT_FALSE(r.ok()) << key;
    EXPECT_NE(std::string(r.message).find(key), std::string::npos) << r.message;
    std::printf("%s\n", r.message);
  };
  DemDesc<2> good;
  good.law = ContactLaw::hertz;
  good.dt = 1e-7;
  good.particles = {sphere<2>()};
  good.planes.resize(1);
  good.planes[0].normal = {0, 1};
  good.particles[0].position = {0, 1};
  {
    DemWorld<2> world;
    const BuildResult r = world.build(good);
    ASSERT_TRUE(r.ok()) << r.message;
  }
  DemDesc<2> d = good;
  d.particles[0].youngs_modulus = 0;
  refused(d, "particles[0].youngs_modulus: must be finite and > 0");
  d.particles[0].youngs_modulus = -1;
  refused(d, "particles[0].youngs_modulus");
  d.particles[0].youngs_modulus = INFINITY;
  refused(d, "particles[0].youngs_modulus");
  d = good;
  d.particles[0].youngs_modulus = NAN;
  refused(d, "particles[0].youngs_modulus: missing");
  d = good;
  d.particles[0].poisson_ratio = NAN;
  refused(d, "particles[0].poisson_ratio: missing");
  d.particles[0].youngs_modulus = NAN;
  refused(d, "both missing");
  for (double nu : {0.5, -1.0, 0.7, -2.0}) {
    d = good;
    d.particles[0].poisson_ratio = nu;
    refused(d, "particles[0].poisson_ratio: must be in (-1, 0.5)");
  }
  for (double e : {0.0, -0.5, 1.5, static_cast<double>(NAN)}) {
    d = good;
    d.restitution = e;
    refused(d, "restitution: must be in (0, 1]");
  }
  d = good;
  d.planes[0].youngs_modulus = 1e9;
  refused(d, "planes[0].poisson_ratio: missing");
  d.planes[0].poisson_ratio = 0.5;
  refused(d, "planes[0].poisson_ratio: must be in (-1, 0.5)");
  d.planes[0].poisson_ratio = 0.3;
  d.planes[0].youngs_modulus = -1;
  refused(d, "planes[0].youngs_modulus");
  d = good;
  d.particles[0].stiffness = 1e5;
  refused(d, "particles[0].stiffness");
  d = good;
  d.damping_ratio = 0.1;
  refused(d, "damping_ratio");
  d = good;
  d.tangential_stiffness_ratio = 0.5;
  refused(d, "tangential_stiffness_ratio");
  // The linear laws take none of the hertz keys.
  DemDesc<2> linear = good;
  linear.law = ContactLaw::linear;
  linear.particles[0].stiffness = 1e5;
  refused(linear, "particles[0].youngs_modulus: only the hertz law");
  linear.particles[0].youngs_modulus = NAN;
  linear.particles[0].poisson_ratio = NAN;
  linear.restitution = 0.5;
  refused(linear, "restitution: only the hertz law");
}

}  // namespace
}  // namespace xfdem::testing
