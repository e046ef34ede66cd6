// Observed order of each integrator that carries rotation (verlet,
// symplectic_euler, rk4, abm4), against closed forms the tests compute:
//  - sliding throughout: the friction force is μ F_n(t), a smooth function of
//    the state, and every integrator keeps its order (2, 1, 4, 4);
//  - sticking throughout: the tangential spring ξ is advanced once per step,
//    ξ_n+1 = ξ_n + h v_t. With Verlet's kicked (midpoint) velocity and
//    symplectic Euler's new one this is the same update as the position's, so
//    they keep 2 and 1; rk4 and abm4 advance the positions to fourth order but
//    the spring to first: they are first order in a sticking contact.
// The incline tests (friction_test.cpp) are exact for all four: a constant
// acceleration tells no order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/dem_scenes.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {
namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr DemIntegrator kRotating[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                       DemIntegrator::abm4, DemIntegrator::abm4_events};

// A disk (2D) or sphere (3D), m = 1, r = 0.05, k = 1e6, undamped, on a floor
// (normal +y, the incline of friction_test.cpp at θ = 0), pressed in by its
// static overlap δs = m g/k plus `lift`, moving at vx.
template <int D>
DemDesc<D> on_floor(DemIntegrator integrator, double dt, double mu, double lift, double vx) {
  DemDesc<D> d = incline<D>(0.0, mu, 0.0, 0.0, integrator);
  d.dt = dt;
  d.particles[0].position[1] -= lift;
  d.particles[0].velocity[0] = vx;
  return d;
}

struct Exact {
  double x, vx, y, w;
};

/// Largest error of (x, v_x, y, ω) at t = steps · dt, each relative to its scale.
/// `spring`: the floor contact's tangential spring ξ_x at the start.
template <int D>
double run_error(const DemDesc<D>& d, std::int64_t steps, Exact exact, Exact scale, double spring = 0) {
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  world.state.plane_xi[0][0] = spring;
  dem_inputs_changed(world.state);  // the start's accelerations, read again with the spring
  for (std::int64_t k = 0; k < steps; ++k) {
    const StepStatus status = world.step();
    if (status != StepStatus::ok) {
      ADD_FAILURE() << "step " << k << ": " << static_cast<unsigned>(status);
      return NAN;
    }
  }
  const DemState<D>& s = world.state;
  return std::max({std::fabs(s.x[0][0] - exact.x) / scale.x, std::fabs(s.v[0][0] - exact.vx) / scale.vx,
                   std::fabs(s.x[1][0] - exact.y) / scale.y, std::fabs(spin_z(s) - exact.w) / scale.w});
}

// Sliding: the disk starts at v0 = 1 m/s without spin, its normal overlap
// oscillating about δs with amplitude A = δs/2 (the contact never opens, and
// F_n = m g + k A cos(ω_n t)). While v_t = v_x + r ω > 0 the friction is
// −μ F_n along x, so with J(t) = g t + A ω_n sin(ω_n t) = ∫F_n/m:
//   v_x = v0 − μ J, x = v0 t − μ (g t²/2 + A (1 − cos ω_n t)),
//   ω = −μ (m r/I) J, y = r − δs − A cos ω_n t.
// Up to T = 0.02 s, v_t ≥ v0 − μ J (1 + m r²/I) > 0.7 m/s: sliding throughout
// (the spring's trial force exceeds the cap by k_t h v_t per step, far more
// than F_n changes in a step). The spring starts at the cap, ξ_x = μ F_n(0)/k_t:
// from ξ = 0 the first evaluation would see no friction, an O(h) start-up.
template <int D>
void sliding_order(DemIntegrator integrator) {
  const double mu = 0.3, v0 = 1.0, m = 1, r = 0.05, k = 1e6, T = 0.02;
  const double wn = std::sqrt(k / m), ds = m * kG / k, A = 0.5 * ds;
  const double J = kG * T + A * wn * std::sin(wn * T);
  const double ratio = 1 / inertia_factor<D>();  // m r²/I
  ASSERT_GT(v0 - mu * J * (1 + ratio), 0.7);
  const Exact exact{v0 * T - mu * (0.5 * kG * T * T + A * (1 - std::cos(wn * T))), v0 - mu * J,
                    r - ds - A * std::cos(wn * T), -mu * ratio / r * J};
  // Scales: the parts that vary non-polynomially (a polynomial motion would be exact).
  const Exact scale{mu * A, mu * A * wn, A, mu * ratio / r * A * wn};
  std::vector<double> dts, errors;
  for (double wh : {0.1, 0.05, 0.025}) {
    const double dt = wh / wn;
    const auto steps = static_cast<std::int64_t>(std::llround(T / dt));
    dts.push_back(dt);
    const double cap = mu * (m * kG + k * A) / (kDefaultTangentialStiffnessRatio * k);
    errors.push_back(run_error<D>(on_floor<D>(integrator, dt, mu, A, v0), steps, exact, scale, cap));
  }
  const double p = observed_order(dts, errors);
  std::printf("D=%d sliding %-16s errors %.3e %.3e %.3e  order %.2f\n", D, integrator_name(integrator), errors[0],
              errors[1], errors[2], p);
  const double formal = integrator == DemIntegrator::verlet             ? 2
                        : integrator == DemIntegrator::symplectic_euler ? 1
                                                                        : 4;
  EXPECT_NEAR(p, formal, 0.25);
}

