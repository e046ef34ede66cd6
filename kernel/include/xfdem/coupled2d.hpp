// The coupled 2D X-FE-DEM stepper: disks (DEM, type a contacts between them)
// against the boundary of the 2D plate (type c contact), in the staggered
// step of the 1D stepper (coupled.hpp, docs/coupling.md) with the scalar tip
// force become a list of contact points with vector forces.
//
// One coupled step advances the plate by dt and the disks by `dem_substeps`
// substeps of h = dt/n. Within the window:
//   - the disks see the plate's boundary (coupling/plate_boundary.hpp) move
//     linearly from its place at t_n to its place at t_{n+1}; their contacts
//     with it (closest point, one contact law: K = k_i, η = 2ζ√(k_i m_i), as
//     against a plane) are evaluated where the particle integrator evaluates
//     its forces: symplectic Euler at the start of each substep, their force
//     held over the substep as the disk's external force; abm4, rk4 and
//     verlet at every stage, at the stage's time, through the DEM's external
//     contact hook (DemDesc::external_contacts);
//   - the plate receives, as a force held constant over its step, the
//     impulse the disks took from it, each contact's force spread to its
//     unknowns by the (enriched) shape functions at the contact point and
//     weighted as the integrator weighs that evaluation (h for symplectic
//     Euler; the DEM's plane ledger for the others), over dt (its
//     acceleration at t_n re-evaluated with that force, so that Newmark
//     delivers exactly its impulse).
// The two depend on each other: the window is iterated to the fixed point
// f̄ = −J(f̄)/dt (a vector over the plate's unknowns) by interface
// quasi-Newton passes (IQN-ILS); at a jump of J (a contact closing at another
// substep as f̄ moves, where no fixed point exists) the window ends in the
// blend of two passes on its two sides, brought together by bisection, as
// the 1D stepper blends (kCoupled2dHistory and below). The plate then takes the step with −J/dt of the last
// pass, so the exchange is impulse-conserving at every step (and carries the
// moment: plate_spread_force), and at the fixed point both sides saw the same
// boundary motion, so the exchange does no net work.
//
// With symplectic Euler the boundary's forces are held over each substep
// (the integrator's own evaluation: forces at the start of the step); with
// abm4, rk4 and verlet the DEM calls the boundary through its external-contact
// hook (DemDesc::external_contacts) at every stage, and weighs the plate's
// share as it weighs a plane's. abm4_events is refused (its event location
// does not see the boundary's contacts).
//
// With friction or rolling resistance (or the hertz law) the disks rotate and
// every disk–boundary contact is the DEM's particle–wall contact
// (dem_detail::wall_contact, the plane contact's own code): Cundall–Strack
// spring with its Coulomb cap, sticking dashpot, rolling resistance; hertz
// with the material the boundary bounds as the second body (the plate's, or
// an inclusion's where the boundary lies in it; R* = the disk's radius).
// With symplectic Euler the disk is held at the contact's force and torque
// (DemState::external_torque); with abm4, rk4 and verlet the rotating DEM
// step calls the hook (DemWorkspace::external_rotating_contacts) at every
// stage, each contact's spring advanced from its value at the substep's
// start by the stage's time offset and kept at the substep's last
// evaluation, as the DEM treats its own planes' springs. The plate receives the opposite force, normal and tangential, at the
// contact's material point, and the opposite rolling couple as two opposite
// forces at its segment's ends. Each contact's spring is kept in
// Coupled2dState::springs by (disk, boundary chain), matched to the contact
// of that chain whose normal is nearest the stored one: a disk slides across
// the joints of a chain (a flat surface of many edges, a polygonal void's
// vertices) with its spring, which the law turns into the new contact plane.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "xfdem/coupling/plate_boundary.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/energy_check.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/status.hpp"

