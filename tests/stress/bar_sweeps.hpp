// The continuum's cases of the stability stress suite, shared by the fast
// sweeps (tests/stress, label `stress`) and the deep runs (tests/long, label
// `long`).
//
// Every case is run step by step and ends in one of two outcomes:
//   - bounded: the total energy stays within a stated bound of the initial
//     energy plus the work done, E(t) ≤ E0 + W(t) + ε·A;
//   - reported: the build refused the case, or a step returned a flag.
//
// The bound comes from the discrete energy identity of Newmark's scheme, which
// every step is also checked against. For M ü + C u̇ + N(u) = f, with
// [x] = x_{n+1} − x_n, the γ-weighted mean x_γ = (1 − γ) x_n + γ x_{n+1}, and the
// algorithmic energy Ê = ½vᵀMv + V(u) + ½Δt²(β − γ/2) aᵀMa, one step gives
// exactly (Hughes, The Finite Element Method, §9.3, extended to the interface):
//
//   [Ê] = [u_tip]·F_γ − c [u_base]·v_base,γ + R − D,
//   D = (γ − ½) ([u]ᵀK[u] + [g][r] + Δt²(β − γ/2) [a]ᵀM[a]),
//   R = [φ] − [g]·½(r_n + r_{n+1}),
//
// where g is the gap, r = k g the interface force while the spring acts (0
// otherwise) and φ = ½ k g² its energy. The first two terms are the work W of
// the tip load and of the base dashpot (at γ = ½ the tip term is exactly the
// trapezoidal ½(F_n + F_{n+1})·[u_tip], the dashpot's is −cΔt⟨v⟩² ≤ 0; for
// γ > ½ the scheme's own weights are the ones that make the identity exact).
// D ≥ 0 is the numerical dissipation of γ > ½ ([g][r] ≥ 0: r is a
// non-decreasing function of g). Since β ≥ (γ + ½)²/4 ≥ γ/2, E ≤ Ê; the cases
// kicked cases start at rest with no load at t = 0, so a_0 = 0 and Ê_0 = E_0;
// the lifted ones start under the press, and the bound is taken from Ê_0. Hence
// E − Ê0 − W ≤ ΣR − ΣD (equality at γ = ½, β = ¼).
//
// R is zero for a linear spring: tied, or a unilateral one that did not switch
// during the step. So a tied interface must satisfy E ≤ E0 + W up to round-off.
// A unilateral one switches, and at a switch the trapezoidal rule integrates a
// force with a kink: opening from g_n < 0 to g_{n+1} > 0 gives
// R = ½ k |g_n| g_{n+1} > 0 (the compressive force of t_n is averaged over the
// whole separation: energy gained), closing gives R = −½ k g_n |g_{n+1}| < 0
// (energy lost). Nothing in the scheme bounds ΣR; the kernel's energy rule
// (bar_step()) takes R − D out of the velocity where it is positive, so the
// bound asked of a unilateral case is the same E ≤ E0 + W + ε·A, and the
// identity above is checked with that taken out. The test computes R and D
// itself from the gaps, the active set and the interface force a holds (r is
// k·g at the end of an opening the kernel held to the step's end and released
// there, with the release's change of a booked).
#pragma once
#include <Eigen/Dense>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfem/reference.hpp"

