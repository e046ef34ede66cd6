// The continuum of the coupled method in 1D: an elastic bar on [0, L] (base at
// x = 0, tip at x = L, positive displacement and force point up), meshed with
// 2-node elements, optionally cut by an interface (type b contact) that the
// X-FEM carries inside an element with the shifted Heaviside enrichment, and
// integrated in time with Newmark GN22. docs/xfem.md gives the formulation.
//
// Model / state / workspace split: build_bar() validates a BarDesc and is the
// only call that allocates; bar_step() advances the BarState in place and never
// allocates, throws, locks or reads a clock. A BarModel is immutable after build
// and may be shared by any number of states (each with its own workspace).
//
// Units: SI throughout (m, s, kg, N, Pa).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "xfdem/energy_check.hpp"
#include "xfdem/status.hpp"
#include "xfdem/xfem/banded.hpp"
#include "xfdem/xfem/newmark.hpp"

namespace xfdem {

/// The interface between the two continua (type b contact).
struct BarInterfaceDesc {
  enum class Behaviour : std::uint8_t {
    tied,        ///< penalty spring in tension and compression (the paper's constant Jacobian)
    unilateral,  ///< spring only while the sides interpenetrate (gap < 0): frictionless contact
  };
  double position = 0.0;   ///< x of the interface, m; strictly inside (0, length)
  double stiffness = 0.0;  ///< penalty spring between the two sides, N/m (the paper's 100·E·A)
  Behaviour behaviour = Behaviour::tied;
};

struct BarDesc {
  enum class Method : std::uint8_t {
    xfem,  ///< `elements` uniform elements; the cut one is enriched
    fem,   ///< conforming mesh: a duplicated node pair at the interface (elements + 1 elements, or
           ///< `elements` when the interface falls on a node, which is then duplicated)
  };
  enum class Base : std::uint8_t {
    fixed,      ///< u(0) = 0
    absorbing,  ///< Lysmer dashpot ρ c A (c = √(E/ρ)) to the ground, plus `base_stiffness`
  };
  enum class TipLoad : std::uint8_t {
    none,
    half_sine,  ///< F = tip_amplitude · sin(π t / tip_duration) for t ≤ tip_duration, else 0
    step,       ///< F = tip_amplitude for t ≥ 0
  };

  double length = 0.0;          ///< L, m
  double youngs_modulus = 0.0;  ///< E, Pa
  double area = 0.0;            ///< A, m²
  double density = 0.0;         ///< ρ, kg/m³
  int elements = 0;             ///< elements of the uniform background mesh
  Method method = Method::xfem;
  Base base = Base::fixed;
  double base_stiffness = 0.0;  ///< spring in parallel with the absorbing base's dashpot, N/m (absorbing only)
  std::optional<BarInterfaceDesc> interface;  ///< absent: a plain bar, no enrichment code path
  double beta = 0.25;   ///< Newmark β; (β, γ) must satisfy γ ≥ 1/2, β ≥ (γ + 1/2)²/4
  double gamma = 0.5;   ///< Newmark γ
  double dt = 0.0;      ///< time step, s
  TipLoad tip_load = TipLoad::none;
  double tip_amplitude = 0.0;  ///< N, positive up
  double tip_duration = 0.0;   ///< s (half_sine only; must be 0 otherwise)
  /// Unilateral interface: at most this many solves per step while the active
  /// set settles (one linear interface settles in at most 2).
  int max_active_set_iterations = 8;
  /// Unilateral interface: at most this many openings and closings located
  /// inside one step (each ends a substep exactly where the gap is zero; see
  /// bar_step()). Beyond it the step is taken whole, under the energy rule of
  /// bar_step(), and counted in BarWorkspace::last_unlocated.
  int max_interface_events = 64;
  /// Unilateral interface: the energy rule of bar_step() (on by default). Off
  /// only to measure what it costs in accuracy: a step may then gain energy
  /// at a switch, which the energy check reports (docs/stability.md).
  bool energy_rule = true;
  /// The energy balance check of bar_step(): Ê ≤ Ê0 + W (see BarState::energy).
  EnergyCheck energy_check;
  /// Upper bound on the number of unknowns; 0 sizes everything to the mesh.
  /// A mesh needing more is a BuildResult::Code::capacity failure.
  int max_dofs = 0;
};

/// Inputs of one step, applied at t_{n+1} (with the tip load).
struct BarInput {
  double tip_force = 0.0;  ///< extra force on the tip node, N, positive up (the particle coupling's share)
};

/// One integration cell: a parent 2-node element [x0, x1] whose linear shape
/// functions are integrated over [a, b] ⊂ [x0, x1]. An uncut element is one cell
/// with [a, b] = [x0, x1]; the cut X-FEM element is two cells (one per side) with
/// the same parent; the conforming mesh splits it into two ordinary elements.
struct BarCell {
  int dof[2] = {-1, -1};  ///< unknowns multiplying N0, N1; −1: constrained to zero
  double x0 = 0.0, x1 = 0.0;
  double a = 0.0, b = 0.0;
  /// 0 or 1 on the conforming mesh's short cell at the interface: that end's
  /// unknown is its offset from the other end's value (the end's value is the
  /// two unknowns' sum), so the cell's stiffness E·A/(s·h) sits on that
  /// unknown's diagonal alone (docs/xfem.md, "Small cuts"). −1: the unknowns
  /// are the end values.
  int offset_end = -1;
};

/// Everything build_bar() derives from a BarDesc. Immutable after build.
struct BarModel {
  BarDesc desc;
  bool built = false;
  int dofs = 0;                 ///< number of unknowns
  double element_length = 0.0;  ///< h of the uniform background mesh, m
  std::vector<BarCell> cells;   ///< ordered by x
  std::vector<int> element_cell;  ///< first cell of each background element