namespace xfdem {

struct Coupled2dDesc {
  /// Disks: dt is set to plate.dt / dem_substeps; external_forces
  /// (symplectic_euler) or external_contacts (the others) is set on, and
  /// external_torques with friction, rolling friction or hertz under
  /// symplectic_euler.
  DemDesc<2> dem;
  PlateDesc plate;  ///< dynamic analysis
  int dem_substeps = 10;
  /// How far the plate's boundary may move from its reference place (m): the
  /// broad phase's bins hold for it; 0: half the smaller cell side. A step
  /// whose boundary moves further says coupling_unstable.
  double boundary_allowance = 0;
  /// Refuse to build when the stiffest disk–boundary contact, a two-mass
  /// oscillator ω_c² = k (1/m_eff + 1/m_disk) with 1/m_eff the largest over
  /// the boundary's vertices of Σ_a N_a² / m_a (the standard functions there,
  /// m_a their lumped masses: at a node of an uncut edge, 1/m_node), has
  /// ω_c·dt above kCoupledMaxOmegaDt or ω_c·dt/n above the disks'
  /// integrator's stable step.
  bool reject_unstable_coupling = true;
  /// The energy balance check of coupled2d_step() on the disks and the plate
  /// together (Coupled2dState::energy), replacing the halves' own.
  EnergyCheck energy_check;
};

struct Coupled2dModel {
  bool built = false;
  DemModel<2> dem;
  PlateModel plate;
  PlateBoundary boundary;
  int substeps = 1;
  double dt = 0;
  double coupling_omega = 0;  ///< ω_c of the stiffest disk–boundary contact, rad/s
  /// 1/m_eff: the largest Σ_a N_a² / m_a over the boundary's vertices, 1/kg.
  double coupling_inv_mass = 0;
  /// Friction, rolling resistance or hertz: the disks rotate, contacts keep springs.
  bool rotating = false;
  /// hertz: the plate's (1 − ν²)/E and 2(2 − ν)(1 + ν)/E, the contacts' second body.
  double plate_inv_e = 0, plate_inv_g = 0;
  /// hertz with discontinuities: the same of each boundary segment's material
  /// (an inclusion's where the segment bounds it); empty otherwise (the plate's).
  std::vector<double> segment_inv_e, segment_inv_g;
  /// Rolling resistance: each segment's turning compliance under a couple at
  /// its ends, (1/m_a + 1/m_b)/|L|² (1/(kg m²); m the lumped mass at each
  /// end's material point across the segment, Σ N² / m_node over the free
  /// standard unknowns): the wall's 1/I in the torque that stops the
  /// relative rolling within a substep, as a pair's 1/I_i + 1/I_j. Empty
  /// otherwise.
  std::vector<double> segment_inv_turn;
  bool beyond_stable_step = false;
  EnergyCheck energy_check;  ///< Coupled2dDesc::energy_check
};

/// A window has settled when |g| ≤ this × (|f̄| + |J/dt|) (Euclidean norms
/// over the plate's unknowns), g = −J/dt − f̄: the 1D stepper's tolerance.
inline constexpr double kCoupled2dTolerance = 1e-10;
/// The window's passes are interface quasi-Newton steps (IQN-ILS): the
/// least-squares fit of the residual's changes over the window's last
/// kCoupled2dHistory passes is the map's Jacobian on their span, Picard's
/// step on the rest.
inline constexpr int kCoupled2dHistory = 16;
/// A pass whose residual is this many times the window's best so far drops
/// the quasi-Newton history and starts again from the best pass (a growth
/// of 10 or so is still a quasi-Newton step on its way; restarting there
/// cycled the 1D Case I column under rk4).
inline constexpr double kCoupled2dRestartGrowth = 100.0;
/// A contact that closes or opens at another substep (or stage) as f̄ moves
/// makes J jump: no force may be a fixed point. Where two passes lie on the
/// two sides of such a jump, close enough that the blend of their residuals,
/// (1 − θ) g_a + θ g_b, is within the tolerance for some 0 < θ < 1, the
/// window ends in the same blend of the two passes' disk states and
/// impulses (as the 1D stepper blends at a jump): its impulse is the
/// plate's, and its energy at most the blend of theirs
/// (Coupled2dState::blended_windows).
/// A window whose smallest residual has not improved for
/// kCoupled2dStallPasses passes (or after kCoupled2dMaxPasses) is taken at
/// its smallest residual, which the state records
/// (Coupled2dState::unsettled_windows, worst_unsettled); above
/// kCoupled2dJumpTolerance the step also says coupling_unstable. The plate
/// still takes exactly the disks' impulse; what is not exact there is the
/// boundary motion the disks saw, off by the plate's response to g. Several
/// contacts switching at other substeps in one window (a jump in several
/// directions at once, which no blend of two passes closes) leave residuals
/// of 1e-5 to 1e-4 of the force (a frictional free plate, verlet: 8.5e-5):
/// an error of the boundary's motion within one window far below the
/// step's own, so such a window goes on, counted, and only a residual
/// above 1e-3 of the force stops the run.
inline constexpr int kCoupled2dStallPasses = 6;
inline constexpr int kCoupled2dMaxPasses = 100;
inline constexpr double kCoupled2dJumpTolerance = 1e-3;
/// A node whose function reaches the disks' boundary with a lumped mass below
/// this fraction of a cell's (ρ t h_x h_y) is refused at build (with
/// reject_unstable_coupling): a sliver that thin breaks the coupled step at
/// any substep (docs/coupled2d.md, "The coupled step").
inline constexpr double kCoupled2dSliverMass = 1e-14;

/// The tangential springs of the disk–boundary contacts: kPlateBoundaryMaxContacts
/// slots per disk (slot i·K + k), as many as a disk can have contacts, so
/// they never run out. A slot holds the boundary chain of its contact
/// (PlateBoundarySegment::chain; −1: free), the contact's unit normal when it
/// was last evaluated, and the spring ξ (m; hertz: the force history, N, as
/// the DEM keeps it). Rotating disks only; empty otherwise.
struct Coupled2dSprings {
  std::vector<std::int32_t> chain;
  std::vector<double> normal, xi;  ///< 2 per slot
};

struct Coupled2dState {
  DemState<2> dem;
  PlateState plate;
  Coupled2dSprings springs;
  /// The force (N per unknown) the plate received over the last step.
  std::vector<double> coupling_force;
  /// abm4, rk4, verlet: the boundary's force on each disk (x, y; N) at the
  /// last force evaluation (empty for symplectic_euler, which holds it in
  /// dem.external_force).
  std::array<std::vector<double>, 2> boundary_force;
  /// Totals since the start: impulse (N·s, x and y) the disks took from the
  /// boundary, and that the plate received (its unknowns' shares, summed as a
  /// rigid translation sees them).
  double impulse_to_particles[2] = {0, 0}, impulse_to_plate[2] = {0, 0};
  /// Work the exchange did on the plate, Σ f̄·Δu, and the work the disks did
  /// on the boundary, Σ −h F·V (F the boundary's force on a disk, V the
  /// contact point's velocity over the window), J. Equal at settled windows:
  /// the exchange creates no energy.
  double work_on_plate = 0, work_by_particles = 0;
  std::int32_t last_passes = 0, peak_passes = 0;
  /// Windows taken at their smallest residual (a jump), and the largest such |g|/scale.
  std::int64_t unsettled_windows = 0;
  double worst_unsettled = 0;
  /// Windows that ended in the blend of two passes across a jump of J.
  std::int64_t blended_windows = 0;
  /// The energy balance check's books (coupled2d_energy_totals) against the
  /// work the halves book on their own ledgers (the plate's loads, self
  /// weight, dampers and absorbing edges; the disks' moving planes); the
  /// exchange is internal.
  EnergyLedger energy;
  std::int64_t step = 0;
  double time = 0;

