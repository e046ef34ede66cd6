// The 2D continuum: an elastic plate (a plane-strain or plane-stress slice of
// thickness t) on a rectangle, meshed with a structured grid of bilinear quads
// (Q4), consistent mass, integrated in time with Newmark GN22 through the same
// xfem::newmark_step() as the bar (its matrices assembled in the bar's profile
// storage, factored by a sparse LDLᵀ on a fill-reducing ordering), or solved
// once (static).
// docs/xfem2d.md gives the formulation. Discontinuities (PlateDiscontinuity)
// are given by geometry that ignores the mesh: cracks that cut through the
// whole plate or end inside it (shifted-Heaviside enrichment; faces free, or
// tied by a penalty, or unilateral: only closing resisted), inclusions (a
// second material, ridge enrichment), voids (no material), and crack tips
// (branch enrichment).
//
// Model / state / workspace split as the bar's: build_plate() validates a
// PlateDesc and is the only call that allocates; plate_step() advances the
// PlateState in place and never allocates, throws, locks or reads a clock.
//
// Units: SI (m, s, kg, N, Pa). Forces and masses are those of the slice of
// thickness `thickness` (a plane-strain scene's "per metre" with thickness 1).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "xfdem/energy_check.hpp"
#include "xfdem/status.hpp"
#include "xfdem/xfem/banded.hpp"
#include "xfdem/xfem/newmark.hpp"