  // Interface (has_interface false: all of this is unused).
  bool has_interface = false;
  bool unilateral = false;
  double interface_position = 0.0;  ///< m
  double interface_stiffness = 0.0; ///< N/m
  int cut_element = -1;             ///< background element holding the interface (x_e < ξ ≤ x_{e+1})
  double cut_fraction = 0.0;        ///< (ξ − x_e)/h ∈ (0, 1]
  int gap_terms = 0;                ///< gap = Σ gap_coeff[i] u[gap_dof[i]] (upper minus lower side), m
  int gap_dof[4] = {-1, -1, -1, -1};
  double gap_coeff[4] = {0, 0, 0, 0};

  // Base and tip.
  int base_dof = -1;          ///< unknown of the base node (absorbing base), −1 when fixed
  double base_damping = 0.0;  ///< ρ c A, N·s/m (absorbing base)
  int tip_dof = -1;           ///< unknown of the node at x = L
  double tip_mass = 0.0;      ///< row sum of M at the tip unknown (its lumped share), kg

  // Operators. `stiffness` holds the elements and the base spring, not the
  // interface spring (added as k·g gᵀ through gap_dof/gap_coeff).
  xfem::SymmetricBand mass;
  xfem::SymmetricBand stiffness;
  std::vector<double> mass_row_sums;  ///< M·r (r the unknowns of a rigid translation by 1): rᵀMa, the net force on the bar
  /// The unknown that is an offset (BarCell::offset_end), 0 in a rigid
  /// translation (every other unknown is 1 there); −1: none.
  int offset_dof = -1;
  xfem::NewmarkScheme scheme;
  xfem::BandLdlt mass_factor;       ///< M alone, for a_0 (u is given there: the interface force goes to the right-hand side)
  /// M⁻¹ e_tip: the acceleration a unit tip force adds. bar_resolve_acceleration
  /// changes a by this times the change of force, instead of re-solving
  /// M a = f − C v − K u (whose round-off M⁻¹ amplifies by the inverse of a
  /// sliver cut's tiny phantom mass: see docs/xfem.md, Small cuts).
  std::vector<double> tip_unit_acceleration;
  /// M⁻¹ g (g the gap's coefficients): the acceleration a unit interface force
  /// along the gap adds. A switch of a unilateral interface's active set
  /// changes a by k·gap times this (the spring's force at the switch, about
  /// zero), instead of re-solving M a = f − C v − K u. Empty unless unilateral.
  std::vector<double> gap_unit_acceleration;
  /// Unilateral only, for the energy rule of bar_step(): rᵀMr (the bar's
  /// mass over its unknowns) and M⁻¹e_base (absorbing base; empty otherwise).
  double total_mass = 0.0;
  std::vector<double> base_unit_acceleration;
  /// True when a step is linear in BarInput::tip_force (a tied interface or
  /// none: no active set to change). Then tip_response_{u,v,a} hold how the end
  /// of one bar_resolve_acceleration + bar_step changes per newton of tip force
  /// (the homogeneous step from u = v = 0, a = M⁻¹e_tip), and
  /// tip_response_displacement the tip's share; the coupled step corrects a
  /// step to another force with them instead of taking it again. Empty otherwise.
  bool linear_in_tip_force = false;
  std::vector<double> tip_response_u, tip_response_v, tip_response_a;
  double tip_response_displacement = 0.0;
  xfem::BandLdlt effective_open;    ///< M + γΔt C + βΔt² K            (no interface, or unilateral open)
  xfem::BandLdlt effective_closed;  ///< M + γΔt C + βΔt² (K + k g gᵀ) (tied, or unilateral closed)
};

/// Everything a step changes. Plain data: copy it to snapshot, hash it through
/// for_each_field().
struct BarState {
  std::vector<double> u;  ///< unknowns (dofs): m. Nodal displacements, and at the cut element the
                          ///< phantom values (each side's field extrapolated to the far node)
  std::vector<double> v;  ///< their rates, m/s
  std::vector<double> a;  ///< their second rates, m/s²
  double time = 0.0;      ///< s, = step · dt
  std::int64_t step = 0;
  std::int32_t interface_closed = 0;  ///< 1 while the interface spring acts (always 1 when tied)
  double tip_input = 0.0;  ///< BarInput::tip_force that `a` was solved with, N
  /// The energy balance check's books, in the algorithmic energy
  /// Ê = ½vᵀMv + ½uᵀKu (+ ½k g² while the interface acts) + ½Δt²(β − γ/2) aᵀMa,
  /// which Newmark's scheme with β ≥ (γ + ½)²/4 never raises on a linear system
  /// beyond the work done on it: W is the work of the tip load, of BarInput and
  /// of the base's dashpot, with the scheme's weights (docs/stability.md).
  EnergyLedger energy;
  double input_work = 0.0;  ///< the part of energy.work that BarInput::tip_force did, J

