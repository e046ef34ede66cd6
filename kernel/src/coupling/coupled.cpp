// The coupled X-FE-DEM step; see coupled.hpp and docs/coupling.md.
#include "xfdem/coupled.hpp"

#include <cmath>
#include <cstring>
#include <type_traits>
#include <limits>
#include <new>

#include "dem/energy_books.hpp"
#include "dem/memory.hpp"

namespace xfdem {

namespace {

/// The particles' state is held five times over: the state itself, the
/// window's start, end and first pass (CoupledWorkspace::dem_start, dem_end,
/// dem_first), and the window's sensitivity (CoupledState::sensitivity, one
/// double per double of the state: at most a state's size).
constexpr int kDemStates = 5;
constexpr const char* kDemStatesNote =
    ", in the state, the coupled window's 3 copies of it and its sensitivity to the force, counted as a fifth";

/// Calls f(name, data, count) for every double field of the particles' state,
/// in the state's field order: the walk the window's sensitivity is laid out by.
template <class F>
void for_each_double(DemState<1>& state, F&& f) {
  state.for_each_array([&](const char* name, auto* data, auto count) {
    using T = std::remove_cv_t<std::remove_pointer_t<decltype(data)>>;
    if constexpr (std::is_same_v<T, double>) f(name, data, static_cast<std::size_t>(count));
  });
}

BuildResult prefixed(const char* prefix, const BuildResult& r) { return BuildResult::failure(r.code, "%s%s", prefix, r.message); }

/// A particle starting deeper in the bar's tip than its radius (its centre
/// inside the bar). Particles build_dem will refuse for their own values are
/// left to it.
BuildResult check_tip_overlaps(const DemDesc<1>& dem, double top, double top_mass) {
  for (std::size_t i = 0; i < dem.particles.size(); ++i) {
    const ParticleDesc<1>& p = dem.particles[i];
    const bool valid = std::isfinite(p.position[0]) && std::isfinite(p.radius) && p.radius > 0 &&
                       std::isfinite(p.mass) && p.mass > 0 && std::isfinite(p.stiffness) && p.stiffness > 0;
    const double overlap = p.radius - (p.position[0] - top);
    if (!valid || !(overlap > p.radius)) continue;
    char speed[32];
    dem_detail::format_speed(overlap * std::sqrt(p.stiffness * (1.0 / top_mass + 1.0 / p.mass)), speed, sizeof(speed));
    return BuildResult::failure(BuildResult::Code::invalid_argument,
                                "dem.particles[%zu].position: overlaps the bar's tip by %g m at the start, more than its "
                                "radius %g m (its centre is inside the bar): its contact would throw it out at up to %s",
                                i, overlap, p.radius, speed);
  }
  return BuildResult::success();
}

/// build_coupled() after its checks. May throw std::bad_alloc.
BuildResult build_coupled_sized(const CoupledDesc& desc, const DemDesc<1>& dem, CoupledModel& m, CoupledState& s,
                                CoupledWorkspace& w) {
  // The coupled check replaces the halves' own.
  BarDesc bar = desc.bar;
  bar.energy_check = kEnergyCheckOff;
  BuildResult r = build_bar(bar, m.bar, s.bar, w.bar);
  if (!r.ok()) return prefixed("bar.", r);
  if (r = check_tip_overlaps(dem, desc.bar.length, m.bar.tip_mass); !r.ok()) return r;
  r = build_dem(dem, m.dem, s.dem, w.dem);
  // Out of memory: said with the coupled world's counts (its copies of the state).
  if (r.code == BuildResult::Code::memory) throw std::bad_alloc();
  if (!r.ok()) return prefixed("dem.", r);

  m.substeps = desc.dem_substeps;
  m.dt = desc.bar.dt;
  m.top_plane = static_cast<std::int32_t>(dem.planes.size() - 1);
  m.top_position = desc.bar.length;
  // A particle on the top node is a two-mass oscillator: stiffer than the
  // particle on a rigid plane that build_dem checked.
  double worst = 0;
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    m.max_contact_stiffness = std::max(m.max_contact_stiffness, m.dem.stiffness[i]);
    worst = std::max(worst, m.dem.stiffness[i] * (1.0 / m.bar.tip_mass + m.dem.inv_mass[i]));
  }
  m.coupling_omega = std::sqrt(worst);
  const double factor = dem_stable_step_factor(dem.integrator, dem.damping_ratio);
  m.beyond_stable_step = m.coupling_omega * dem.dt > factor || m.coupling_omega * m.dt > kCoupledMaxOmegaDt;
  if (desc.reject_unstable_coupling && m.coupling_omega * dem.dt > factor)
    return BuildResult::failure(BuildResult::Code::unstable_time_step,
                                "time.dt: the particle substep %g s (dt / dem_substeps) exceeds the stable step %g s of "
                                "%s for a particle on the bar's top node (omega = sqrt(k (1/m_top + 1/m_particle)) = %g "
                                "rad/s, m_top = %g kg); reduce time.dt or raise time.dem_substeps",
                                dem.dt, factor / m.coupling_omega, integrator_name(dem.integrator), m.coupling_omega,
                                m.bar.tip_mass);
  if (desc.reject_unstable_coupling && m.coupling_omega * m.dt > kCoupledMaxOmegaDt)
    return BuildResult::failure(BuildResult::Code::unstable_time_step,
                                "time.dt: %g s is too long for the particle-bar exchange to settle: omega*dt = %.3g > %.3g "
                                "(omega = sqrt(k (1/m_top + 1/m_particle)) = %g rad/s, m_top = %g kg); reduce time.dt",
                                m.dt, m.coupling_omega * m.dt, kCoupledMaxOmegaDt, m.coupling_omega, m.bar.tip_mass);
  m.energy_check = desc.energy_check;
  // The sensitivity has one entry per double of the particles' state.
  std::int32_t doubles = 0;
  for_each_double(s.dem, [&](const char* name, double*, std::size_t count) {
    if (std::strcmp(name, "plane_impulse") == 0) m.sensitivity_top_impulse = doubles + m.top_plane;
    doubles += static_cast<std::int32_t>(count);
  });
  s.sensitivity.assign(static_cast<std::size_t>(doubles), 0.0);
  coupled_restart_energy_ledger(m, s);
  w.dem_start = s.dem;
  w.bar_start = s.bar;
  w.dem_end = s.dem;
  w.bar_end = s.bar;
  w.dem_first = s.dem;
  return BuildResult::success();
}

}  // namespace

