// The staggered X-FE-DEM step; see coupled.hpp and docs/coupling.md.
#include "xfdem/coupled.hpp"

#include <cmath>

namespace xfdem {

BuildResult build_coupled(const CoupledDesc& desc, CoupledModel& m, CoupledState& s, CoupledWorkspace& w) {
  m = CoupledModel{};
  s = CoupledState{};
  if (desc.dem_substeps < 1 || desc.dem_substeps > 1'000'000)
    return BuildResult::failure(BuildResult::Code::invalid_argument, "dem_substeps: must be in [1, 1e6] (got %d)",
                                desc.dem_substeps);
  BuildResult r = build_bar(desc.bar, m.bar, s.bar, w.bar);
  if (!r.ok()) return BuildResult::failure(r.code, "bar.%s", r.message);

  // The bar's top is a plane at x = L, normal up, that coupled_step drives.
  DemDesc<1> dem = desc.dem;
  dem.dt = desc.bar.dt / desc.dem_substeps;
  dem.planes.push_back({{desc.bar.length}, {1.0}});
  r = build_dem(dem, m.dem, s.dem, w.dem);
  if (!r.ok()) return BuildResult::failure(r.code, "dem.%s", r.message);

  m.substeps = desc.dem_substeps;
  m.dt = desc.bar.dt;
  m.top_plane = static_cast<std::int32_t>(dem.planes.size() - 1);
  m.top_position = desc.bar.length;
  // Stability of the exchange: the stiffest contact between a particle and the
  // top node, as a two-mass oscillator, against the continuum step.
  double worst = 0;
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    m.max_contact_stiffness = std::max(m.max_contact_stiffness, m.dem.stiffness[i]);
    worst = std::max(worst, m.dem.stiffness[i] * (1.0 / m.bar.tip_mass + m.dem.inv_mass[i]));
  }
  m.coupling_omega_dt = std::sqrt(worst) * m.dt;
  if (desc.reject_unstable_coupling && m.coupling_omega_dt > kCoupledStableOmegaDt)
    return BuildResult::failure(
        BuildResult::Code::unstable_time_step,
        "time.dt: %g s puts the particle-bar contact outside the staggered scheme's stable region "
        "(omega_c*dt = %.3g > %.3g, omega_c^2 = k (1/m_top + 1/m_particle), m_top = %g kg); reduce dt or the "
        "particles' stiffness",
        m.dt, m.coupling_omega_dt, kCoupledStableOmegaDt, m.bar.tip_mass);
  return BuildResult::success();
}

StepStatus coupled_step(const CoupledModel& m, CoupledState& s, CoupledWorkspace& w) {
  if (!m.bar.built || m.dem.accelerations == nullptr) return StepStatus::not_built;
  // 1. The bar, under last window's average force, held constant over the step.
  const double u_start = bar_tip_displacement(m.bar, s.bar);
  const BarInput input{s.coupling_force};
  StepStatus status = bar_initial_acceleration(m.bar, s.bar, w.bar, input);
  if (has(status, kStepNotTaken)) return status;
  status |= bar_step(m.bar, s.bar, w.bar, input);
  if (has(status, kStepNotTaken)) return status;
  s.impulse_to_bar += s.coupling_force * m.dt;
  const double u_end = bar_tip_displacement(m.bar, s.bar);

  // 2. The particles, seeing the top move linearly from u_start to u_end.
  dem_drive_plane(m.dem, s.dem, m.top_plane, u_start, (u_end - u_start) / m.dt);
  s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)] = 0.0;
  for (int k = 0; k < m.substeps; ++k) {
    status |= dem_step(m.dem, s.dem, w.dem);
    if (has(status, kStepNotTaken)) return status;  // the bar has stepped: report, the caller decides
  }

  // 3. Their impulse from the top becomes the next step's force on the bar.
  const double J = s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)];
  s.impulse_to_particles += J;
  s.pending_impulse = J;
  s.coupling_force = -J / m.dt;
  ++s.step;
  s.time = static_cast<double>(s.step) * m.dt;
  if (J != 0.0 && m.coupling_omega_dt > kCoupledStableOmegaDt) status |= StepStatus::coupling_unstable;
  return status;
}

double coupled_top_force(const CoupledModel& m, const CoupledState& s, std::int32_t particle) {
  return dem_plane_force(m.dem, s.dem, particle, m.top_plane);
}

CoupledEnergy coupled_energy(const CoupledModel& m, const CoupledState& s) {
  const DemEnergy d = dem_energy(m.dem, s.dem);  // includes ½Kδ² against the top plane
  const BarEnergy b = bar_energy(m.bar, s.bar);
  return {d.kinetic + b.kinetic, d.elastic + b.elastic, d.potential};
}

}  // namespace xfdem
