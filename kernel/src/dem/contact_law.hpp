// The contact law, in one place: the normal spring-dashpot, its stored
// energy, the tangential (Cundall–Strack) spring with its Coulomb cap, and
// rolling resistance. The step's kernels (plain and frozen), the granular
// step, the probes and the energy books all call these, so that they round
// alike and cannot drift apart.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

#include "xfdem/dem.hpp"

namespace xfdem::dem_detail {

/// Whether a contact is "on": overlap δ > 0 for `linear`; for the non-tensile
/// law additionally the unclamped force K δ + η δ' > 0. Written as a continuous
/// function (min of the two, in metres) so that events can be located by
/// its sign change.
inline double contact_indicator(bool nontensile, double overlap, double rate, double K, double eta) {
  if (!nontensile) return overlap;
  return std::min(overlap, overlap + eta * rate / K);
}

/// Normal force of the plain law at overlap δ > 0 and overlap rate δ'
/// (compressive positive).
template <bool Damped, bool NonTensile>
inline double normal_force(double K, double eta, double overlap, double rate) {
  double force = K * overlap;
  if constexpr (Damped) force += eta * rate;
  if constexpr (NonTensile) force = std::max(force, 0.0);
  return force;
}

/// The same law for any δ with the law chosen at run time (probes, the
/// granular step): 0 when apart.
inline double normal_force(bool nontensile, double K, double eta, double overlap, double rate) {
  if (!(overlap > 0)) return 0.0;
  return nontensile ? normal_force<true, true>(K, eta, overlap, rate) : normal_force<true, false>(K, eta, overlap, rate);
}

/// Energy of the normal spring at overlap δ > 0: ½ K δ².
inline double spring_energy(double K, double overlap) { return 0.5 * K * overlap * overlap; }

/// The hertz law at one contact: E*, G*, R* and m* of the two bodies, the
/// model's −2√(5/6) β (`damping`), overlap δ > 0 and rate δ'.
///   F_n = 4/3 E* √R* δ^{3/2} + η_n δ',  S_n = 2 E* √(R* δ),  S_t = 8 G* √(R* δ),
///   η_n = −2√(5/6) β √(S_n m*),  η_t = −2√(5/6) β √(S_t m*).
/// Like `linear`, the dashpot may pull at the end of a contact (as LIGGGHTS
/// without `limitForce`).
struct HertzContact {
  double fn, sn, st, eta_n, eta_t;
};
inline HertzContact hertz_contact(double e_star, double g_star, double r_star, double m_star, double damping,
                                  double overlap, double rate) {
  HertzContact c{};
  if (!(overlap > 0)) return c;
  const double root = std::sqrt(r_star * overlap);
  c.sn = 2.0 * e_star * root;
  c.st = 8.0 * g_star * root;
  c.eta_n = damping * std::sqrt(c.sn * m_star);
  c.eta_t = damping * std::sqrt(c.st * m_star);
  c.fn = (2.0 / 3.0) * c.sn * overlap + c.eta_n * rate;
  return c;
}

/// Energy of the Hertz normal spring at overlap δ > 0: 8/15 E* √R* δ^{5/2}
/// (= 2/5 of its elastic force times δ).
inline double hertz_energy(double e_star, double r_star, double overlap) {
  if (!(overlap > 0)) return 0.0;
  return (8.0 / 15.0) * e_star * std::sqrt(r_star * overlap) * overlap * overlap;
}

/// Energy of a pair's normal spring at overlap δ > 0; K the pair's cached
/// stiffness (hertz: E*).
template <int D>
double pair_spring_energy(const DemModel<D>& m, std::int32_t i, std::int32_t j, double K, double overlap) {
  if (m.law != ContactLaw::hertz) return spring_energy(K, overlap);
  return hertz_energy(K, m.radius[i] * m.radius[j] / (m.radius[i] + m.radius[j]), overlap);
}

/// −2√(5/6) β with β = ln e / √(ln² e + π²): 0 for e = 1.
inline double hertz_damping(double restitution) {
  const double l = std::log(restitution);
  return -2.0 * std::sqrt(5.0 / 6.0) * l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

/// Tangential spring of one contact: stiffness k_t, sticking dashpot η_t and
/// Coulomb coefficient μ.
struct TangentialLaw {
  double kt, eta_t, mu;
};

/// Cundall–Strack tangential force on the second body of a contact whose unit
/// normal n points from the first to the second body and whose contact point
/// slides at vt (second relative to first, in the contact plane).
///  1. the stored spring ξ is turned into the current contact plane, its
///     length kept (the plane rotates with the bodies);
///  2. ξ += h vt (h = 0: a probe, nothing accumulates);
///  3. trial F = −k_t ξ − η_t vt; above the cap μ|F_n| the contact slides:
///     F is scaled to the cap and ξ reset to the cap, the spring that gives
///     that F with the same dashpot term, ξ = −(F + η_t vt)/k_t. (Resetting
///     ξ to carry the cap alone would store the dashpot's share in the spring
///     and create energy at every slip.)
/// Returns F; writes ξ back.
/// The hertz law keeps its history as a force instead (Mindlin's stiffness
/// changes with the overlap): it calls this with k_t = 1 and h' = S_t h, so
/// that ξ holds −F_spring and each step adds S_t Δξ to the spring force.
template <int D>
inline void tangential_force(const TangentialLaw& law, const double (&n)[D], const double (&vt)[D], double fn,
                             double h, double (&xi)[D], double (&force)[D]) {
  double along = 0, before = 0;
  for (int d = 0; d < D; ++d) {
    along += xi[d] * n[d];
    before += xi[d] * xi[d];
  }
  if (along != 0.0) {
    double after = 0;
    for (int d = 0; d < D; ++d) {
      xi[d] -= along * n[d];
      after += xi[d] * xi[d];
    }
    const double keep = after > 0 ? std::sqrt(before / after) : 0.0;
    for (int d = 0; d < D; ++d) xi[d] *= keep;
  }
  double f2 = 0;
  for (int d = 0; d < D; ++d) {
    xi[d] += h * vt[d];
    force[d] = -law.kt * xi[d] - law.eta_t * vt[d];
    f2 += force[d] * force[d];
  }
  const double cap = law.mu * std::fabs(fn);
  if (f2 > cap * cap) {
    const double scale = cap / std::sqrt(f2);
    for (int d = 0; d < D; ++d) {
      force[d] *= scale;
      xi[d] = -(force[d] + law.eta_t * vt[d]) / law.kt;
    }
  }
}

/// Energy of the tangential spring for the books: ½ k_t |ξ|², its force
/// k_t |ξ| counted at most to `cap`, the Coulomb cap μ K δ of the normal
/// spring's force now (0 apart). While a contact slides, step 3 above resets
/// ξ to carry the cap and the dashpot's share, so k_t |ξ| reaches η_t |vt|,
/// far above the cap for a fast slip; that part is the dashpot's, not
/// elastic energy a motion gets back, and as the slip slows it leaves ξ
/// without doing work. Counted whole, a disk thrown along a surface showed
/// a third of its kinetic energy as a rise (an energy check's false alarm).
template <int D>
inline double tangential_energy(double kt, const double* const (&xi)[D], std::size_t k, double cap) {
  double sum = 0;
  for (int d = 0; d < D; ++d) sum += xi[d][k] * xi[d][k];
  if (kt * kt * sum <= cap * cap) return 0.5 * kt * sum;
  return 0.5 * cap * cap / kt;
}

/// Rolling resistance torque on the second body of a contact (the first gets
/// its opposite): a couple of at most μ_r R* |F_n| that holds the relative
/// rolling w (second minus first; 3D: its part in the contact plane) at rest
/// and resists it otherwise. The caller passes `held`, the relative rolling
/// the contact would have after `hold` (> 0; the model's step) under its own
/// tangential torques alone,
///   held = w + hold (τ_t2/I_2 − τ_t1/I_1),
/// and K = 1/I_1 + 1/I_2 (`inv_inertia`; a plane does not turn: 1/I = 0).
/// The torque is the point of the ball |τ| ≤ μ_r R* |F_n| nearest the one
/// that brings `held` to zero, −held/(hold K):
///   |held|/(hold K) ≤ μ_r R* |F_n|: τ_r = −held/(hold K), which cancels the
///     tangential torques' effect on w and stops w within the hold: a disk on
///     a slope with tan θ ≤ μ_r, whose sticking contact carries m g sin θ and
///     so a torque m g sin θ r, rests exactly (α = 0 up to round-off);
///   otherwise τ_r = −μ_r R* |F_n| held/|held|: a constant couple against the
///     rolling, as a rolling disk feels.
/// (A couple against w alone, capped at −w/(hold K), balanced a steady
/// tangential torque only while w was h τ_t/I: the particle crept.)
/// Energy: with λ = min(1, μ_r R* |F_n| hold K/|held|) ∈ (0, 1],
///   τ_r = λ (−w/(hold K)) + λ (−(τ_t2/I_2 − τ_t1/I_1)/K).
/// The first part's power against the relative rolling, −λ|w|²/(hold K), is
/// never positive; the second is the fraction λ of the couple that cancels the
/// tangential torques' share of d w/dt: it takes back (at most all of) the
/// rolling the tangential force would drive, and adds none of its own. After
/// the hold, w⁺ = held + hold K τ_r is 0 or (1 − λ) held, so τ_r · w⁺ =
/// −μ_r R* |F_n| |w⁺| ≤ 0: the implicit step of the set-valued law
/// τ_r ∈ −μ_r R* |F_n| ∂|w| (tests/dem/rolling_hold_test.cpp books the
/// energy). Every path calls this with the same hold (the model's dt): the
/// step at each stage, the frozen kernels, the probes (h = 0 there is the
/// spring's advance only).
template <int S>
inline void rolling_torque(double mu_r, double r_eff, double fn, const double (&held)[S], double inv_inertia,
                           double hold, double (&torque)[S]) {
  double w2 = 0;
  for (int k = 0; k < S; ++k) w2 += held[k] * held[k];
  for (int k = 0; k < S; ++k) torque[k] = 0.0;
  if (!(w2 > 0)) return;
  const double speed = std::sqrt(w2);
  const double magnitude = std::min(mu_r * r_eff * std::fabs(fn), speed / (hold * inv_inertia));
  for (int k = 0; k < S; ++k) torque[k] = -magnitude * held[k] / speed;
}

}  // namespace xfdem::dem_detail