BuildResult build_coupled(const CoupledDesc& desc, CoupledModel& m, CoupledState& s, CoupledWorkspace& w) {
  m = CoupledModel{};
  s = CoupledState{};
  if (desc.dem_substeps < 1 || desc.dem_substeps > 1'000'000)
    return BuildResult::failure(BuildResult::Code::invalid_argument, "dem_substeps: must be in [1, 1e6] (got %d)",
                                desc.dem_substeps);
  if (BuildResult r = validate_energy_check(desc.energy_check); !r.ok()) return r;

  // The bar's top is a plane at x = L, normal up, that coupled_step drives.
  DemDesc<1> dem = desc.dem;
  dem.energy_check = kEnergyCheckOff;
  dem.dt = desc.bar.dt / desc.dem_substeps;
  dem.planes.push_back({{desc.bar.length}, {1.0}});
  // The budget is the coupled description's, counting the window's copies of
  // the particles' state, checked before anything is allocated.
  dem.max_memory_bytes = 0;
  const DemMemory memory = dem_memory(dem);
  if (desc.max_memory_bytes > 0 && memory.total(kDemStates) > desc.max_memory_bytes)
    return prefixed("dem.", dem_detail::memory_refusal(dem, memory, kDemStates, kDemStatesNote, desc.max_memory_bytes, false));
  try {
    return build_coupled_sized(desc, dem, m, s, w);
  } catch (const std::bad_alloc&) {
    m = CoupledModel{};
    s = CoupledState{};
    w.dem = DemWorkspace<1>{};
    w.bar = BarWorkspace{};
    w.dem_start = DemState<1>{};
    w.bar_start = BarState{};
    w.dem_end = DemState<1>{};
    w.bar_end = BarState{};
    w.dem_first = DemState<1>{};
    return prefixed("dem.", dem_detail::memory_refusal(dem, memory, kDemStates, kDemStatesNote, desc.max_memory_bytes, true));
  }
}

