// The coupled X-FE-DEM stepper (paper, section IV) for the 1D scenes: particles
// (DEM, type a contacts between them) falling on an X-FEM/FEM bar (type b
// contact at its interface) and touching its top end (type c contact).
//
// One coupled step advances the bar by dt and the particles by `dem_substeps`
// substeps of dt/n (the paper's step delay, n = 10). Within the window:
//   - the particles see the bar's top as a plane moving linearly from its
//     position at t_n to its position at t_{n+1} (speed (u_{n+1} − u_n)/dt,
//     which their dashpot sees too);
//   - the bar receives, as a force held constant over the step, the impulse
//     the particles took from the top over the window, averaged: f̄ = −J/dt
//     (its acceleration at t_n is re-evaluated with f̄, so the impulse Newmark
//     delivers is exactly f̄·dt).
// The two depend on each other, so the window is iterated to the fixed point
// f̄ = −J(f̄)/dt: a first pass with last window's force, then Newton, secant
// and bracketing steps. For a linear contact on a tied bar the window is
// affine in f̄: once two passes have measured its sensitivity (the particles'
// end state's derivative in f̄), a window that sees the same contacts settles
// in one pass, moved along it to the root; a contact that opens or closes
// inside the window takes a few passes. Without contact with the top one pass
// suffices. At the fixed
// point the particles and the bar see the same top motion and exchange equal
// and opposite impulses, so the exchange creates no momentum and no energy
// (the work −J·v̄ done on the bar equals the work J·v̄ the particles did).
// Whatever residual is left is carried into the next window's force, so the
// momentum books close to round-off at every step (CoupledState::pending_impulse).
// docs/coupling.md gives the details and the stability map.
#pragma once
#include <cstdint>
#include <vector>

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
  /// Refuse to build when the stiffest particle–top contact, a two-mass
  /// oscillator ω_c² = k (1/m_top + 1/m_particle), has ω_c·dt above
  /// kCoupledMaxOmegaDt or ω_c·dt/n above the particle integrator's stable step.
  bool reject_unstable_coupling = true;
  /// The energy balance check of coupled_step(), on particles and bar together
  /// (CoupledState::energy). It replaces the bar's own: bar.energy_check is
  /// not used (the bar alone is an open system whose input the exchange sets).
  EnergyCheck energy_check;
  /// Memory budget (bytes) of the particles' arrays, their state counted three
  /// times (the state and CoupledWorkspace::dem_start, dem_end): checked before
  /// anything is allocated, as DemDesc::max_memory_bytes is for particles
  /// alone, which it replaces (dem.max_memory_bytes is not used). The bar's
  /// arrays, sized by its elements, are not counted. 0: no budget.
  std::uint64_t max_memory_bytes = 0;
};

struct CoupledModel {
  DemModel<1> dem;
  BarModel bar;
  int substeps = 1;
  double dt = 0;                  ///< continuum step, s
  std::int32_t top_plane = -1;    ///< index of the plane that stands for the bar's top
  double top_position = 0;        ///< x of the undeformed top (the bar's length), m
  double max_contact_stiffness = 0;  ///< max over particles of k_i (the type c contact is K = k_i), N/m
  /// The entry of CoupledState::sensitivity (one per double of a DemState)
  /// that is the top plane's impulse: dJ/df̄.
  std::int32_t sensitivity_top_impulse = -1;
  /// ω_c of the stiffest particle–top contact, ω_c² = k (1/m_top + 1/m_p), with
  /// m_top the top node's lumped mass (rad/s).
  double coupling_omega = 0;
  /// ω_c·dt past kCoupledMaxOmegaDt or ω_c·dt/n past the particle integrator's
  /// stable step (built with reject_unstable_coupling off): every step says
  /// StepStatus::unstable_time_step.
  bool beyond_stable_step = false;
  EnergyCheck energy_check;  ///< CoupledDesc::energy_check
};

/// Passes of one window at most while looking for the fixed point. The root is
/// bracketed and the bracket shrinks at least by half every other pass, so a
/// window settles long before this (the randomized sweep's peak is printed by
/// CoupledStress.RandomizedCaseVariants); one that has not is taken with its
/// last force and flagged coupling_unstable (its residual is carried, so
/// momentum stays exact).
inline constexpr int kCoupledMaxPasses = 100;

/// Largest ω_c·dt (ω_c² = k (1/m_top + 1/m_particle), dt the continuum step)
/// the build accepts. It was set where the secant iteration stopped settling
/// (at 2 some windows did not); the bracketed iteration settles every window
/// at 4 too (tests/coupling/stability_map_test.cpp), and the energy bound is
/// measured only inside 1, so the limit stays until it is re-measured there.
/// The substep dt/n must also be inside the particle integrator's own stable
/// step for ω_c.
inline constexpr double kCoupledMaxOmegaDt = 1.0;