namespace xfdem {

enum class PlateEdge : std::uint8_t { left, right, bottom, top };

/// Time shape of a load, as the bar's tip load: none (no load), step (the
/// amplitude for t ≥ 0), half_sine (amplitude · sin(π t / duration) for
/// t ≤ duration, then 0).
enum class PlateLoadShape : std::uint8_t { none, step, half_sine };

/// Supports of one edge: the fixed components are held at zero on every node
/// of the edge (corners included). `absorbing` puts Lysmer dashpots on the edge's
/// free components: ρ c_p on the normal one, ρ c_s on the tangential one, per
/// unit area of the edge, lumped to its nodes (each gets its share of the
/// edge's length times the thickness); where a discontinuity reaches the
/// edge, with the material of each part and on the enrichment unknowns too
/// (docs/xfem2d.md, "Absorbing edges").
struct PlateSupport {
  PlateEdge edge = PlateEdge::left;
  bool fix[2] = {false, false};  ///< x, y
  bool absorbing = false;
};

/// Time shape of a prescribed displacement d (dynamic analysis): step (d for
/// t ≥ 0, the default: held at d from the start), half_sine (d · sin(π t /
/// duration) for t ≤ duration, then 0), ramp (d · t / duration for t ≤
/// duration, then d). A static analysis takes d (step only; the others are
/// refused: it has no time).
enum class PlatePrescribedShape : std::uint8_t { step, half_sine, ramp };

/// Both components of the node at `at` (within 1e-9 of a cell of one) held at
/// `displacement` times the shape's value at t (docs/xfem2d.md, "Prescribed
/// nodes with a time shape").
struct PlatePrescribed {
  double at[2] = {0, 0};
  double displacement[2] = {0, 0};
  PlatePrescribedShape shape = PlatePrescribedShape::step;
  double duration = 0.0;  ///< s, half_sine and ramp only (0 otherwise)
};

/// An edge traction (Pa, consistent nodal forces: each edge segment gives each
/// of its two nodes half its length × thickness × traction) or a point force
/// (N, spread to the nodes of the cell holding `at` by the shape functions
/// there). Components on constrained nodal components go to the reactions.
struct PlateLoad {
  enum class Kind : std::uint8_t { edge_traction, point_force };
  Kind kind = Kind::edge_traction;
  PlateEdge edge = PlateEdge::right;  ///< edge_traction
  double at[2] = {0, 0};              ///< point_force
  double value[2] = {0, 0};           ///< traction (Pa) or force (N), x and y
  PlateLoadShape shape = PlateLoadShape::step;
  double duration = 0.0;              ///< s, half_sine only (0 otherwise)
};

/// A linear elastic material (an inclusion's; the plate's are PlateDesc's fields).
struct PlateMaterial {
  double youngs_modulus = 0.0;  ///< Pa
  double poisson_ratio = 0.0;
  double density = 0.0;  ///< kg/m³
};

/// A discontinuity, by geometry that need not follow the mesh (docs/xfem2d.md).
struct PlateDiscontinuity {
  enum class Kind : std::uint8_t { crack, inclusion, hole };  ///< hole: the scene's "void"
  enum class Shape : std::uint8_t { polyline, circle, polygon };
  enum class Faces : std::uint8_t { free, tied, unilateral };
  std::string name;
  Kind kind = Kind::crack;
  Shape shape = Shape::polyline;  ///< crack: polyline; inclusion, hole: circle or polygon
  std::vector<std::array<double, 2>> points;  ///< polyline (crack) or closed polygon, m
  double centre[2] = {0, 0};                  ///< circle, m
  double radius = 0.0;                        ///< circle, m
  Faces faces = Faces::free;                  ///< crack
  /// Crack faces tied: traction k·[u] per unit area, k = (normal, tangential), Pa/m.
  double stiffness[2] = {0, 0};
  PlateMaterial material;  ///< inclusion
  /// Inclusion: enrich the nodes of the cells it cuts with the ridge (false:
  /// the cut cells are still integrated by material, but the kink inside a
  /// cell is not represented; for comparison only, no scene key).
  bool enrich = true;
};

struct PlateDesc {
  enum class Plane : std::uint8_t { strain, stress };
  enum class Analysis : std::uint8_t {
    dynamic,  ///< Newmark GN22 from rest at t = 0
    statics,  ///< one solve K u = f with every load at its amplitude (shape step; half_sine refused)
  };
  double min[2] = {0, 0};  ///< lower-left corner of the domain, m
  double max[2] = {0, 0};  ///< upper-right corner, m
  int cells[2] = {0, 0};   ///< nx, ny
  Plane plane = Plane::strain;
  double thickness = 1.0;       ///< m
  double youngs_modulus = 0.0;  ///< E, Pa
  double poisson_ratio = 0.0;   ///< ν: (−1, 1/2) in plane strain, (−1, 1/2] in plane stress
  double density = 0.0;         ///< ρ, kg/m³
  bool self_weight = false;     ///< body force ρ g on the plate
  double gravity[2] = {0, 0};   ///< m/s² (self_weight only)
  Analysis analysis = Analysis::dynamic;
  double beta = 0.25;  ///< Newmark β; γ ≥ 1/2, β ≥ (γ + 1/2)²/4 (dynamic only)
  double gamma = 0.5;  ///< Newmark γ
  double dt = 0.0;     ///< s (dynamic only)
  std::vector<PlateSupport> supports;
  std::vector<PlatePrescribed> prescribed;
  std::vector<PlateLoad> loads;
  /// The energy balance check of plate_step(): Ê ≤ Ê0 + W (see PlateState::energy).
  EnergyCheck energy_check;
  /// Upper bound on the number of unknowns; 0 sizes everything to the mesh.
  int max_dofs = 0;
  std::vector<PlateDiscontinuity> discontinuities;
  /// Capacities fixed at build: enriched unknowns, cut cells (integrated on
  /// sub-triangles) and crack-face quadrature points. Exceeding one fails the
  /// build with BuildResult::Code::capacity naming it.
  int max_enriched_dofs = 200000;
  int max_cut_cells = 100000;
  /// Tip enrichment (the scene's tip_enrichment.radius, m): 0 enriches the
  /// nodes of the cell holding each crack tip with the four branch functions
  /// (topological); r > 0 also every node within r of a tip (geometric).
  double tip_radius = 0.0;
  /// Absorbing edges act on the enrichment unknowns of a discontinuity that
  /// reaches them too (false: on the standard unknowns only, as before; for
  /// comparison only, no scene key).
  bool absorb_enrichment = true;
};

/// Everything build_plate() derives from a PlateDesc. Immutable after build.
struct PlateModel {
  PlateDesc desc;
  bool built = false;
  int nodes = 0;              ///< (nx + 1)(ny + 1), natural index n = j (nx + 1) + i
  int dofs = 0;               ///< free nodal components
  double cell_size[2] = {0, 0};
  double elasticity[3][3] = {};  ///< D: σ = D ε, ε = (ε_xx, ε_yy, γ_xy)
  double wave_speed[2] = {0, 0};  ///< c_p, c_s, m/s
  /// Unknown of natural node n's component c at [2n + c]; −1 when held
  /// (then node_held[2n + c] is its displacement).
  std::vector<int> node_dof;
  std::vector<double> node_held;
  std::vector<double> node_mass;  ///< ρ t ∫ N_n dA, kg: column sums of the full consistent mass
  /// The loads, flattened: entry e adds load_value[e]·shape_{load_of[e]}(t) to unknown load_dof[e].
  std::vector<int> load_dof, load_of;
  std::vector<double> load_value;
  /// Lumped dashpots of absorbing edges: damper_coeff[d] (N·s/m) on unknown damper_dof[d].
  std::vector<int> damper_dof;
  std::vector<double> damper_coeff;
  /// Where an enrichment reaches an absorbing edge, the dashpots' products
  /// that involve an enrichment function, kept consistent: block b couples
  /// unknowns absorb_dof[absorb_start[b] … absorb_start[b + 1]) by the
  /// row-major symmetric matrix at absorb_matrix[absorb_matrix_start[b]]
  /// (N·s/m; one block per edge segment and component; the products of two
  /// standard functions are 0 in it: those are lumped in damper_coeff).
  std::vector<int> absorb_start, absorb_dof, absorb_matrix_start;
  std::vector<double> absorb_matrix;
  /// −K_fh g: what the constant held displacements push on the unknowns.
  std::vector<double> held_force;
  /// Moving held components (a prescribed node whose shape is not step),
  /// empty without them: node_moving[2n + c] is h (−1: not moving), the
  /// natural component of h is moving_component[h], its prescribed entry
  /// moving_prescribed[h] and its amplitude moving_amplitude[h] (m). Their
  /// couplings, summed over the cells: with the unknowns, rows
  /// moving_free_start[h] … moving_free_start[h + 1] of (moving_free_dof,
  /// moving_free_k = K_fh, moving_free_m = M_fh); with the held components
  /// (constant or moving), rows moving_held_start[h] … of
  /// (moving_held_component (natural), moving_held_k, moving_held_m).
  std::vector<int> node_moving, moving_component, moving_prescribed;
  std::vector<double> moving_amplitude;
  std::vector<int> moving_free_start, moving_free_dof, moving_held_start, moving_held_component;
  std::vector<double> moving_free_k, moving_free_m, moving_held_k, moving_held_m;
  xfem::SymmetricBand mass;       ///< M on the unknowns
  xfem::SymmetricBand stiffness;  ///< K on the unknowns
  std::vector<double> mass_row_sums;  ///< M·1 (the net force 1ᵀMa the integrator sums)
  xfem::NewmarkScheme scheme;
  /// Sparse LDLᵀ on a minimum-degree ordering fixed at build (xfem::SparseLdlt).
  xfem::SparseLdlt mass_factor;       ///< M (initial acceleration), dynamic
  xfem::SparseLdlt effective_factor;  ///< M + γΔt C + βΔt² K, dynamic
  /// K, static: the profile factor, solved once at build (its round-off is
  /// what the static closed-form tests were set against).
  xfem::BandLdlt stiffness_factor;
  /// The 8×8 element stiffness and mass (all cells of the structured grid are
  /// the same rectangle), row-major, unknowns (x0, y0, x1, y1, x2, y2, x3, y3)
  /// with nodes counter-clockwise from the lower left.
  double element_stiffness[64] = {};
  double element_mass[64] = {};