namespace {

/// One pass of the window from the saved start: the bar under `force`, then
/// the particles seeing its top move linearly. Returns J (the particles'
/// impulse from the top). A bar linear in its tip force is stepped by the
/// first pass only; a later pass moves its top's end along the step's
/// response (coupled_step corrects the bar itself once the window settles).
StepStatus window_pass(const CoupledModel& m, CoupledState& s, CoupledWorkspace& w, double force, bool restore,
                       double& impulse) {
  const bool bar_stepped = !restore || !m.bar.linear_in_tip_force;
  if (restore) {  // the first pass starts from the state as it is
    if (bar_stepped) s.bar = w.bar_start;  // same sizes: element-wise copies, no allocation
    dem_copy_state(s.dem, w.dem_start);
  }
  // A step not taken leaves the state as the window found it.
  const auto not_taken = [&](StepStatus status) {
    s.bar = w.bar_start;
    dem_copy_state(s.dem, w.dem_start);
    return status;
  };
  const auto now = [&w] { return w.clock_ns ? w.clock_ns() : 0; };
  const std::int64_t t0 = now();
  StepStatus status = StepStatus::ok;
  double u_end;
  if (bar_stepped) {
    w.tip_start = bar_tip_displacement(m.bar, s.bar);
    const BarInput input{force};
    status |= bar_resolve_acceleration(m.bar, s.bar, w.bar, input);
    if (has(status, kStepNotTaken)) return not_taken(status);
    status |= bar_step(m.bar, s.bar, w.bar, input);
    if (has(status, kStepNotTaken)) return not_taken(status);
    u_end = bar_tip_displacement(m.bar, s.bar);
    w.first_force = force;
    w.first_tip_end = u_end;
  } else {
    u_end = w.first_tip_end + (force - w.first_force) * m.bar.tip_response_displacement;
  }
  const std::int64_t t1 = now();
  dem_drive_plane(m.dem, s.dem, m.top_plane, w.tip_start, (u_end - w.tip_start) / m.dt);
  s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)] = 0.0;
  const std::int32_t history_at_start = s.dem.history_count;
  const std::int64_t events_before = s.dem.events_located;
  w.dem.contact_signature = 0;
  status |= dem_steps(m.dem, s.dem, w.dem, m.substeps);
  if (has(status, kStepNotTaken)) return not_taken(status);
  // What decides the window's map from the force to the particles' end: the
  // contacts that carried a force at each evaluation and where the multistep
  // history started. A located event makes the map nonlinear.
  w.pass_affine = s.dem.events_located == events_before;
  w.pass_signature = static_cast<std::int64_t>(w.dem.contact_signature * 8 + static_cast<std::uint64_t>(history_at_start));
  if (w.clock_ns) {
    w.profile.continuum_ns += t1 - t0;
    w.profile.particles_ns += now() - t1;
  }
  impulse = s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)];
  return status;
}

/// Whether the values the window reads before the halves' own checks can see
/// them are finite: the force and the books (the exchange's and the energy
/// check's), and the top plane's drive state,
/// which dem_drive_plane compares (a NaN compares unequal) and then overwrites.
/// 0·x is NaN exactly when x is NaN or infinite.
bool start_finite(const CoupledModel& m, const CoupledState& s) {
  const auto top = static_cast<std::size_t>(m.top_plane);
  const DemState<1>& dem = s.dem;
  const double sum = 0.0 * s.coupling_force + 0.0 * s.coupling_slope + 0.0 * s.coupling_slope_width + 0.0 * s.pending_impulse + 0.0 * s.impulse_to_particles +
                     0.0 * s.impulse_to_bar + 0.0 * dem.plane_offset[top] + 0.0 * dem.plane_speed[top] +
                     0.0 * dem.plane_time + 0.0 * dem.hist_plane_force[static_cast<std::size_t>(dem.history_head)][top] +
                     0.0 * s.energy.reference + 0.0 * s.energy.work + 0.0 * s.energy.peak;
  return sum == 0.0;
}

