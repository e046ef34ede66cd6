#include "xfdem/bar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <numbers>

#include "xfdem/xfem/element.hpp"
#include "xfem/bar_operator.hpp"

namespace xfdem {

namespace {

using Code = BuildResult::Code;

bool positive_finite(double x) { return std::isfinite(x) && x > 0.0; }

// ---- the one operation the integrator needs ---------------------------------

}  // namespace

namespace detail {

StepStatus BarOperator::implicit_solve(double fac0, double fac1, double t, const double* x, const double* v,
                                       double* k) const {
  (void)fac1;  // only selects the factorisation, which build fixed together with fac0
  const int n = m_.dofs;
  // One solve (no interface, or a tied one) is made in place in k; the active
  // set's loop keeps the right-hand side for its second solve.
  double* rhs = m_.unilateral ? ws_.rhs.data() : k;
  m_.stiffness.negated_product(x, rhs);  // −K x
  if (m_.base_dof >= 0) rhs[m_.base_dof] -= m_.base_damping * v[m_.base_dof];
  rhs[m_.tip_dof] += (homogeneous_ ? 0.0 : bar_tip_load(m_, t)) + extra_tip_force_;

  const bool initial = (fac0 == 0.0);
  const double gap_x = bar_gap_of(m_, x);
  // The interface spring's force on the unknowns at the predicted state, −k (gᵀx) g.
  auto solve_with = [&](bool closed) {
    if (rhs != k)
      for (int i = 0; i < n; ++i) k[i] = rhs[i];
    if (closed) {
      const double f = m_.interface_stiffness * gap_x;
      for (int i = 0; i < m_.gap_terms; ++i) k[m_.gap_dof[i]] -= f * m_.gap_coeff[i];
    }
    if (initial) {
      m_.mass_factor.solve(k);
    } else if (substep_factor_ != nullptr) {
      substep_factor_->solve(k);
    } else {
      (closed ? m_.effective_closed : m_.effective_open).solve(k);
    }
  };

  if (!m_.has_interface) {
    solve_with(false);
    return StepStatus::ok;
  }
  if (!m_.unilateral) {
    closed_ = 1;
    solve_with(true);
    return StepStatus::ok;
  }
  if (substep_factor_ != nullptr) {
    solve_with(closed_ != 0);
    ws_.solved_gap = gap_x + fac0 * bar_gap_of(m_, k);
    return StepStatus::ok;
  }
  if (initial) {
    // x does not move in this solve: the active set is read off the gap.
    closed_ = gap_x < 0.0 ? 1 : 0;
    solve_with(closed_ != 0);
    ws_.solved_gap = gap_x;
    return StepStatus::ok;
  }
  // Active set: start from last step's, solve, compare with the gap it gives.
  // For one spring the closed gap has the sign of the open one (the spring only
  // scales it by 1/(1 + k gᵀA⁻¹g)), so this settles in at most two solves; the
  // bound guards the contract, not a known cycle.
  // When both sets disagree with the gaps they give, the gaps are round-off:
  // in exact arithmetic they have one sign, but the closed one, the open one
  // scaled by 1/(1 + k gᵀA⁻¹g), is computed as gᵀũ + βh²gᵀa, which cancels to
  // ε|gᵀũ|; below that its sign is noise (a stiff penalty resting ahead of the
  // wave, gaps of 1e-34 m, flipped the set at every solve until the bound
  // reported active_set_not_converged). Either set is then consistent to
  // round-off; the one whose gap is smaller is kept. Its gap may have the other
  // sign by as much: a located event at the next step's start (step_with_events).
  const int max_iterations = m_.desc.max_active_set_iterations;
  double gap_other = 0.0;
  bool tried_other = false;
  for (int it = 0; it < max_iterations; ++it) {
    solve_with(closed_ != 0);
    const double gap_new = gap_x + fac0 * bar_gap_of(m_, k);
    ws_.solved_gap = gap_new;
    const std::int32_t want = gap_new < 0.0 ? 1 : 0;
    if (want == closed_) return StepStatus::ok;
    if (tried_other) {
      if (std::fabs(gap_new) > std::fabs(gap_other)) {
        closed_ = want;
        solve_with(closed_ != 0);
        ws_.solved_gap = gap_other;
      }
      return StepStatus::ok;
    }
    if (it + 1 == max_iterations) break;
    gap_other = gap_new;
    tried_other = true;
    closed_ = want;
  }
  return StepStatus::active_set_not_converged;
}

void assemble_effective(const BarModel& m, double fac0, double fac1, bool closed, xfem::SymmetricBand& out) {
  out = m.mass;  // same profile: reuses out's storage once it has held one
  for (int i = 0; i < m.dofs; ++i)
    for (int j = m.mass.first_column(i); j <= i; ++j) out.add(i, j, fac0 * m.stiffness.get(i, j));
  if (m.base_dof >= 0) out.add(m.base_dof, m.base_dof, fac1 * m.base_damping);
  if (closed)
    for (int i = 0; i < m.gap_terms; ++i)
      for (int j = 0; j <= i; ++j)
        out.add(m.gap_dof[i], m.gap_dof[j], fac0 * m.interface_stiffness * m.gap_coeff[i] * m.gap_coeff[j]);
}

}  // namespace detail

namespace {

BuildResult fail(const char* format, double value) {
  return BuildResult::failure(Code::invalid_argument, format, value);
}

/// A cell's values at its two ends from the unknowns f (BarCell::offset_end).
void cell_end_values(const BarCell& c, const double* f, double& d0, double& d1) {
  d0 = c.dof[0] >= 0 ? f[c.dof[0]] : 0.0;
  d1 = c.dof[1] >= 0 ? f[c.dof[1]] : 0.0;
  if (c.offset_end == 0) d0 += d1;
  if (c.offset_end == 1) d1 += d0;
}

/// d1 − d0 of a cell's end values; an offset cell's is its offset unknown
/// itself (no cancellation of two nearly equal end values).
double cell_rise(const BarCell& c, const double* f) {
  if (c.offset_end == 0) return -f[c.dof[0]];
  if (c.offset_end == 1) return f[c.dof[1]];
  const double d0 = c.dof[0] >= 0 ? f[c.dof[0]] : 0.0;
  const double d1 = c.dof[1] >= 0 ? f[c.dof[1]] : 0.0;
  return d1 - d0;
}

// Evaluate one field (u, v or a) at x.
double field_at(const BarModel& m, const std::vector<double>& f, double x) {
  if (!m.built || !(x >= 0.0 && x <= m.desc.length)) return std::numeric_limits<double>::quiet_NaN();
  const int ne = m.desc.elements;
  const int nc = static_cast<int>(m.cells.size());
  int e = static_cast<int>(x / m.element_length);
  e = std::clamp(e, 0, ne - 1);
  int c = m.element_cell[static_cast<std::size_t>(e)];
  while (c > 0 && x < m.cells[static_cast<std::size_t>(c)].a) --c;
  while (c + 1 < nc && x > m.cells[static_cast<std::size_t>(c)].b) ++c;
  // At the interface coordinate itself, the lower side.
  if (m.has_interface && c > 0 && x <= m.interface_position && m.cells[static_cast<std::size_t>(c)].a >= m.interface_position) --c;
  const BarCell& cell = m.cells[static_cast<std::size_t>(c)];
  const double h = cell.x1 - cell.x0;
  double d0 = 0.0, d1 = 0.0;
  cell_end_values(cell, f.data(), d0, d1);
  return (cell.x1 - x) / h * d0 + (x - cell.x0) / h * d1;
}

/// The energy check's books and the input they book with (0·x is NaN exactly
/// for a non-finite x).
bool ledger_finite(const BarState& st) {
  const EnergyLedger& l = st.energy;
  return 0.0 * st.tip_input + 0.0 * st.input_work + 0.0 * l.reference + 0.0 * l.work + 0.0 * l.peak == 0.0;
}

/// ½uᵀKu (and ½k g² while the interface acts), summed cell by cell from the
/// strains, ½·EA·(b − a)·((d1 − d0)/h)², rather than as uᵀKu: a rigid
/// displacement then has no energy to lose in cancellation (uᵀKu of a bar
/// lifted by 0.1 m carries ~1e-9 J of round-off, more than a slow gain).
double elastic_energy(const BarModel& m, const double* u, std::int32_t closed) {
  const double ea = m.desc.youngs_modulus * m.desc.area;
  double e = 0.0;
  for (const BarCell& c : m.cells) {
    const double h = c.x1 - c.x0;
    const double k = ea * (c.b - c.a) / (h * h);  // as xfem::bar_piece_matrices()
    // One unknown on both ends is assembled as 2k on its diagonal (see build).
    if (c.dof[0] >= 0 && c.dof[0] == c.dof[1]) {
      e += k * u[c.dof[0]] * u[c.dof[0]];
    } else {
      const double rise = cell_rise(c, u);
      e += 0.5 * k * rise * rise;
    }
  }
  if (m.base_dof >= 0) e += 0.5 * m.desc.base_stiffness * u[m.base_dof] * u[m.base_dof];
  if (m.has_interface && closed != 0) {
    const double g = detail::bar_gap_of(m, u);
    e += 0.5 * m.interface_stiffness * g * g;
  }
  return e;
}

bool all_finite(const std::vector<double>& f) {
  // 0·x is 0 for finite x and NaN otherwise; one sum, no branch per entry.
  double acc = 0.0;
  for (double x : f) acc += 0.0 * x;
  return acc == 0.0;
}

}  // namespace

BuildResult validate_bar(const BarDesc& d) {
  if (!positive_finite(d.length)) return fail("length: must be a positive finite number of metres, got %g", d.length);
  if (!positive_finite(d.youngs_modulus)) return fail("youngs_modulus: must be positive and finite (Pa), got %g", d.youngs_modulus);
  if (!positive_finite(d.area)) return fail("area: must be positive and finite (m^2), got %g", d.area);
  if (!positive_finite(d.density)) return fail("density: must be positive and finite (kg/m^3), got %g", d.density);
  if (d.elements < 1) return BuildResult::failure(Code::invalid_argument, "elements: must be at least 1, got %d", d.elements);
  if (d.method != BarDesc::Method::xfem && d.method != BarDesc::Method::fem)
    return BuildResult::failure(Code::invalid_argument, "method: must be xfem or fem, got %d", static_cast<int>(d.method));
  if (d.base != BarDesc::Base::fixed && d.base != BarDesc::Base::absorbing)
    return BuildResult::failure(Code::invalid_argument, "base: must be fixed or absorbing, got %d", static_cast<int>(d.base));
  if (!std::isfinite(d.base_stiffness) || d.base_stiffness < 0.0)
    return fail("base_stiffness: must be finite and >= 0 (N/m), got %g", d.base_stiffness);
  if (d.base == BarDesc::Base::fixed && d.base_stiffness != 0.0)
    return fail("base_stiffness: only an absorbing base has a spring; a fixed base needs 0, got %g", d.base_stiffness);
  if (d.interface) {
    const BarInterfaceDesc& i = *d.interface;
    if (!std::isfinite(i.position) || !(i.position > 0.0 && i.position < d.length))
      return BuildResult::failure(Code::invalid_argument,
                                  "interface.position: must lie strictly inside the bar (0, %g) m, got %g", d.length,
                                  i.position);
    if (!positive_finite(i.stiffness)) return fail("interface.stiffness: must be positive and finite (N/m), got %g", i.stiffness);
    if (i.behaviour != BarInterfaceDesc::Behaviour::tied && i.behaviour != BarInterfaceDesc::Behaviour::unilateral)
      return BuildResult::failure(Code::invalid_argument, "interface.behaviour: must be tied or unilateral, got %d",
                                  static_cast<int>(i.behaviour));
  }
  if (!positive_finite(d.dt)) return fail("dt: must be a positive finite time step (s), got %g", d.dt);
  // A non-finite β or γ is bad input; a finite one past the stability boundary
  // is a scheme no time step makes stable for a stiff enough mode (a penalty or
  // a sliver cut has one): unstable_time_step, as the DEM's limit is. Printed in
  // full, so a value a hair past the bound does not read as the bound.
  if (!std::isfinite(d.gamma)) return fail("gamma: Newmark gamma must be finite, got %g", d.gamma);
  if (!std::isfinite(d.beta)) return fail("beta: Newmark beta must be finite, got %g", d.beta);
  if (d.gamma < 0.5)
    return BuildResult::failure(Code::unstable_time_step,
                                "gamma: Newmark gamma must be >= 1/2 (stability), got %.17g", d.gamma);
  const xfem::NewmarkScheme scheme{d.beta, d.gamma, d.dt};
  if (!scheme.unconditionally_stable())
    return BuildResult::failure(Code::unstable_time_step,
                                "beta: Newmark beta must be >= (gamma + 1/2)^2 / 4 = %.17g for gamma = %.17g "
                                "(unconditional stability), got %.17g",
                                0.25 * (d.gamma + 0.5) * (d.gamma + 0.5), d.gamma, d.beta);
  switch (d.tip_load) {
    case BarDesc::TipLoad::none:
    case BarDesc::TipLoad::step:
      if (d.tip_duration != 0.0) return fail("tip_duration: only a half_sine load has a duration; must be 0, got %g", d.tip_duration);
      break;
    case BarDesc::TipLoad::half_sine:
      if (!positive_finite(d.tip_duration)) return fail("tip_duration: must be positive and finite (s), got %g", d.tip_duration);
      break;
    default:
      return BuildResult::failure(Code::invalid_argument, "tip_load: must be none, half_sine or step, got %d",
                                  static_cast<int>(d.tip_load));
  }
  if (!std::isfinite(d.tip_amplitude)) return fail("tip_amplitude: must be finite (N), got %g", d.tip_amplitude);
  if (d.tip_load == BarDesc::TipLoad::none && d.tip_amplitude != 0.0)
    return fail("tip_amplitude: a tip_load of none has no amplitude; must be 0, got %g", d.tip_amplitude);
  if (d.max_active_set_iterations < 1)
    return BuildResult::failure(Code::invalid_argument, "max_active_set_iterations: must be at least 1, got %d",
                                d.max_active_set_iterations);
  if (d.max_interface_events < 1)
    return BuildResult::failure(Code::invalid_argument, "max_interface_events: must be at least 1, got %d",
                                d.max_interface_events);
  if (d.max_dofs < 0) return BuildResult::failure(Code::invalid_argument, "max_dofs: must be >= 0, got %d", d.max_dofs);
  if (BuildResult r = validate_energy_check(d.energy_check); !r.ok()) return r;
  // Unknowns: nodes + 2 at most (phantoms or the duplicated node). Keep index arithmetic in int.
  if (d.elements > std::numeric_limits<int>::max() / 8)
    return BuildResult::failure(Code::capacity, "elements: %d is more than this build can index", d.elements);
  return BuildResult::success();
}

namespace {
BuildResult build_bar_sized(const BarDesc& d, BarModel& model, BarState& state, BarWorkspace& workspace);
}  // namespace

BuildResult build_bar(const BarDesc& d, BarModel& model, BarState& state, BarWorkspace& workspace) {
  model = BarModel{};
  state = BarState{};
  workspace = BarWorkspace{};
  if (BuildResult r = validate_bar(d); !r.ok()) return r;
  // The kernel never throws: an allocation the system refuses is a refusal,
  // and leaves nothing allocated.
  try {
    return build_bar_sized(d, model, state, workspace);
  } catch (const std::bad_alloc&) {
    model = BarModel{};
    state = BarState{};
    workspace = BarWorkspace{};
    return BuildResult::failure(Code::memory, "elements: the allocator could not provide the arrays of %d elements",
                                d.elements);
  }
}

namespace {
/// Below this fraction of an element, the conforming mesh's shorter cell at
/// the interface takes an offset as its unknown (BarCell::offset_end); above
/// it the end values lose at most ~ε/kOffsetCell to cancellation.
constexpr double kOffsetCell = 1e-2;

BuildResult build_bar_sized(const BarDesc& d, BarModel& model, BarState& state, BarWorkspace& workspace) {

  model.desc = d;
  const int ne = d.elements;
  const double h = d.length / ne;
  model.element_length = h;
  // Node i at L·i/ne: the tip is exactly L.
  auto node_x = [&](int i) { return i == ne ? d.length : d.length * i / ne; };
  const bool fixed = d.base == BarDesc::Base::fixed;
  const bool xfem = d.method == BarDesc::Method::xfem;

  // ---- locate the interface: element e with x_e < ξ ≤ x_{e+1} (H = 1 for φ ≥ 0,
  // so a node on the interface belongs to the upper side) -----------------------
  const bool has_if = d.interface.has_value();
  double xi = 0.0;
  int e = -1;
  if (has_if) {
    xi = d.interface->position;
    e = std::clamp(static_cast<int>(std::ceil(xi / h)) - 1, 0, ne - 1);
    while (e + 1 < ne && node_x(e + 1) < xi) ++e;
    while (e > 0 && node_x(e) >= xi) --e;
    model.has_interface = true;
    model.unilateral = d.interface->behaviour == BarInterfaceDesc::Behaviour::unilateral;
    model.interface_position = xi;
    model.interface_stiffness = d.interface->stiffness;
    model.cut_element = e;
    model.cut_fraction = (xi - node_x(e)) / h;
  }
  const bool on_node = has_if && node_x(e + 1) == xi;

  // ---- number the unknowns node by node (keeps the band narrow) ------------
  std::vector<int> u_dof(static_cast<std::size_t>(ne + 1), -1);
  int next = 0;
  int lower_phantom = -1;  // xfem: p_{e+1}, lower side extrapolated to node e+1
  int upper_phantom = -1;  // xfem: p_e, upper side extrapolated to node e (absent when ξ = x_{e+1})
  int if_lower = -1, if_upper = -1;  // fem: the duplicated node pair
  for (int i = 0; i <= ne; ++i) {
    if (has_if && !xfem && !on_node && i == e + 1) {  // fem: the interface node pair sits before node e+1
      if_lower = next++;
      if_upper = next++;
    }
    if (has_if && !xfem && on_node && i == e + 1) {  // fem: node e+1 on the interface, duplicated
      if_lower = next++;
      if_upper = next++;
      u_dof[static_cast<std::size_t>(i)] = if_upper;
      continue;
    }
    if (!(i == 0 && fixed)) u_dof[static_cast<std::size_t>(i)] = next++;
    if (has_if && xfem && i == e && !on_node) upper_phantom = next++;
    if (has_if && xfem && i == e + 1) lower_phantom = next++;
  }
  model.dofs = next;
  if (d.max_dofs > 0 && model.dofs > d.max_dofs)
    return BuildResult::failure(Code::capacity, "max_dofs: the mesh needs %d unknowns, more than max_dofs = %d",
                                model.dofs, d.max_dofs);

  // ---- cells ------------------------------------------------------------------
  model.element_cell.assign(static_cast<std::size_t>(ne), 0);
  for (int j = 0; j < ne; ++j) {
    model.element_cell[static_cast<std::size_t>(j)] = static_cast<int>(model.cells.size());
    const double x0 = node_x(j), x1 = node_x(j + 1);
    const int d0 = u_dof[static_cast<std::size_t>(j)], d1 = u_dof[static_cast<std::size_t>(j + 1)];
    if (!has_if || j != e) {
      model.cells.push_back({{d0, d1}, x0, x1, x0, x1});
    } else if (xfem) {
      // Lower side: N0 u_e + N1 p_{e+1} on [x_e, ξ]; upper: N0 p_e + N1 u_{e+1} on [ξ, x_{e+1}].
      model.cells.push_back({{d0, lower_phantom}, x0, x1, x0, xi});
      if (!on_node) model.cells.push_back({{upper_phantom, d1}, x0, x1, xi, x1});
    } else if (on_node) {
      model.cells.push_back({{d0, if_lower}, x0, x1, x0, x1});
    } else {
      // The shorter cell, when below kOffsetCell of an element, takes its
      // interface node's offset from its other node as the unknown: its
      // stiffness E·A/(s·h) then sits on that unknown's diagonal alone, where
      // the end values would couple two unknowns by it and lose ~ε/s of the
      // rest of the bar's stiffness to cancellation (a cut 1e-13 of an
      // element from a node moved the tip by 25 %; one ulp from it gave a
      // matrix that did not factor). The same space: the answer does not
      // jump where the unknowns change, beyond round-off (docs/xfem.md).
      BarCell lower{{d0, if_lower}, x0, xi, x0, xi}, upper{{if_upper, d1}, xi, x1, xi, x1};
      if (xi - x0 <= x1 - xi) {
        if (d0 >= 0 && xi - x0 < kOffsetCell * h) lower.offset_end = 1, model.offset_dof = if_lower;
      } else if (x1 - xi < kOffsetCell * h) {
        upper.offset_end = 0, model.offset_dof = if_upper;
      }
      model.cells.push_back(lower);
      model.cells.push_back(upper);
    }
  }

  // ---- the gap, upper minus lower side at ξ -----------------------------------
  if (has_if) {
    auto add_term = [&](int dof, double coeff) {
      if (dof < 0 || coeff == 0.0) return;
      model.gap_dof[model.gap_terms] = dof;
      model.gap_coeff[model.gap_terms] = coeff;
      ++model.gap_terms;
    };
    if (xfem) {
      const double n0 = (node_x(e + 1) - xi) / h, n1 = (xi - node_x(e)) / h;
      add_term(upper_phantom, n0);
      add_term(u_dof[static_cast<std::size_t>(e + 1)], n1);
      add_term(u_dof[static_cast<std::size_t>(e)], -n0);
      add_term(lower_phantom, -n1);
    } else {  // each side's end value at ξ (cell_end_values)
      add_term(if_upper, 1.0);
      if (model.offset_dof == if_upper) add_term(u_dof[static_cast<std::size_t>(e + 1)], 1.0);
      add_term(if_lower, -1.0);
      if (model.offset_dof == if_lower) add_term(u_dof[static_cast<std::size_t>(e)], -1.0);
    }
  }

  // ---- assemble: each row stored from the first unknown it couples to -----
  std::vector<int> first(static_cast<std::size_t>(model.dofs));
  for (int i = 0; i < model.dofs; ++i) first[static_cast<std::size_t>(i)] = i;
  auto couple = [&](int i, int j) {
    if (i < 0 || j < 0) return;
    if (i < j) std::swap(i, j);
    first[static_cast<std::size_t>(i)] = std::min(first[static_cast<std::size_t>(i)], j);
  };
  for (const BarCell& c : model.cells) couple(c.dof[0], c.dof[1]);
  for (int i = 0; i < model.gap_terms; ++i)
    for (int j = 0; j < model.gap_terms; ++j) couple(model.gap_dof[i], model.gap_dof[j]);
  const double ea = d.youngs_modulus * d.area;
  const double rho_a = d.density * d.area;
  model.mass.resize(model.dofs, first);
  model.stiffness.resize(model.dofs, first);
  const int kd = model.mass.bandwidth();
  for (const BarCell& c : model.cells) {
    xfem::PieceMatrices pm = xfem::bar_piece_matrices(ea, rho_a, c.x0, c.x1, c.a, c.b);
    if (c.offset_end >= 0) {  // end values = T·unknowns: Tᵀ(·)T
      xfem::Mat2 t = xfem::Mat2::Identity();
      t(c.offset_end, 1 - c.offset_end) = 1.0;
      pm.mass = (t.transpose() * pm.mass * t).eval();
      pm.stiffness = (t.transpose() * pm.stiffness * t).eval();
    }
    for (int r = 0; r < 2; ++r)
      for (int s = 0; s <= r; ++s) {
        if (c.dof[r] < 0 || c.dof[s] < 0) continue;
        if (r != s && c.dof[r] == c.dof[s]) continue;
        model.mass.add(c.dof[r], c.dof[s], pm.mass(r, s));
        model.stiffness.add(c.dof[r], c.dof[s], pm.stiffness(r, s));
      }
  }
  if (!fixed) {
    model.base_dof = u_dof[0];
    model.base_damping = d.density * std::sqrt(d.youngs_modulus / d.density) * d.area;
    model.stiffness.add(model.base_dof, model.base_dof, d.base_stiffness);
  }
  model.tip_dof = u_dof[static_cast<std::size_t>(ne)];
  {
    std::vector<double> rigid(static_cast<std::size_t>(model.dofs), 1.0);  // a translation by 1
    if (model.offset_dof >= 0) rigid[static_cast<std::size_t>(model.offset_dof)] = 0.0;
    model.mass_row_sums.assign(static_cast<std::size_t>(model.dofs), 0.0);
    model.mass.multiply(rigid.data(), model.mass_row_sums.data());
  }
  for (int j = std::max(0, model.tip_dof - kd); j <= std::min(model.dofs - 1, model.tip_dof + kd); ++j)
    if (j != model.offset_dof) model.tip_mass += model.mass.get(model.tip_dof, j);

  // ---- factor -----------------------------------------------------------------
  model.scheme = xfem::NewmarkScheme{d.beta, d.gamma, d.dt};
  const double fac0 = model.scheme.fac0(), fac1 = model.scheme.fac1();
  xfem::SymmetricBand eff;
  auto build_effective = [&](bool closed) { detail::assemble_effective(model, fac0, fac1, closed, eff); };

  if (!model.mass_factor.factor(model.mass))
    return BuildResult::failure(Code::invalid_argument, "elements: the mass matrix is not positive definite");
  model.tip_unit_acceleration.assign(static_cast<std::size_t>(model.dofs), 0.0);
  model.tip_unit_acceleration[static_cast<std::size_t>(model.tip_dof)] = 1.0;
  model.mass_factor.solve(model.tip_unit_acceleration.data());
  if (model.unilateral) {
    model.gap_unit_acceleration.assign(static_cast<std::size_t>(model.dofs), 0.0);
    for (int i = 0; i < model.gap_terms; ++i)
      model.gap_unit_acceleration[static_cast<std::size_t>(model.gap_dof[i])] += model.gap_coeff[i];
    model.mass_factor.solve(model.gap_unit_acceleration.data());
    for (int i = 0; i < model.dofs; ++i)
      if (i != model.offset_dof) model.total_mass += model.mass_row_sums[static_cast<std::size_t>(i)];
    if (!fixed) {
      model.base_unit_acceleration.assign(static_cast<std::size_t>(model.dofs), 0.0);
      model.base_unit_acceleration[static_cast<std::size_t>(u_dof[0])] = 1.0;
      model.mass_factor.solve(model.base_unit_acceleration.data());
    }
  }
  if (!has_if || model.unilateral) {
    build_effective(false);
    if (!model.effective_open.factor(eff))
      return BuildResult::failure(Code::invalid_argument, "dt: the effective stiffness is not positive definite");
  }
  if (has_if) {
    build_effective(true);
    if (!model.effective_closed.factor(eff))
      return BuildResult::failure(Code::invalid_argument, "dt: the effective stiffness is not positive definite");
  }

  const auto n = static_cast<std::size_t>(model.dofs);
  workspace.u_pred.assign(n, 0.0);
  workspace.v_pred.assign(n, 0.0);
  workspace.rhs.assign(n, 0.0);
  // ---- the step's response to the tip force, where it is linear ---------------
  // One homogeneous step (no load, u = v = 0) under a unit tip force, from the
  // acceleration a unit force adds at its start (what bar_resolve_acceleration does).
  model.linear_in_tip_force = !model.unilateral;
  if (model.linear_in_tip_force) {
    model.tip_response_u.assign(n, 0.0);
    model.tip_response_v.assign(n, 0.0);
    model.tip_response_a = model.tip_unit_acceleration;
    std::int32_t closed = has_if ? 1 : 0;
    const detail::BarOperator op(model, workspace, 1.0, closed, detail::BarOperator::homogeneous);
    double net_force[2];
    (void)xfem::newmark_step(model.scheme, op, model.scheme.dt, model.tip_response_u.data(),
                             model.tip_response_v.data(), model.tip_response_a.data(), workspace.u_pred.data(),
                             workspace.v_pred.data(), model.mass_row_sums.data(), net_force);
    model.tip_response_displacement = model.tip_response_u[static_cast<std::size_t>(model.tip_dof)];  // as bar_tip_displacement
  }

  // ---- state at rest, a_0 from the equation of motion at t = 0 ---------------
  state.u.assign(n, 0.0);
  state.v.assign(n, 0.0);
  state.a.assign(n, 0.0);
  state.interface_closed = (has_if && !model.unilateral) ? 1 : 0;
  if (model.unilateral) {
    // Size the substep scratch now (a factor of this profile), so that a step
    // that locates an interface event allocates nothing.
    workspace.u_start.assign(n, 0.0);
    workspace.v_start.assign(n, 0.0);
    workspace.a_start.assign(n, 0.0);
    workspace.u_step.assign(n, 0.0);
    workspace.v_step.assign(n, 0.0);
    workspace.a_step.assign(n, 0.0);
    workspace.substep_matrix = eff;
    workspace.substep_factor.factor(eff);
  }
  model.built = true;
  bar_initial_acceleration(model, state, workspace);
  return BuildResult::success();
}
}  // namespace

double bar_tip_load(const BarModel& m, double t) {
  const BarDesc& d = m.desc;
  switch (d.tip_load) {
    case BarDesc::TipLoad::half_sine:
      return (t >= 0.0 && t <= d.tip_duration) ? d.tip_amplitude * std::sin(std::numbers::pi * t / d.tip_duration) : 0.0;
    case BarDesc::TipLoad::step:
      return t >= 0.0 ? d.tip_amplitude : 0.0;
    case BarDesc::TipLoad::none:
      break;
  }
  return 0.0;
}

StepStatus bar_resolve_acceleration(const BarModel& model, BarState& state, BarWorkspace& workspace,
                                    const BarInput& input) {
  if (!model.built) return StepStatus::not_built;
  (void)workspace;  // kept in the signature: the full solve it once did needed it
  StepStatus s = StepStatus::ok;
  const double change = input.tip_force - state.tip_input;
  double zero_if_finite = 0.0;  // all_finite(a), in the update's loop when there is one
  if (change != 0.0) {
    double* a = state.a.data();
    const double* unit = model.tip_unit_acceleration.data();
    for (std::size_t i = 0; i < state.a.size(); ++i) {
      a[i] += change * unit[i];
      zero_if_finite += 0.0 * a[i];
    }
  } else if (!all_finite(state.a)) {
    zero_if_finite = 1.0;
  }
  state.tip_input = input.tip_force;
  // The load is taken at state.time, and a load law tests t against its
  // bounds: a NaN time would read as "no load" rather than propagate.
  if (!(zero_if_finite == 0.0) || !std::isfinite(state.time)) s |= StepStatus::non_finite;
  return s;
}

StepStatus bar_initial_acceleration(const BarModel& model, BarState& state, BarWorkspace& workspace,
                                    const BarInput& input) {
  if (!model.built) return StepStatus::not_built;
  // The full solve M a = f − C v − K u: after an edit, a says nothing about u and v.
  const detail::BarOperator op(model, workspace, input.tip_force, state.interface_closed);
  StepStatus s = op.implicit_solve(0.0, 0.0, state.time, state.u.data(), state.v.data(), state.a.data());
  state.tip_input = input.tip_force;
  if (!all_finite(state.a) || !std::isfinite(state.time)) s |= StepStatus::non_finite;
  bar_restart_energy_ledger(model, state);
  return s;
}

void bar_restart_energy_ledger(const BarModel& model, BarState& state) {
  if (!model.built) return;
  const double energy = bar_algorithmic_energy(model, state);
  energy_restart(state.energy, {energy, energy, energy});
  state.input_work = 0.0;
}

namespace {

// ---- unilateral interface: substeps that end where the gap is zero ----------

/// The active set `closed` agrees with the gap g (closed iff g < 0, as the
/// active-set iteration decides it).
bool agrees(std::int32_t closed, double gap) { return (gap < 0.0) == (closed != 0); }

void save_start(const BarState& st, BarWorkspace& ws) {
  std::copy(st.u.begin(), st.u.end(), ws.u_start.begin());
  std::copy(st.v.begin(), st.v.end(), ws.v_start.begin());
  std::copy(st.a.begin(), st.a.end(), ws.a_start.begin());
}
void restore_start(BarState& st, const BarWorkspace& ws) {
  std::copy(ws.u_start.begin(), ws.u_start.end(), st.u.begin());
  std::copy(ws.v_start.begin(), ws.v_start.end(), st.v.begin());
  std::copy(ws.a_start.begin(), ws.a_start.end(), st.a.begin());
}

/// One Newmark substep of length h ending at t_end, from the state in `st`,
/// with the active set `closed` held. A substep of the model's Δt uses the
/// factor the build made; any other length factors its own. `net_force`
/// receives 1ᵀMa at its start and end (see book_impulse()).
StepStatus held_substep(const BarModel& m, BarState& st, BarWorkspace& ws, double tip_force, std::int32_t closed,
                        double t_end, double h, double net_force[2]) {
  const xfem::NewmarkScheme scheme{m.scheme.beta, m.scheme.gamma, h};
  const xfem::BandLdlt* factor = closed != 0 ? &m.effective_closed : &m.effective_open;
  if (h != m.scheme.dt) {
    detail::assemble_effective(m, scheme.fac0(), scheme.fac1(), closed != 0, ws.substep_matrix);
    ++ws.last_factorisations;
    if (!ws.substep_factor.factor(ws.substep_matrix)) return StepStatus::non_finite;  // h not finite
    factor = &ws.substep_factor;
  }
  std::int32_t held = closed;
  const detail::BarOperator op(m, ws, tip_force, held, *factor);
  return xfem::newmark_step(scheme, op, t_end, st.u.data(), st.v.data(), st.a.data(), ws.u_pred.data(),
                            ws.v_pred.data(), m.mass_row_sums.data(), net_force);
}

/// Books a Newmark (sub)step of length h whose net force 1ᵀMa was net_force[0]
/// at its start and net_force[1] at its end: its momentum identity
/// 1ᵀM(v_end − v_start) = h[(1 − γ) 1ᵀM a_start + γ 1ᵀM a_end].
void book_impulse(const BarModel& m, BarWorkspace& ws, double h, const double net_force[2]) {
  ws.last_external_impulse += h * ((1.0 - m.scheme.gamma) * net_force[0] + m.scheme.gamma * net_force[1]);
}

/// Where a (sub)step starts, for booking the work done over it: the tip's and
/// the base's motion, and the tip force split into the load and the input.
using PieceStart = BarWorkspace::StepStart;
PieceStart piece_start(const BarModel& m, const double* u, const double* v, double t, double input) {
  PieceStart p;
  p.u_tip = u[m.tip_dof];
  if (m.base_dof >= 0) {
    p.u_base = u[m.base_dof];
    p.v_base = v[m.base_dof];
  }
  p.load = bar_tip_load(m, t);
  p.input = input;
  return p;
}

/// Books the work of a Newmark (sub)step from `start` to the state in `st` at
/// t_end under `input`, with the scheme's weights, for which the discrete
/// energy identity of a linear system is exact (docs/stability.md):
/// [u_tip]·F_γ − c [u_base]·v_base,γ, with x_γ = (1 − γ) x_start + γ x_end.
double book_work(const BarModel& m, BarState& st, const PieceStart& start, double t_end, double input) {
  const double g = m.scheme.gamma;
  const double du_tip = st.u[static_cast<std::size_t>(m.tip_dof)] - start.u_tip;
  const double input_work = du_tip * ((1.0 - g) * start.input + g * input);
  double work = du_tip * ((1.0 - g) * start.load + g * bar_tip_load(m, t_end)) + input_work;
  if (m.base_dof >= 0) {
    const auto b = static_cast<std::size_t>(m.base_dof);
    work -= m.base_damping * (st.u[b] - start.u_base) * ((1.0 - g) * start.v_base + g * st.v[b]);
  }
  st.energy.work += work;
  st.input_work += input_work;
  return work;
}

/// Σ |terms of the gap|: the size of the numbers whose difference is the gap,
/// hence the round-off floor of a computed gap.
double gap_magnitude(const BarModel& m, const double* u) {
  double s = 0.0;
  for (int i = 0; i < m.gap_terms; ++i) s += std::fabs(m.gap_coeff[i] * u[m.gap_dof[i]]);
  return s;
}

/// The step from t_n (state `st`, active set st.interface_closed) to t_next
/// for a unilateral interface whose active set changes on the way. Each piece
/// is taken with the set held; when its end disagrees with the set, the piece
/// is cut back to where the gap crosses zero (regula falsi, Illinois variant,
/// on the substep's length; the kept end is always past the crossing or on it,
/// so the new set agrees with the gap it starts from), the set flips, the
/// acceleration is re-solved from the equation of motion with the new set, and
/// the rest of the step is the next piece. The spring acts over a piece either
/// throughout or not at all, so each piece integrates a linear system.
StepStatus step_with_events(const BarModel& m, BarState& st, BarWorkspace& ws, double tip_force, double t_n,
                            double t_next, double& booked) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  constexpr int kMaxIterations = 100;  // Illinois converges superlinearly; this only bounds the loop
  StepStatus status = StepStatus::ok;
  double t = t_n;
  // 1ᵀMa at the start and end of the latest substep taken: the committed
  // substep is always the latest one when it is booked.
  double net_force[2] = {0.0, 0.0};
  // The first piece starts from the acceleration of the input before this step.
  double input_start = st.tip_input;
  // Whether the last event was at the start of its piece (hi = 0): the piece
  // now starting starts from the same state with the other set.
  bool event_at_start = false;
  for (;;) {
    const std::int32_t closed = st.interface_closed;
    const double h_rest = t_next - t;
    save_start(st, ws);
    const PieceStart start = piece_start(m, st.u.data(), st.v.data(), t, input_start);
    input_start = tip_force;
    const double g_start = detail::bar_gap_of(m, st.u.data());
    status |= held_substep(m, st, ws, tip_force, closed, t_next, h_rest, net_force);
    const double g_end = detail::bar_gap_of(m, st.u.data());
    if (agrees(closed, g_end) || !std::isfinite(g_end) || has(status, StepStatus::non_finite)) {
      book_impulse(m, ws, h_rest, net_force);
      booked += book_work(m, st, start, t_next, tip_force);
      return status;
    }
    const bool starts_on_zero = g_start == 0.0 || !agrees(closed, g_start);
    if (starts_on_zero && event_at_start) {
      // Both sets, held from this start on the zero, leave it on the other's
      // side. For one spring the two end gaps have one sign (as in the
      // active-set loop), so both are round-off: an interface at rest ahead of
      // the wave, whose unknowns are still exactly 0, ends a closed piece at
      // +3.6e-46 m and an open one at −2.8e-45 m, and the step switched at its
      // start until max_interface_events (active_set_not_converged). This
      // piece is kept as it is.
      book_impulse(m, ws, h_rest, net_force);
      booked += book_work(m, st, start, t_next, tip_force);
      return status;
    }
    if (ws.last_events == m.desc.max_interface_events) {
      // Out of events: the rest of the step as one plain Newmark step with the
      // other set (for one spring the gap keeps its sign when the spring is
      // switched, so the other set agrees with the end it gives), counted:
      // bar_step() takes the step whole instead.
      restore_start(st, ws);
      st.interface_closed = closed == 0 ? 1 : 0;
      status |= held_substep(m, st, ws, tip_force, st.interface_closed, t_next, h_rest, net_force);
      book_impulse(m, ws, h_rest, net_force);
      booked += book_work(m, st, start, t_next, tip_force);
      ++ws.last_unlocated;
      return status;
    }

    // Bracket of the crossing in fractions of h_rest: lo agrees with the held
    // set, hi does not (or is the zero itself).
    // g_lo and g_hi are the secant's weights (Illinois halves them); the
    // crossing is found when hi's gap is round-off (8ε of its terms) or the
    // bracket is a few ulps of the step.
    double lo = 0.0, g_lo = g_start, hi = 1.0, g_hi = g_end;
    auto relative = [&](double g) { return g == 0.0 ? 0.0 : std::fabs(g) / gap_magnitude(m, st.u.data()); };
    double hi_residual = relative(g_end);
    if (starts_on_zero) {
      // The piece starts on the zero (an interface at rest), or past it by
      // round-off (a set the active-set solve kept where both sets' gaps were
      // its noise), and leaves it on the other set's side: the event is its
      // start. (Bracketing would halve towards it for ever: the gap there
      // shrinks with the piece's length; and the substep of a few ulps it would
      // end with solves an effective matrix that is M, re-solving a with the
      // round-off of K u divided by a sliver's mass.)
      hi = 0.0;
      hi_residual = 0.0;
    }
    double at = 1.0;   // the fraction the state in `st` was stepped to
    int replaced = 0;  // +1: hi was replaced last, −1: lo was
    for (int it = 0; it < kMaxIterations; ++it) {
      if (hi_residual <= 8.0 * kEps || hi - lo <= 4.0 * kEps * hi) break;
      double theta = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
      if (!(theta > lo && theta < hi)) theta = 0.5 * (lo + hi);
      restore_start(st, ws);
      status |= held_substep(m, st, ws, tip_force, closed, t + theta * h_rest, theta * h_rest, net_force);
      at = theta;
      const double g = detail::bar_gap_of(m, st.u.data());
      if (!std::isfinite(g)) return status | StepStatus::non_finite;
      if (agrees(closed, g)) {
        lo = theta;
        g_lo = g;
        if (replaced == -1) g_hi *= 0.5;
        replaced = -1;
      } else {
        hi = theta;
        g_hi = g;
        hi_residual = relative(g);
        if (replaced == +1) g_lo *= 0.5;
        replaced = +1;
      }
    }
    const double t_event = hi == 1.0 ? t_next : t + hi * h_rest;
    if (at != hi) {
      restore_start(st, ws);
      if (hi > 0.0) status |= held_substep(m, st, ws, tip_force, closed, t_event, hi * h_rest, net_force);
    }
    if (hi > 0.0) {
      book_impulse(m, ws, hi * h_rest, net_force);
      booked += book_work(m, st, start, t_event, tip_force);
    }
    // The switch puts ½k g² into the energy (closing) or takes it out (opening).
    // Where the crossing could not be found that closely (a gap moving too fast
    // for the floating-point resolution of the step, e.g. a sliver's phantom
    // mode), say so rather than let it add up.
    // Such a switch is counted, and bar_step() takes the step whole instead.
    if (hi_residual > 8.0 * kEps) {
      const double g = detail::bar_gap_of(m, st.u.data());
      const double energy = 0.5 * m.mass.quadratic(st.v.data()) + elastic_energy(m, st.u.data(), 0);
      if (0.5 * m.interface_stiffness * g * g > 16.0 * kEps * energy) ++ws.last_unlocated;
    }
    ++ws.last_events;
    event_at_start = hi == 0.0;
    // The other set, and the acceleration that goes with it. Held, not read
    // off the gap: at a gap of exactly zero the gap says "open" whichever side
    // the state is leaving for. The acceleration changes only by the spring's
    // force at the switch, k·gap (about zero), along M⁻¹g, solved at build:
    // re-solving M a = f − C v − K u here, as this did, divides the round-off
    // of K u by a sliver's phantom mass (docs/xfem.md, Small cuts), and the
    // next substep turned it into energy (an X-FEM cut 1.3e-3 of an element
    // from a node gained 1e5 J over one 1e-4 s substep of a 13 J bar).
    st.interface_closed = closed == 0 ? 1 : 0;
    // An opening takes out the force the substep's solve put in, k times the
    // gap it solved with (the rounded u's gap differs from it by ε|u|, a force
    // of k·ε|u| that, left in a, gained energy at every switch in proportion
    // to k: 1.1e-9 of A at 1e6·E·A); a closing puts in k times the gap of u,
    // which the next substep's solve starts from. An event at a piece's start
    // (hi = 0) has no substep behind it: the gap of u.
    const double switched_gap = closed != 0 && hi > 0.0 ? ws.solved_gap : detail::bar_gap_of(m, st.u.data());
    const double spring = static_cast<double>(closed - st.interface_closed) * m.interface_stiffness * switched_gap;
    if (spring != 0.0)
      for (std::size_t i = 0; i < st.a.size(); ++i) st.a[i] += spring * m.gap_unit_acceleration[i];
    if (hi == 1.0) return status;
    t = t_event;
  }
}

/// The energy rule of a unilateral interface (bar_step()): Ê at the end of
/// the step must not exceed Ê at its start plus the work booked over it.
/// Newmark guarantees that for a linear system, but not across a switch of
/// the active set: the average of the kinked force gains k(1 − γ)|g_n|g_{n+1}
/// − k(γ − ½)g_n² at an opening (closings only lose), and an event not placed
/// at the zero (a sliver's unresolved mode) adds ½k g² with the gap it found.
/// An excess ΔE beyond the round-off of the three terms is taken out, in this
/// order, of
///   1. the relative velocity of the two faces: v moves along g (an impact's
///      loss of the restitution kind, only as much as is gained);
///   2. the rest of the motion: v moves along itself.
/// Each direction is first made to keep the bar's momentum 1ᵀMv and the
/// absorbing base's velocity (whose dashpot force a holds), so the momentum
/// books and a stay exact; the kinetic energy is then quadratic in the step
/// along it, and the step is the root nearest 0 that takes out the excess, or
/// the minimum when that does not reach it.
/// u and a are never changed, so neither is the tip's motion, the work booked
/// nor the forces the next step starts from.
/// `work` is what the step booked. Returns the energy taken out; `left` is
/// what the velocity could not give (bar_step() then holds an opening).
double energy_rule(const BarModel& m, BarState& st, BarWorkspace& ws, double e_start, double work, double& left) {
  left = 0.0;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double e_end = bar_algorithmic_energy(m, st);
  double excess = e_end - e_start - work;
  if (!(excess > 4.0 * kEps * (std::fabs(e_start) + std::fabs(e_end) + std::fabs(work)))) return 0.0;
  const double removed = excess;
  const auto n = st.v.size();
  double* x = ws.rhs.data();      // the direction v moves along
  double* mx = ws.u_pred.data();  // M x
  const int b = m.base_dof;
  const double* e = m.base_unit_acceleration.data();  // M⁻¹e_b (absorbing base)
  // Moves v along x − μ e − ν 1 with μ, ν such that the base's velocity and
  // 1ᵀMv do not change (the base's dashpot force in a is −c v_b: a changed
  // v_b would leave a out of step with v), by the root nearest 0 of
  // ½(xᵀMx) s² + (vᵀMx) s + excess (or its minimum, when that is short).
  const auto move = [&] {
    double p = 0.0;  // 1ᵀMx
    for (std::size_t i = 0; i < n; ++i) p += m.mass_row_sums[i] * x[i];
    if (b >= 0) {
      // x_b − μ e_b − ν = 0, p − μ − ν 1ᵀM1 = 0 (1ᵀMe = 1ᵀe_b = 1)
      const double eb = e[b], xb = x[b];
      const double nu = (p * eb - xb) / (m.total_mass * eb - 1.0);
      const double mu = p - nu * m.total_mass;
      for (std::size_t i = 0; i < n; ++i) x[i] -= mu * e[i] + nu;
      if (m.offset_dof >= 0) x[m.offset_dof] += nu;  // 0 in the translation
      x[b] = 0.0;
    } else {
      const double nu = p / m.total_mass;
      for (std::size_t i = 0; i < n; ++i) x[i] -= nu;
      if (m.offset_dof >= 0) x[m.offset_dof] += nu;
    }
    m.mass.multiply(x, mx);
    double c = 0.0, slope = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      c += x[i] * mx[i];
      slope += st.v[i] * mx[i];
    }
    if (!(c > 0.0) || slope == 0.0) return;
    const double disc = slope * slope - 2.0 * c * excess;
    double step = 0.0;
    if (disc <= 0.0) {
      step = -slope / c;
      excess -= 0.5 * slope * slope / c;
    } else {
      step = -2.0 * excess / (slope + std::copysign(std::sqrt(disc), slope));
      excess = 0.0;
    }
    for (std::size_t i = 0; i < n; ++i) st.v[i] += step * x[i];
  };
  // 1. The faces' relative velocity, along g itself (the unknowns of the
  // gap, weighted as the gap weighs them). Not along M⁻¹g: a sliver's
  // phantom mass makes that huge on the phantom, and the next step's
  // predictor rounds it into energy (an X-FEM cut 1e-12 of an element from a
  // node blew up so).
  std::fill(x, x + n, 0.0);
  // Nor along a conforming sliver's offset (BarModel::offset_dof): that
  // moves only the sliver's own mode, whose energy the next steps round off
  // (a cut 1e-9 of an element off: 1.6e-10 of the energy scale against
  // X-FEM's 2e-14); its face moves with the anchor node, as X-FEM's sliver
  // face moves with its node and not its phantom.
  for (int i = 0; i < m.gap_terms; ++i)
    if (m.gap_dof[i] != m.offset_dof) x[m.gap_dof[i]] += m.gap_coeff[i];
  move();
  // 2. The rest of the motion, along v itself.
  if (excess > 0.0) {
    std::copy(st.v.begin(), st.v.end(), x);
    move();
  }
  left = excess;
  return removed - excess;
}

}  // namespace

