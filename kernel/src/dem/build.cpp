// build_dem(): validation, feature resolution, capacities and sizing. The only
// DEM call that allocates.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <new>
#include <utility>
#include <vector>

#include "dem/contact_parameters.hpp"
#include "dem/forces.hpp"
#include "dem/granular.hpp"
#include "dem/memory.hpp"
#include "dem/network.hpp"

namespace xfdem {

const char* integrator_name(DemIntegrator integrator) noexcept {
  switch (integrator) {
    case DemIntegrator::abm4: return "abm4";
    case DemIntegrator::abm4_events: return "abm4_events";
    case DemIntegrator::verlet: return "verlet";
    case DemIntegrator::symplectic_euler: return "symplectic_euler";
    case DemIntegrator::rk4: return "rk4";
  }
  return "unknown";
}

const char* contact_law_name(ContactLaw law) noexcept {
  return law == ContactLaw::linear ? "linear" : law == ContactLaw::linear_nontensile ? "linear_nontensile" : "hertz";
}

namespace dem_detail {

template <int D, bool Frozen>
AccelerationKernel<D> pick(const DemFeatures& f) {
  // 2^3 feature combinations; the compiler drops the dead branches of each.
  const int key = (f.gravity ? 4 : 0) | (f.damped ? 2 : 0) | (f.nontensile ? 1 : 0);
  switch (key) {
    case 0: return &accelerations<D, false, false, false, Frozen>;
    case 1: return &accelerations<D, false, false, true, Frozen>;
    case 2: return &accelerations<D, false, true, false, Frozen>;
    case 3: return &accelerations<D, false, true, true, Frozen>;
    case 4: return &accelerations<D, true, false, false, Frozen>;
    case 5: return &accelerations<D, true, false, true, Frozen>;
    case 6: return &accelerations<D, true, true, false, Frozen>;
    default: return &accelerations<D, true, true, true, Frozen>;
  }
}

template <int D>
AccelerationKernel<D> select_kernel(const DemFeatures& f, bool frozen) {
  return frozen ? pick<D, true>(f) : pick<D, false>(f);
}

}  // namespace dem_detail

namespace {

using Code = BuildResult::Code;

bool finite_array(const double* a, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(a[i])) return false;
  return true;
}

/// Largest ω² = K/m_eff over all possible contacts. Pairs are grouped by
/// distinct (k, m) so that a large uniform packing costs O(n), not O(n²).
template <int D>
double max_contact_omega2(const DemDesc<D>& desc, bool pairs_possible) {
  double best = 0;
  if (!desc.planes.empty())
    for (const auto& p : desc.particles) best = std::max(best, p.stiffness / p.mass);
  if (!pairs_possible) return best;
  // Past 2048 classes the bound below is used: stop collecting there (a
  // packing of distinct particles would otherwise map every one of them).
  std::map<std::pair<double, double>, int> classes;
  for (const auto& p : desc.particles) {
    classes.emplace(std::make_pair(p.stiffness, p.mass), 0);
    if (classes.size() > 2048) break;
  }
  if (classes.size() > 2048) {
    // Bound: K(1/m_i + 1/m_j) <= k_i/m_i + k_j/m_j <= 2 max(k/m).
    for (const auto& p : desc.particles) best = std::max(best, 2.0 * p.stiffness / p.mass);
    return best;
  }
  for (auto a = classes.begin(); a != classes.end(); ++a)
    for (auto b = a; b != classes.end(); ++b) {
      const auto [ka, ma] = a->first;
      const auto [kb, mb] = b->first;
      best = std::max(best, ka * kb / (ka + kb) * (1.0 / ma + 1.0 / mb));
    }
  return best;
}

/// A particle's moment of inertia: its own, or ½ m r² (disk, 2D), 2/5 m r² (sphere).
template <int D>
double inertia_of(const ParticleDesc<D>& p) {
  if (p.inertia > 0) return p.inertia;
  return (D == 2 ? 0.5 : 0.4) * p.mass * p.radius * p.radius;
}

/// (1 − ν²)/E and 2(2 − ν)(1 + ν)/E of a material (0, 0: rigid).
struct Compliance {
  double inv_e, inv_g;
};
inline Compliance compliance(double E, double nu) {
  if (std::isnan(E) && std::isnan(nu)) return {0.0, 0.0};
  return {(1.0 - nu * nu) / E, 2.0 * (2.0 - nu) * (1.0 + nu) / E};
}

using dem_detail::law_rotates;
using dem_detail::rotates;

/// The hertz law's stable-step rule: its stiffness grows with the overlap, so
/// the build checks the stiffest contact at the reference overlap
/// δ = kHertzReferenceOverlap · R* (S_n = 2 E* R* √0.01 there); the step's
/// network bound then uses every contact's actual overlap.
template <int D>
double hertz_omega2(const DemDesc<D>& desc, bool pairs_possible) {
  const double root = std::sqrt(kHertzReferenceOverlap);
  double best = 0;
  for (const auto& pl : desc.planes) {
    const Compliance w = compliance(pl.youngs_modulus, pl.poisson_ratio);
    for (const auto& p : desc.particles) {
      const Compliance c = compliance(p.youngs_modulus, p.poisson_ratio);
      best = std::max(best, 2.0 / (c.inv_e + w.inv_e) * p.radius * root / p.mass);
    }
  }
  if (!pairs_possible) return best;
  std::map<std::array<double, 4>, int> classes;
  for (const auto& p : desc.particles) {
    classes.emplace(std::array<double, 4>{p.youngs_modulus, p.poisson_ratio, p.mass, p.radius}, 0);
    if (classes.size() > 2048) break;
  }
  if (classes.size() > 2048) {
    // Bound: E* ≤ min of the two E/(1 − ν²), R* ≤ min r, so
    // S_n (1/m_i + 1/m_j) ≤ 2 · 2√0.01 max(E r / ((1 − ν²) m)).
    for (const auto& p : desc.particles)
      best = std::max(best, 4.0 * root * p.radius / (compliance(p.youngs_modulus, p.poisson_ratio).inv_e * p.mass));
    return best;
  }
  for (auto a = classes.begin(); a != classes.end(); ++a)
    for (auto b = a; b != classes.end(); ++b) {
      const auto [ea, na, ma, ra] = a->first;
      const auto [eb, nb, mb, rb] = b->first;
      const double e_star = 1.0 / (compliance(ea, na).inv_e + compliance(eb, nb).inv_e);
      best = std::max(best, 2.0 * e_star * (ra * rb / (ra + rb)) * root * (1.0 / ma + 1.0 / mb));
    }
  return best;
}

template <std::size_t N>
void size_columns(std::array<std::vector<double>, N>& c, std::size_t n) {
  for (auto& col : c) col.assign(n, 0.0);
}

/// A particle starting deeper in a plane than its radius (its centre on the
/// solid side): refused, naming the particle and the plane.
template <int D>
BuildResult check_plane_overlaps(const DemDesc<D>& desc) {
  for (std::size_t p = 0; p < desc.planes.size(); ++p) {
    const auto& pl = desc.planes[p];
    double len = 0;
    for (double c : pl.normal) len += c * c;
    len = std::sqrt(len);
    for (std::size_t i = 0; i < desc.particles.size(); ++i) {
      const auto& q = desc.particles[i];
      double height = 0;  // of the centre above the plane
      for (int d = 0; d < D; ++d) height += (q.position[d] - pl.point[d]) * (pl.normal[d] / len);
      const double overlap = q.radius - height;
      if (!(overlap > q.radius)) continue;
      char speed[32];
      // The speed its spring's energy would give it: ½ k δ² (hertz: 8/15 E* √r δ^{5/2}).
      double e_star = 0;
      if (desc.law == ContactLaw::hertz)
        e_star = 1.0 / (compliance(q.youngs_modulus, q.poisson_ratio).inv_e +
                        compliance(pl.youngs_modulus, pl.poisson_ratio).inv_e);
      dem_detail::format_speed(desc.law == ContactLaw::hertz
                                   ? std::sqrt(2.0 * dem_detail::hertz_energy(e_star, q.radius, overlap) / q.mass)
                                   : overlap * std::sqrt(q.stiffness / q.mass),
                               speed, sizeof(speed));
      return BuildResult::failure(Code::invalid_argument,
                                  "particles[%zu].position: overlaps planes[%zu] by %g m at the start, more than its "
                                  "radius %g m (its centre is on the plane's solid side): its contact would throw it "
                                  "out at up to %s",
                                  i, p, overlap, q.radius, speed);
    }
  }
  return BuildResult::success();
}

/// Two particles starting overlapped by more than the smaller radius: refused,
/// naming the first such pair of the (built, sorted) pair list.
template <int D>
BuildResult check_pair_overlaps(const DemModel<D>& m, const DemState<D>& s) {
  for (std::int32_t c = 0; c < s.pair_count; ++c) {
    const std::int32_t i = s.pair_i[c], j = s.pair_j[c];
    double dist2 = 0;
    for (int d = 0; d < D; ++d) {
      const double dx = s.x[d][j] - s.x[d][i];
      dist2 += dx * dx;
    }
    const double overlap = m.radius[i] + m.radius[j] - std::sqrt(dist2);
    const double smaller = std::min(m.radius[i], m.radius[j]);
    if (!(overlap > smaller)) continue;
    char speed[32];
    const double inv_m = m.inv_mass[i] + m.inv_mass[j];
    dem_detail::format_speed(
        m.law == ContactLaw::hertz
            ? std::sqrt(2.0 * dem_detail::pair_spring_energy(m, i, j, s.pair_stiffness[c], overlap) * inv_m)
            : overlap * std::sqrt(s.pair_stiffness[c] * inv_m),
        speed, sizeof(speed));
    return BuildResult::failure(Code::invalid_argument,
                                "particles[%d].position: overlaps particles[%d] by %g m at the start, more than the "
                                "smaller radius %g m: their contact would throw them apart at up to %s",
                                j, i, overlap, smaller, speed);
  }
  return BuildResult::success();
}

/// build_dem() after its checks: sizes and fills the model, state and
/// workspace. May throw std::bad_alloc (build_dem turns it into a refusal).
template <int D>
BuildResult size_world(const DemDesc<D>& desc, const dem_detail::ResolvedSizes& sizes, DemModel<D>& m,
                       DemState<D>& s, DemWorkspace<D>& w) {
  const auto n = static_cast<std::int64_t>(desc.particles.size());
  // ---- stable step -----------------------------------------------------------
  const bool hertz = desc.law == ContactLaw::hertz;
  const bool pairs_possible = m.features.broad_phase != BroadPhase::none;
  const double omega2 = hertz ? hertz_omega2(desc, pairs_possible) : max_contact_omega2(desc, pairs_possible);
  // hertz: η = −2√(5/6) β √(S m*) is the damping ratio ζ = −√(5/6) β.
  const double zeta = hertz ? 0.5 * dem_detail::hertz_damping(desc.restitution) : desc.damping_ratio;
  const double factor = dem_stable_step_factor(desc.integrator, zeta);
  m.stable_factor = factor;  // the normal springs' (the network bound counts those only)
  m.max_contact_omega = std::sqrt(omega2);
  m.stable_dt = omega2 > 0 ? factor / m.max_contact_omega : INFINITY;
  // The tangential spring with the particle free to turn is a mode of its
  // own: a body's inverse mass there is 1/m + r²/I = g/m, g = 1 + m r²/I, so
  // ω_t² ≤ s g ω_n² (s = k_t/k_n; hertz: S_t/S_n = 4 G*/E* ≤ 4 max over the
  // bodies of (1/E)/(1/G) = 2(1 − ν)/(2 − ν), a mediant of their ratios), and
  // its dashpot, η_t = 2ζ√(k_t m*) on the translational m*, is a damping
  // ratio ζ_t = ζ√(m* Σ g/m) ≤ ζ√g: a disk (g = 3) at ζ = 0.9 has ζ_t = 1.56,
  // which the integrators hold at a smaller ω·dt than the normal mode's ζ;
  // and RK4 and ABM4 advance the spring to first order, a scheme of its own
  // (dem_tangential_stable_step_factor). Left to the normal mode's limit, a
  // sticking contact rang between ±μF_n and froze a rolling disk's slip.
  // Bounded by the largest s g and the smallest factor over the particles' ζ√g.
  double omega2_t = 0, mode_zeta = zeta;
  if ((hertz || m.features.rotation) && desc.friction > 0 && omega2 > 0) {
    // hertz: a body's (1/E)/(1/G) bound on S_t/S_n.
    auto hertz_ratio = [](double nu) { return 2.0 * (1.0 - nu) / (2.0 - nu); };
    double stiffness_ratio = hertz ? 0.0 : m.tangential_ratio, g_max = 1.0;
    std::vector<double> turning;
    for (const auto& p : desc.particles) {
      const double g = 1.0 + p.mass * p.radius * p.radius / inertia_of(p);
      turning.push_back(g);
      g_max = std::max(g_max, g);
      if (hertz) stiffness_ratio = std::max(stiffness_ratio, hertz_ratio(p.poisson_ratio));
    }
    if (hertz)
      for (const auto& pl : desc.planes)
        if (!std::isnan(pl.poisson_ratio))
          stiffness_ratio = std::max(stiffness_ratio, hertz_ratio(pl.poisson_ratio));
    omega2_t = omega2 * stiffness_ratio * g_max;
    std::sort(turning.begin(), turning.end());
    turning.erase(std::unique(turning.begin(), turning.end()), turning.end());
    // Many distinct g (inertias of their own): 32 samples of the range, ends included.
    constexpr std::size_t kSamples = 32;
    const std::size_t count = std::min(turning.size(), kSamples);
    double factor_t = INFINITY;
    for (std::size_t k = 0; k < count; ++k) {
      const double g = turning.size() <= kSamples ? turning[k]
                                                   : turning.front() + (turning.back() - turning.front()) *
                                                                           static_cast<double>(k) / (kSamples - 1);
      const double f = dem_tangential_stable_step_factor(desc.integrator, zeta * std::sqrt(g));
      if (f < factor_t) factor_t = f, mode_zeta = zeta * std::sqrt(g);
    }
    const double dt_t = factor_t / std::sqrt(omega2_t);
    if (dt_t < m.stable_dt) m.stable_dt = dt_t;
    m.max_contact_omega = std::max(m.max_contact_omega, std::sqrt(omega2_t));
  }
  if (desc.reject_unstable_dt && desc.dt > m.stable_dt) {
    if (omega2_t > 0 && m.stable_dt < factor / std::sqrt(omega2))
      return BuildResult::failure(Code::unstable_time_step,
                                  "dt: %g s exceeds the stable step %g s of integrator %s for the stiffest contact's "
                                  "tangential spring with the particle turning (omega_t = %g rad/s, damping ratio "
                                  "%g of that mode; stable omega*dt = %.4f)",
                                  desc.dt, m.stable_dt, integrator_name(desc.integrator), std::sqrt(omega2_t),
                                  mode_zeta, m.stable_dt * std::sqrt(omega2_t));
    return BuildResult::failure(Code::unstable_time_step,
                                "dt: %g s exceeds the stable step %g s of integrator %s for the stiffest contact "
                                "(omega = %g rad/s, damping ratio %g; stable omega*dt = %.4f)",
                                desc.dt, m.stable_dt, integrator_name(desc.integrator), std::sqrt(omega2), zeta,
                                factor);
  }

  // ---- particle columns ------------------------------------------------------
  const auto un = static_cast<std::size_t>(n);
  m.mass.resize(un);
  m.inv_mass.resize(un);
  m.radius.resize(un);
  m.stiffness.resize(un);
  m.plane_eta.resize(un);
  for (std::size_t i = 0; i < un; ++i) {
    const auto& p = desc.particles[i];
    m.mass[i] = p.mass;
    m.inv_mass[i] = 1.0 / p.mass;
    m.radius[i] = p.radius;
    m.stiffness[i] = p.stiffness;
    m.plane_eta[i] = 2.0 * desc.damping_ratio * std::sqrt(p.stiffness * p.mass);
  }
  if (hertz) {
    m.hertz_inv_e.resize(un);
    m.hertz_inv_g.resize(un);
    for (std::size_t i = 0; i < un; ++i) {
      const Compliance c = compliance(desc.particles[i].youngs_modulus, desc.particles[i].poisson_ratio);
      m.hertz_inv_e[i] = c.inv_e;
      m.hertz_inv_g[i] = c.inv_g;
    }
    for (const auto& pl : desc.planes) {
      const Compliance c = compliance(pl.youngs_modulus, pl.poisson_ratio);
      m.plane_inv_e.push_back(c.inv_e);
      m.plane_inv_g.push_back(c.inv_g);
    }
    m.hertz_damping = dem_detail::hertz_damping(desc.restitution);
  }
  if (m.features.rotation) {
    m.inv_inertia.resize(un);
    for (std::size_t i = 0; i < un; ++i) m.inv_inertia[i] = 1.0 / inertia_of(desc.particles[i]);
  }
  m.plane_point.reserve(desc.planes.size());
  m.plane_normal.reserve(desc.planes.size());
  for (const auto& pl : desc.planes) {
    double len = 0;
    for (double c : pl.normal) len += c * c;
    len = std::sqrt(len);
    std::array<double, D> normal;
    for (int d = 0; d < D; ++d) normal[d] = pl.normal[d] / len;
    m.plane_point.push_back(pl.point);
    m.plane_normal.push_back(normal);
  }

  // ---- state and workspace -----------------------------------------------------
  size_columns<D>(s.x, un);
  size_columns<D>(s.v, un);
  for (int k = 0; k < 4; ++k) {
    size_columns<D>(s.hist_v[k], un);
    size_columns<D>(s.hist_a[k], un);
  }
  size_columns<D>(s.x_ref, un);
  if (desc.external_forces) size_columns<D>(s.external_force, un);
  if (desc.external_torques) size_columns(s.external_torque, un);
  for (std::size_t i = 0; i < un; ++i)
    for (int d = 0; d < D; ++d) {
      s.x[d][i] = desc.particles[i].position[d];
      s.v[d][i] = desc.particles[i].velocity[d];
    }
  const auto up = static_cast<std::size_t>(sizes.max_pairs);
  s.pair_i.assign(up, 0);
  s.pair_j.assign(up, 0);
  s.pair_stiffness.assign(up, 0.0);
  s.pair_eta.assign(up, 0.0);
  if (m.features.rotation) {
    constexpr int S = spin_components(D);
    size_columns(s.w, un);
    for (int k = 0; k < 4; ++k) {
      size_columns(s.hist_w[k], un);
      size_columns(s.hist_alpha[k], un);
    }
    size_columns(w.w1, un);
    size_columns(w.cross_spin, static_cast<std::size_t>(m.n - m.split));
    size_columns(w.alpha1, un);
    for (std::size_t i = 0; i < un; ++i)
      for (int k = 0; k < S; ++k) s.w[k][i] = desc.particles[i].angular_velocity[k];
    size_columns(s.angle, un);
    size_columns(w.angle1, un);
    for (auto* c : {&w.ws, &w.alphas, &w.sum_w}) size_columns(*c, un);
    size_columns(w.angle_s, un);
    size_columns(w.sum_angle, un);
    if (desc.integrator == DemIntegrator::abm4_events) {
      size_columns(w.start_a, un);
      size_columns(w.start_w, un);
      size_columns(w.start_alpha, un);
      size_columns(w.start_angle, un);
    }
    size_columns(s.pair_xi, up);
    size_columns(s.plane_xi, un * desc.planes.size());
    if (m.features.broad_phase == BroadPhase::grid) {
      w.old_pair_i.assign(up, 0);
      w.old_pair_j.assign(up, 0);
      size_columns(w.old_pair_xi, up);
    }
  }
  for (auto* c : {&w.xs, &w.vs, &w.as, &w.sum_x, &w.sum_v, &w.x0, &w.v0, &w.a0, &w.x1, &w.v1}) size_columns<D>(*c, un);
  const std::size_t planes = desc.planes.size();
  // The impulse ledger: the planes, then the host's totals (DemDesc::external_contacts).
  const std::size_t ledger = planes + static_cast<std::size_t>(desc.external_contact_totals);
  s.plane_offset.assign(planes, 0.0);
  s.plane_speed.assign(planes, 0.0);
  s.plane_impulse.assign(ledger, 0.0);
  for (auto& f : s.hist_plane_force) f.assign(ledger, 0.0);
  for (auto* v : {&w.plane_force, &w.plane_force0, &w.plane_weighted, &w.plane_step_impulse}) v->assign(ledger, 0.0);
  w.plane_force_part.assign(2 * planes, 0.0);
  size_columns<D>(w.cross, static_cast<std::size_t>(m.n - m.split));
  if (m.features.broad_phase == BroadPhase::grid) {
    w.cell_start.assign(static_cast<std::size_t>(sizes.max_cells) + 1, 0);
    w.cell_particles.assign(un, 0);
    w.particle_cell.assign(un, 0);
  }
  w.network_row.assign(un * static_cast<std::size_t>(D * (D + 1) / 2), 0.0);
  if (m.features.broad_phase == BroadPhase::all_pairs) {
    std::int32_t c = 0;
    for (std::int32_t i = 0; i < m.n; ++i)
      for (std::int32_t j = i + 1; j < m.n; ++j, ++c) {
        const dem_detail::PairParameters pp = dem_detail::pair_parameters(m, i, j);
        s.pair_i[c] = i;
        s.pair_j[c] = j;
        s.pair_stiffness[c] = pp.stiffness;
        s.pair_eta[c] = pp.eta;
      }
    s.pair_count = c;
    s.pairs_valid = 1;
    s.peak_pairs = c;
  }

  m.accelerations = dem_detail::select_kernel<D>(m.features, false);
  m.accelerations_frozen = dem_detail::select_kernel<D>(m.features, true);

  // f(y_0): the first history entry.
  s.history_head = 0;
  s.history_count = 0;
  if (n > 0) {
    ConstColumns<D> x, v;
    Columns<D> a;
    for (int d = 0; d < D; ++d) {
      x[d] = s.x[d].data();
      v[d] = s.v[d].data();
      a[d] = s.hist_a[0][d].data();
    }
    w.eval_time = 0.0;
    StepStatus status;
    if constexpr (D > 1)
      status = m.features.rotation ? dem_detail::granular_evaluate_current<D>(m, s, w) : m.accelerations(m, s, w, x, v, a);
    else
      status = m.accelerations(m, s, w, x, v, a);
    if (has(status, kStepNotTaken)) {
      char text[128];
      m.accelerations = nullptr;
      return BuildResult::failure(Code::capacity,
                                  "capacities: the initial configuration does not fit (%s); raise the named capacity",
                                  describe(status, text, sizeof(text)));
    }
    // The list holds every pair within reach: the deep overlaps among them.
    if (BuildResult r = check_pair_overlaps(m, s); !r.ok()) {
      m.accelerations = nullptr;
      return r;
    }
    for (int d = 0; d < D; ++d) s.hist_v[0][d] = s.v[d];
    s.hist_plane_force[0] = w.plane_force;
    if (m.features.broad_phase != BroadPhase::grid)
      s.network_omega2 = m.law == ContactLaw::hertz ? dem_detail::network_omega2<D, true>(m, s, w, x)
                                                    : dem_detail::network_omega2<D>(m, s, w, x);
  }
  s.history_count = 1;
  m.energy_check = desc.energy_check;
  if (desc.small_system_path && !m.features.rotation) m.small_step = dem_detail::select_small_step<D>(m);
  dem_restart_energy_ledger(m, s);
  return BuildResult::success();
}

}  // namespace

