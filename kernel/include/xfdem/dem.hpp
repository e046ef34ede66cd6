// The DEM kernel: spheres (disks in 2D, rods on a line in 1D) with normal
// spring-dashpot contacts, fixed planes, gravity, and five time integrators;
// in 2D and 3D optionally rotation with Coulomb friction (Cundall–Strack
// tangential spring) and rolling resistance (DemDesc::friction).
//
//   DemDesc<D>  --build_dem()-->  DemModel<D> (immutable) + DemState<D> + DemWorkspace<D>
//   dem_step(model, state, workspace) -> StepStatus          (never allocates, throws or locks)
//
// Everything a step changes lives in DemState (plain data: copy it to snapshot);
// DemWorkspace is scratch whose contents do not survive a step. Every array is
// sized by build_dem(); capacities are fixed there and exceeding one is a
// StepStatus flag, never a reallocation. Contact mechanics follow
// shared/spec/paper-notes.md (full overlap, springs in series, damping ratio).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "xfdem/energy_check.hpp"
#include "xfdem/parallel.hpp"
#include "xfdem/status.hpp"

namespace xfdem {

/// Time integrators for the particles. See docs/dem.md for order and stable step.
enum class DemIntegrator : std::uint8_t {
  /// Adams–Bashforth–Moulton 4, PECE, started by three RK4 steps (paper, appendix C).
  abm4,
  /// abm4 plus contact-event location: a step in which a contact starts or ends
  /// is split at the event (located by bisection to ~1e-13 of the step), both
  /// parts integrated by RK4 with the contact set frozen, and the multistep
  /// history restarted. Meant for scenes with few particles.
  abm4_events,
  /// Velocity Verlet (kick-drift-kick), one force evaluation per step; the
  /// dashpot sees the half-step velocity, as in LIGGGHTS.
  verlet,
  /// Symplectic (semi-implicit) Euler: v += h a(x, v); x += h v.
  symplectic_euler,
  /// Classical Runge–Kutta 4 (S3 evaluated at y_n + S2 h/2).
  rk4,
};

/// Normal force law (paper-notes: eq 6 and its non-tensile variant).
enum class ContactLaw : std::uint8_t {
  /// F = K δ + η δ' while δ > 0 (the dashpot may pull at the end of a contact).
  linear,
  /// As linear, but the total normal force is clamped at zero (never attractive).
  linear_nontensile,
  /// Hertz normal + Mindlin tangential (no micro-slip), damped by the
  /// restitution (DemDesc::restitution), from the particles' and planes'
  /// Young's moduli and Poisson's ratios (2D and 3D; docs/dem.md).
  hertz,
};

/// Components of a particle's angular velocity: 1 in 2D (about z), 3 in 3D,
/// none on a line.
constexpr int spin_components(int dimension) { return dimension == 3 ? 3 : dimension == 2 ? 1 : 0; }
/// Columns of a tangential spring: D in 2D and 3D, none on a line (so that a
/// 1D state, which the coupled stepper copies every step, carries no empty arrays).
constexpr int spring_components(int dimension) { return dimension == 1 ? 0 : dimension; }
/// The angle turned is kept in 2D only.
constexpr int angle_components(int dimension) { return dimension == 2 ? 1 : 0; }

/// Default tangential_stiffness_ratio k_t / k_n: 2/7, at which a sphere's
/// tangential contact oscillation (k_t (1/m + r²/I) = 3.5 k_t/m) has the
/// normal one's frequency, so the stable step is unchanged.
inline constexpr double kDefaultTangentialStiffnessRatio = 2.0 / 7.0;

/// The hertz law's stiffness grows with the overlap: build_dem() checks dt
/// against the stiffest contact at the overlap δ = kHertzReferenceOverlap · R*
/// (S_n = 2 E* R* √0.01); the step's network bound uses the actual overlaps
/// (StepStatus::unstable_time_step when a contact goes deeper than dt allows).
inline constexpr double kHertzReferenceOverlap = 0.01;

const char* integrator_name(DemIntegrator integrator) noexcept;
const char* contact_law_name(ContactLaw law) noexcept;

/// How candidate pairs are found, chosen by build_dem() from the scene.
enum class BroadPhase : std::uint8_t {
  none,       ///< fewer than two particles: no pair contacts possible, stage skipped
  all_pairs,  ///< few particles: a fixed list of every pair, never rebuilt
  grid,       ///< uniform grid (counting sort) + Verlet list with a skin
};

template <int D>
struct ParticleDesc {
  double mass = 0;       ///< kg, > 0
  double radius = 0;     ///< m, > 0
  double stiffness = 0;  ///< N/m, > 0 (the particle's own normal stiffness k_i)
  std::array<double, D> position{};  ///< m
  std::array<double, D> velocity{};  ///< m/s
  /// rad/s: 2D about z; 3D [wx, wy, wz]. A non-zero spin makes the model
  /// rotate (DemFeatures::rotation), with or without friction.
  std::array<double, spin_components(D)> angular_velocity{};
  /// kg·m², > 0; 0: the solid's own, ½ m r² (disk) or 2/5 m r² (sphere).
  double inertia = 0;
  /// The hertz law's material (Pa, > 0; and ν in (−1, 0.5)); NaN: not given.
  double youngs_modulus = NAN;
  double poisson_ratio = NAN;
};

/// A fixed half-space boundary: the solid side is where (x − point)·normal < 0.
/// Overlap with a particle is δ = r − (x − point)·normal, however deep.
template <int D>
struct PlaneDesc {
  std::array<double, D> point{};
  std::array<double, D> normal{};  ///< normalised by build_dem(); must not be zero
  /// The hertz law's wall material; both NaN (not given): a rigid wall (1/E = 0).
  double youngs_modulus = NAN;
  double poisson_ratio = NAN;
};

/// Fixed bounds. 0 picks the default documented on each field. The two that
/// size arrays count against DemDesc::max_memory_bytes (DemMemory).
struct DemCapacities {
  /// Entries of the pair (Verlet) list of the grid broad phase, 24 bytes each
  /// in the state. Default: 8 per particle + 64. An all_pairs model's list
  /// holds its n(n−1)/2 pairs whatever this says.
  std::int32_t max_pairs = 0;
  /// Entries of one particle's half of the pair list (partners j > i).
  /// Default 48 (enough for a dense 3D packing with a skin of half a radius).
  std::int32_t max_neighbors_per_particle = 0;
  /// Cells of the broad-phase grid over the particles' bounding box, 4 bytes
  /// each in the workspace; at most 2^31 − 2. Default: 8 per particle + 4096.
  std::int32_t max_grid_cells = 0;
  /// Events located inside one step (abm4_events). Default 16.
  std::int32_t max_events_per_step = 0;
};

template <int D>
struct DemDesc {
  std::vector<ParticleDesc<D>> particles;
  std::vector<PlaneDesc<D>> planes;
  std::array<double, D> gravity{};  ///< m/s²
  ContactLaw law = ContactLaw::linear;
  double damping_ratio = 0;  ///< ζ in [0, 1): η = 2 ζ √(K m_eff)
  DemIntegrator integrator = DemIntegrator::abm4;
  double dt = 0;  ///< s, > 0
  /// Verlet-list skin (m) for the grid broad phase; 0 = half the largest radius.
  double skin = 0;
  /// Particle counts up to this use the all_pairs broad phase instead of the grid.
  std::int32_t all_pairs_up_to = 8;
  /// From this many particles on, the model splits a step's work into two
  /// fixed parts (particles [0, n/2) and [n/2, n)) that a host's ParallelFor
  /// may run on two workers; the bits do not depend on the worker count.
  /// 0: never split. Default from docs/benchmarks.md (where two workers pay).
  std::int32_t split_from = 1000;
  DemCapacities capacities;
  /// Coulomb friction coefficient μ (>= 0) of every contact, pairs and planes.
  /// With friction or rolling_friction > 0 (2D and 3D only) the particles
  /// rotate and each contact keeps a tangential spring (see docs/dem.md);
  /// both 0: the frictionless step, unchanged.
  double friction = 0;
  /// k_t / k_n of the tangential spring (> 0); 0: kDefaultTangentialStiffnessRatio.
  double tangential_stiffness_ratio = 0;
  /// Rolling resistance μ_r (>= 0): a couple ≤ μ_r R* |F_n| that stops the relative rolling
  /// within dt with the contact's tangential torques (holds tan θ ≤ μ_r), the cap above (docs/dem.md).
  double rolling_friction = 0;
  /// Coefficient of restitution e in (0, 1] of the hertz law (normal and
  /// tangential damping, β = ln e / √(ln² e + π²)); 1: undamped. Other laws: must stay 1.
  double restitution = 1;
  /// Give every particle an external force input (DemState::external_force,
  /// N, set by the host between steps, held over a step). Off: no such term.
  bool external_forces = false;
  /// Give every particle an external torque input too (DemState::external_torque,
  /// N·m about z, held over a step like the force): 2D rotating models only
  /// (friction or rolling_friction > 0, or hertz). Off: no such term, and the
  /// state has no such field.
  bool external_torques = false;
  /// Contacts the host evaluates itself (e.g. against a deforming boundary,
  /// coupled2d.hpp): every force evaluation of the plain kernels calls
  /// DemWorkspace::external_contacts, when set, with the evaluation's time
  /// and state, after the planes and the pairs, and the host adds its
  /// accelerations there: the integrator then evaluates them at each of its
  /// stages, as a moving plane. The host also writes
  /// `external_contact_totals` numbers of its own (e.g. the force each
  /// unknown of a structure takes), which the step weighs as it weighs the
  /// planes' forces (entries [planes, planes + totals) of
  /// DemState::plane_impulse and the planes' history): their impulse is then
  /// integrated with the integrator's own weights. Off: no call, no entries.
  /// Rotating models (friction, rolling friction, hertz) call
  /// DemWorkspace::external_rotating_contacts instead, at every evaluation of
  /// the granular step, after its planes and pairs, with the spins, the
  /// angular accelerations and how far (in time) the evaluation advances the
  /// tangential springs and whether it keeps them, as the step treats its own
  /// planes' springs. Not with abm4_events (its frozen contact sets and event
  /// tests do not see the host's contacts) or the energy check (the host
  /// books the work of its contacts).
  bool external_contacts = false;
  std::int32_t external_contact_totals = 0;
  /// Refuse to build when dt exceeds the integrator's stable step for the
  /// stiffest contact (see dem_stable_step_factor). Tests of instability turn it off.
  bool reject_unstable_dt = true;
  /// Memory budget (bytes) of the arrays build_dem() sizes: a description
  /// whose arrays (dem_memory) take more is refused with BuildResult::Code::memory
  /// before anything is allocated, naming the capacity, or the particle count,
  /// that takes the most. 0: no budget. The kernel asks the system nothing: a
  /// host passes the machine's memory (platform::physical_memory_bytes(), as
  /// the scene loader does) or its own share of it.
  std::uint64_t max_memory_bytes = 0;
  /// The energy balance check of dem_step() (DemState::energy).
  EnergyCheck energy_check;
  /// Few particles (at most 8) in one part with a fixed pair list (broad phase
  /// none or all_pairs), any integrator but abm4_events, no external contacts: step them by the
  /// small-system step (DemModel::small_step), the general step's code
  /// instantiated for the scene's features, without its per-part loops and
  /// kernel calls through a pointer. Same bits either way; false forces the
  /// general step (tests compare the two).
  bool small_system_path = true;
};

/// The broad phase build_dem() picks for a number of particles: none below
/// two, all_pairs up to `all_pairs_up_to` (DemDesc), grid beyond.
BroadPhase dem_broad_phase(std::int64_t particles, std::int32_t all_pairs_up_to) noexcept;

/// Bytes of the arrays build_dem() sizes for a description, counted without
/// allocating anything (the containers' own bookkeeping and the description
/// itself are not counted). What DemDesc::max_memory_bytes is compared with.
struct DemMemory {
  std::uint64_t model = 0;      ///< particle properties, planes
  std::uint64_t state = 0;      ///< positions, velocities, history, the pair list, planes' drive
  std::uint64_t workspace = 0;  ///< stage scratch, the grid's cell index, planes' forces
  std::int64_t pairs = 0;       ///< entries of the pair list (the resolved max_pairs)
  std::int64_t grid_cells = 0;  ///< cells of the grid's index (the resolved max_grid_cells; 0 without a grid)
  /// A pair-list entry, in the state: i and j (4 bytes each), K and η (8 each).
  static constexpr std::uint64_t kBytesPerPair = 24;
  /// A pair-list entry's bytes in the state for this description: kBytesPerPair,
  /// plus its record's tangential spring (D doubles) when the particles rotate.
  std::uint64_t bytes_per_pair = kBytesPerPair;
  /// A grid cell, in the workspace: where its particles start in the sorted list.
  static constexpr std::uint64_t kBytesPerGridCell = 4;
  /// model + workspace + `states` × state (a host that keeps copies of the state counts them).
  [[nodiscard]] std::uint64_t total(int states = 1) const {
    return model + workspace + static_cast<std::uint64_t>(states) * state;
  }
};

/// The bytes build_dem(desc) would allocate for its arrays. max_neighbors_per_particle
/// and max_events_per_step bound work, not storage: they size nothing.
template <int D>
DemMemory dem_memory(const DemDesc<D>& desc);

/// Features resolved once at build: the stepper and its kernels skip what a
/// scene does not need (no gravity term when g = 0, no dashpot when ζ = 0, …).
struct DemFeatures {
  bool gravity = false;
  bool damped = false;
  bool nontensile = false;
  bool planes = false;
  bool external_forces = false;
  bool external_torques = false;
  bool external_contacts = false;  ///< DemDesc::external_contacts
  /// Friction, rolling resistance, the hertz law, or a particle given a
  /// non-zero angular velocity: the particles rotate, contacts keep a
  /// tangential history, and the step is the granular one (dem/granular.cpp).
  bool rotation = false;
  BroadPhase broad_phase = BroadPhase::none;
};

template <int D>
struct DemModel;
template <int D>
struct DemState;
template <int D>
struct DemWorkspace;

/// Column views: one pointer per axis (struct of arrays).
template <int D>
using Columns = std::array<double*, D>;
template <int D>
using ConstColumns = std::array<const double*, D>;

/// Force kernel chosen at build for the scene's features (see dem/forces.hpp).
template <int D>
using AccelerationKernel = StepStatus (*)(const DemModel<D>&, DemState<D>&, DemWorkspace<D>&, ConstColumns<D> x,
                                          ConstColumns<D> v, Columns<D> a);

/// The host's contacts (DemDesc::external_contacts): adds their
/// accelerations at the state (x, v) at `time` to a, writes the
/// model's external_contact_totals numbers to totals, and returns the sum of
/// tags of the contacts that carried a force (DemWorkspace::contact_signature;
/// 0 if the host keeps none). Must not allocate, throw or lock.
template <int D>
using ExternalContacts = std::uint64_t (*)(void* context, double time, ConstColumns<D> x, ConstColumns<D> v,
                                           Columns<D> a, double* totals);

/// One evaluation of a rotating model's host contacts
/// (DemWorkspace::external_rotating_contacts): the state (x, v, spin) at
/// `time`; the host adds its accelerations to a and its angular
/// accelerations (torque / I) to alpha. `advance`: the time by which the
/// evaluation advances the contacts' tangential springs from their values
/// kept at the step's start (the step's own planes' ξ + advance · v_t);
/// `keep`: whether the springs so advanced are kept (the step's last
/// evaluation, at its end state) or only read (a stage).
template <int D>
struct ExternalStage {
  double time = 0, advance = 0;
  bool keep = false;
  ConstColumns<D> x{}, v{};
  std::array<const double*, spin_components(D)> spin{};
  Columns<D> a{};
  std::array<double*, spin_components(D)> alpha{};
};

/// The host's contacts of a rotating model: as ExternalContacts, at one
/// ExternalStage.
template <int D>
using ExternalRotatingContacts = std::uint64_t (*)(void* context, const ExternalStage<D>& stage, double* totals);

/// `steps` whole steps, up to the first not taken (DemModel::small_step).
template <int D>
using StepFunction = StepStatus (*)(const DemModel<D>&, DemState<D>&, DemWorkspace<D>&, std::int32_t steps);

template <int D>
struct DemModel {
  std::int32_t n = 0;  ///< particles
  // Particle properties, struct of arrays, index = particle id (creation order).
  std::vector<double> mass, inv_mass, radius, stiffness;
  /// Dashpot coefficient against a plane, 2 ζ √(k_i m_i), per particle.
  std::vector<double> plane_eta;
  /// 1 / moment of inertia (rotating models only, else empty).
  std::vector<double> inv_inertia;
  /// hertz: each particle's (1 − ν²)/E and 2(2 − ν)(1 + ν)/E, each plane's
  /// (0 for a rigid wall), and −2√(5/6) β (empty / 0 for the linear laws).
  std::vector<double> hertz_inv_e, hertz_inv_g, plane_inv_e, plane_inv_g;
  double hertz_damping = 0;
  std::vector<std::array<double, D>> plane_point, plane_normal;
  double friction = 0, tangential_ratio = 0, rolling_friction = 0;  ///< DemDesc's (ratio resolved)
  std::array<double, D> gravity{};
  ContactLaw law = ContactLaw::linear;
  double damping_ratio = 0;
  DemIntegrator integrator = DemIntegrator::abm4;
  double dt = 0;
  double skin = 0;       ///< m (grid broad phase)
  double cell_size = 0;  ///< m, 2 r_max + skin
  DemCapacities capacities;  ///< resolved (no zeros)
  DemFeatures features;
  /// Parts of a step's work (1 or 2) and the first particle of part 1.
  std::int32_t parts = 1;
  std::int32_t split = 0;
  /// Largest angular frequency √(K/m_eff) over every possible contact (rad/s).
  double max_contact_omega = 0;
  /// Stable step of the chosen integrator for the stiffest contact (s): its
  /// normal spring, and with friction its tangential spring with the particle
  /// turning (a mode of its own frequency and damping ratio; docs/dem.md).
  double stable_dt = 0;
  /// The integrator's stable ω·dt (dem_stable_step_factor at the damping ratio).
  double stable_factor = 0;
  /// Kernels: plain (overlap decides) and frozen-mode (the contact set of the
  /// interval start decides; abm4_events only).
  AccelerationKernel<D> accelerations = nullptr;
  AccelerationKernel<D> accelerations_frozen = nullptr;
  /// The small-system step (DemDesc::small_system_path) or nullptr: the
  /// general one. dem_step() takes it unless the host installed a clock.
  StepFunction<D> small_step = nullptr;
  EnergyCheck energy_check;  ///< DemDesc::energy_check
};

/// Another state's field, walked alongside (DemState::for_each_array).
template <class T>
struct StateArray {
  T* data;
  std::size_t count;
};
/// Spelled out for compilers without C++20's deduction for aggregates (clang 14).
template <class T>
StateArray(T*, std::size_t) -> StateArray<T>;

/// Everything a step changes. Plain data: copying it is a snapshot.
template <int D>
struct DemState {
  double time = 0;        ///< s
  std::int64_t step = 0;  ///< steps taken
  std::array<std::vector<double>, D> x, v;  ///< positions (m), velocities (m/s)
  // Rotation (rotating models only; empty otherwise): angular velocity
  // (rad/s), its history ring (the same slots as hist_v/hist_a: copies of ω
  // and the angular accelerations, rad/s²), and in 2D the angle turned since
  // t = 0 (rad).
  std::array<std::vector<double>, spin_components(D)> w;
  std::array<std::array<std::vector<double>, spin_components(D)>, 4> hist_w, hist_alpha;
  std::array<std::vector<double>, angle_components(D)> angle;
  /// Tangential spring ξ (m) of each pair-list entry, the contact record that
  /// survives list rebuilds (merged by (i, j)), and of each particle–plane
  /// contact (index p · n + i). Zero while apart. Rotating models only.
  std::array<std::vector<double>, spring_components(D)> pair_xi, plane_xi;
  /// External force on each particle (N), an input the host sets between steps
  /// and the kernel holds constant over a step; empty unless
  /// DemDesc::external_forces. A change felt by a multistep history: call
  /// dem_inputs_changed() after setting it.
  std::array<std::vector<double>, D> external_force;
  /// External torque on each particle (N·m, about z), held like external_force;
  /// empty unless DemDesc::external_torques, and then no field of the state.
  std::array<std::vector<double>, spin_components(D)> external_torque;
  /// Multistep history, a ring of 4 slots: hist_v/hist_a[slot][axis][particle].
  /// Slot `history_head` holds f(y_n) = (v_n, a_n); older slots follow.
  /// Verlet, symplectic Euler and RK4 use slot head for the last acceleration.
  std::array<std::array<std::vector<double>, D>, 4> hist_v, hist_a;
  std::int32_t history_head = 0;
  /// Valid history slots since the last (re)start, 1..4.
  std::int32_t history_count = 1;
  // Pair (Verlet) list: pairs (i, j), i < j, sorted by i; K and η per pair.
  std::int32_t pair_count = 0;
  std::vector<std::int32_t> pair_i, pair_j;
  std::vector<double> pair_stiffness, pair_eta;
  /// Positions at the last list build (grid broad phase).
  std::array<std::vector<double>, D> x_ref;
  std::int32_t pairs_valid = 0;
  // Moving planes, driven by the host between steps (the coupled stepper drives
  // one with the continuum's boundary). Plane p's point at time t is
  //   point_p + normal_p · (plane_offset[p] + plane_speed[p] · (t − plane_time)),
  // and the dashpot sees the particle's velocity relative to plane_speed.
  std::vector<double> plane_offset, plane_speed;
  double plane_time = 0;
  /// Impulse the particles received from each plane (N·s along its normal)
  /// since the host last zeroed it, integrated with the integrator's own
  /// weights: it equals the planes' share of Σ m Δv to round-off. Followed
  /// by the host's DemDesc::external_contact_totals, weighted alike.
  std::vector<double> plane_impulse;
  /// Total normal force of each plane (and the host's totals) at the
  /// evaluations kept in the history slots (same ring as hist_a), for the
  /// multistep weights.
  std::array<std::vector<double>, 4> hist_plane_force;
  // Diagnostics (high-water marks and counters), part of the state so that
  // a replay reproduces them.
  std::int64_t list_builds = 0;
  std::int32_t peak_pairs = 0, peak_neighbors = 0, peak_grid_cells = 0, peak_events = 0;
  std::int64_t events_located = 0;
  /// Bound on the squared highest frequency of the contact network (rad²/s²):
  /// per particle, the sum of K (1/m_i + 1/m_j) over its contacts (see
  /// docs/stability.md). Updated after every step from the touching contacts
  /// (few particles) or at every pair-list build (grid: every few steps);
  /// a step with dt²·network_omega2 past the stable factor² says
  /// StepStatus::unstable_time_step.
  double network_omega2 = 0;
  /// The energy balance check's books: kinetic, contacts' ½Kδ² (pairs from the
  /// pair list, planes) and gravity's −m g·x, against the work of the external
  /// forces (F·Δx, F held over a step) and of moving planes (speed × the
  /// impulse they gave, and what dem_drive_plane() puts into the contacts when
  /// it moves one). The dashpots only take energy out. After editing x or v,
  /// restart them (dem_restart_energy_ledger).
  EnergyLedger energy;