namespace xfdem::stress {

/// The project writes the interface penalty as a multiple of E·A per metre of
/// bar (the paper's "100·E·A" is 1.2e9 N/m for the V2 rod, E·A = 1.2e7 N).
inline double penalty(const BarDesc& d, double multiple_of_ea) {
  return multiple_of_ea * d.youngs_modulus * d.area / 1.0;  // ÷ 1 m
}

/// The loading of every case. The V2 rod (30 elements, Δt = 1 ms, interface at
/// 14.5 m) is kicked up by a tensile half sine at the tip (3e4 N over 0.25 s,
/// the description's own tip load) and then pressed down by a constant
/// compressive 1e4 N (through BarInput, the coupling's channel) from the end of
/// the kick on. A unilateral interface opens under the kick; the upper piece
/// (15.5 m, 12.4 t) leaves at ~0.4 m/s, comes back under the constant force,
/// lands and bounces (about once a second) until the scheme's dissipation, if
/// any, lets it settle, so the active set switches hundreds of times. A tied
/// interface carries the same loads in tension and compression.
struct KickedRod {
  double kick = 3e4;            ///< N, tensile half sine
  double kick_duration = 0.25;  ///< s
  double press = -1e4;          ///< N, from the end of the kick on
  /// The unilateral cases: no kick. The upper piece starts lifted by `lift`
  /// (m, a rigid shift, so no strain and E0 = 0) and the press acts from
  /// t = 0, so the tip force is the same on every step and the work of a step
  /// the kernel splits at interface events is F·[u_tip] whatever its substeps.
  double lift = 0.0;
};

inline BarDesc kicked_rod(const KickedRod& load = {}) {
  BarDesc d = test::v2_rod(30, 1e-3);
  d.tip_amplitude = load.kick;
  d.tip_duration = load.kick_duration;
  d.interface = BarInterfaceDesc{14.5, penalty(d, 100.0), BarInterfaceDesc::Behaviour::tied};
  return d;
}

/// Absorbing base for `d`: the Lysmer dashpot with a spring E·A/L in parallel.
/// Without the spring the pressed bar would sink at F/(ρcA) for ever, and the
/// rounding of K·u would then grow with the rigid displacement rather than with
/// the strain (the identity's residual was seen growing like t²).
inline void make_absorbing(BarDesc& d) {
  d.base = BarDesc::Base::absorbing;
  d.base_stiffness = d.youngs_modulus * d.area / d.length;
}

/// The load of case `d`: the kick for a tied interface; for a unilateral one
/// the lifted start (0.1 m: the upper piece lands at ~0.4 m/s), `d`'s own tip
/// load switched off.
inline KickedRod load_for(BarDesc& d) {
  if (!d.interface || d.interface->behaviour != BarInterfaceDesc::Behaviour::unilateral) return {};
  d.tip_load = BarDesc::TipLoad::none;
  d.tip_amplitude = 0.0;
  d.tip_duration = 0.0;
  KickedRod load;
  load.kick = 0.0;
  load.lift = 0.1;
  return load;
}

/// Extra tip force (BarInput) at time t.
inline double press_at(const KickedRod& load, double t) {
  return t > load.kick_duration || load.lift > 0.0 ? load.press : 0.0;
}

/// Condition number of the Jacobi-scaled effective matrix M + γΔt C + βΔt² K
/// (with the interface spring on, and off too when it is unilateral): the
/// kernel factors exactly that scaled matrix, so it bounds how much one solve
/// amplifies round-off. Computed densely here, independently of the kernel's
/// factorisation.
inline double scaled_condition(const BarModel& m) {
  auto cond = [&](bool with_interface) {
    Eigen::MatrixXd a = test::dense(m.mass) + m.scheme.fac0() * test::dense_stiffness(m, with_interface);
    if (m.base_dof >= 0) a(m.base_dof, m.base_dof) += m.scheme.fac1() * m.base_damping;
    const Eigen::VectorXd s = a.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::VectorXd ev =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(s.asDiagonal() * a * s.asDiagonal()).eigenvalues();
    return ev.maxCoeff() / ev.minCoeff();
  };
  double c = cond(m.has_interface);
  if (m.unilateral) c = std::max(c, cond(false));
  return c;
}

/// Round-off allowance ε over `steps` steps. Each step the computed state is the
/// exact Newmark image of the previous one plus a rounding error of relative
/// size ≤ c·κ·u in the scaled unknowns (u = 2⁻⁵³, κ the condition number above,
/// c = 16 ≈ twice the rounded operations per entry of a band row of width 3
/// plus the predictor and corrector). Through the identity that is an energy
/// error of the same relative size, and successive steps' errors add at worst
/// linearly: ε = 16·κ·u·N, i.e. 3.6e-11·κ for 2e4 steps and 1.8e-9·κ for 1e6
/// (a random walk would give √N: this is a worst case, not a fit).
inline double roundoff_epsilon(double condition, std::int64_t steps) {
  return 16.0 * condition * (DBL_EPSILON / 2) * static_cast<double>(steps);
}

/// What one run of a case did. Energies are relative to A unless said otherwise.
struct BarOutcome {
  bool built = true;  ///< false: the build refused the case (message kept)
  std::string build_message;
  StepStatus flags = StepStatus::ok;  ///< union of every step's flags
  std::int64_t first_flag_step = -1;
  std::int64_t steps = 0;
  double scale = 0;           ///< A = max over the run of E0 + W (J)
  double condition = 0;       ///< κ of the scaled effective matrix
  double epsilon = 0;         ///< stated round-off allowance ε
  double worst_excess = 0;    ///< max over unflagged steps of (E − E0 − W)/A: the bound asks ≤ ε
  double peak_energy = 0;     ///< max over the run of E/A
  double worst_identity = 0;  ///< max |Ê − Ê0 − W − ΣR + ΣD| / max(A, max E): round-off only
  double switching_gain = 0;  ///< Σ max(R, 0)/A: energy gained at openings
  double switching_net = 0;   ///< ΣR/A at the end
  double dissipated = 0;      ///< ΣD/A at the end
  double removed = 0;         ///< Σ max(R − D, 0)/A: what the unilateral energy rule took out (unsplit steps)
  double kernel_removed = 0;  ///< the same as the kernel reports it (BarWorkspace::last_energy_removed), printed only
  double left = 0;            ///< Σ BarWorkspace::last_energy_left / A: gains the rule could not take out
  double left_switching = 0;  ///< the part of `left` on steps whose set changed (the rest: linear steps' round-off)
  std::int64_t switches = 0;  ///< changes of the active set
  std::int64_t held = 0;      ///< openings the kernel held to the step's end (BarWorkspace::last_held_open ≠ 0)
  std::int64_t released = 0;  ///< of those, released at that end (last_held_open = 1)
  std::int64_t split_steps = 0;  ///< steps the kernel split at interface events (Newmark (¼, ½) only)
  std::int64_t split_with_varying_force = 0;  ///< of those, steps whose tip force changed (not checked)
  double worst_split_excess = 0;  ///< max over split steps of ([E] − F·[u_tip]) / A: ≤ ε (see below)
  bool finite = true;         ///< every energy along the run was finite