/// Whether a double of the particles' state moves with the window's force as
/// the state does (affinely, within one contact set). The network's frequency
/// bound and the particles' own energy books do not: the bound is the contact
/// set's, and the books are unused in a coupled world (its check is off; the
/// coupled check computes the energy from the state), so both keep the pass's.
bool moves_with_force(const char* name) {
  return std::strcmp(name, "network_omega2") != 0 && std::strcmp(name, "energy_reference") != 0 &&
         std::strcmp(name, "energy_work") != 0 && std::strcmp(name, "energy_peak") != 0;
}

/// CoupledState::sensitivity = (s.dem − first) / df, field by field; 0 where
/// the two passes agree, so that applying it leaves those bits alone.
void measure_sensitivity(CoupledState& s, const DemState<1>& first, double df) {
  std::size_t k = 0;
  for_each_double(const_cast<DemState<1>&>(first), [&](const char*, double* data, std::size_t count) {  // only read
    for (std::size_t i = 0; i < count; ++i) s.sensitivity[k++] = data[i];
  });
  k = 0;
  for_each_double(s.dem, [&](const char* name, double* data, std::size_t count) {
    const bool moves = moves_with_force(name);
    for (std::size_t i = 0; i < count; ++i, ++k) {
      // A field that did not change, or is not finite (a value nothing reads,
      // or one the halves have reported), has no sensitivity.
      const double change = data[i] - s.sensitivity[k];
      s.sensitivity[k] = moves && change != 0.0 && std::isfinite(change) ? change / df : 0.0;
    }
  });
}

/// Moves the particles' state along CoupledState::sensitivity by a force change df.
void apply_sensitivity(CoupledState& s, double df) {
  std::size_t k = 0;
  for_each_double(s.dem, [&](const char*, double* data, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i, ++k)
      if (s.sensitivity[k] != 0.0) data[i] += df * s.sensitivity[k];
  });
}

/// What the energy check weighs: the particles' books (dem/energy_books.hpp,
/// the bar's top among the planes) plus the bar's algorithmic energy.
EnergyTotals energy_totals(const CoupledModel& m, const CoupledState& s) {
  EnergyTotals t = dem_detail::energy_totals(m.dem, s.dem);
  const double bar = bar_algorithmic_energy(m.bar, s.bar);
  return {t.total + bar, t.in_motion + bar, t.magnitude + bar};
}

/// Books the work done from outside over the step just taken (the window's
/// start is in the workspace): the bar's tip load and base (its ledger's work
/// less what the exchange did on it), and the particles' external forces,
/// held constant over the window (O(n), so only with the check on).
void book_work(const CoupledModel& m, CoupledState& s, const CoupledWorkspace& w) {
  double work = (s.bar.energy.work - s.bar.input_work) - (w.bar_start.energy.work - w.bar_start.input_work);
  if (m.dem.features.external_forces && m.energy_check.interval > 0)
    for (std::int32_t i = 0; i < m.dem.n; ++i)
      work += s.dem.external_force[0][static_cast<std::size_t>(i)] *
              (s.dem.x[0][static_cast<std::size_t>(i)] - w.dem_start.x[0][static_cast<std::size_t>(i)]);
  s.energy.work += work;
}

}  // namespace

StepStatus coupled_step_untimed(const CoupledModel& m, CoupledState& s, CoupledWorkspace& w);

StepStatus coupled_step(const CoupledModel& m, CoupledState& s, CoupledWorkspace& w) {
  w.dem.clock_ns = w.clock_ns;
  if (w.clock_ns == nullptr) return coupled_step_untimed(m, s, w);
  const std::int64_t start = w.clock_ns();
  const StepStatus status = coupled_step_untimed(m, s, w);
  w.profile.step_ns += w.clock_ns() - start;
  ++w.profile.steps;
  w.profile.passes += s.last_passes;
  return status;
}