  /// Calls visitor(name, pointer, count) for every field, in a fixed order.
  template <class Visitor>
  void for_each_field(Visitor&& visitor) {
    visit_fields(*this, visitor);
  }
  template <class Visitor>
  void for_each_field(Visitor&& visitor) const {
    visit_fields(*this, visitor);
  }

 private:
  /// The one list of fields, for a const and a mutable state alike.
  template <class Self, class Visitor>
  static void visit_fields(Self& self, Visitor& visitor) {
    visitor("u", self.u.data(), self.u.size());
    visitor("v", self.v.data(), self.v.size());
    visitor("a", self.a.data(), self.a.size());
    visitor("time", &self.time, std::size_t{1});
    visitor("step", &self.step, std::size_t{1});
    visitor("interface_closed", &self.interface_closed, std::size_t{1});
    visitor("tip_input", &self.tip_input, std::size_t{1});
    visitor("input_work", &self.input_work, std::size_t{1});
    visitor("energy_reference", &self.energy.reference, std::size_t{1});
    visitor("energy_work", &self.energy.work, std::size_t{1});
    visitor("energy_peak", &self.energy.peak, std::size_t{1});
    visitor("energy_exceeded", &self.energy.exceeded, std::size_t{1});
  }
};

/// Scratch of a step, sized at build.
struct BarWorkspace {
  std::vector<double> u_pred, v_pred, rhs;
  // Unilateral interface only: the state a substep starts from, and the
  // effective matrix of a substep's length with its factor.
  std::vector<double> u_start, v_start, a_start;
  /// Unilateral interface only: the state the step started from.
  std::vector<double> u_step, v_step, a_step;
  xfem::SymmetricBand substep_matrix;
  xfem::BandLdlt substep_factor;
  /// Diagnostics of the last bar_step(): interface events located in it (0: one
  /// Newmark step of Δt), and substep factorisations it took.
  int last_events = 0;
  int last_factorisations = 0;
  /// The external impulse of the last bar_step(): Σ over its substeps of
  /// h·[(1 − γ) 1ᵀM a_start + γ 1ᵀM a_end], the net force the scheme integrates
  /// (the tip load and input, the base's dashpot and spring, or a fixed base's
  /// reaction: the elastic and interface forces are internal). By Newmark's
  /// momentum identity the bar's momentum 1ᵀMv changes by exactly this. A
  /// step split at interface events samples the forces at its substeps' ends,
  /// not only at t_n and t_{n+1}.
  double last_external_impulse = 0.0;
  /// What the last bar_step() booked, so that a linear model's step can be
  /// re-booked for another tip force (the coupled step's correction): where it
  /// started (tip and base motion, load and input) and the work it booked.
  struct StepStart {
    double u_tip = 0, u_base = 0, v_base = 0, load = 0, input = 0;
  } last_start;
  double work_before = 0.0, input_work_before = 0.0;  ///< BarState's books before it booked
  double last_net_force[2] = {0.0, 0.0};
  /// Unilateral interface: the gap the last solve's spring acted on,
  /// gᵀ(ũ + βh²a) as the solve saw it (not gᵀu of the rounded u). An opening
  /// takes out exactly that force (step_with_events).
  double solved_gap = 0.0;
  /// Unilateral interface, the last bar_step(): switches it could not place
  /// where the gap is zero (the crossing not found to round-off, or more than
  /// max_interface_events), and the energy the step's rule took out, J (both
  /// 0 on a step that needed neither; see bar_step()).
  int last_unlocated = 0;
  double last_energy_removed = 0.0;
  /// What the rule could not take out of the last step (J; 0 but where the
  /// velocity could not give a gain that was not an opening).
  double last_energy_left = 0.0;
  /// An opening whose gain the velocity could not give, taken by the last
  /// bar_step() with the spring held to the step's end: 1 when the faces had
  /// separated there and it released them (the set open, the spring's force
  /// taken out of a); 2 when it kept the set closed with g > 0 for the next
  /// step's solve to open (a sliver cut, or a release whose change of a the
  /// velocity could not pay for); 0 otherwise. a always holds the force of
  /// the set the step ends with.
  int last_held_open = 0;
};

/// Validates every field (the message starts with the field's name, e.g.
/// "interface.position: ..."), meshes, assembles, factors, and sets the state to
/// rest at t = 0 with a_0 from M a_0 = f(0). On failure the model is not built
/// and bar_step() returns StepStatus::not_built.
BuildResult build_bar(const BarDesc& desc, BarModel& model, BarState& state, BarWorkspace& workspace);

/// Turns the step bar_step() just took into the one it would have taken with
/// `tip_force` instead, for a model linear in it (BarModel::linear_in_tip_force;
/// otherwise returns not_built and changes nothing): the state moves along
/// BarModel::tip_response_*, and the step's books (impulse, work) are booked
/// again as if that force had acted throughout. O(dofs), no solve; never
/// allocates. The step must have been taken right after
/// bar_resolve_acceleration() with its input (the coupled window's pattern),
/// with the bar's own energy check off (a check already taken is not redone).
StepStatus bar_adjust_step_input(const BarModel& model, BarState& state, BarWorkspace& workspace, double tip_force);

/// Blends the two ends of one step taken from the same state under two tip
/// forces (the coupled window at a jump of its impulse, docs/coupling.md):
/// into = (1 − θ)·into + θ·other for u, v, a, the tip input and the books (the
/// books' peak the larger; equal values kept as they are). A unilateral
/// interface whose active set differs at the two ends is closed at the blend
/// when its blended gap is < 0 and the open end's gap ≥ 0, and open otherwise:
/// then ½k g² of the blend is at most the blend of the ends' (so is the rest
/// of Ê, convex), and the blend creates no energy. Where bar_step() locates
/// switches (under (¼, ½), whose Ê does not weigh a, and not at a sliver
/// cut), a is moved along M⁻¹g to hold that set's spring force, as at a
/// located switch (a blend of the ends' a holds the blend of theirs; each
/// end's a holds the force of its own set). Returns false, changing nothing,
/// unless both have the same sizes and step count and 0 < θ < 1. No allocation.
bool bar_blend_step_ends(const BarModel& model, BarState& into, const BarState& other, double theta);

/// Only the validation of build_bar() (no allocation), for tools that check input first.
BuildResult validate_bar(const BarDesc& desc);

/// Advances one step of dt: loads at t_{n+1} = (step + 1)·dt.
///
/// A unilateral interface is a force with a kink, which Newmark's average
/// integrates with a gain across a switch: k(1 − γ)|g_n|g_{n+1} − k(γ − ½)g_n²
/// at an opening (a closing only loses). Under (¼, ½) a step whose active set
/// changes is split where the gap reaches zero (regula falsi on the substep
/// length, each trial a Newmark substep with the old set held), and each
/// substep of a linear system conserves energy; other (β, γ), and a cut
/// within 1e-6 of an element from a node (either mesh), take the whole step. Then, for every step of a unilateral interface,
/// the energy rule: Ê at the end must not exceed Ê at the start plus the work
/// booked. An excess (beyond the round-off of those terms) is taken out of the
/// velocity, first the faces' relative velocity along g, then the rest of the
/// motion, each keeping the bar's momentum 1ᵀMv and an absorbing base's
/// velocity (BarWorkspace::last_energy_removed). A split step the velocity
/// cannot pay for, or one with a switch it could not place at the zero
/// (BarWorkspace::last_unlocated), is taken whole instead; an opening the
/// velocity cannot pay for is taken with the spring held to the end of the
/// step, a linear step, and released there if the faces have separated (the
/// set opened, ½k g² dropped and the spring's force taken out of a), but at a
/// sliver cut, where the set stays closed for the next step's solve to open
/// (BarWorkspace::last_held_open). What is still left is reported in
/// BarWorkspace::last_energy_left (docs/stability.md says where it was seen).
/// A step without a change is exactly one Newmark step.
/// Every EnergyCheck::interval steps the energy balance is checked (BarState::energy).
/// Returns ok, or
/// energy_growth (the check found Ê above Ê0 + W by more than its tolerance,
/// at this step or an earlier one), or
/// active_set_not_converged (the active-set loop did not settle within
/// max_active_set_iterations solves; step taken with the last set), or
/// non_finite (step taken, the state holds the non-finite values), or
/// not_built (nothing done).
StepStatus bar_step(const BarModel& model, BarState& state, BarWorkspace& workspace, const BarInput& input = {});

/// Recomputes state.a from the equation of motion at state.time
/// (M a = f − C v − K u, interface active set from the current gap), with
/// `input` as the extra tip force, and restarts the energy ledger from the
/// state as it is (an edit is not work the ledger could book). Call after
/// editing u or v. No allocation.
StepStatus bar_initial_acceleration(const BarModel& model, BarState& state, BarWorkspace& workspace,
                                    const BarInput& input = {});

/// Changes state.a to hold `input` as the extra tip force at state.time instead
/// of state.tip_input, keeping the energy ledger: for a host that changes the
/// force held over the coming step (the coupled stepper). The state's a is the
/// equation of motion's solution for its tip_input (bar_step and
/// bar_initial_acceleration leave it so), so the new one is exactly
/// a + M⁻¹e_tip·(input − tip_input): an axpy, the same bits when the force is
/// unchanged, and no round-off of K u divided by a sliver's phantom mass (a
/// full re-solve injected that at every call and pumped the sliver's mode).
/// The change of ½Δt²(β − γ/2) aᵀMa this makes is not booked as work (it is
/// zero for β = ¼, γ = ½). No allocation.
StepStatus bar_resolve_acceleration(const BarModel& model, BarState& state, BarWorkspace& workspace,
                                    const BarInput& input);

/// Starts new energy books at the state as it is (Ê0 = Ê, W = 0, not exceeded).
void bar_restart_energy_ledger(const BarModel& model, BarState& state);

/// The tip load of the description at time t, N.
double bar_tip_load(const BarModel& model, double t);

/// Displacement at x ∈ [0, L], m, through the (enriched) shape functions. At the
/// interface coordinate: the value just below it. NaN outside [0, L].
double bar_displacement(const BarModel& model, const BarState& state, double x);
/// Velocity at x, m/s, same conventions.
double bar_velocity(const BarModel& model, const BarState& state, double x);
/// Upper minus lower displacement at the interface, m (positive: open). 0 without interface.
double bar_interface_gap(const BarModel& model, const BarState& state);
/// Tip (x = L) displacement and velocity.
double bar_tip_displacement(const BarModel& model, const BarState& state);
double bar_tip_velocity(const BarModel& model, const BarState& state);

struct BarEnergy {
  double kinetic = 0.0;  ///< ½ vᵀ M v, J
  double elastic = 0.0;  ///< ½ uᵀ K u, J: elements, base spring, and the interface spring while it acts
};
BarEnergy bar_energy(const BarModel& model, const BarState& state);
/// Ê = kinetic + elastic + ½Δt²(β − γ/2) aᵀMa: the energy the energy check books (J).
double bar_algorithmic_energy(const BarModel& model, const BarState& state);

}  // namespace xfdem