constexpr double kSliver = 1e-6;

namespace {
/// A cut within kSliver of an element from a node (the conforming mesh's
/// sliver element, or X-FEM's sliver side).
bool sliver_cut(const BarModel& m) {
  const double s = std::min(m.cut_fraction, 1.0 - m.cut_fraction);
  return s > 0.0 && s < kSliver;
}

/// y += c·x, element by element. The arrays do not overlap (restrict), so
/// the compiler runs the loop in both SSE2 lanes without checking.
void add_scaled(double* __restrict y, double c, const double* __restrict x, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) y[i] += c * x[i];
}
}  // namespace

/// Interface events are located for the trapezoidal rule (β = ¼, γ = ½), the
/// one accepted scheme with no numerical dissipation, which is energy-exact on
/// every substep. For γ > ½ the algorithmic energy ½h²(β − γ/2)aᵀMa depends
/// on the step length, so substeps of other lengths pump the unresolved modes
/// of a sliver cut; those schemes take whole steps under the energy rule.
bool locates_interface_events(const BarModel& m) {
  if (!(m.unilateral && m.scheme.beta == 0.25 && m.scheme.gamma == 0.5)) return false;
  // A cut within kSliver of an element from a node: the conforming mesh's
  // sliver element is a spring of E·A/(s·h) on a node of mass ∝ s, X-FEM's
  // sliver side a phantom of mass ∝ s; their modes, which the trapezoidal rule
  // does not damp, move the gap faster than a substep's length resolves, and
  // substeps pump them (coupled, X-FEM cuts of 1e-12 … 1e-8 blew up). Such a
  // cut takes whole steps, the energy rule taking out the switch.
  return !sliver_cut(m);
}

