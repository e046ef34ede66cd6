// The coupled X-FE-DEM stepper (paper, section IV) for the 1D scenes: particles
// (DEM, type a contacts between them) falling on an X-FEM/FEM bar (type b
// contact at its interface) and touching its top end (type c contact).
//
// One coupled step advances the bar by dt and the particles by `dem_substeps`
// substeps of dt/n (the paper's step delay, n = 10):
//   1. the bar steps from t_n to t_{n+1} under the average force f̄ the
//      particles exerted on its top during the previous window, held constant
//      over the step (its acceleration at t_n is re-evaluated with f̄, so the
//      impulse the bar receives is exactly dt·f̄);
//   2. the particles take n substeps seeing the bar's top as a plane that moves
//      linearly from its position at t_n to its position at t_{n+1} (speed
//      (u_{n+1} − u_n)/dt, which the dashpot sees too);
//   3. the impulse J the particles received from the top over the window, as
//      their integrator integrated it, becomes the next window's f̄ = −J/dt.
// So the impulse given to the particles equals minus the impulse received by
// the bar, window by window, one step later: CoupledState::pending_impulse
// holds the one not yet delivered. docs/coupling.md gives the details and the
// stability region that coupled_step() checks.
#pragma once
#include <cstdint>

#include "xfdem/bar.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/status.hpp"

namespace xfdem {

struct CoupledDesc {
  /// Particles (1D): their dt is ignored and set to bar.dt / dem_substeps.
  /// Planes may be given too (fixed walls); the bar's top is added after them.
  DemDesc<1> dem;
  BarDesc bar;
  int dem_substeps = 10;
  /// Refuse to build when the stiffest particle–top contact is outside the
  /// staggered scheme's stable region (see coupled_stability_margin).
  bool reject_unstable_coupling = true;
};

struct CoupledModel {
  DemModel<1> dem;
  BarModel bar;
  int substeps = 1;
  double dt = 0;                  ///< continuum step, s
  std::int32_t top_plane = -1;    ///< index of the plane that stands for the bar's top
  double top_position = 0;        ///< x of the undeformed top (the bar's length), m
  double max_contact_stiffness = 0;  ///< max over particles of k_i (the type c contact is K = k_i), N/m
  /// ω_c dt of the stiffest particle–top contact, ω_c² = k (1/m_tip + 1/m_p)
  /// with m_tip the top node's lumped mass; must stay below kCoupledStableOmegaDt.
  double coupling_omega_dt = 0;
};

/// Largest ω_c·dt for which the staggered scheme is stable (measured by
/// tests/coupling/stability_map_test.cpp; docs/coupling.md shows the map).
inline constexpr double kCoupledStableOmegaDt = 1.0;

struct CoupledState {
  DemState<1> dem;
  BarState bar;
  double coupling_force = 0;   ///< f̄ applied to the bar's top during the current step, N (up)
  double pending_impulse = 0;  ///< J of the last window, not yet delivered to the bar, N·s (up on particles)
  /// Totals since the start, for the momentum check: Σ J over the windows the
  /// particles lived, and Σ f̄ dt delivered to the bar.
  double impulse_to_particles = 0, impulse_to_bar = 0;
  std::int64_t step = 0;
  double time = 0;
};

struct CoupledWorkspace {
  DemWorkspace<1> dem;
  BarWorkspace bar;
};

/// Builds both halves; the only allocating call. Messages name the field
/// ("dem.particles[0].mass: ...", "bar.interface.position: ...").
BuildResult build_coupled(const CoupledDesc& desc, CoupledModel& model, CoupledState& state,
                          CoupledWorkspace& workspace);

/// One continuum step and its particle substeps. Never allocates. Flags:
/// whatever the halves return, plus coupling_unstable when a particle touches
/// the top with ω_c dt above the stable bound (the step is still taken).
StepStatus coupled_step(const CoupledModel& model, CoupledState& state, CoupledWorkspace& workspace);

/// Force of particle i on the bar's top, compressive positive (N).
double coupled_top_force(const CoupledModel& model, const CoupledState& state, std::int32_t particle);

struct CoupledEnergy {
  double kinetic = 0, elastic = 0, potential = 0;
};
/// Kinetic (bar ½vᵀMv + particles), elastic (bar incl. interface spring, and
/// ½Kδ² of every contact: pairs, walls, the bar's top), potential (particles).
CoupledEnergy coupled_energy(const CoupledModel& model, const CoupledState& state);

struct CoupledWorld {
  CoupledModel model;
  CoupledState state;
  CoupledWorkspace workspace;
  BuildResult build(const CoupledDesc& desc) { return build_coupled(desc, model, state, workspace); }
  StepStatus step() { return coupled_step(model, state, workspace); }
};

}  // namespace xfdem