  // ---- discontinuities (empty without them) ----------------------------------
  /// Level set of discontinuity k at natural node n: node_phi[k·nodes + n]
  /// (xfem/level_set.hpp: positive outside, left of a crack, 0 counts as +).
  std::vector<double> node_phi;
  /// Enrichments of node n: discontinuity node_enrichment[2n + s] (s = 0, 1; −1 none),
  /// its unknowns at enriched_dof[2(2n + s) + c] (−1: held at 0 by a support).
  std::vector<int> node_enrichment;
  std::vector<int> enriched_dof;
  int enriched_dofs = 0;  ///< unknowns of enrichment functions
  /// Per cell (c = j nx + i): the discontinuity that cuts it (−1 none); for an
  /// uncut cell, its material: 0 the plate's, 1 + k inclusion k's, −1 none (a hole).
  std::vector<int> cell_cut_by, cell_material;
  /// Per cell: the void or the inclusion that cuts it together with the crack
  /// cell_cut_by holds (a crack from a hole, a crack into an inclusion; −1
  /// none). Sized with cell_cut_by.
  std::vector<int> cell_second_cut;
  int cut_cells = 0;
  /// Elasticity and density of material 0 (the plate) and 1 + k (inclusion k).
  std::vector<std::array<double, 9>> material_elasticity;
  std::vector<double> material_density;
  /// Crack-face penalty points (tied or unilateral faces): the jump [u] at the
  /// point is Σ c_f a_f over the unknowns a_f of the functions that jump
  /// there: the crack's shifted Heaviside (c = 2 N_a) and, near a tip, the
  /// branch function √r sin(θ/2) (c = ±2√r N_a; the other three are
  /// continuous across the crack). Stored as the unknowns and the
  /// coefficients of the normal and tangential jumps, weight = thickness ×
  /// length × quadrature weight.
  static constexpr int kMaxFaceTerms = 16;  ///< 4 nodes × 2 components × (Heaviside, √r sin(θ/2))
  struct FacePoint {
    int terms;
    int dof[kMaxFaceTerms];
    double normal[kMaxFaceTerms], tangential[kMaxFaceTerms];
    double weight, k_normal, k_tangential;
    /// Unilateral faces: the normal penalty acts only while the faces
    /// interpenetrate ([u]·n < 0), frictionless (k_tangential = 0); not in K.
    bool unilateral;
  };
  int unilateral_points = 0;
  /// M + γΔt C + βΔt² K without the unilateral penalties (dynamic, with unilateral faces).
  xfem::SymmetricBand base_effective;
  std::vector<FacePoint> face_points;
  /// ρ t ∫ N_n ψ dA of node n's enrichment function in slot s, at [2n + s], kg.
  std::vector<double> enrichment_mass;

