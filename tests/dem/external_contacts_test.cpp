// The external contact hook (DemDesc::external_contacts): a host function
// the force stage calls at every evaluation, whose totals the step weighs as
// it weighs the planes' forces. A hook that is a plane gives the plane's
// bits, trajectory and impulse, with every integrator that takes it; misuse
// is refused naming the key.
#include <gtest/gtest.h>

#include <cstring>

#include "xfdem/dem.hpp"

namespace xfdem {
namespace {

/// Two disks falling onto the floor y = 0 (far apart: no pair contact),
/// damped; a plane or none.
DemDesc<2> falling_disks(DemIntegrator integrator, bool plane) {
  DemDesc<2> d;
  d.gravity = {0.0, -9.81};
  d.damping_ratio = 0.1;
  d.integrator = integrator;
  d.dt = 1e-4;
  ParticleDesc<2> a, b;
  a.mass = 1.0, a.radius = 0.1, a.stiffness = 1e5, a.position = {0.0, 0.15}, a.velocity = {0.3, -1.0};
  b.mass = 0.5, b.radius = 0.05, b.stiffness = 2e5, b.position = {1.0, 0.08}, b.velocity = {-0.2, 0.0};
  d.particles = {a, b};
  if (plane) d.planes = {{{0.0, 0.0}, {0.0, 1.0}}};
  d.energy_check = kEnergyCheckOff;
  return d;
}

/// The floor as the kernel evaluates a resting plane (dem/forces.hpp,
/// plane_forces, the linear law), written as a host would.
std::uint64_t floor_hook(void* context, double, ConstColumns<2> x, ConstColumns<2> v, Columns<2> a, double* totals) {
  const DemModel<2>& m = *static_cast<const DemModel<2>*>(context);
  const double normal[2] = {0.0, 1.0};
  double total = 0;
  for (std::int32_t i = 0; i < m.n; ++i) {
    double gap = 0;
    for (int d = 0; d < 2; ++d) gap += (x[d][i] - 0.0) * normal[d];
    const double overlap = m.radius[i] - gap;
    if (!(overlap > 0)) continue;
    double rate = 0.0;
    for (int d = 0; d < 2; ++d) rate -= v[d][i] * normal[d];
    const double force = m.stiffness[i] * overlap + m.plane_eta[i] * rate;
    total += force;
    const double scaled = force * m.inv_mass[i];
    for (int d = 0; d < 2; ++d) a[d][i] += scaled * normal[d];
  }
  totals[0] = total;
  return 0;
}

TEST(ExternalContacts, AHookThatIsAPlaneGivesThePlanesBitsAndImpulse) {
  for (const DemIntegrator integrator :
       {DemIntegrator::abm4, DemIntegrator::rk4, DemIntegrator::verlet, DemIntegrator::symplectic_euler}) {
    SCOPED_TRACE(integrator_name(integrator));
    DemWorld<2> plane, hook;
    ASSERT_TRUE(plane.build(falling_disks(integrator, true)).ok());
    DemDesc<2> d = falling_disks(integrator, false);
    d.external_contacts = true;
    d.external_contact_totals = 1;
    ASSERT_TRUE(hook.build(d).ok());
    EXPECT_EQ(hook.model.small_step, nullptr);  // the general step calls the hook
    hook.workspace.external_contacts = &floor_hook;
    hook.workspace.external_context = &hook.model;
    for (int step = 0; step < 3000; ++step) {
      ASSERT_EQ(plane.step(), StepStatus::ok);
      ASSERT_EQ(hook.step(), StepStatus::ok);
    }
    for (int axis = 0; axis < 2; ++axis) {
      EXPECT_EQ(plane.state.x[axis], hook.state.x[axis]);
      EXPECT_EQ(plane.state.v[axis], hook.state.v[axis]);
    }
    EXPECT_GT(plane.state.plane_impulse[0], 1.0);  // the floor carried the disks
    EXPECT_EQ(plane.state.plane_impulse[0], hook.state.plane_impulse[0]);
  }
}

TEST(ExternalContacts, MisuseIsRefusedNamingTheKey) {
  auto refused = [](const DemDesc<2>& d, const char* key) {
    DemWorld<2> w;
    const BuildResult r = w.build(d);
    EXPECT_FALSE(r.ok()) << key;
    EXPECT_NE(std::strstr(r.message, key), nullptr) << r.message;
  };
  DemDesc<2> d = falling_disks(DemIntegrator::rk4, false);
  d.external_contact_totals = 3;  // without external_contacts
  refused(d, "external_contact_totals");
  d.external_contacts = true;
  d.external_contact_totals = -1;
  refused(d, "external_contact_totals");
  d.external_contact_totals = 3;
  d.integrator = DemIntegrator::abm4_events;
  refused(d, "integrator");
  d.integrator = DemIntegrator::rk4;
  d.friction = 0.5;  // rotating models call DemWorkspace::external_rotating_contacts
  {
    DemWorld<2> w;
    EXPECT_TRUE(w.build(d).ok());
  }
  d.friction = 0;
  d.energy_check = EnergyCheck{};
  refused(d, "energy_check");
}

}  // namespace
}  // namespace xfdem