  [[nodiscard]] bool reported() const { return !built || flags != StepStatus::ok; }
  [[nodiscard]] bool bounded() const { return built && finite && worst_excess <= epsilon; }
};

inline std::string flag_text(StepStatus s) {
  char text[200];
  return describe(s, text, sizeof(text));
}

/// Builds `d`, runs `steps` steps under the kicked-rod loading and measures
/// everything in BarOutcome. Stops at the first non-finite state.
inline BarOutcome run_bar_case(const BarDesc& d, const KickedRod& load, std::int64_t steps) {
  BarOutcome o;
  BarModel m;
  BarState st;
  BarWorkspace ws;
  // Builds `desc` and sets the start: at rest, or the lifted one.
  const auto start = [&](const BarDesc& desc) {
    const BuildResult r = build_bar(desc, m, st, ws);
    if (!r.ok()) {
      o.built = false;
      o.build_message = r.message;
      return false;
    }
    if (load.lift > 0.0) {
      // Every unknown of the upper side's field (the cells above the interface)
      // moves by `lift`, but an offset (BarModel::offset_dof), which a rigid
      // lift leaves 0; a_0 from the equation of motion under the press (which
      // also restarts the energy check's books from this start).
      for (const BarCell& c : m.cells)
        if (c.a >= m.interface_position)
          for (int dof : c.dof)
            if (dof >= 0 && dof != m.offset_dof) st.u[static_cast<std::size_t>(dof)] = load.lift;
      if (bar_initial_acceleration(m, st, ws, BarInput{load.press}) != StepStatus::ok) {
        o.built = false;
        o.build_message = "the lifted start";
        return false;
      }
    }
    return true;
  };
  if (!start(d)) return o;
  o.condition = scaled_condition(m);
  o.epsilon = roundoff_epsilon(o.condition, steps);
  // The kernel's energy check at every step, at half the round-off allowance:
  // a case it lets through must be bounded by ε (the contract below), and a
  // linear one must never trip it (expect_case()).
  BarDesc checked = d;
  checked.energy_check = EnergyCheck{1, 0.5 * o.epsilon};
  if (!start(checked)) return o;

  const auto n = static_cast<std::size_t>(m.dofs);
  const auto tip = static_cast<std::size_t>(m.tip_dof);
  const double beta = d.beta, gamma = d.gamma, dt = d.dt, k = m.interface_stiffness;
  const double c = m.base_damping;  // 0 for a fixed base
  auto energy = [&] {
    const BarEnergy e = bar_energy(m, st);
    return e.kinetic + e.elastic;
  };
  // Ê − E: zero at β = γ/2, i.e. for the trapezoidal rule.
  auto algorithmic_term = [&] {
    return beta == 0.5 * gamma ? 0.0 : 0.5 * dt * dt * (beta - 0.5 * gamma) * m.mass.quadratic(st.a.data());
  };
  auto interface_force = [&](double gap, std::int32_t closed) { return m.has_interface && closed ? k * gap : 0.0; };

  const double e0 = energy();
  const double ehat0 = e0 + algorithmic_term();
  std::vector<double> u0 = st.u, v0 = st.v, a0 = st.a, du(n), da(n);
  // The force a_0 was computed with (no input at build; the press for a lifted start).
  double f0 = bar_tip_load(m, 0.0) + (load.lift > 0.0 ? load.press : 0.0);
  double ehat_prev = ehat0, worst_split = 0;
  // M⁻¹g, g the gap's vector (upper minus lower side): the direction along
  // which a released opening's force leaves a.
  Eigen::VectorXd gap_acceleration = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  if (m.unilateral) {
    Eigen::VectorXd gvec = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    for (int i = 0; i < m.gap_terms; ++i) gvec[m.gap_dof[i]] += m.gap_coeff[i];
    gap_acceleration = test::dense(m.mass).ldlt().solve(gvec);
  }
  double g0 = bar_interface_gap(m, st);
  std::int32_t closed0 = st.interface_closed;
  double force_in_a = interface_force(g0, closed0);
  double work = 0, sum_r = 0, sum_d = 0, gain = 0, available = e0, peak = e0, removed = 0, kernel_removed = 0, left = 0,
         left_switching = 0;
  // Raw extremes (J), divided by the scales once they are known at the end.
  double worst_excess = 0, worst_identity = 0;

  for (std::int64_t i = 0; i < steps; ++i) {
    const double t1 = static_cast<double>(st.step + 1) * dt;
    const BarInput in{press_at(load, t1)};
    const StepStatus s = bar_step(m, st, ws, in);
    ++o.steps;
    if (s != StepStatus::ok && o.first_flag_step < 0) o.first_flag_step = o.steps;
    o.flags |= s;
    if (has(s, StepStatus::non_finite)) {
      o.finite = false;
      break;
    }
    const double f1 = bar_tip_load(m, t1) + in.tip_force;
    const double g1 = bar_interface_gap(m, st);
    const std::int32_t closed1 = st.interface_closed;
    if (closed1 != closed0) ++o.switches;
    o.held += ws.last_held_open != 0 ? 1 : 0;
    o.released += ws.last_held_open == 1 ? 1 : 0;
    double e = 0, ehat = 0;  // this step's energy, and the algorithmic energy the identity carries on from
    if (ws.last_events > 0) {
      // Split at interface events into trapezoidal substeps, each of a linear
      // system: [E] = F·[u_tip] − (the dashpot's Σ c h v̄² ≥ 0) exactly, with
      // the tip force constant over the step. The single-step identity does
      // not apply; the step is checked against that instead and the identity
      // carried on from its end (what the dashpot took is booked as D).
      ++o.split_steps;
      e = energy();
      ehat = e;
      if (!std::isfinite(e)) {
        o.finite = false;
        break;
      }
      if (f1 != f0) {
        ++o.split_with_varying_force;
      } else {
        const double tip_work = (st.u[tip] - u0[tip]) * f1;
        worst_split = std::max(worst_split, (e - ehat_prev) - tip_work);
        work += tip_work;
        sum_d += tip_work - (e - ehat_prev);
      }
    } else {
      for (std::size_t j = 0; j < n; ++j) {
        du[j] = st.u[j] - u0[j];
        da[j] = st.a[j] - a0[j];
      }
      // Work of the tip load and of the base dashpot, with the scheme's weights.
      work += du[tip] * ((1 - gamma) * f0 + gamma * f1);
      if (m.base_dof >= 0) {
        const auto b = static_cast<std::size_t>(m.base_dof);
        // The base's velocity at the step's end as the scheme computed it,
        // from the accelerations: a unilateral interface's energy rule may
        // change v after the step, an instantaneous change the dashpot does
        // no work in.
        const double vb1 = v0[b] + dt * ((1 - gamma) * a0[b] + gamma * st.a[b]);
        work -= c * du[b] * ((1 - gamma) * v0[b] + gamma * vb1);
      }
      // Switching term and numerical dissipation of this step.
      // r: the interface force a holds, k·g while the spring acts; φ: its
      // energy, ½k g² while the set is closed. An opening the kernel held to
      // the step's end and released there (BarWorkspace::last_held_open = 1)
      // was integrated with r = k·g at the end, and its release took that
      // force out of a (a_held = a − k g M⁻¹g, M⁻¹g solved here), which
      // moves Ê by ½Δt²(β − γ/2)(aᵀMa − a_heldᵀMa_held); the next step
      // starts with r = 0.
      const bool released = ws.last_held_open == 1;
      double release = 0;
      if (released) {
        for (std::size_t j = 0; j < n; ++j) da[j] -= k * g1 * gap_acceleration[static_cast<Eigen::Index>(j)];
        if (beta != 0.5 * gamma) {
          std::vector<double> held(st.a);
          for (std::size_t j = 0; j < n; ++j) held[j] -= k * g1 * gap_acceleration[static_cast<Eigen::Index>(j)];
          release = 0.5 * dt * dt * (beta - 0.5 * gamma) * (m.mass.quadratic(st.a.data()) - m.mass.quadratic(held.data()));
        }
      }
      const double r0 = force_in_a, r1 = released ? k * g1 : interface_force(g1, closed1);
      const double phi0 = 0.5 * interface_force(g0, closed0) * g0, phi1 = 0.5 * interface_force(g1, closed1) * g1;
      const double rstep = (phi1 - phi0) - (g1 - g0) * 0.5 * (r0 + r1) + release;
      force_in_a = interface_force(g1, closed1);
      const double dstep =
          gamma == 0.5 ? 0.0
                       : (gamma - 0.5) * (m.stiffness.quadratic(du.data()) + (g1 - g0) * (r1 - r0) +
                                          dt * dt * (beta - 0.5 * gamma) * m.mass.quadratic(da.data()));
      sum_r += rstep;
      sum_d += dstep;
      gain += std::max(rstep, 0.0);
      // A unilateral interface's energy rule (bar_step()) takes out what the
      // step would gain, R − D when positive: computed here from the gaps, not
      // read from the kernel, so the identity below checks the rule too.
      // Where the velocity could not give it all (BarWorkspace::
      // last_energy_left, summed apart and printed), less that.
      if (m.unilateral) removed += std::max(rstep - dstep, 0.0) - ws.last_energy_left;
      left += ws.last_energy_left;
      if (closed1 != closed0 || released) left_switching += ws.last_energy_left;
      kernel_removed += ws.last_energy_removed;

      e = energy();
      ehat = e + algorithmic_term();
      if (!std::isfinite(e) || !std::isfinite(ehat)) {
        o.finite = false;
        break;
      }
    }
    available = std::max(available, e0 + work);
    peak = std::max(peak, e);
    if (s == StepStatus::ok) worst_excess = std::max(worst_excess, e - ehat0 - work);
    worst_identity = std::max(worst_identity, std::abs(ehat - ehat0 - work - sum_r + sum_d + removed));

    u0 = st.u;
    v0 = st.v;
    a0 = st.a;
    f0 = f1;
    g0 = g1;
    closed0 = closed1;
    if (ws.last_events > 0) force_in_a = interface_force(g1, closed1);
    ehat_prev = ehat;
  }
  o.scale = available;
  o.worst_excess = worst_excess / available;
  o.peak_energy = peak / available;
  o.worst_identity = worst_identity / std::max(available, peak);
  o.switching_gain = gain / available;
  o.switching_net = sum_r / available;
  o.dissipated = sum_d / available;
  o.removed = removed / available;
  o.kernel_removed = kernel_removed / available;
  o.left = left / available;
  o.left_switching = left_switching / available;
  o.worst_split_excess = worst_split / available;
  return o;
}

inline const char* name(BarInterfaceDesc::Behaviour b) {
  return b == BarInterfaceDesc::Behaviour::tied ? "tied" : "unilateral";
}
inline const char* name(BarDesc::Method m) { return m == BarDesc::Method::xfem ? "xfem" : "fem"; }
inline const char* name(BarDesc::Base b) { return b == BarDesc::Base::fixed ? "fixed" : "absorbing"; }

/// One line of the map; `label` carries the case's parameters.
inline void print_outcome(const char* label, const BarOutcome& o) {
  if (!o.built) {
    std::printf("  %s | refused: %s\n", label, o.build_message.c_str());
    return;
  }
  std::printf(
      "  %s | %s | cond %.1e eps %.1e | (E-E0-W)/A %.2e identity %.1e peak E/A %.3g | switches %lld gain %.2e "
      "net %+.2e D %.2e removed %.2e (kernel %.2e, left %.2e, switching %.2e) held %lld (released %lld) | split %lld worst %.1e\n",
      label, flag_text(o.flags).c_str(), o.condition, o.epsilon, o.worst_excess, o.worst_identity, o.peak_energy,
      static_cast<long long>(o.switches), o.switching_gain, o.switching_net, o.dissipated, o.removed, o.kernel_removed, o.left, o.left_switching,
      static_cast<long long>(o.held),
      static_cast<long long>(o.released), static_cast<long long>(o.split_steps), o.worst_split_excess);
}

/// The assertions every case makes. The suite's contract: bounded or reported.
/// Beyond it, what theory says of the accepted (β, γ): the kernel's step obeys
/// the energy identity above to round-off (|residual| ≤ ε relative to the
/// largest energy of the run), with what a unilateral interface's energy rule
/// takes out computed from the gaps (R − D where positive); no case reports
/// (a tied interface is a linear system under an unconditionally stable
/// scheme; a unilateral one's gains are taken out) and every case is bounded.
inline void expect_case(const char* label, const BarDesc& d, const BarOutcome& o) {
  ASSERT_TRUE(o.built) << label << ": " << o.build_message;
  EXPECT_TRUE(o.bounded() || o.reported())
      << label << ": (E - E0 - W)/A reached " << o.worst_excess << " > eps " << o.epsilon
      << " with no status; switching gain " << o.switching_gain << ", net " << o.switching_net << ", peak E/A "
      << o.peak_energy;
  // Neither interface reports: a unilateral one's switches that could not be
  // placed, and what any switch gains, are taken out by bar_step()'s energy
  // rule, so its energy never rises either.
  EXPECT_EQ(o.flags, StepStatus::ok) << label << ": " << flag_text(o.flags) << " at step " << o.first_flag_step;
  EXPECT_TRUE(o.bounded()) << label << ": (E - E0 - W)/A reached " << o.worst_excess << " > eps " << o.epsilon;
  if (o.finite) {
    EXPECT_LE(o.worst_identity, o.epsilon) << label;
    EXPECT_LE(o.worst_split_excess, o.epsilon) << label << ": a step split at interface events gained energy";
  }
  EXPECT_EQ(o.split_with_varying_force, 0) << label << ": a split step the check could not cover";
  if (!(d.beta == 0.25 && d.gamma == 0.5)) {
    EXPECT_EQ(o.split_steps, 0) << label << ": only (1/4, 1/2) is split";
  }
}

}  // namespace xfdem::stress