  // ---- crack tips (empty without them) ----------------------------------------
  /// A crack end strictly inside the domain: its frame (xfem::TipFrame's
  /// fields), the cell holding it and the point where the crack leaves that
  /// cell (the tip cell is fanned from the tip through it).
  struct Tip {
    int crack = -1;
    bool at_end = false;  ///< the polyline's last point (false: its first)
    double origin[2] = {0, 0};
    double cos_a = 1.0, sin_a = 0.0;
    int cell = -1;
    double exit[2] = {0, 0};  ///< parent coordinates in the tip cell
  };
  std::vector<Tip> tips;
  /// The tip whose four branch functions node n carries (−1 none), their
  /// unknowns at tip_dof[8n + 2i + c] (function i, component c; −1: held by a
  /// support), ρ t ∫ N_n (F_i − F_i(x_n)) dA at tip_mass[4n + i].
  std::vector<int> node_tip, tip_dof;
  std::vector<double> tip_mass;
  /// The tip in cell c (−1 none).
  std::vector<int> cell_tip;
  int tip_nodes = 0;

  // ---- K x cell by cell (the step's product; K's profile holds zeros) ---------
  /// The plain cells' 8 unknowns (−1: held), 8 per cell (element_stiffness applies).
  std::vector<int> plain_cell_dof;
  /// The other cells (cut, enriched, inclusion): cell e has other_cell_dof[
  /// other_cell_start[e] … other_cell_start[e + 1]) (−1: held) and its element
  /// stiffness, row-major, from other_cell_matrix[other_cell_matrix_start[e]].
  std::vector<int> other_cell_start, other_cell_dof, other_cell_matrix_start;
  std::vector<double> other_cell_matrix;
};

/// Everything a step changes. Plain data: copy it to snapshot, hash it through
/// for_each_field().
struct PlateState {
  std::vector<double> u;  ///< unknowns: free nodal displacements, m
  std::vector<double> v;  ///< m/s
  std::vector<double> a;  ///< m/s²
  /// Velocity and acceleration of the moving held components
  /// (PlateModel::moving_component; empty without them): Newmark's own,
  /// from their displacement d·g(t) (docs/xfem2d.md). Their displacement is
  /// a function of `time`, not state.
  std::vector<double> held_v, held_a;
  double time = 0.0;      ///< s, = step · dt
  std::int64_t step = 0;
  /// The energy balance check's books, in Ê = ½vᵀMv + ½uᵀKu (all nodes) +
  /// ½Δt²(β − γ/2)aᵀMa; W is the work of the loads (self weight included) and
  /// of the dashpots, with the scheme's weights.
  EnergyLedger energy;