  /// The state's one field list (state_io.hpp hashes, saves, restores and
  /// names what it lists): visit(part, name, data, count) for the disks
  /// ("dem"), the plate ("plate"), the springs ("springs"; no elements
  /// unless the disks rotate), then the exchange's own fields (""). The
  /// workspace carries nothing from one step to the next.
  template <class Visitor>
  void for_each_field(Visitor&& visit) {
    dem.for_each_array(
        [&](const char* name, auto* data, auto count) { visit("dem", name, data, static_cast<std::size_t>(count)); });
    plate.for_each_field([&](const char* name, auto* data, std::size_t count) { visit("plate", name, data, count); });
    visit("springs", "chain", springs.chain.data(), springs.chain.size());
    visit("springs", "normal", springs.normal.data(), springs.normal.size());
    visit("springs", "xi", springs.xi.data(), springs.xi.size());
    visit("", "coupling_force", coupling_force.data(), coupling_force.size());
    for (auto& f : boundary_force) visit("", "boundary_force", f.data(), f.size());
    visit("", "impulse_to_particles", impulse_to_particles, std::size_t{2});
    visit("", "impulse_to_plate", impulse_to_plate, std::size_t{2});
    visit("", "work_on_plate", &work_on_plate, std::size_t{1});
    visit("", "work_by_particles", &work_by_particles, std::size_t{1});
    visit("", "last_passes", &last_passes, std::size_t{1});
    visit("", "peak_passes", &peak_passes, std::size_t{1});
    visit("", "unsettled_windows", &unsettled_windows, std::size_t{1});
    visit("", "worst_unsettled", &worst_unsettled, std::size_t{1});
    visit("", "blended_windows", &blended_windows, std::size_t{1});
    visit("", "energy_reference", &energy.reference, std::size_t{1});
    visit("", "energy_work", &energy.work, std::size_t{1});
    visit("", "energy_peak", &energy.peak, std::size_t{1});
    visit("", "energy_exceeded", &energy.exceeded, std::size_t{1});
    visit("", "step", &step, std::size_t{1});
    visit("", "time", &time, std::size_t{1});
  }
};

struct Coupled2dWorkspace {
  DemWorkspace<2> dem;
  PlateWorkspace plate;
  DemState<2> dem_start;
  PlateState plate_start;
  Coupled2dSprings springs_start;
  std::vector<double> start_positions, end_positions, positions;  ///< boundary vertices (2 each)
  std::vector<double> impulse;  ///< the pass's impulse to the plate, per unknown
  std::vector<double> residual, previous_residual, best_force;
  /// The quasi-Newton's columns (kCoupled2dHistory of dofs each, a ring):
  /// the changes of the residual and of the map's output −J/dt between
  /// passes; its QR factor's Q (as many) and R, and the fit's coefficients.
  std::vector<double> history_residual, history_output, q, r, coefficients;
  std::vector<double> previous_output;
  /// Passes kept for a blend across a jump: [0] the last, [1] the other
  /// side of a jump while the two are brought together by bisection.
  struct Pass {
    DemState<2> dem;
    Coupled2dSprings springs;
    std::vector<double> residual, force, impulse;
    double taken[2] = {0, 0}, work = 0, scale = 0;
  };
  Pass kept[2];
  /// The disks' contacts with the boundary run on the DEM's parts (DemModel::
  /// parts: disks [0, split) and [split, n), fixed at build): each part finds
  /// its disks' contacts and forces, writes each disk's own force, and lists
  /// the plate's share of each contact in its own stretch of `shares` (part
  /// p's from slot begin·kPlateBoundaryMaxContacts on, `share_count[p]` of
  /// them). The calling thread then spreads the lists onto the plate's
  /// unknowns, part 0's then part 1's: disk by disk, contact by contact, the
  /// order of one part's loop, so the sums are the same bits on one and two
  /// workers (and with or without the split).
  struct PlateShare {
    PlateMaterialPoint at[kPlateBoundaryMaxPoints];  ///< where the force acts (plate_boundary_material_points)
    double at_share[kPlateBoundaryMaxPoints] = {1.0, 0.0, 0.0, 0.0};  ///< the force's share at each
    int points = 1;
    double partner_weight = 0;  ///< a blended contact's w: its couple's share on the second segment
    double force[2] = {0, 0};  ///< on the plate, × the evaluation's weight
    double work = 0;           ///< weight × F·V, taken from the book
    int couple_segment = -1;   ///< a rolling couple's segment (−1: none)
    int couple_partner = -1;   ///< a blended contact's second segment (the couple shared 1 − w, w)
    double couple = 0, couple_work = 0;
  };
  std::vector<PlateShare> shares;
  std::int32_t share_count[2] = {0, 0};
  /// Contacts of each disk that carried a force at the last evaluation.
  std::vector<std::int32_t> carried;
  /// What the DEM's external contact hook reads (set by each step; the
  /// workspace is its context).
  const Coupled2dModel* stage_model = nullptr;
  Coupled2dState* stage_state = nullptr;
};

/// Builds both halves and the boundary; the only allocating call. Messages
/// name the key ("dem.integrator: ...", "dem.particles[0].position: ...").
/// Refuses a disk whose centre starts in the plate's material.
BuildResult build_coupled2d(const Coupled2dDesc& desc, Coupled2dModel& model, Coupled2dState& state,
                            Coupled2dWorkspace& workspace);

/// One plate step and its disk substeps, then, every energy_check.interval
/// steps, the energy balance check E(t) − E0 − W(t) ≤ tolerance · max
/// E_motion (+ round-off) on both bodies (energy_check.hpp; E from
/// coupled2d_energy_totals, W the halves' booked work): from the first check
/// that finds the energy above its books, every step says energy_growth.
/// Never allocates.
StepStatus coupled2d_step(const Coupled2dModel& model, Coupled2dState& state, Coupled2dWorkspace& workspace);

/// What the energy check weighs now: the disks' energy (dem_energy: kinetic
/// and rotational, their contacts with each other and with planes, gravity's
/// −m g·x), the disk–boundary contacts' (coupled2d_boundary_energy) and the
/// plate's algorithmic energy (plate_algorithmic_energy); the total, the part
/// in motion (all but gravity's) and the magnitudes' sum. `positions`: the
/// caller's scratch, 2 doubles per boundary vertex. No allocation.
EnergyTotals coupled2d_energy_totals(const Coupled2dModel& model, const Coupled2dState& state, double* positions);

/// Starts new energy books at the state as it is (build does): call after
/// editing the state.
void coupled2d_restart_energy_ledger(const Coupled2dModel& model, Coupled2dState& state, Coupled2dWorkspace& workspace);

/// Force (x, y; N) of the boundary on disk i (the sum of its contacts'):
/// for symplectic_euler what the last substep of the last step held, for the
/// others its last force evaluation (at the end of the step); false for a
/// bad index.
bool coupled2d_boundary_force(const Coupled2dModel& model, const Coupled2dState& state, std::int32_t particle,
                              double force[2]);

/// Energy (J) of the disk–boundary contacts with the disks and the plate
/// where they are now: each contact's normal spring (½ k_i δ²; hertz 8/15 E*
/// √r δ^{5/2} with the plate's material as the second body) and, with linear
/// friction, ½ k_t |ξ|² of the kept tangential springs, each force counted
/// up to its contact's Coulomb cap μ k_i δ (the rest is the dashpot's share a
/// sliding contact resets into ξ: dem_detail::tangential_energy) (hertz's, kept as a
/// force, has no potential: the DEM's books leave it out too). `positions`
/// is the caller's scratch, 2 doubles per boundary vertex. No allocation.
double coupled2d_boundary_energy(const Coupled2dModel& model, const Coupled2dState& state, double* positions);

struct Coupled2dWorld {
  Coupled2dModel model;
  Coupled2dState state;
  Coupled2dWorkspace workspace;
  BuildResult build(const Coupled2dDesc& desc) { return build_coupled2d(desc, model, state, workspace); }
  StepStatus step() { return coupled2d_step(model, state, workspace); }
};

}  // namespace xfdem