StepStatus bar_step(const BarModel& model, BarState& state, BarWorkspace& workspace, const BarInput& input) {
  if (!model.built) return StepStatus::not_built;
  // t_{n+1} from the step count, not by accumulation: no drift, same bits on replay.
  const double t_next = static_cast<double>(state.step + 1) * model.scheme.dt;
  workspace.last_events = 0;
  workspace.last_factorisations = 0;
  workspace.last_external_impulse = 0.0;
  workspace.last_unlocated = 0;
  workspace.last_energy_removed = 0.0;
  workspace.last_held_open = 0;
  workspace.last_energy_left = 0.0;
  const double t_n = static_cast<double>(state.step) * model.scheme.dt;
  // A unilateral interface's energy rule compares the end with these.
  const double energy_start = model.unilateral ? bar_algorithmic_energy(model, state) : 0.0;
  double work = 0.0;  // booked over the step
  const std::int32_t closed_before = state.interface_closed;
  const double work_before = state.energy.work, input_work_before = state.input_work;
  if (model.unilateral) {
    std::copy(state.u.begin(), state.u.end(), workspace.u_step.begin());
    std::copy(state.v.begin(), state.v.end(), workspace.v_step.begin());
    std::copy(state.a.begin(), state.a.end(), workspace.a_step.begin());
  }
  const auto restore_step_start = [&] {
    std::copy(workspace.u_step.begin(), workspace.u_step.end(), state.u.begin());
    std::copy(workspace.v_step.begin(), workspace.v_step.end(), state.v.begin());
    std::copy(workspace.a_step.begin(), workspace.a_step.end(), state.a.begin());
    state.interface_closed = closed_before;
    state.energy.work = work_before;
    state.input_work = input_work_before;
    workspace.last_external_impulse = 0.0;
  };
  const PieceStart start = piece_start(model, state.u.data(), state.v.data(), t_n, state.tip_input);
  const detail::BarOperator op(model, workspace, input.tip_force, state.interface_closed);
  double net_force[2];  // 1ᵀMa at t_n and t_{n+1}
  double zero_if_finite = 0.0;  // of u, v and a, summed by the corrector
  // Books a step of Δt taken in one piece.
  const auto book_whole = [&] {
    workspace.last_start = start;
    workspace.work_before = state.energy.work;
    workspace.input_work_before = state.input_work;
    workspace.last_net_force[0] = net_force[0];
    workspace.last_net_force[1] = net_force[1];
    book_impulse(model, workspace, model.scheme.dt, net_force);
    work = book_work(model, state, start, t_next, input.tip_force);
  };
  // One Newmark step of Δt, booked.
  const auto whole_step = [&] {
    zero_if_finite = 0.0;
    const StepStatus status =
        xfem::newmark_step(model.scheme, op, t_next, state.u.data(), state.v.data(), state.a.data(),
                           workspace.u_pred.data(), workspace.v_pred.data(), model.mass_row_sums.data(), net_force,
                           &zero_if_finite);
    book_whole();
    return status;
  };
  StepStatus s = whole_step();
  if (locates_interface_events(model) && state.interface_closed != closed_before &&
      !has(s, StepStatus::active_set_not_converged)) {
    // The set changed within the step: take it again, in substeps that end at the change.
    restore_step_start();
    work = 0.0;
    s = step_with_events(model, state, workspace, input.tip_force, t_n, t_next, work);
    zero_if_finite = all_finite(state.u) && all_finite(state.v) && all_finite(state.a) ? 0.0 : 1.0;
    if (workspace.last_unlocated > 0) {
      // A switch it could not place at the zero (a sliver's unresolved mode
      // moves the gap faster than the substep's length resolves): substeps of
      // a few ulps and a switch off the zero, whose gains the energy rule
      // could only take out of the velocity. The whole step instead, whose
      // one gain at the switch, R − D, the rule takes out.
      restore_step_start();
      workspace.last_events = 0;
      s = whole_step();
    }
  }
  if (model.unilateral && model.desc.energy_rule && zero_if_finite == 0.0) {
    double left = 0.0;
    const auto rule = [&] {
      left = 0.0;
      return zero_if_finite == 0.0 ? energy_rule(model, state, workspace, energy_start, work, left) : 0.0;
    };
    workspace.last_energy_removed = rule();
    if (left > 0.0 && workspace.last_events > 0) {
      // Split, and the gain is not in the velocity (a sliver's mode pumped by
      // substeps of a few ulps): the whole step, whose only gain is its switch.
      restore_step_start();
      workspace.last_events = 0;
      s = whole_step();
      workspace.last_energy_removed = rule();
    }
    if (left > 0.0 && zero_if_finite == 0.0 && closed_before != 0 && state.interface_closed == 0) {
      // An opening whose gain the velocity cannot give (the pieces nearly at
      // rest, the energy elastic): the step again with the spring held on
      // throughout, a linear step whose energy cannot rise, with ½k g² counted
      // at its end.
      restore_step_start();
      s = held_substep(model, state, workspace, input.tip_force, 1, t_next, model.scheme.dt, net_force);
      book_whole();
      zero_if_finite = all_finite(state.u) && all_finite(state.v) && all_finite(state.a) ? 0.0 : 1.0;
      workspace.last_energy_removed = rule();
      if (zero_if_finite == 0.0 && !agrees(1, detail::bar_gap_of(model, state.u.data()))) {
        // The faces have separated: released here, the set opened and the
        // spring's force at the end, k times the gap the solve saw, taken out
        // of a along M⁻¹g (as at a located switch; 1ᵀg = 0, so 1ᵀMa and the
        // momentum books do not change). Opening drops ½k g²; a's change
        // moves Ê only through ½Δt²(β − γ/2)aᵀMa (nothing under (¼, ½)),
        // which the rule takes out of the velocity. Left in a (as it was),
        // the force pulled the faces together over the next step, whose
        // closing then gave back ½k g² that no velocity could pay (a sliver's
        // mode closed and reopened every step so: 1.55·A over the stress
        // sweep's run).
        // Not released: at a sliver cut (M⁻¹g is ∝ 1/s on the sliver's
        // unknown, and the next predictor rounds it into energy: a conforming
        // 1e-9 sliver gained up to 1.2·A), or where the velocity cannot pay
        // for a's change. The set then stays closed with g > 0 and a
        // consistent with it, and the next step's solve opens it: from g_n > 0
        // with the spring acting, an opening loses k(1 − γ)g_n g_{n+1} +
        // k(γ − ½)g_n².
        save_start(state, workspace);
        const double removed_held = workspace.last_energy_removed, left_held = left;
        const double spring = model.interface_stiffness * workspace.solved_gap;
        bool released = false;
        if (!sliver_cut(model)) {
          state.interface_closed = 0;
          add_scaled(state.a.data(), spring, model.gap_unit_acceleration.data(), state.a.size());
          workspace.last_energy_removed = removed_held + rule();
          released = !(left > left_held);  // a's change paid for
          if (!released) {
            restore_start(state, workspace);
            state.interface_closed = 1;
            workspace.last_energy_removed = removed_held;
            left = left_held;
          }
        }
        workspace.last_held_open = released ? 1 : 2;
      }
    }
    workspace.last_energy_left = left;
  }
  state.tip_input = input.tip_force;
  state.step += 1;
  state.time = t_next;
  if (!(zero_if_finite == 0.0) || !ledger_finite(state)) s |= StepStatus::non_finite;
  if (energy_check_due(model.desc.energy_check, state.step)) {
    const double energy = bar_algorithmic_energy(model, state);
    energy_check(state.energy, model.desc.energy_check, {energy, energy, energy});
  }
  if (state.energy.exceeded != 0) s |= StepStatus::energy_growth;
  return s;
}