  /// Calls visit(name, data, count) for every field, in one fixed order (the
  /// one list of fields: snapshots, hashes and the coupled window's copies
  /// and blends walk it). With other states of the same dimension, their
  /// field is passed alongside as a StateArray each: visit(name, data, count,
  /// StateArray{other.data, other.count}...).
  template <class Visitor, class... Others>
  void for_each_array(Visitor&& visit, Others&... others);
};

/// Time spent per stage, accumulated over steps while the host has installed
/// a clock (DemWorkspace::clock_ns); the kernel reads no clock of its own.
struct DemProfile {
  std::int64_t steps = 0;
  std::int64_t step_ns = 0;         ///< whole steps
  std::int64_t broad_phase_ns = 0;  ///< pair-list builds (grid and counting sort)
  std::int64_t contacts_ns = 0;     ///< force evaluations, without the broad phase
  /// The rest of the steps (the integrator's own loops): step − contacts − broad phase.
  [[nodiscard]] std::int64_t integration_ns() const { return step_ns - contacts_ns - broad_phase_ns; }
};

/// Scratch for one step; no content survives between steps (but the profile,
/// which the host reads and resets).
template <int D>
struct DemWorkspace {
  /// Host clock in nanoseconds for the per-stage profile; nullptr: no timing.
  std::int64_t (*clock_ns)() = nullptr;
  DemProfile profile;
  std::array<std::vector<double>, D> xs, vs, as;  ///< stage state and its acceleration
  std::array<std::vector<double>, D> sum_x, sum_v;  ///< RK4 accumulators
  std::array<std::vector<double>, D> x0, v0;  ///< start of the current (sub)interval
  std::array<std::vector<double>, D> a0;      ///< acceleration at x0, v0
  std::array<std::vector<double>, D> x1, v1;  ///< end of a trial (sub)interval
  std::vector<std::int32_t> cell_start, cell_particles, particle_cell;
  /// Runs a step's parts; set by the host (e.g. platform::TwoWorkerPool), or
  /// left empty to run them in order on the calling thread.
  ParallelFor parallel;
  /// Part 0's pair contributions to part 1's particles, added after both parts.
  std::array<std::vector<double>, D> cross;
  /// The same for torques / I (rotating models; empty otherwise).
  std::array<std::vector<double>, spin_components(D)> cross_spin;
  std::vector<double> plane_force_part;  ///< per part, per plane (parts × planes)
  /// Frozen contact set for abm4_events: start-of-interval state the kernels read.
  ConstColumns<D> mode_x{}, mode_v{};
  /// The host's contacts and their context (DemDesc::external_contacts);
  /// nullptr: none are evaluated. Set by the host between steps.
  ExternalContacts<D> external_contacts = nullptr;
  /// Rotating models' (DemFeatures::rotation) instead; the same context.
  ExternalRotatingContacts<D> external_rotating_contacts = nullptr;
  void* external_context = nullptr;
  /// Time of the state being evaluated (moving planes), set before each evaluation.
  double eval_time = 0;
  /// Time of the frozen start-of-interval state (abm4_events).
  double mode_time = 0;
  /// Total normal force of each plane on the particles at the last
  /// evaluation (N), then the host's external_contact_totals.
  std::vector<double> plane_force;
  std::vector<double> plane_force0;    ///< at (x0, v0) (abm4_events)
  std::vector<double> plane_weighted;  ///< Σ weights · force of the step being built
  std::vector<double> plane_step_impulse;  ///< sum over the pieces of an event-split step
  std::int32_t grid_cells_used = 0;
  /// Which contacts carried a force at each force evaluation since the host
  /// last zeroed it, hashed in evaluation order (dem/forces.hpp, fold_contacts):
  /// two runs with the same value saw the same contacts at the same
  /// evaluations, but for a collision. The coupled stepper's test that its
  /// window was affine in its input.
  std::uint64_t contact_signature = 0;
  std::vector<double> network_row;  ///< per particle: the D × D bound matrix of network_omega2 (packed)
  // Rotating models: the trial angular state and torques / I of a step, and
  // the previous pair list's records while a rebuild merges them.
  std::array<std::vector<double>, spin_components(D)> w1, alpha1;
  std::array<std::vector<double>, angle_components(D)> angle1;
  /// RK4's stage angular velocity and acceleration and their weighted sums (and the 2D angle's).
  std::array<std::vector<double>, spin_components(D)> ws, alphas, sum_w;
  std::array<std::vector<double>, angle_components(D)> angle_s, sum_angle;
  /// abm4_events with rotation: the start of the step's remaining interval
  /// (with x0, v0): acceleration, angular velocity and acceleration, 2D angle.
  std::array<std::vector<double>, D> start_a;
  std::array<std::vector<double>, spin_components(D)> start_w, start_alpha;
  std::array<std::vector<double>, angle_components(D)> start_angle;
  std::vector<std::int32_t> old_pair_i, old_pair_j;
  std::array<std::vector<double>, spring_components(D)> old_pair_xi;
};

/// Validates `desc` and sizes model, state and workspace. The only call that
/// allocates. On failure the message names the field ("particles[3].mass").
/// Besides each field's own range it refuses, naming the particle:
///  - a particle that starts overlapping a plane by more than its radius (its
///    centre on the solid side), or another particle by more than the smaller
///    radius: its contact would throw it out at a speed no scene means
///    (invalid_argument; only the initial state is checked, a step may go deeper);
///  - arrays past DemDesc::max_memory_bytes, before allocating, and arrays the
///    allocator could not provide (memory): it never throws.
template <int D>
BuildResult build_dem(const DemDesc<D>& desc, DemModel<D>& model, DemState<D>& state, DemWorkspace<D>& workspace);

/// Advances the particles by model.dt. Never allocates, throws or locks. Every
/// EnergyCheck::interval steps the energy balance is checked (DemState::energy):
/// energy_growth from the check that finds it broken on.
template <int D>
StepStatus dem_step(const DemModel<D>& model, DemState<D>& state, DemWorkspace<D>& workspace);

/// `steps` calls of dem_step(), up to and including the first not taken
/// (kStepNotTaken); returns their flags together. The same steps with the
/// same bits; the small-system step runs them in one call (the coupled
/// window's substeps).
template <int D>
StepStatus dem_steps(const DemModel<D>& model, DemState<D>& state, DemWorkspace<D>& workspace, std::int32_t steps);

/// Moves plane p from now on: its point is at `offset` along its normal from
/// where it was built at the current time, moving at `speed` (m/s along the
/// normal). Call between steps (the coupled stepper does, once per continuum
/// step). If a particle touches the plane now, the force at the current state
/// changes with the plane's speed, so the stored acceleration is re-evaluated at
/// the next step and a multistep history restarts (three RK4 steps); otherwise
/// nothing else changes. A move of the plane's position changes the energy of
/// its contacts: the energy check books that as work done by the host (O(n)
/// when the check is on). Allocation-free.
template <int D>
void dem_drive_plane(const DemModel<D>& model, DemState<D>& state, std::int32_t plane, double offset, double speed);

/// Starts new energy books at the state as it is (not exceeded). No allocation.
template <int D>
void dem_restart_energy_ledger(const DemModel<D>& model, DemState<D>& state);

/// Tells the stepper that inputs it holds over a step (external forces) were
/// changed: the stored acceleration is re-evaluated at the next step and a
/// multistep history restarts. Allocation-free.
template <int D>
void dem_inputs_changed(DemState<D>& state);

/// to = from for two states of one model (the same array sizes), as a coupled
/// window saves and restarts its particles: each array by a plain loop,
/// walking the two states' one list of fields side by side. For the few
/// particles of a coupled scene that costs two thirds of DemState's
/// assignment, whose std::vector assignments check capacities and call
/// memmove for arrays of two values. States of other sizes take the
/// assignment, which may allocate. Out of line, so that a profile names it
/// (tools/callgrind_steps.py).
template <int D>
void dem_copy_state(DemState<D>& to, const DemState<D>& from);

/// into = (1 − θ)·into + θ·other for two states of one model, field by field
/// through the state's one list of fields, as a coupled window blends the
/// particles of its passes on the two sides of a jump of its map (a contact
/// closing at another substep). Equal values are kept as they are (a blend
/// of equal values could move them by an ulp); bounds (network_omega2,
/// energy_peak) take the larger. Returns false, changing nothing, unless
/// every integer field (pair list, history ring, counters) is the same in
/// both: then the two differ only in values, and the blend is a state the
/// window could have ended in.
template <int D>
bool dem_blend_state(DemState<D>& into, const DemState<D>& other, double theta);

/// Stable step factor y = ω h of an integrator for one linear contact with
/// damping ratio ζ: the largest ω h at which one undamped contact period
/// (2π/(ω h) steps) amplifies the free response by at most 1 %. See docs/dem.md.
double dem_stable_step_factor(DemIntegrator integrator, double damping_ratio);

/// Spectral radius of one step of `integrator` on the contact oscillator
/// δ'' + 2ζω δ' + ω² δ = 0 at ω h = y (what dem_stable_step_factor inspects).
double dem_amplification(DemIntegrator integrator, double damping_ratio, double y);

/// The same for a contact's tangential spring mode ξ'' + 2ζω ξ' + ω² ξ = 0 as
/// the integrator advances it: Verlet and symplectic Euler as their own
/// oscillator, RK4 and ABM4 with the spring advanced to first order from ξ_n
/// at each evaluation and kept as ξ_n + h u_n+1 (docs/dem.md).
double dem_tangential_amplification(DemIntegrator integrator, double damping_ratio, double y);

/// Stable step factor of the tangential spring mode (as dem_stable_step_factor).
double dem_tangential_stable_step_factor(DemIntegrator integrator, double damping_ratio);

/// Model, state and workspace of one world, for callers who do not need them
/// apart (the split exists so that many states can share one model).
template <int D>
struct DemWorld {
  DemModel<D> model;
  DemState<D> state;
  DemWorkspace<D> workspace;
  BuildResult build(const DemDesc<D>& desc) { return build_dem(desc, model, state, workspace); }
  StepStatus step() { return dem_step(model, state, workspace); }
};

// ---- probes (read the current state; cheap, allocation-free) --------------

struct DemEnergy {
  double kinetic = 0;    ///< Σ ½ m v²
  double elastic = 0;    ///< Σ ½ K δ² over overlapping contacts (planes and pairs)
  double potential = 0;  ///< Σ −m g·x (datum x = 0)
};
template <int D>
DemEnergy dem_energy(const DemModel<D>& model, const DemState<D>& state);

/// Normal force K δ + η δ' between particles i and j (compressive positive; 0
/// when apart; slightly negative at the end of a `linear` contact; clamped at 0
/// for linear_nontensile), δ' at the state's velocities (Verlet's step used
/// its kicked v_n+1/2: see docs/dem.md, "Probes").
template <int D>
double dem_pair_force(const DemModel<D>& model, const DemState<D>& state, std::int32_t i, std::int32_t j);

/// Normal force between particle i and plane p (same conventions).
template <int D>
double dem_plane_force(const DemModel<D>& model, const DemState<D>& state, std::int32_t i, std::int32_t p);

/// Tangential force of a rotating model's contact on the second body, from
/// the stored spring and the state's velocities (the step's law, not
/// advanced; Verlet's step used its kicked v_n+1/2, see docs/dem.md):
/// 2D signed along t = (−n_y, n_x), n from particle i to particle j (a plane
/// is the first body: n its normal, the force on the particle); 3D its
/// magnitude. 0 when apart or in a model without friction; NaN for a bad index.
template <int D>
double dem_pair_tangential_force(const DemModel<D>& model, const DemState<D>& state, std::int32_t i, std::int32_t j);
template <int D>
double dem_plane_tangential_force(const DemModel<D>& model, const DemState<D>& state, std::int32_t i, std::int32_t p);

/// Angular velocity of particle i (component 0 in 2D; 0–2 in 3D), rad/s; 0
/// in a model that does not rotate; NaN for a bad index.
template <int D>
double dem_angular_velocity(const DemModel<D>& model, const DemState<D>& state, std::int32_t i, int component);
/// Linear momentum Σ m v of the particles along axis `component` (kg·m/s,
/// per unit thickness in 2D); NaN for a component outside 0 … D−1.
template <int D>
double dem_momentum(const DemModel<D>& model, const DemState<D>& state, int component);
/// 2D: the angle particle i has turned since t = 0 (rad, counter-clockwise); 0
/// in a model that does not rotate; NaN for a bad index or in 3D.
template <int D>
double dem_rotation(const DemModel<D>& model, const DemState<D>& state, std::int32_t i);

// ---- implementation of the template member ---------------------------------

template <int D>
template <class Visitor, class... Others>
void DemState<D>::for_each_array(Visitor&& visit, Others&... others) {
  visit("time", &time, 1, StateArray{&others.time, std::size_t{1}}...);
  visit("step", &step, 1, StateArray{&others.step, std::size_t{1}}...);
  for (int d = 0; d < D; ++d)
    visit("x", x[d].data(), x[d].size(), StateArray{others.x[d].data(), others.x[d].size()}...);
  for (int d = 0; d < D; ++d)
    visit("v", v[d].data(), v[d].size(), StateArray{others.v[d].data(), others.v[d].size()}...);
  for (std::size_t c = 0; c < w.size(); ++c)
    visit("w", w[c].data(), w[c].size(), StateArray{others.w[c].data(), others.w[c].size()}...);
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < spin_components(D); ++c) {
      visit("hist_w", hist_w[k][c].data(), hist_w[k][c].size(),
            StateArray{others.hist_w[k][c].data(), others.hist_w[k][c].size()}...);
      visit("hist_alpha", hist_alpha[k][c].data(), hist_alpha[k][c].size(),
            StateArray{others.hist_alpha[k][c].data(), others.hist_alpha[k][c].size()}...);
    }
  for (std::size_t c = 0; c < angle.size(); ++c)
    visit("angle", angle[c].data(), angle[c].size(), StateArray{others.angle[c].data(), others.angle[c].size()}...);
  for (std::size_t c = 0; c < pair_xi.size(); ++c)
    visit("pair_xi", pair_xi[c].data(), pair_xi[c].size(),
          StateArray{others.pair_xi[c].data(), others.pair_xi[c].size()}...);
  for (std::size_t c = 0; c < plane_xi.size(); ++c)
    visit("plane_xi", plane_xi[c].data(), plane_xi[c].size(),
          StateArray{others.plane_xi[c].data(), others.plane_xi[c].size()}...);
  for (int d = 0; d < D; ++d)
    visit("external_force", external_force[d].data(), external_force[d].size(),
          StateArray{others.external_force[d].data(), others.external_force[d].size()}...);
  // Listed only when on, so that a state without it keeps its layout and hashes.
  for (std::size_t c = 0; c < external_torque.size(); ++c)
    if (!external_torque[c].empty())
      visit("external_torque", external_torque[c].data(), external_torque[c].size(),
            StateArray{others.external_torque[c].data(), others.external_torque[c].size()}...);
  for (int s = 0; s < 4; ++s)
    for (int d = 0; d < D; ++d) {
      visit("hist_v", hist_v[s][d].data(), hist_v[s][d].size(),
            StateArray{others.hist_v[s][d].data(), others.hist_v[s][d].size()}...);
      visit("hist_a", hist_a[s][d].data(), hist_a[s][d].size(),
            StateArray{others.hist_a[s][d].data(), others.hist_a[s][d].size()}...);
    }
  visit("history_head", &history_head, 1, StateArray{&others.history_head, std::size_t{1}}...);
  visit("history_count", &history_count, 1, StateArray{&others.history_count, std::size_t{1}}...);
  visit("pair_count", &pair_count, 1, StateArray{&others.pair_count, std::size_t{1}}...);
  visit("pair_i", pair_i.data(), pair_i.size(), StateArray{others.pair_i.data(), others.pair_i.size()}...);
  visit("pair_j", pair_j.data(), pair_j.size(), StateArray{others.pair_j.data(), others.pair_j.size()}...);
  visit("pair_stiffness", pair_stiffness.data(), pair_stiffness.size(),
        StateArray{others.pair_stiffness.data(), others.pair_stiffness.size()}...);
  visit("pair_eta", pair_eta.data(), pair_eta.size(), StateArray{others.pair_eta.data(), others.pair_eta.size()}...);
  for (int d = 0; d < D; ++d)
    visit("x_ref", x_ref[d].data(), x_ref[d].size(), StateArray{others.x_ref[d].data(), others.x_ref[d].size()}...);
  visit("pairs_valid", &pairs_valid, 1, StateArray{&others.pairs_valid, std::size_t{1}}...);
  visit("plane_offset", plane_offset.data(), plane_offset.size(),
        StateArray{others.plane_offset.data(), others.plane_offset.size()}...);
  visit("plane_speed", plane_speed.data(), plane_speed.size(),
        StateArray{others.plane_speed.data(), others.plane_speed.size()}...);
  visit("plane_time", &plane_time, 1, StateArray{&others.plane_time, std::size_t{1}}...);
  visit("plane_impulse", plane_impulse.data(), plane_impulse.size(),
        StateArray{others.plane_impulse.data(), others.plane_impulse.size()}...);
  for (int k = 0; k < 4; ++k)
    visit("hist_plane_force", hist_plane_force[k].data(), hist_plane_force[k].size(),
          StateArray{others.hist_plane_force[k].data(), others.hist_plane_force[k].size()}...);
  visit("list_builds", &list_builds, 1, StateArray{&others.list_builds, std::size_t{1}}...);
  visit("peak_pairs", &peak_pairs, 1, StateArray{&others.peak_pairs, std::size_t{1}}...);
  visit("peak_neighbors", &peak_neighbors, 1, StateArray{&others.peak_neighbors, std::size_t{1}}...);
  visit("peak_grid_cells", &peak_grid_cells, 1, StateArray{&others.peak_grid_cells, std::size_t{1}}...);
  visit("peak_events", &peak_events, 1, StateArray{&others.peak_events, std::size_t{1}}...);
  visit("events_located", &events_located, 1, StateArray{&others.events_located, std::size_t{1}}...);
  visit("network_omega2", &network_omega2, 1, StateArray{&others.network_omega2, std::size_t{1}}...);
  visit("energy_reference", &energy.reference, 1, StateArray{&others.energy.reference, std::size_t{1}}...);
  visit("energy_work", &energy.work, 1, StateArray{&others.energy.work, std::size_t{1}}...);
  visit("energy_peak", &energy.peak, 1, StateArray{&others.energy.peak, std::size_t{1}}...);
  visit("energy_exceeded", &energy.exceeded, 1, StateArray{&others.energy.exceeded, std::size_t{1}}...);
}

}  // namespace xfdem