  template <class Visitor>
  void for_each_field(Visitor&& visitor) {
    visit_fields(*this, visitor);
  }
  template <class Visitor>
  void for_each_field(Visitor&& visitor) const {
    visit_fields(*this, visitor);
  }

 private:
  template <class Self, class Visitor>
  static void visit_fields(Self& self, Visitor& visitor) {
    visitor("u", self.u.data(), self.u.size());
    visitor("v", self.v.data(), self.v.size());
    visitor("a", self.a.data(), self.a.size());
    // Only with moving held components: every other scene's fields (and
    // their snapshots and hashes) stay as they were.
    if (!self.held_v.empty()) {
      visitor("held_v", self.held_v.data(), self.held_v.size());
      visitor("held_a", self.held_a.data(), self.held_a.size());
    }
    visitor("time", &self.time, std::size_t{1});
    visitor("step", &self.step, std::size_t{1});
    visitor("energy_reference", &self.energy.reference, std::size_t{1});
    visitor("energy_work", &self.energy.work, std::size_t{1});
    visitor("energy_peak", &self.energy.peak, std::size_t{1});
    visitor("energy_exceeded", &self.energy.exceeded, std::size_t{1});
  }
};

/// Scratch of a step, sized at build.
struct PlateWorkspace {
  std::vector<double> u_pred, v_pred, rhs;
  std::vector<double> solve_work;  ///< scratch of the factors' solves
  std::vector<double> shape_start, shape_end;       ///< each load's shape at t_n and t_{n+1}
  std::vector<double> load_u_start;                 ///< u at each load entry's unknown, at t_n
  std::vector<double> damper_u_start, damper_v_start;
  std::vector<double> absorb_u_start, absorb_v_start;  ///< u, v at absorb_dof, at t_n
  /// Moving held components: the accelerations the next solve uses, and
  /// the step's start (displacement, (Ma + Ku) on their rows) for the books.
  std::vector<double> held_accel, held_u_start, held_force_start;
  /// Σ h[(1 − γ) 1ᵀMa_n + γ 1ᵀMa_{n+1}] of the last step (free unknowns).
  double last_external_impulse = 0.0;
  /// Unilateral faces: the active set being tried, the one `factor` holds,
  /// and the effective matrix and its factor for it (sized at build).
  std::vector<char> active, factored_active;
  xfem::SymmetricBand effective;
  xfem::SparseLdlt factor;
  /// When the active set cycles, the damped Newton iteration that follows
  /// (docs/xfem2d.md, "Unilateral faces"): its iterate, M_eff k − f at it
  /// and at the Newton point (per unknown), and each point's gap at the
  /// iterate and its change along the step (per face point).
  std::vector<double> line_k, line_q, line_qn, line_gap, line_dgap;
  std::int64_t damped_solves = 0;  ///< solves that needed the damped iteration (summed)
  /// The energy rule of unilateral faces (docs/xfem2d.md): the state the
  /// step started from, the points held closed when a step is redone, and
  /// its books: steps redone with openings held, energy taken out of the
  /// velocity (J, summed) and energy it could not take (J, summed).
  std::vector<double> u_start, v_start, a_start;
  std::vector<char> held;
  std::int64_t held_steps = 0;
  double energy_removed = 0.0, energy_left = 0.0;
  /// A host's force on the unknowns (N), held over a step like a load of
  /// shape step: empty (the default) for none, else one entry per unknown,
  /// sized by the host after build (the coupled 2D stepper's contact forces).
  /// Its work is the host's to book (the plate's energy check does not see
  /// it); plate_start_acceleration() makes the step start from it.
  std::vector<double> external_force;
};

/// Validates every field (the message starts with the field's name as in the
/// scene file's continuum block, e.g. "material.poisson_ratio: ..."). No allocation.
BuildResult validate_plate(const PlateDesc& desc);

/// Validates, meshes, assembles, factors. Dynamic: the state is at rest at
/// t = 0 (held nodes at their displacement) with a_0 from M a_0 = f(0) − K u_0.
/// Static: the state holds the solution of K u = f (v = a = 0). On failure the
/// model is not built and plate_step() returns StepStatus::not_built.
BuildResult build_plate(const PlateDesc& desc, PlateModel& model, PlateState& state, PlateWorkspace& workspace);

/// Advances one step of dt, loads at t_{n+1} = (step + 1)·dt. Returns ok,
/// energy_growth, non_finite (step taken) or not_built (nothing done; also for
/// a static model, which has nothing to step).
StepStatus plate_step(const PlateModel& model, PlateState& state, PlateWorkspace& workspace);

/// Recomputes state.a from M a = f(t) − C v − K u at state.time and restarts the
/// energy books: call after editing u or v. No allocation.
StepStatus plate_initial_acceleration(const PlateModel& model, PlateState& state, PlateWorkspace& workspace);

/// Recomputes state.a at state.time as plate_initial_acceleration() does, but
/// keeps the energy books: the acceleration a step starts from after the host
/// changed workspace.external_force (its right limit), so that Newmark
/// delivers the force's impulse f·Δt exactly. No allocation.
StepStatus plate_start_acceleration(const PlateModel& model, PlateState& state, PlateWorkspace& workspace);

/// The time shape of load `load` at t (1 for self weight, load index −1).
double plate_load_shape(const PlateModel& model, int load, double t);
/// The time shape of prescribed entry `prescribed` at t (its displacement is
/// desc.prescribed[prescribed].displacement times it); step: 1 for t ≥ 0.
double plate_prescribed_shape(const PlateModel& model, int prescribed, double t);

/// Field values at a point of the domain (within 1e-9 of a cell of its edges;
/// NaN outside), by the shape functions of the cell holding it (on a cell edge:
/// the cell with the smaller index). component 0: x, 1: y.
double plate_displacement(const PlateModel& model, const PlateState& state, double x, double y, int component);
double plate_velocity(const PlateModel& model, const PlateState& state, double x, double y, int component);
double plate_acceleration(const PlateModel& model, const PlateState& state, double x, double y, int component);
/// Stress at a point, Pa: component 0 σ_xx, 1 σ_yy, 2 σ_xy (same cell rule).
double plate_stress(const PlateModel& model, const PlateState& state, double x, double y, int component);

struct PlateEnergy {
  double kinetic = 0.0;    ///< ½ vᵀMv, J
  double elastic = 0.0;    ///< ½ uᵀKu over all nodes (held ones at their displacement), J
  double potential = 0.0;  ///< −∫ ρ g·u dV (self weight; datum: the undeformed plate), J
};
PlateEnergy plate_energy(const PlateModel& model, const PlateState& state);
/// Ê of the energy check: kinetic + elastic + ½Δt²(β − γ/2)aᵀMa, J (self
/// weight is booked as work, W, not as potential).
double plate_algorithmic_energy(const PlateModel& model, const PlateState& state);
/// ∫ ρ v_c dV (component c), kg·m/s.
double plate_momentum(const PlateModel& model, const PlateState& state, int component);

/// The force (N, x and y) the supports exert on the plate: Σ (K u) over the
/// rows of the held standard components (supports and prescribed nodes; the
/// held displacements at state.time), cell by cell from the element
/// stiffnesses the step uses, i.e. the stress resultant the plate passes to
/// them. It is the held rows' reaction of a plate at rest; in motion it
/// leaves out those rows' share of the consistent inertia (M_hf a_f), so that
/// R + Σ f = Σ_f (M a)_f, the free rows' inertia, summed as a rigid
/// translation sees them. Loads, self weight and a host's forces
/// (PlateWorkspace::external_force, the coupled stepper's contact forces)
/// that fall on held components are not in it: they never reach the
/// plate's unknowns and pass straight into the support. Both NaN for an
/// unbuilt model. No allocation.
void plate_support_reaction(const PlateModel& model, const PlateState& state, double reaction[2]);

/// The jump upper (left of the crack) minus lower across crack `crack` (an index
/// of desc.discontinuities) at a point on it: component 0 normal (left of the
/// polyline's direction, positive when opening), 1 tangential (along it). NaN
/// when the point is not in the plate or the index is not a crack.
double plate_crack_opening(const PlateModel& model, const PlateState& state, int crack, double x, double y,
                           int component);

/// One piece of cell (i, j) as the plate integrates it, in parent coordinates
/// (ξ, η ∈ [−1, 1], corners counter-clockwise): an uncut cell is one piece,
/// its four corners; a cut cell is the triangles of its four sub-triangles
/// split along the cutting level set, each on one side of it; the cell holding
/// a crack tip is the triangles fanned from the tip (at most 15). Pieces with
/// no material (a hole's) are not listed.
struct PlateCellPiece {
  int corners = 0;                     ///< 4 (an uncut cell) or 3
  double xi[4] = {}, eta[4] = {};
  int triangle = -1;                   ///< sub-triangle of a cut cell (−1: uncut)
  int side = 1;                        ///< side of the cutting level set (+1 uncut)
  int material = 0;                    ///< 0 the plate's, 1 + k inclusion k's
};
/// A cell cut by a crack and a void: up to 12 crack pieces, each split by the void in up to 3.
inline constexpr int kPlateMaxCellPieces = 36;
/// The pieces of cell (i, j) (read-only geometry of the model; 0 for an
/// unbuilt model, a cell out of range or a cell with no material).
int plate_cell_pieces(const PlateModel& model, int i, int j, PlateCellPiece out[kPlateMaxCellPieces]);
/// Whether the cut-cell geometry takes discontinuity k's exact level set at
/// the centre of cell (i, j) instead of its nodes' mean (a void's or an
/// inclusion's flat saddle, docs/xfem2d.md "Through nodes at a slant"), and
/// then that value. For the 2D contact boundary, which traces the same
/// sub-triangles. False for an unbuilt model or indices out of range.
bool plate_flat_centre(const PlateModel& model, int k, int i, int j, double& value);
/// Displacement, velocity and stress at parent point (ξ, η) of a piece of cell
/// (i, j) (from plate_cell_pieces), by the enriched field of the piece's own
/// side: on a crack, the two sides' pieces give the two faces' values.
void plate_piece_fields(const PlateModel& model, const PlateState& state, int i, int j, const PlateCellPiece& piece,
                        double xi, double eta, double u[2], double v[2], double stress[3]);

/// The plate's functions at one material point: parent point (ξ, η) of cell
/// (i, j), on side `side` (±1) of the discontinuity that cuts the cell (+1 for
/// an uncut cell): the standard N_a of the cell's four nodes, then the
/// enrichments of its enriched nodes, each with its unknowns. A field's value
/// there is Σ n[f]·(its unknown dof[f][c], or held[f][c] for a held
/// displacement); a force F there is Σ n[f]·F_c on each unknown dof[f][c].
/// Four standard, two Heaviside and four branch functions per node at most.
inline constexpr int kPlateMaxPointFunctions = 4 + 4 * 2 + 4 * 4;
struct PlatePointBasis {
  int count = 0;
  double n[kPlateMaxPointFunctions] = {};
  int dof[kPlateMaxPointFunctions][2] = {};       ///< −1: held (or absent)
  double held[kPlateMaxPointFunctions][2] = {};   ///< a held standard component's displacement at `time`, m
};
/// False for an unbuilt model or a cell out of range. `time` (s): where a
/// prescribed node moves, the held displacement is its value then. No allocation.
bool plate_point_basis(const PlateModel& model, int i, int j, double xi, double eta, int side, PlatePointBasis& out,
                       double time);

/// y −= K x on the unknowns, cell by cell (each cell's element stiffness, in
/// cell order, then the tied crack faces' penalties): the product the step
/// uses. Equals model.stiffness.subtract_product() to round-off. No allocation.
void plate_subtract_stiffness_product(const PlateModel& model, const double* x, double* y);

/// The stress intensity factors K_I, K_II (Pa·√m, in the tip's frame: mode
/// II positive when the local-y face slides towards local x) of the first
/// (at_end false) or last point of crack `crack`, by the domain form of the
/// interaction integral: the weight q is 1 on the nodes within `radius` of
/// the tip, 0 on the others, interpolated by the shape functions, and the
/// integral runs over the cells where it varies, on their own quadrature
/// (docs/xfem2d.md). Both NaN when that end is not a tip, the radius is not
/// positive and finite, no node is within it, or a node with q = 1 is on the
/// domain's boundary. No allocation.
///
/// `inertia` (the default) adds the inertia term of the dynamic interaction
/// integral of a stationary crack, ∫ ρ ü·∂u^aux/∂x₁ q dA over the cells where
/// q ≠ 0 (Réthoré, Gravouil and Combescure 2005, with static auxiliary
/// fields, whose kinetic cross term is zero); false gives the static form
/// alone (for comparison). In a static analysis ü = 0 and the two agree.
void plate_stress_intensity(const PlateModel& model, const PlateState& state, int crack, bool at_end, double radius,
                            double k[2], bool inertia = true);

/// Where a point lies: −1 outside the domain, 0 in material, 1 on a
/// discontinuity (within `tolerance` of it, by its exact level set), 2 in a
/// hole (a point on a crack's line inside a hole too: no material there).
int plate_point_region(const PlateDesc& desc, double x, double y, double tolerance);

/// The void whose interior holds the point (its exact level set negative:
/// no material there), as its index in desc.discontinuities, or −1. The
/// test plate_point_region's 2 and the refusals of point loads and
/// prescribed nodes in a void use.
int plate_void_at(const PlateDesc& desc, double x, double y);

/// What an end of a crack is: a tip (inside the domain by more than 1e-6 of
/// a cell (of min(h_x, h_y)) and not in a void), on the boundary (on or
/// outside it, or within 1e-6 of a cell of it: the tiny-cut rule puts such
/// an end on the boundary), or in a void (plate_void_at names which).
enum class PlateCrackEnd : std::uint8_t { tip, on_boundary, in_void };
PlateCrackEnd plate_crack_end(const PlateDesc& desc, int crack, bool at_end);

/// Q4 element matrices of a rectangle hx × hy (2×2 Gauss, exact for it):
/// stiffness t∫BᵀDB and consistent mass ρt∫NᵀN, 8×8 row-major, unknowns
/// (x0, y0, …, x3, y3), nodes counter-clockwise from the lower left.
void plate_element_matrices(double hx, double hy, const double elasticity[3][3], double thickness, double density,
                            double stiffness[64], double mass[64]);

}  // namespace xfdem