StepStatus bar_adjust_step_input(const BarModel& m, BarState& st, BarWorkspace& ws, double tip_force) {
  if (!m.built || !m.linear_in_tip_force) return StepStatus::not_built;
  const double change = tip_force - st.tip_input;
  if (change == 0.0) return StepStatus::ok;
  const auto n = static_cast<std::size_t>(m.dofs);
  double net_start = ws.last_net_force[0], net_end = 0.0;
  double* u = st.u.data();
  double* v = st.v.data();
  double* a = st.a.data();
  // The update, element by element, apart from the net forces (sums in
  // order, a scalar loop): two unknowns at a time.
  add_scaled(u, change, m.tip_response_u.data(), n);
  add_scaled(v, change, m.tip_response_v.data(), n);
  add_scaled(a, change, m.tip_response_a.data(), n);
  double zero_if_finite = 0.0;  // of u, v and a, summed in the same loop
  for (std::size_t i = 0; i < n; ++i) {
    net_start += change * m.mass_row_sums[i] * m.tip_unit_acceleration[i];
    net_end += m.mass_row_sums[i] * a[i];
    zero_if_finite += 0.0 * u[i] + 0.0 * v[i] + 0.0 * a[i];
  }
  // The books, as bar_step would have kept them with this force throughout.
  const double net_force[2] = {net_start, net_end};
  ws.last_net_force[0] = net_start;
  ws.last_net_force[1] = net_end;
  ws.last_external_impulse = 0.0;
  book_impulse(m, ws, m.scheme.dt, net_force);
  st.energy.work = ws.work_before;
  st.input_work = ws.input_work_before;
  ws.last_start.input = tip_force;
  book_work(m, st, ws.last_start, st.time, tip_force);
  st.tip_input = tip_force;
  StepStatus s = StepStatus::ok;
  if (!(zero_if_finite == 0.0) || !ledger_finite(st)) s |= StepStatus::non_finite;
  return s;
}