template <int D>
BuildResult build_dem(const DemDesc<D>& desc, DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  m = DemModel<D>{};
  s = DemState<D>{};
  w = DemWorkspace<D>{};
  const auto n = static_cast<std::int64_t>(desc.particles.size());
  if (n > 50'000'000) return BuildResult::failure(Code::capacity, "particles: %lld exceeds the 5e7 limit", (long long)n);
  if (!(std::isfinite(desc.dt) && desc.dt > 0))
    return BuildResult::failure(Code::invalid_argument, "dt: must be finite and > 0 (got %g)", desc.dt);
  if (!(desc.damping_ratio >= 0 && desc.damping_ratio < 1))
    return BuildResult::failure(Code::invalid_argument, "damping_ratio: must be in [0, 1) (got %g)", desc.damping_ratio);
  if (!finite_array(desc.gravity.data(), D))
    return BuildResult::failure(Code::invalid_argument, "gravity: must be finite");
  if (BuildResult r = validate_energy_check(desc.energy_check); !r.ok()) return r;
  if (!(std::isfinite(desc.skin) && desc.skin >= 0))
    return BuildResult::failure(Code::invalid_argument, "skin: must be finite and >= 0 (got %g)", desc.skin);
  for (std::int64_t i = 0; i < n; ++i) {
    const auto& p = desc.particles[static_cast<std::size_t>(i)];
    const auto fail = [&](const char* field, const char* what, double value) {
      return BuildResult::failure(Code::invalid_argument, "particles[%lld].%s: %s (got %g)", (long long)i, field, what,
                                  value);
    };
    if (!(std::isfinite(p.mass) && p.mass > 0)) return fail("mass", "must be finite and > 0", p.mass);
    if (!(std::isfinite(p.radius) && p.radius > 0)) return fail("radius", "must be finite and > 0", p.radius);
    if (desc.law != ContactLaw::hertz) {
      if (!(std::isfinite(p.stiffness) && p.stiffness > 0)) return fail("stiffness", "must be finite and > 0", p.stiffness);
    } else {
      if (p.stiffness != 0) return fail("stiffness", "the hertz law takes youngs_modulus and poisson_ratio instead", p.stiffness);
      if (std::isnan(p.youngs_modulus) && std::isnan(p.poisson_ratio))
        return BuildResult::failure(Code::invalid_argument,
                                    "particles[%lld]: the hertz law needs youngs_modulus and poisson_ratio (both missing)",
                                    (long long)i);
      if (std::isnan(p.youngs_modulus))
        return BuildResult::failure(Code::invalid_argument,
                                    "particles[%lld].youngs_modulus: missing (the hertz law needs it; poisson_ratio is given)",
                                    (long long)i);
      if (std::isnan(p.poisson_ratio))
        return BuildResult::failure(Code::invalid_argument,
                                    "particles[%lld].poisson_ratio: missing (the hertz law needs it; youngs_modulus is given)",
                                    (long long)i);
      if (!(std::isfinite(p.youngs_modulus) && p.youngs_modulus > 0))
        return fail("youngs_modulus", "must be finite and > 0", p.youngs_modulus);
      if (!(p.poisson_ratio > -1 && p.poisson_ratio < 0.5))
        return fail("poisson_ratio", "must be in (-1, 0.5)", p.poisson_ratio);
    }
    if (desc.law != ContactLaw::hertz && !(std::isnan(p.youngs_modulus) && std::isnan(p.poisson_ratio)))
      return fail(std::isnan(p.youngs_modulus) ? "poisson_ratio" : "youngs_modulus",
                  "only the hertz law takes a material (this model's law is linear)",
                  std::isnan(p.youngs_modulus) ? p.poisson_ratio : p.youngs_modulus);
    if (!finite_array(p.position.data(), D))
      return BuildResult::failure(Code::invalid_argument, "particles[%lld].position: must be finite", (long long)i);
    if (!finite_array(p.velocity.data(), D))
      return BuildResult::failure(Code::invalid_argument, "particles[%lld].velocity: must be finite", (long long)i);
  }
  for (std::size_t p = 0; p < desc.planes.size(); ++p) {
    const auto& pl = desc.planes[p];
    if (!finite_array(pl.point.data(), D) || !finite_array(pl.normal.data(), D))
      return BuildResult::failure(Code::invalid_argument, "planes[%zu]: point and normal must be finite", p);
    double len2 = 0;
    for (double c : pl.normal) len2 += c * c;
    if (!(len2 > 1e-300)) return BuildResult::failure(Code::invalid_argument, "planes[%zu].normal: must not be zero", p);
    const bool no_e = std::isnan(pl.youngs_modulus), no_nu = std::isnan(pl.poisson_ratio);
    if (!(no_e && no_nu)) {  // absent (both): a rigid wall
      if (desc.law != ContactLaw::hertz)
        return BuildResult::failure(Code::invalid_argument,
                                    "planes[%zu].%s: only the hertz law takes a wall material (this model's law is linear)",
                                    p, no_e ? "poisson_ratio" : "youngs_modulus");
      if (no_e || no_nu)
        return BuildResult::failure(Code::invalid_argument,
                                    "planes[%zu].%s: missing (a wall's material needs youngs_modulus and poisson_ratio; "
                                    "neither: a rigid wall)",
                                    p, no_e ? "youngs_modulus" : "poisson_ratio");
      if (!(std::isfinite(pl.youngs_modulus) && pl.youngs_modulus > 0))
        return BuildResult::failure(Code::invalid_argument, "planes[%zu].youngs_modulus: must be finite and > 0 (got %g)",
                                    p, pl.youngs_modulus);
      if (!(pl.poisson_ratio > -1 && pl.poisson_ratio < 0.5))
        return BuildResult::failure(Code::invalid_argument, "planes[%zu].poisson_ratio: must be in (-1, 0.5) (got %g)",
                                    p, pl.poisson_ratio);
    }
  }
  if (BuildResult r = check_plane_overlaps(desc); !r.ok()) return r;
  // ---- friction and rotation ---------------------------------------------------
  if (!(std::isfinite(desc.friction) && desc.friction >= 0))
    return BuildResult::failure(Code::invalid_argument, "friction: must be finite and >= 0 (got %g)", desc.friction);
  if (!(std::isfinite(desc.rolling_friction) && desc.rolling_friction >= 0))
    return BuildResult::failure(Code::invalid_argument, "rolling_friction: must be finite and >= 0 (got %g)",
                                desc.rolling_friction);
  if (!(std::isfinite(desc.tangential_stiffness_ratio) && desc.tangential_stiffness_ratio >= 0))
    return BuildResult::failure(Code::invalid_argument,
                                "tangential_stiffness_ratio: must be finite and > 0, or 0 for the default %g (got %g)",
                                kDefaultTangentialStiffnessRatio, desc.tangential_stiffness_ratio);
  for (std::int64_t i = 0; i < n; ++i) {
    const auto& p = desc.particles[static_cast<std::size_t>(i)];
    if (!(std::isfinite(p.inertia) && p.inertia >= 0))
      return BuildResult::failure(Code::invalid_argument,
                                  "particles[%lld].inertia: must be finite and > 0, or 0 for the solid's own (got %g)",
                                  (long long)i, p.inertia);
    if (!finite_array(p.angular_velocity.data(), spin_components(D)))
      return BuildResult::failure(Code::invalid_argument, "particles[%lld].angular_velocity: must be finite",
                                  (long long)i);
  }
  if (!(desc.restitution > 0 && desc.restitution <= 1))
    return BuildResult::failure(Code::invalid_argument, "restitution: must be in (0, 1] (got %g)", desc.restitution);
  if (desc.law == ContactLaw::hertz) {
    if (D == 1)
      return BuildResult::failure(Code::invalid_argument, "law: hertz needs 2D or 3D (rods on a line take the linear laws)");
    if (desc.damping_ratio != 0)
      return BuildResult::failure(Code::invalid_argument,
                                  "damping_ratio: the hertz law is damped by its restitution instead (got %g)",
                                  desc.damping_ratio);
    if (desc.tangential_stiffness_ratio != 0)
      return BuildResult::failure(Code::invalid_argument,
                                  "tangential_stiffness_ratio: the hertz law's tangential stiffness is Mindlin's 8 G* "
                                  "sqrt(R* delta) (got %g)",
                                  desc.tangential_stiffness_ratio);
  } else if (desc.restitution != 1) {
    return BuildResult::failure(Code::invalid_argument,
                                "restitution: only the hertz law takes it (the linear laws take damping_ratio; got %g)",
                                desc.restitution);
  }
  if (desc.friction > 0 || desc.rolling_friction > 0 || desc.law == ContactLaw::hertz) {
    if (D == 1)
      return BuildResult::failure(Code::invalid_argument,
                                  "%s: rods on a line do not rotate: friction and rolling friction need 2D or 3D",
                                  desc.friction > 0 ? "friction" : "rolling_friction");
  }
  if (desc.external_torques && !(D == 2 && law_rotates(desc)))
    return BuildResult::failure(Code::invalid_argument,
                                "external_torques: needs particles that rotate in 2D (friction or rolling_friction > 0, "
                                "or the hertz law; the energy books count a torque's work on the 2D angle) (D = %d)",
                                D);
  if (desc.split_from < 0)
    return BuildResult::failure(Code::invalid_argument, "split_from: must be >= 0 (got %d)", desc.split_from);
  if (desc.external_contact_totals < 0 || desc.external_contact_totals > 100'000'000 ||
      (desc.external_contact_totals > 0 && !desc.external_contacts))
    return BuildResult::failure(Code::invalid_argument,
                                "external_contact_totals: must be in [0, 1e8], and 0 without external_contacts (got %d)",
                                desc.external_contact_totals);
  if (desc.external_contacts) {
    if (desc.integrator == DemIntegrator::abm4_events)
      return BuildResult::failure(Code::invalid_argument,
                                  "integrator: %s cannot take external contacts: its frozen contact sets and event "
                                  "tests do not see them (use abm4, rk4, verlet or symplectic_euler)",
                                  integrator_name(desc.integrator));
    if (desc.energy_check.interval > 0)
      return BuildResult::failure(Code::invalid_argument,
                                  "energy_check: the work of external contacts is the host's to book; turn the "
                                  "particles' check off (interval 0) and check the energy in the host");
  }

  // ---- sizes, and what they take, before anything is allocated ----------------
  const dem_detail::ResolvedSizes sizes = dem_detail::resolve_sizes(desc);
  if (sizes.max_pairs > std::numeric_limits<std::int32_t>::max())
    return BuildResult::failure(Code::capacity,
                                "particles: %lld particles paired all with all need %lld pairs, more than this build "
                                "can index (2147483647); lower all_pairs_up_to",
                                (long long)n, (long long)sizes.max_pairs);
  // abm4_events with rotation keeps each piece's tangential springs as it
  // lands, before the step is known to complete; a grid rebuild is the one
  // stage that could still refuse the step, and would leave them advanced.
  if (desc.integrator == DemIntegrator::abm4_events && rotates(desc) && sizes.broad_phase == BroadPhase::grid)
    return BuildResult::failure(Code::invalid_argument,
                                "integrator: %s with friction, rolling friction, the hertz law or a spinning particle takes the pairs of "
                                "broad phase none or all_pairs (%lld particles need the grid; raise all_pairs_up_to "
                                "or use abm4, rk4, verlet or symplectic_euler)",
                                integrator_name(desc.integrator), (long long)n);
  if (sizes.max_cells > dem_detail::kMaxGridCells)
    return BuildResult::failure(Code::capacity, "capacities.max_grid_cells: %lld is more than this build can index (%lld)",
                                (long long)sizes.max_cells, (long long)dem_detail::kMaxGridCells);
  const DemMemory memory = dem_memory(desc);
  if (desc.max_memory_bytes > 0 && memory.total() > desc.max_memory_bytes)
    return dem_detail::memory_refusal(desc, memory, 1, "", desc.max_memory_bytes, false);

  // ---- features and broad phase --------------------------------------------
  m.n = static_cast<std::int32_t>(n);
  m.gravity = desc.gravity;
  m.law = desc.law;
  m.damping_ratio = desc.damping_ratio;
  m.integrator = desc.integrator;
  m.dt = desc.dt;
  m.features.gravity = std::any_of(desc.gravity.begin(), desc.gravity.end(), [](double g) { return g != 0.0; });
  m.features.damped = desc.damping_ratio > 0;
  m.features.nontensile = desc.law == ContactLaw::linear_nontensile;
  m.features.planes = !desc.planes.empty();
  m.features.external_forces = desc.external_forces;
  m.features.external_torques = desc.external_torques;
  m.features.external_contacts = desc.external_contacts;
  m.features.broad_phase = sizes.broad_phase;
  m.features.rotation = rotates(desc);
  m.friction = desc.friction;
  m.rolling_friction = desc.rolling_friction;
  m.tangential_ratio =
      desc.tangential_stiffness_ratio > 0 ? desc.tangential_stiffness_ratio : kDefaultTangentialStiffnessRatio;
  m.parts = sizes.parts;
  m.split = sizes.split;
  double r_max = 0;
  for (const auto& p : desc.particles) r_max = std::max(r_max, p.radius);
  m.skin = desc.skin > 0 ? desc.skin : 0.5 * r_max;
  m.cell_size = 2.0 * r_max + m.skin;
  m.capacities.max_pairs = static_cast<std::int32_t>(sizes.max_pairs);
  m.capacities.max_neighbors_per_particle = static_cast<std::int32_t>(sizes.max_neighbors);
  m.capacities.max_grid_cells = static_cast<std::int32_t>(sizes.max_cells);
  m.capacities.max_events_per_step = static_cast<std::int32_t>(sizes.max_events);

  // The kernel never throws: an allocation the system refuses is a refusal too,
  // and leaves nothing allocated.
  try {
    return size_world(desc, sizes, m, s, w);
  } catch (const std::bad_alloc&) {
    m = DemModel<D>{};
    s = DemState<D>{};
    w = DemWorkspace<D>{};
    return dem_detail::memory_refusal(desc, memory, 1, "", desc.max_memory_bytes, true);
  }
}

template BuildResult build_dem<1>(const DemDesc<1>&, DemModel<1>&, DemState<1>&, DemWorkspace<1>&);
template BuildResult build_dem<2>(const DemDesc<2>&, DemModel<2>&, DemState<2>&, DemWorkspace<2>&);
template BuildResult build_dem<3>(const DemDesc<3>&, DemModel<3>&, DemState<3>&, DemWorkspace<3>&);

}  // namespace xfdem