StepStatus coupled_step_untimed(const CoupledModel& m, CoupledState& s, CoupledWorkspace& w) {
  if (!m.bar.built || m.dem.accelerations == nullptr) return StepStatus::not_built;
  dem_copy_state(w.dem_start, s.dem);
  w.bar_start = s.bar;
  w.last_blend = false;
  w.last_blend_tip_spread = 0;
  // A non-finite start is stepped once and reported, like a non-finite pass.
  StepStatus status = start_finite(m, s) ? StepStatus::ok : StepStatus::non_finite;
  // The bar also takes back what earlier windows left unbalanced.
  const double carried = -s.pending_impulse / m.dt;
  // The fixed point of the window: a root of g(f) = −J(f)/dt − f, from last
  // window's force. g is continuous but only piecewise smooth (a contact that
  // opens or closes inside the window puts a kink in J), and decreasing: more
  // force up on the bar lifts its top, which pushes the particles harder.
  // Secant steps alone can cycle across a kink, so the root is bracketed and
  // every step stays inside the bracket (regula falsi with the Illinois
  // weights, bisection when the secant would land outside or stalls); until a
  // bracket exists, steps go the way g's sign says and double in length.
  double f = s.coupling_force, J = 0;
  status |= window_pass(m, s, w, f + carried, false, J);
  if (has(status, kStepNotTaken)) return status;
  double g = -J / m.dt - f;
  // 1e-10: J carries the round-off of ~40 weighted force sums and a bar
  // solve (observed 1e-12 relative); what is left is carried, not lost.
  const auto within_tolerance = [&m](double force, double impulse, double residual) {
    return std::fabs(residual) <= 1e-10 * (std::fabs(force) + std::fabs(impulse / m.dt)) ||
           (impulse == 0.0 && force == 0.0);
  };
  // lo: a force with g > 0 (the root is above it); hi: one with g < 0.
  double lo = 0, g_lo = 0, hi = 0, g_hi = 0;
  bool have_lo = false, have_hi = false;
  double f_prev = 0, g_prev = 0, step = 0;
  double width_last = std::numeric_limits<double>::infinity(), width_before = width_last;
  int passes = 1, same_side = 0;
  s.coupling_slope_width *= 0.5;
  bool settled = false;
  // One pass. A window that saw the contacts the sensitivity was measured
  // with is affine in f: its root is one Newton step away, and the pass at the
  // root is this pass moved along the sensitivity (the bar, linear in its tip
  // force, is corrected at the end as after any window). The step is taken
  // only within 64 measuring widths, so that the sensitivity's round-off
  // (that of two passes over their force difference) moves the state by at
  // most 64 times the passes' own. A root it misses (it cannot, but for
  // round-off) is taken to a real pass below.
  const std::int64_t first_signature = w.pass_signature;
  const bool first_affine = w.pass_affine;
  bool first_kept = false;  // w.dem_first holds the first pass
  if (m.bar.linear_in_tip_force && !has(status, StepStatus::non_finite) && !within_tolerance(f, J, g) &&
      s.sensitivity_width > 0 && first_affine && first_signature == s.sensitivity_signature) {
    const double slope = -s.sensitivity[static_cast<std::size_t>(m.sensitivity_top_impulse)] / m.dt - 1.0;
    const double move = -g / slope;
    if (slope < 0 && std::isfinite(move) && std::fabs(move) <= 64 * s.sensitivity_width) {
      apply_sensitivity(s, move);
      f_prev = f, g_prev = g;
      f += move;
      J = s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)];
      g = -J / m.dt - f;
      if (!within_tolerance(f, J, g)) {
        status |= window_pass(m, s, w, f + carried, true, J);
        if (has(status, kStepNotTaken)) return status;
        g = -J / m.dt - f;
        ++passes;
      }
    }
  }
  for (;;) {
    // Nothing to iterate once a value is NaN or infinite: the window is taken as it is.
    if (has(status, StepStatus::non_finite)) break;
    const double scale = std::fabs(f) + std::fabs(J / m.dt);
    if (within_tolerance(f, J, g)) {
      settled = true;
      break;
    }
    // Update the bracket with the pass just taken (the Illinois rule halves
    // the weight of an end kept twice in a row, so regula falsi cannot stall).
    if (g > 0) {
      lo = f, g_lo = g, have_lo = true;
      same_side = same_side > 0 ? same_side + 1 : 1;
      if (same_side >= 2 && have_hi) g_hi *= 0.5;
    } else {
      hi = f, g_hi = g, have_hi = true;
      same_side = same_side < 0 ? same_side - 1 : -1;
      if (same_side <= -2 && have_lo) g_lo *= 0.5;
    }
    // A bracket narrower than the tolerance's resolution holds a jump of J,
    // not a root: the linear contact's dashpot force starts at η·δ' when a
    // contact closes, so J jumps where the closing moves from one substep to
    // the next. (A smooth g would change by at most |g'|·width ≤ the
    // tolerance across it, and both ends would have settled; |g'| is taken
    // from the cached slope, at least 1.) No force is a fixed point there;
    // the window ends instead in the blend of the particles' states at the two
    // ends whose impulse is the bar's: the top's motion is the same at both to
    // within the tolerance, so the exchange stays exact, and the blend's
    // energy is at most the blend of the two ends' (kinetic and contact
    // energies are convex), so it creates none.
    const double resolution =
        std::max(64 * std::numeric_limits<double>::epsilon(), 1e-10 / std::max(1.0, std::fabs(s.coupling_slope))) *
        scale;
    if (have_lo && have_hi && std::fabs(hi - lo) <= resolution) {
      const double f_other = f == lo ? hi : lo;
      const double J_here = J, f_here = f, g_here = g;
      dem_copy_state(w.dem_end, s.dem);
      // A bar stepped at every pass ends the pass at each end on its own
      // state, and a unilateral interface may switch between the two: its
      // top then moves differently at the two ends (a tied bar's by the
      // tolerance), so the bar is blended too, with the particles' weight.
      const bool blend_bar = !m.bar.linear_in_tip_force;
      if (blend_bar) w.bar_end = s.bar;  // same sizes: element-wise copies, no allocation
      status |= window_pass(m, s, w, f_other + carried, true, J);
      if (has(status, kStepNotTaken)) return status;
      ++passes;
      f = f_other;
      // Both halves blended: the bar received (1 − θ) f + θ f_here, the
      // particles took (1 − θ) J + θ J_here, and θ zeroes the blend of the
      // two ends' residuals g. Only the particles blended: the bar keeps f,
      // and θ makes the particles' impulse −f dt.
      const double theta = blend_bar ? (-J / m.dt - f) / ((-J / m.dt - f) - g_here) : (-f * m.dt - J) / (J_here - J);
      if (theta > 0.0 && theta < 1.0 &&
          (!blend_bar || (w.bar_end.step == s.bar.step && w.bar_end.u.size() == s.bar.u.size())) &&
          dem_blend_state(s.dem, w.dem_end, theta)) {
        w.last_blend = true;
        if (blend_bar) {
          w.last_blend_tip_spread =
              std::fabs(bar_tip_displacement(m.bar, s.bar) - bar_tip_displacement(m.bar, w.bar_end));
          (void)bar_blend_step_ends(m.bar, s.bar, w.bar_end, theta);  // checked above
          f = (1.0 - theta) * f + theta * f_here;
        }
        J = s.dem.plane_impulse[static_cast<std::size_t>(m.top_plane)];
        settled = true;
      } else {
        settled = within_tolerance(f, J, -J / m.dt - f);  // this end is a root
      }
      break;
    }
    if (passes == kCoupledMaxPasses) break;
    double f_next;
    if (have_lo && have_hi) {
      // Regula falsi, but bisection when it would leave the bracket or when
      // the bracket has not halved over the last two passes (a root beside a
      // jump of J draws every secant to one end).
      const double width = std::fabs(hi - lo);
      f_next = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
      if (!(f_next > std::min(lo, hi) && f_next < std::max(lo, hi)) || width > 0.5 * width_before)
        f_next = 0.5 * (lo + hi);
      width_before = width_last;
      width_last = width;
    } else {
      // No bracket yet: a secant step if it goes the way g's sign says (g
      // decreasing), else a Picard step f + g; then at least double the last
      // step, so that a bracket is found in a few passes whatever the slope.
      // (the first move: a Newton step on the last window's slope, if it measured one)
      const double secant = passes > 1 && g != g_prev ? -g * (f - f_prev) / (g - g_prev)
                            : s.coupling_slope < 0 ? -g / s.coupling_slope
                                                   : g;
      double move = (secant > 0) == (g > 0) ? secant : g;
      if (passes > 2 && std::fabs(move) < 2 * std::fabs(step)) move = std::copysign(2 * std::fabs(step), g);
      f_next = f + move;
    }
    step = f_next - f;
    f_prev = f;
    g_prev = g;
    f = f_next;
    if (passes == 1 && m.bar.linear_in_tip_force && first_affine) {
      dem_copy_state(w.dem_first, s.dem);
      first_kept = true;
    }
    status |= window_pass(m, s, w, f + carried, true, J);
    if (has(status, kStepNotTaken)) return status;
    g = -J / m.dt - f;
    ++passes;
    // Two passes that saw the same contacts measure the window's sensitivity
    // for the windows after it that see them too.
    if (passes == 2 && first_kept && w.pass_affine && w.pass_signature == first_signature && f != f_prev &&
        !has(status, StepStatus::non_finite)) {
      measure_sensitivity(s, w.dem_first, f - f_prev);
      s.sensitivity_width = std::fabs(f - f_prev);
      s.sensitivity_signature = first_signature;
    }
    // The slope of the widest secant: g's round-off (~1e-11 of its scale)
    // divided by the width is the slope's error. The width a cached slope was
    // measured over halves every window (below), so the slope of a new
    // contact set takes over within a few windows.
    const double slope = (g - g_prev) / (f - f_prev);
    if (slope < 0 && std::isfinite(slope) && std::fabs(f - f_prev) >= s.coupling_slope_width) {
      s.coupling_slope_width = std::fabs(f - f_prev);
      s.coupling_slope = slope;
    }
  }
  if (m.bar.linear_in_tip_force && f + carried != w.first_force && !has(status, StepStatus::non_finite)) {
    const std::int64_t t0 = w.clock_ns ? w.clock_ns() : 0;
    status |= bar_adjust_step_input(m.bar, s.bar, w.bar, f + carried);
    if (w.clock_ns) w.profile.continuum_ns += w.clock_ns() - t0;
  }
  if (!settled && !has(status, StepStatus::non_finite)) status |= StepStatus::coupling_unstable;
  if (m.beyond_stable_step) status |= StepStatus::unstable_time_step;
  // Books: the particles took J, the bar received (f + carried)·dt.
  s.impulse_to_particles += J;
  s.impulse_to_bar += (f + carried) * m.dt;
  s.pending_impulse = s.impulse_to_particles + s.impulse_to_bar;
  s.coupling_force = f;
  s.last_passes = passes;
  s.peak_passes = std::max(s.peak_passes, passes);
  ++s.step;
  s.time = static_cast<double>(s.step) * m.dt;
  book_work(m, s, w);
  if (energy_check_due(m.energy_check, s.step)) {
    energy_check(s.energy, m.energy_check, energy_totals(m, s));
  }
  if (s.energy.exceeded != 0) status |= StepStatus::energy_growth;
  return status;
}

void coupled_restart_energy_ledger(const CoupledModel& m, CoupledState& s) {
  if (!m.bar.built) return;
  energy_restart(s.energy, energy_totals(m, s));
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