// Sticking: the disk rests at its static overlap and starts sliding at
// v_s0 = 3e-3 m/s; the contact sticks (k_t |ξ| ≤ k_t v_s0/ω_t < μ m g) and
// the slip s = x + r θ oscillates on the tangential spring, s'' = −ω_t² ξ
// with ω_t² = k_t (1/m + r²/I), ξ = (v_s0/ω_t) sin(ω_t t). Then
//   v_x = v0 − (k_t/m) (v_s0/ω_t²)(1 − cos ω_t t), x = ∫v_x,
//   ω = −(r k_t/I)(v_s0/ω_t²)(1 − cos ω_t t).
template <int D>
void sticking_order(DemIntegrator integrator) {
  const double mu = 0.3, v0 = 3e-3, m = 1, r = 0.05, k = 1e6, T = 0.02;
  const double kt = kDefaultTangentialStiffnessRatio * k, I = inertia_factor<D>() * m * r * r;
  const double wt = std::sqrt(kt * (1 / m + r * r / I));
  ASSERT_LT(kt * v0 / wt, 0.5 * mu * m * kG);
  const double c = v0 / (wt * wt);
  // y has no motion: scale it by the slip amplitude, which it must not pick up.
  const Exact scale{kt / m * c / wt, kt / m * c, v0 / wt, r * kt / I * c};
  std::vector<double> dts, errors;
  for (double wh : {0.05, 0.025, 0.0125}) {
    const double dt = wh / wt;
    const auto steps = static_cast<std::int64_t>(std::llround(T / dt));
    const double t_end = static_cast<double>(steps) * dt;
    const double ph = wt * t_end;
    const Exact at{v0 * t_end - kt / m * c * (t_end - std::sin(ph) / wt), v0 - kt / m * c * (1 - std::cos(ph)),
                   r - m * kG / k, -r * kt / I * c * (1 - std::cos(ph))};
    dts.push_back(dt);
    errors.push_back(run_error<D>(on_floor<D>(integrator, dt, mu, 0, v0), steps, at, scale));
  }
  const double p = observed_order(dts, errors);
  std::printf("D=%d sticking %-16s errors %.3e %.3e %.3e  order %.2f\n", D, integrator_name(integrator), errors[0],
              errors[1], errors[2], p);
  const double expected = integrator == DemIntegrator::verlet ? 2 : 1;
  EXPECT_NEAR(p, expected, 0.25);
}

// Oblique impacts on the floor (no gravity, undamped linear law, m = 1,
// r = 0.05, k = 1e6: ω_n = 1e3 rad/s, contact time π/ω_n), run to T = 6 ms,
// past the lift-off: two contact events, which abm4_events locates.
template <int D>
DemDesc<D> impact(DemIntegrator integrator, double dt, double mu, double vt, double vn) {
  DemDesc<D> d;
  d.dt = dt;
  d.friction = mu;
  d.integrator = integrator;
  ParticleDesc<D> p;
  p.mass = 1;
  p.radius = 0.05;
  p.stiffness = 1e6;
  p.position[1] = p.radius + 1e-3 * vn;  // touches down at t = 1 ms
  p.velocity[0] = vt;
  p.velocity[1] = -vn;
  d.particles.push_back(p);
  PlaneDesc<D> floor;
  floor.normal[1] = 1;
  d.planes.push_back(floor);
  return d;
}

/// (x, v_x, y, v_y, ω) of the disk or sphere at T = steps · dt.
template <int D>
std::array<double, 5> impact_end(const DemDesc<D>& d, std::int64_t steps) {
  DemWorld<D> world;
  const BuildResult built = world.build(d);
  EXPECT_TRUE(built.ok()) << built.message;
  for (std::int64_t k = 0; k < steps; ++k) EXPECT_EQ(world.step(), StepStatus::ok);
  const DemState<D>& s = world.state;
  return {s.x[0][0], s.v[0][0], s.x[1][0], s.v[1][0], spin_z(s)};
}

