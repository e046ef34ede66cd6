// The stable step of a contact's tangential spring (docs/dem.md, "Stable
// step"). With the particle free to turn, the spring is a mode of its own:
// ω_t² = k_t (1/m + r²/I) and, its dashpot being η_t = 2ζ√(k_t m) on the
// translational mass, a damping ratio ζ√(1 + m r²/I) (√3 ζ for a disk); RK4
// and ABM4 advance the spring to first order, a scheme of its own. The build
// once checked dt against the normal mode's factor only: a disk thrown along
// a floor with ζ = 0.9 at 0.44 of that step never stopped slipping (the
// sticking contact rang between ±μF_n, exit 0, no warning).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/dem_scenes.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {
namespace {

constexpr DemIntegrator kRotating[] = {DemIntegrator::verlet, DemIntegrator::symplectic_euler, DemIntegrator::rk4,
                                       DemIntegrator::abm4, DemIntegrator::abm4_events};

// A disk (2D) or sphere (3D), m = 1, r = 0.05, k = 1e6, at its static
// overlap on a floor, thrown at v0 = 2 m/s without spin, μ = 0.5. It slides
// at −μ g until v_x = −ω r, then rolls at v0 / (1 + I/(m r²)) (2/3 v0 for a
// disk, 5/7 for a sphere) — the closed form, computed here.
template <int D>
void thrown_disk_stops_slipping(double zeta, double fraction) {
  constexpr double kV0 = 2.0, kMu = 0.5, kG = 9.81;
  for (const DemIntegrator integrator : kRotating) {
    DemDesc<D> d = incline<D>(0.0, kMu, 0.0, zeta, integrator);
    d.particles[0].velocity[0] = kV0;
    d.dt = 1.0;  // past every limit: the refusal states the stable step
    DemWorld<D> probe;
    const BuildResult refused = probe.build(d);
    ASSERT_FALSE(refused.ok());
    // The stable step the build states, read back from a build at a step below it.
    d.dt = 1e-6;
    ASSERT_TRUE(probe.build(d).ok());
    const double stable = probe.model.stable_dt;
    const double m = 1.0, r = 0.05, inertia = (D == 2 ? 0.5 : 0.4) * m * r * r;
    const double rolling = kV0 / (1.0 + inertia / (m * r * r));
    const double slip_time = kV0 / (kMu * kG * (1.0 + m * r * r / inertia));
    d.dt = fraction * stable;
    DemWorld<D> w;
    const BuildResult built = w.build(d);
    ASSERT_TRUE(built.ok()) << built.message;
    // Slipping ends at slip_time; then the sticking spring rings down at its
    // damping ratio ζ√g ≥ 0.5 (here): 0.3 s is hundreds of its periods.
    const auto steps = static_cast<std::int64_t>((slip_time + 0.3) / d.dt);
    for (std::int64_t k = 0; k < steps; ++k) ASSERT_EQ(w.step(), StepStatus::ok) << "step " << k;
    const double v = w.state.v[0][0], w_z = spin_z(w.state);
    const double slip = v + w_z * r;  // the contact point's velocity (ω about +z)
    EXPECT_NEAR(v, rolling, 1e-4 * kV0) << integrator_name(integrator) << " zeta " << zeta;
    EXPECT_LE(std::fabs(slip), 1e-6 * kV0) << integrator_name(integrator) << " zeta " << zeta;
    std::printf("%dD %-16s zeta %.2f at %.2f of the stable step %.4g s: v %.8f (rolling %.8f), slip %.2e m/s\n", D,
                integrator_name(integrator), zeta, fraction, stable, v, rolling, slip);
  }
}

TEST(TangentialStability, AThrownDiskRollsAtTwoThirdsWithHeavyDamping) {
  for (const double zeta : {0.5, 0.9, 0.99})
    for (const double fraction : {0.5, 0.95}) thrown_disk_stops_slipping<2>(zeta, fraction);
}

TEST(TangentialStability, AThrownSphereRollsAtFiveSeventhsWithHeavyDamping) {
  for (const double zeta : {0.5, 0.9}) thrown_disk_stops_slipping<3>(zeta, 0.95);
}

// The scene that showed it: ζ = 0.9, rk4, dt = 1.25e-3 s (0.44 of the normal
// mode's stable step, 2.86e-3 s) is refused now, naming time.dt's mode.
TEST(TangentialStability, TheStepPastTheTangentialLimitIsRefusedNamingTheMode) {
  DemDesc<2> d = incline<2>(0.0, 0.5, 0.0, 0.9, DemIntegrator::rk4);
  d.tangential_stiffness_ratio = 2.0 / 7.0;
  d.dt = 1.25e-3;
  DemWorld<2> w;
  const BuildResult r = w.build(d);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.code, BuildResult::Code::unstable_time_step);
  EXPECT_NE(std::string(r.message).find("tangential spring with the particle turning"), std::string::npos)
      << r.message;
  // Without friction the same step is the normal mode's and builds.
  d.friction = 0.0;
  EXPECT_TRUE(w.build(d).ok());
}

// The tangential mode's amplification: Verlet and symplectic Euler advance
// the spring as their own drift, so the mode is their oscillator; an
// overdamped mode (ζ ≥ 1) is stable below its limit and refused above it for
// every integrator (the RK4/ABM4 radius used the real eigenvalues' pair).
TEST(TangentialStability, AmplificationOfTheSpringMode) {
  for (const DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::symplectic_euler})
    for (const double y : {0.1, 0.5, 1.0, 1.5})
      EXPECT_EQ(dem_tangential_amplification(integrator, 0.3, y), dem_amplification(integrator, 0.3, y));
  for (const DemIntegrator integrator : kRotating)
    for (const double zeta : {1.0, 1.56, 3.0}) {
      const double f = dem_tangential_stable_step_factor(integrator, zeta);
      EXPECT_GT(f, 0.0);
      EXPECT_LE(dem_tangential_amplification(integrator, zeta, 0.99 * f), 1.0 + 1e-2)
          << integrator_name(integrator) << " zeta " << zeta;
      EXPECT_GT(dem_tangential_amplification(integrator, zeta, 1.2 * f), 1.0)
          << integrator_name(integrator) << " zeta " << zeta;
      std::printf("%-16s tangential mode, zeta %.2f: stable omega*dt %.4f (normal mode at that zeta %.4f)\n",
                  integrator_name(integrator), zeta, f, dem_stable_step_factor(integrator, zeta));
    }
}

}  // namespace
}  // namespace xfdem::testing