bool bar_blend_step_ends(const BarModel& m, BarState& into, const BarState& other, double theta) {
  if (!m.built || !(theta > 0.0 && theta < 1.0) || into.u.size() != other.u.size() || into.step != other.step)
    return false;
  const auto blend = [theta](double& x, double y) {
    if (x != y) x = (1.0 - theta) * x + theta * y;  // equal values keep their bits
  };
  // The spring force each end's a holds: that of its set (bar_step() releases
  // a held opening's force, or keeps the set closed).
  const double carried_into = into.interface_closed != 0 ? detail::bar_gap_of(m, into.u.data()) : 0.0;
  const double carried_other = other.interface_closed != 0 ? detail::bar_gap_of(m, other.u.data()) : 0.0;
  const double gap_into = detail::bar_gap_of(m, into.u.data()), gap_other = detail::bar_gap_of(m, other.u.data());
  for (std::size_t i = 0; i < into.u.size(); ++i) {
    blend(into.u[i], other.u[i]);
    blend(into.v[i], other.v[i]);
    blend(into.a[i], other.a[i]);
  }
  blend(into.tip_input, other.tip_input);
  blend(into.input_work, other.input_work);
  blend(into.energy.work, other.energy.work);
  into.energy.peak = std::max(into.energy.peak, other.energy.peak);
  into.energy.exceeded = std::max(into.energy.exceeded, other.energy.exceeded);
  if (!m.unilateral || into.interface_closed == other.interface_closed) return true;
  const double gap = detail::bar_gap_of(m, into.u.data());
  if (into.interface_closed != other.interface_closed) {
    // (1 − θ)g₁ + θg₂ < 0 with the open end's g ≥ 0 bounds g² by the closed
    // end's weight times its g², whose ½k g² that end's energy holds.
    const double open_gap = into.interface_closed != 0 ? gap_other : gap_into;
    into.interface_closed = gap < 0.0 && open_gap >= 0.0 ? 1 : 0;
  }
  // As at a located switch (step_with_events): not at a sliver cut, whose
  // phantom M⁻¹g is huge and the next predictor would round into energy.
  if (locates_interface_events(m)) {
    const double carried = (1.0 - theta) * carried_into + theta * carried_other;
    const double spring = m.interface_stiffness * (carried - (into.interface_closed != 0 ? gap : 0.0));
    if (spring != 0.0) add_scaled(into.a.data(), spring, m.gap_unit_acceleration.data(), into.a.size());
  }
  return true;
}