// Gross sliding (v_t = 5 v_n, μ = 0.3): the friction is −μ F_n at every
// evaluation, a smooth function of the state inside the contact, so the
// motion has a closed form, with τ = π/ω_n the contact time and
// t_off = t_on + τ:
//   v_x = v_t − μ v_n (1 − cos ω_n (t − t_on)) inside, v_t − 2 μ v_n after,
//   x(T) = v_t T − μ v_n τ − 2 μ v_n (T − t_off), y(T) = r + v_n (T − t_off),
//   v_y = v_n, ω = −2 μ v_n m r / I after.
// abm4_events lands a step on both events and keeps its fourth order; abm4,
// which steps across the force's kinks, is printed beside it.
template <int D>
void gross_sliding_impact_order(DemIntegrator integrator) {
  const double mu = 0.3, vn = 1.0, vt = 5.0, r = 0.05, wn = 1e3, T = 6e-3;
  const double tau = kPi / wn, t_on = 1e-3, t_off = t_on + tau;
  const double ratio = 1 / inertia_factor<D>();  // m r²/I
  const std::array<double, 5> exact{vt * T - mu * vn * tau - 2 * mu * vn * (T - t_off), vt - 2 * mu * vn,
                                    r + vn * (T - t_off), vn, -2 * mu * vn * ratio / r};
  const std::array<double, 5> scale{mu * vn / wn, mu * vn, vn / wn, vn, mu * vn * ratio / r};
  std::vector<double> dts, errors;
  for (double wh : {0.1, 0.05, 0.025}) {
    const double dt = wh / wn;
    const auto steps = static_cast<std::int64_t>(std::llround(T / dt));
    const std::array<double, 5> got = impact_end<D>(impact<D>(integrator, dt, mu, vt, vn), steps);
    double e = 0;
    for (int k = 0; k < 5; ++k) e = std::max(e, std::fabs(got[k] - exact[k]) / scale[k]);
    dts.push_back(dt);
    errors.push_back(e);
  }
  const double p = observed_order(dts, errors);
  std::printf("D=%d gross-sliding impact %-12s errors %.3e %.3e %.3e  order %.2f\n", D, integrator_name(integrator),
              errors[0], errors[1], errors[2], p);
  if (integrator == DemIntegrator::abm4_events) {
    EXPECT_NEAR(p, 4.0, 0.3);
  }
}

// Stick and slip (v_t = 0.2 v_n, μ = 0.3): the contact point slides, sticks
// on the tangential spring, and slips again as the normal force falls. The
// spring is advanced once per step (first order while sticking) and the
// switches between the two are no events, so abm4_events is first order
// here. No closed form: the reference is rk4 at a step 64 times finer than
// the finest measured (its own error, first order too, is 1/64 of it).
template <int D>
void stick_slip_impact_order(DemIntegrator integrator) {
  const double mu = 0.3, vn = 1.0, vt = 0.2, wn = 1e3, T = 6e-3;
  const double fine = 0.025 / wn / 64;
  const std::array<double, 5> ref =
      impact_end<D>(impact<D>(DemIntegrator::rk4, fine, mu, vt, vn), std::llround(T / fine));
  const double ratio = 1 / inertia_factor<D>();
  const std::array<double, 5> scale{mu * vn / wn, mu * vn, vn / wn, vn, mu * vn * ratio / 0.05};
  std::vector<double> dts, errors;
  for (double wh : {0.1, 0.05, 0.025}) {
    const double dt = wh / wn;
    const std::array<double, 5> got = impact_end<D>(impact<D>(integrator, dt, mu, vt, vn), std::llround(T / dt));
    double e = 0;
    for (int k = 0; k < 5; ++k) e = std::max(e, std::fabs(got[k] - ref[k]) / scale[k]);
    dts.push_back(dt);
    errors.push_back(e);
  }
  const double p = observed_order(dts, errors);
  std::printf("D=%d stick-slip impact %-12s errors %.3e %.3e %.3e  order %.2f\n", D, integrator_name(integrator),
              errors[0], errors[1], errors[2], p);
  if (integrator == DemIntegrator::abm4_events) {
    EXPECT_NEAR(p, 1.0, 0.25);
  }
}

TEST(RotationConvergence, Abm4EventsKeepsFourthOrderThroughAGrossSlidingImpact) {
  for (DemIntegrator integrator : {DemIntegrator::abm4, DemIntegrator::abm4_events}) {
    gross_sliding_impact_order<2>(integrator);
    gross_sliding_impact_order<3>(integrator);
  }
}

TEST(RotationConvergence, Abm4EventsIsFirstOrderThroughAStickSlipImpact) {
  for (DemIntegrator integrator : {DemIntegrator::abm4, DemIntegrator::abm4_events}) {
    stick_slip_impact_order<2>(integrator);
    stick_slip_impact_order<3>(integrator);
  }
}

TEST(RotationConvergence, SlidingKeepsEachIntegratorsOrder) {
  for (DemIntegrator integrator : kRotating) {
    sliding_order<2>(integrator);
    sliding_order<3>(integrator);
  }
}

TEST(RotationConvergence, StickingSpringIsFirstOrderButForVerlet) {
  for (DemIntegrator integrator : kRotating) {
    sticking_order<2>(integrator);
    sticking_order<3>(integrator);
  }
}

}  // namespace
}  // namespace xfdem::testing