struct CoupledState {
  DemState<1> dem;
  BarState bar;
  double coupling_force = 0;   ///< f̄ the bar's top received over the last step, N (up)
  /// Σ impulse to particles + Σ impulse to the bar: the part of the exchange not
  /// yet balanced (a round-off-sized fixed-point residual), N·s. It is added to
  /// the next window's force on the bar.
  double pending_impulse = 0;
  /// Totals since the start: Σ J the particles took from the top, Σ f̄ dt the
  /// bar received (N·s, up).
  double impulse_to_particles = 0, impulse_to_bar = 0;
  /// dg/df of the window's residual g(f) = −J(f)/Δt − f, as the last window
  /// that measured it left it (0: none yet): the first step of the next
  /// window's iteration when the sensitivity below does not apply.
  double coupling_slope = 0;
  double coupling_slope_width = 0;  ///< the secant's width it was measured over, halved every window, N
  /// d(particles' state)/df̄ over a window in which no contact switched: one
  /// entry per double of DemState, in its field order (0 where a field does
  /// not move with f̄). Within one contact set the window is affine in f̄, so
  /// a pass at any force plus this times the force's change is the pass at the
  /// new force: a window whose contacts match it (sensitivity_signature)
  /// settles in one pass. Measured by the first two passes of a window that
  /// saw the same contacts at every force evaluation.
  std::vector<double> sensitivity;
  double sensitivity_width = 0;  ///< |Δf̄| it was measured over, N (0: none yet)
  /// The window it holds for: which contacts carried a force at each
  /// evaluation (DemWorkspace::contact_signature) and the multistep
  /// history's length at the window's start (CoupledWorkspace::pass_signature).
  std::int64_t sensitivity_signature = 0;
  std::int32_t last_passes = 0;  ///< passes the last window needed
  std::int32_t peak_passes = 0;
  std::int64_t step = 0;
  double time = 0;
  /// The energy balance check's books: particles (kinetic, contacts, gravity)
  /// plus the bar's algorithmic energy (BarState::energy), against the work of
  /// the bar's tip load and base and of the particles' external forces. The
  /// exchange is internal: at its fixed point it does no net work.
  EnergyLedger energy;
};

/// Time per stage of coupled steps while the host has installed a clock.
struct CoupledProfile {
  std::int64_t steps = 0, passes = 0;
  std::int64_t step_ns = 0;       ///< whole coupled steps
  std::int64_t continuum_ns = 0;  ///< the bar: acceleration re-evaluation and Newmark solve, all passes
  std::int64_t particles_ns = 0;  ///< the particle substeps, all passes (their own stages: dem.profile)
  /// The exchange itself: saving and restoring the window's start, the fixed point.
  [[nodiscard]] std::int64_t coupling_ns() const { return step_ns - continuum_ns - particles_ns; }
};

struct CoupledWorkspace {
  /// Host clock in nanoseconds; nullptr: no timing. Also times the particles'
  /// stages (copied into dem.clock_ns at each step).
  std::int64_t (*clock_ns)() = nullptr;
  CoupledProfile profile;
  DemWorkspace<1> dem;
  BarWorkspace bar;
  DemState<1> dem_start;  ///< the particles at t_n, restored for every pass
  BarState bar_start;     ///< the bar at t_n
  /// The particles at one end of a window whose impulse jumps (coupled_step).
  DemState<1> dem_end;
  /// The bar at that end, when it is stepped at every pass (a unilateral
  /// interface): the window ends in the blend of both halves' two ends.
  BarState bar_end;
  /// The particles after a window's first pass, kept when a second pass may
  /// measure CoupledState::sensitivity.
  DemState<1> dem_first;
  /// A bar linear in its tip force is stepped once per window, at the first
  /// pass's force; later passes move its top along the step's response, and
  /// the window's end corrects the bar to the force it settled on.
  double first_force = 0, tip_start = 0, first_tip_end = 0;
  /// What the last pass saw: DemWorkspace::contact_signature and the length
  /// of the multistep history at its start; and whether its map from the
  /// force was affine as far as the signature can tell (no located event).
  std::int64_t pass_signature = 0;
  bool pass_affine = false;
  /// Whether the last window ended on the blend of two ends at a jump of its
  /// impulse (the particles, and a bar stepped at every pass) rather than on
  /// a pass; and, for a bar stepped at every pass, |u_tip| between its two
  /// ends (m; 0 otherwise), which a blend of the particles alone would have
  /// left between the halves.
  bool last_blend = false;
  double last_blend_tip_spread = 0;
};

/// Builds both halves; the only allocating call. Messages name the field
/// ("dem.particles[0].mass: ...", "bar.interface.position: ..."). Besides
/// build_dem's and build_bar's refusals it refuses a particle that starts
/// overlapping the bar's tip by more than its radius (its centre inside the
/// bar), and particle arrays past max_memory_bytes (before allocating).
BuildResult build_coupled(const CoupledDesc& desc, CoupledModel& model, CoupledState& state,
                          CoupledWorkspace& workspace);

/// One continuum step and its particle substeps. Never allocates. Flags:
/// whatever the halves return, plus coupling_unstable when the window's
/// fixed point was not reached in kCoupledMaxPasses passes (the step is taken),
/// and energy_growth from the energy balance check (CoupledDesc::energy_check).
StepStatus coupled_step(const CoupledModel& model, CoupledState& state, CoupledWorkspace& workspace);

/// Starts new energy books at the state as it is: call after editing the state.
void coupled_restart_energy_ledger(const CoupledModel& model, CoupledState& state);

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