double bar_displacement(const BarModel& model, const BarState& state, double x) { return field_at(model, state.u, x); }
double bar_velocity(const BarModel& model, const BarState& state, double x) { return field_at(model, state.v, x); }

double bar_interface_gap(const BarModel& model, const BarState& state) {
  return model.built ? detail::bar_gap_of(model, state.u.data()) : 0.0;
}

double bar_tip_displacement(const BarModel& model, const BarState& state) {
  return model.built ? state.u[static_cast<std::size_t>(model.tip_dof)] : 0.0;
}
double bar_tip_velocity(const BarModel& model, const BarState& state) {
  return model.built ? state.v[static_cast<std::size_t>(model.tip_dof)] : 0.0;
}

BarEnergy bar_energy(const BarModel& model, const BarState& state) {
  BarEnergy e;
  if (!model.built) return e;
  e.kinetic = 0.5 * model.mass.quadratic(state.v.data());
  e.elastic = elastic_energy(model, state.u.data(), state.interface_closed);
  return e;
}

double bar_algorithmic_energy(const BarModel& model, const BarState& state) {
  if (!model.built) return 0.0;
  const BarEnergy e = bar_energy(model, state);
  const xfem::NewmarkScheme& k = model.scheme;
  const double c = k.beta - 0.5 * k.gamma;  // 0 for the trapezoidal rule: skip the product
  return e.kinetic + e.elastic + (c == 0.0 ? 0.0 : 0.5 * k.dt * k.dt * c * model.mass.quadratic(state.a.data()));
}

}  // namespace xfdem
