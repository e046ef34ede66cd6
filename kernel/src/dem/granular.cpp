// The granular step: particles that rotate, with Coulomb friction and rolling
// resistance (DemFeatures::rotation). A frictionless model never comes here
// (integrators.cpp keeps its step, bit for bit).
//
// The step, in the order it runs (granular_step below):
//   1. integrate (first part): the one-step integrator's kick and drift of
//      every column it advances, translation (x, v) and rotation (θ, ω), into
//      a trial state in the workspace;
//   2. broad phase: the grid's pair list rebuilt at the trial positions when
//      stale, the contact records (tangential springs) carried over by (i, j);
//   3. contacts and forces at the trial state: normal, tangential (the spring
//      advanced by dt) and rolling, one law (dem/contact_law.hpp), planes then
//      pairs in list order;
//   4. integrate (second part): the final kick;
//   (rk4: 1-3 for each of its four stages and for y_n+1, rk4_columns; abm4
//   after three rk4 steps: for the prediction and for y_n+1, abm4_columns;)
//   5. commit and books: the trial state becomes the state (a refused step
//      leaves it untouched), time, the network bound, the finiteness check,
//      the planes' impulses and the energy books.
// A model of two parts (DemModel::parts) runs stages 1-4 on them as the
// frictionless step does (granular_forces); every sum has the model's order,
// so the bits do not depend on the host's workers.
#include <algorithm>
#include <bit>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "dem/contact_law.hpp"
#include "dem/contact_parameters.hpp"
#include "dem/energy_books.hpp"
#include "dem/forces.hpp"
#include "dem/granular.hpp"
#include "dem/network.hpp"

namespace xfdem::dem_detail {
namespace {

/// ω × n for the contact geometry: 2D ω (about z) × n = ω (−n_y, n_x).
template <int D, class T>
inline void spin_cross(const T* w, const T (&n)[D], T (&out)[D]) {
  if constexpr (D == 2) {
    out[0] = -w[0] * n[1];
    out[1] = w[0] * n[0];
  } else {
    out[0] = w[1] * n[2] - w[2] * n[1];
    out[1] = w[2] * n[0] - w[0] * n[2];
    out[2] = w[0] * n[1] - w[1] * n[0];
  }
}

/// n × F (the torque of F applied at the arm n), S components.
template <int D, class T>
inline void moment(const T (&n)[D], const T (&f)[D], T (&out)[spin_components(D)]) {
  if constexpr (D == 2) {
    out[0] = n[0] * f[1] - n[1] * f[0];
  } else {
    out[0] = n[1] * f[2] - n[2] * f[1];
    out[1] = n[2] * f[0] - n[0] * f[2];
    out[2] = n[0] * f[1] - n[1] * f[0];
  }
}

}  // namespace

namespace {

/// The law's run-time choices as template arguments, so that the contact
/// kernels below test none of them per contact.
/// Frozen: abm4_events' trial and pieces, whose contact set is the one of
/// the interval's start (DemWorkspace::mode_x, mode_v, mode_time) and whose
/// linear normal law continues past a contact's end (see normal_of).
template <ContactLaw L, bool Friction, bool Rolling, bool Frozen = false>
struct LawKind {
  static constexpr ContactLaw law = L;
  static constexpr bool friction = Friction, rolling = Rolling, frozen = Frozen;
};

/// Calls f(LawKind<...>{}) for the model's law, friction and rolling
/// resistance (frozen: the abm4_events kernels; only that integrator asks).
template <int D, class F>
decltype(auto) with_law(const DemModel<D>& m, F&& f, bool frozen = false) {
  const bool friction = m.friction > 0, rolling = m.rolling_friction > 0;
  auto pick = [&]<ContactLaw L, bool Z>() -> decltype(auto) {
    if (friction) return rolling ? f(LawKind<L, true, true, Z>{}) : f(LawKind<L, true, false, Z>{});
    return rolling ? f(LawKind<L, false, true, Z>{}) : f(LawKind<L, false, false, Z>{});
  };
  auto law = [&]<bool Z>() -> decltype(auto) {
    switch (m.law) {
      case ContactLaw::hertz: return pick.template operator()<ContactLaw::hertz, Z>();
      case ContactLaw::linear_nontensile: return pick.template operator()<ContactLaw::linear_nontensile, Z>();
      default: return pick.template operator()<ContactLaw::linear, Z>();
    }
  };
  if (frozen && m.integrator == DemIntegrator::abm4_events) return law.template operator()<true>();
  return law.template operator()<false>();
}

/// The linear laws' normal force at a contact (overlap δ, rate δ'). Frozen
/// (a contact of the interval start's set): the spring-dashpot continued
/// past δ = 0 without the cut, as the frictionless frozen kernel continues
/// it, so that a trial or a piece that crosses the contact's end sees a
/// force continuous in the state; the set's change is located instead.
template <class Kind>
inline double normal_of(double K, double eta, double overlap, double rate) {
  if constexpr (Kind::frozen) return normal_force<true, false>(K, eta, overlap, rate);
  return normal_force(Kind::law == ContactLaw::linear_nontensile, K, eta, overlap, rate);
}

/// What the contact law reads of the model, copied out of it once per
/// evaluation: the kernels' stores into acceleration columns (doubles) could
/// otherwise alias the model's double parameters, which the compiler would
/// then reload at every contact.
template <int D>
struct LawView {
  const double *radius, *mass, *inv_mass, *inv_inertia, *stiffness, *plane_eta;
  const double *hertz_inv_e, *hertz_inv_g, *plane_inv_e, *plane_inv_g;
  const std::array<double, D>* plane_normal;
  double friction, tangential_ratio, damping_ratio, hertz_damping, rolling_friction;
  double hold;  ///< the rolling resistance's hold: the model's step (rolling_torque)
  explicit LawView(const DemModel<D>& m)
      : radius(m.radius.data()), mass(m.mass.data()), inv_mass(m.inv_mass.data()),
        inv_inertia(m.inv_inertia.data()), stiffness(m.stiffness.data()), plane_eta(m.plane_eta.data()),
        hertz_inv_e(m.hertz_inv_e.data()), hertz_inv_g(m.hertz_inv_g.data()), plane_inv_e(m.plane_inv_e.data()),
        plane_inv_g(m.plane_inv_g.data()), plane_normal(m.plane_normal.data()), friction(m.friction),
        tangential_ratio(m.tangential_ratio), damping_ratio(m.damping_ratio), hertz_damping(m.hertz_damping),
        rolling_friction(m.rolling_friction), hold(m.dt) {}
};

template <int D, class Kind>
[[gnu::always_inline]] inline ContactResult<D> pair_contact_as(const LawView<D>& m, std::int32_t i, std::int32_t j,
                                                               double K, double eta, const double (&dx)[D],
                                                               double dist2, const double (&vi)[D],
                                                               const double (&vj)[D], const double* wi,
                                                               const double* wj, double h, double (&xi)[D]) {
  constexpr int S = spin_components(D);
  constexpr bool hertz = Kind::law == ContactLaw::hertz;
  ContactResult<D> r{};
  const double reach = m.radius[i] + m.radius[j];
  const double dist = std::sqrt(dist2);
  if (dist > 0) [[likely]] {
    for (int d = 0; d < D; ++d) r.normal[d] = dx[d] / dist;
  } else {
    for (int d = 0; d < D; ++d) r.normal[d] = d == 0 ? 1.0 : 0.0;
    r.coincident = true;
  }
  double rate = 0;
  for (int d = 0; d < D; ++d) rate -= (vj[d] - vi[d]) * r.normal[d];
  const double m_eff = 1.0 / (m.inv_mass[i] + m.inv_mass[j]);
  // hertz: the list caches E* and G* in K and eta (contact_parameters.hpp).
  HertzContact hc{};
  if constexpr (hertz) {
    hc = hertz_contact(K, eta, m.radius[i] * m.radius[j] / reach, m_eff, m.hertz_damping, reach - dist, rate);
    r.fn = hc.fn;
  } else {
    r.fn = normal_of<Kind>(K, eta, reach - dist, rate);
  }
  // The contact point's sliding velocity, j relative to i: (v_j − v_i) − (r_i ω_i + r_j ω_j) × n.
  double spin[S], turn[D], vt[D], vn = 0;
  for (int k = 0; k < S; ++k) spin[k] = m.radius[i] * wi[k] + m.radius[j] * wj[k];
  spin_cross<D>(spin, r.normal, turn);
  for (int d = 0; d < D; ++d) {
    vt[d] = vj[d] - vi[d] - turn[d];
    vn += vt[d] * r.normal[d];
  }
  for (int d = 0; d < D; ++d) vt[d] -= vn * r.normal[d];
  if constexpr (Kind::friction) {
    if constexpr (hertz) {  // the history is a force: k_t = 1, each step adds S_t Δξ
      tangential_force<D>(TangentialLaw{1.0, hc.eta_t, m.friction}, r.normal, vt, r.fn, hc.st * h, xi, r.ft);
    } else {
      const double kt = m.tangential_ratio * K;
      const TangentialLaw law{kt, 2.0 * m.damping_ratio * std::sqrt(kt * m_eff), m.friction};
      tangential_force<D>(law, r.normal, vt, r.fn, h, xi, r.ft);
    }
  }
  // Torques: −r_i n × F_t on i, −r_j n × F_t on j (F_t acts on j, −F_t on i).
  double nf[S];
  moment<D>(r.normal, r.ft, nf);
  for (int k = 0; k < S; ++k) {
    r.torque_i[k] = -m.radius[i] * nf[k];
    r.torque_j[k] = -m.radius[j] * nf[k];
  }
  if constexpr (Kind::rolling) {
    // The relative rolling ω_j − ω_i the pair would have after the hold under
    // this contact's tangential torques alone, ω_j − ω_i + hold (τ_j/I_j −
    // τ_i/I_i): the rolling torque stops it (rolling_torque), so that a
    // particle whose sticking contact carries a tangential force can rest.
    // Both particles turn under the couple: K = 1/I_i + 1/I_j.
    const double hold = m.hold;
    double rolling[S], along = 0;
    for (int k = 0; k < S; ++k)
      rolling[k] = wj[k] - wi[k] + hold * (r.torque_j[k] * m.inv_inertia[j] - r.torque_i[k] * m.inv_inertia[i]);
    if constexpr (D == 3) {  // rolling, not twisting: the part in the contact plane
      for (int k = 0; k < S; ++k) along += rolling[k] * r.normal[k];
      for (int k = 0; k < S; ++k) rolling[k] -= along * r.normal[k];
    }
    double roll[S];
    rolling_torque<S>(m.rolling_friction, m.radius[i] * m.radius[j] / reach, r.fn, rolling,
                      m.inv_inertia[i] + m.inv_inertia[j], hold, roll);
    for (int k = 0; k < S; ++k) {
      r.torque_j[k] += roll[k];
      r.torque_i[k] -= roll[k];
    }
  }
  return r;
}

/// A particle against a wall, the contact's first body: its unit normal n
/// (towards the particle), the speed of its surface along n, the velocity of
/// its contact point, its spin (rad/s, S components) and its hertz
/// compliances (0: rigid); the particle's arm to the contact point (its
/// radius, as between particles), which the contact point's velocity and the
/// torque both use, so that the tangential force's power on the particle is
/// F·v_t, the spring's. torque_j is the particle's torque; torque_i
/// the couple the wall receives (rolling resistance; the tangential force
/// acts on the wall at the contact point). A plane is a wall of velocity
/// speed · n that does not turn (plane_contact_as).
template <int D, class Kind>
[[gnu::always_inline]] inline ContactResult<D> wall_contact_as(const LawView<D>& m, std::int32_t i,
                                                               const double (&normal)[D], double speed,
                                                               const double (&wall_velocity)[D], const double* wall_spin,
                                                               double inv_e, double inv_g, double arm, double overlap,
                                                               const double (&vi)[D], const double* wi, double h,
                                                               double (&xi)[D], double hold = 0.0,
                                                               double wall_inv_inertia = 0.0) {
  constexpr int S = spin_components(D);
  constexpr bool hertz = Kind::law == ContactLaw::hertz;
  ContactResult<D> r{};
  for (int d = 0; d < D; ++d) r.normal[d] = normal[d];
  double rate = speed;
  for (int d = 0; d < D; ++d) rate -= vi[d] * r.normal[d];
  HertzContact hc{};
  if constexpr (hertz) {
    hc = hertz_contact(1.0 / (m.hertz_inv_e[i] + inv_e), 1.0 / (m.hertz_inv_g[i] + inv_g), m.radius[i], m.mass[i],
                       m.hertz_damping, overlap, rate);
    r.fn = hc.fn;
  } else {
    r.fn = normal_of<Kind>(m.stiffness[i], m.plane_eta[i], overlap, rate);
  }
  double spin[S], turn[D], vt[D], vn = 0;
  for (int k = 0; k < S; ++k) spin[k] = arm * wi[k];
  spin_cross<D>(spin, r.normal, turn);
  for (int d = 0; d < D; ++d) {
    vt[d] = vi[d] - wall_velocity[d] - turn[d];
    vn += vt[d] * r.normal[d];
  }
  for (int d = 0; d < D; ++d) vt[d] -= vn * r.normal[d];
  if constexpr (Kind::friction) {
    if constexpr (hertz) {
      tangential_force<D>(TangentialLaw{1.0, hc.eta_t, m.friction}, r.normal, vt, r.fn, hc.st * h, xi, r.ft);
    } else {
      const double kt = m.tangential_ratio * m.stiffness[i];
      const TangentialLaw law{kt, 2.0 * m.damping_ratio * std::sqrt(kt * m.mass[i]), m.friction};
      tangential_force<D>(law, r.normal, vt, r.fn, h, xi, r.ft);
    }
  }
  double nf[S];
  moment<D>(r.normal, r.ft, nf);
  for (int k = 0; k < S; ++k) r.torque_j[k] = -arm * nf[k];
  if constexpr (Kind::rolling) {
    // −τ_t − (ω − Ω)/(hold (1/I + 1/I_wall)) below the cap (rolling_torque):
    // the couple that cancels this contact's tangential torque and stops the
    // relative rolling within `hold`, the wall turning back under it too (a
    // plane: 1/I_wall = 0). hold 0: the model's step.
    const double step = hold > 0 ? hold : m.hold;
    double rolling[S], along = 0;
    for (int k = 0; k < S; ++k) rolling[k] = wall_spin != nullptr ? wi[k] - wall_spin[k] : wi[k];
    const double inv_inertia = m.inv_inertia[i] + wall_inv_inertia;
    for (int k = 0; k < S; ++k) rolling[k] += step * inv_inertia * r.torque_j[k];
    if constexpr (D == 3) {
      for (int k = 0; k < S; ++k) along += rolling[k] * r.normal[k];
      for (int k = 0; k < S; ++k) rolling[k] -= along * r.normal[k];
    }
    double roll[S];
    rolling_torque<S>(m.rolling_friction, m.radius[i], r.fn, rolling, inv_inertia, step, roll);
    for (int k = 0; k < S; ++k) {
      r.torque_j[k] += roll[k];
      r.torque_i[k] = -roll[k];
    }
  }
  return r;
}

/// A plane: the first body, with normal n (towards the particle), moving at
/// `speed` along it without turning.
template <int D, class Kind>
[[gnu::always_inline]] inline ContactResult<D> plane_contact_as(const LawView<D>& m, std::int32_t i, std::size_t p,
                                                                double overlap, double speed, const double (&vi)[D],
                                                                const double* wi, double h, double (&xi)[D]) {
  double normal[D], velocity[D];
  for (int d = 0; d < D; ++d) {
    normal[d] = m.plane_normal[p][d];
    velocity[d] = speed * normal[d];
  }
  constexpr bool hertz = Kind::law == ContactLaw::hertz;
  return wall_contact_as<D, Kind>(m, i, normal, speed, velocity, nullptr, hertz ? m.plane_inv_e[p] : 0.0,
                                  hertz ? m.plane_inv_g[p] : 0.0, m.radius[i], overlap, vi, wi, h, xi);
}

}  // namespace

template <int D>
ContactResult<D> pair_contact(const DemModel<D>& m, std::int32_t i, std::int32_t j, double K, double eta,
                              const double (&dx)[D], double dist2, const double (&vi)[D], const double (&vj)[D],
                              const double* wi, const double* wj, double h, double (&xi)[D]) {
  return with_law<D>(m, [&]<class Kind>(Kind) {
    return pair_contact_as<D, Kind>(LawView<D>(m), i, j, K, eta, dx, dist2, vi, vj, wi, wj, h, xi);
  });
}

template <int D>
ContactResult<D> plane_contact(const DemModel<D>& m, std::int32_t i, std::size_t p, double overlap, double speed,
                               const double (&vi)[D], const double* wi, double h, double (&xi)[D]) {
  return with_law<D>(m, [&]<class Kind>(Kind) { return plane_contact_as<D, Kind>(LawView<D>(m), i, p, overlap, speed, vi, wi, h, xi); });
}

template <int D>
ContactResult<D> wall_contact(const DemModel<D>& m, std::int32_t i, const WallContact<D>& wall, double overlap,
                              const double (&vi)[D], const double* wi, double h, double (&xi)[D]) {
  return with_law<D>(m, [&]<class Kind>(Kind) {
    return wall_contact_as<D, Kind>(LawView<D>(m), i, wall.normal, wall.speed, wall.velocity, wall.spin, wall.inv_e,
                                    wall.inv_g, wall.arm, overlap, vi, wi, h, xi, wall.hold, wall.inv_inertia);
  });
}

namespace {

/// Where an evaluation reads the state and writes its accelerations.
template <int D>
struct Views {
  ConstColumns<D> x, v;
  std::array<const double*, spin_components(D)> spin;
  Columns<D> a;
  std::array<double*, spin_components(D)> alpha;
};

/// Particle–plane contacts of particles [begin, end), plane by plane (each
/// particle receives its plane contributions in plane order); each plane's
/// total normal force into totals[p]. Returns the sum of the tags of the
/// contacts that carried a force.
template <int D, class Kind>
std::uint64_t granular_planes(const DemModel<D>& m, DemState<D>& s, const DemWorkspace<D>& w, const Views<D>& at,
                              double t, double h, bool keep, std::int32_t begin, std::int32_t end, double* totals) {
  constexpr int S = spin_components(D);
  const std::int32_t n = m.n;
  const LawView<D> law(m);
  const double* radius = law.radius;
  const double* inv_mass = law.inv_mass;
  const double* inv_inertia = law.inv_inertia;
  std::uint64_t active = 0;
  for (std::size_t p = 0; p < m.plane_point.size(); ++p) {
    const std::array<double, D> point = plane_point_at(m, s, p, t);
    const std::array<double, D> normal = m.plane_normal[p];
    const double speed = s.plane_speed[p];
    // Frozen: whether the contact is on is decided at the interval start, with the plane where it was then.
    std::array<double, D> point0{};
    if constexpr (Kind::frozen) point0 = plane_point_at(m, s, p, w.mode_time);
    double* xi_of[D];
    for (int d = 0; d < D; ++d) xi_of[d] = s.plane_xi[d].data() + p * static_cast<std::size_t>(n);
    double total = 0;
    // Apart: the contact forgets its spring (a store only where one was kept).
    auto forget = [&](std::int32_t i) {
      if constexpr (Kind::friction) {
        if (!keep) return;
        std::uint64_t stored = 0;  // any bit, so that a kept −0 is zeroed as well
        for (int d = 0; d < D; ++d) stored |= std::bit_cast<std::uint64_t>(xi_of[d][i]);
        if (stored != 0) [[unlikely]]
          for (int d = 0; d < D; ++d) xi_of[d][i] = 0.0;
      }
    };
    auto contact = [&](std::int32_t i) {
      double gap = 0;
      for (int d = 0; d < D; ++d) gap += (at.x[d][i] - point[d]) * normal[d];
      const double overlap = radius[i] - gap;
      if constexpr (Kind::frozen) {
        if (!(plane_indicator<D>(m, s, p, point0, w.mode_x, w.mode_v, i) > 0)) return forget(i);
      } else {
        if (!(overlap > 0)) return forget(i);
      }
      double vi[D], wi[S], xi[D];
      for (int d = 0; d < D; ++d) vi[d] = at.v[d][i];
      for (int k = 0; k < S; ++k) wi[k] = at.spin[k][i];
      for (int d = 0; d < D; ++d) xi[d] = Kind::friction ? xi_of[d][i] : 0.0;
      const ContactResult<D> c = plane_contact_as<D, Kind>(law, i, p, overlap, speed, vi, wi, h, xi);
      for (int d = 0; d < D; ++d) {
        if (Kind::friction && keep) xi_of[d][i] = xi[d];
        at.a[d][i] += (c.fn * c.normal[d] + c.ft[d]) * inv_mass[i];
      }
      for (int k = 0; k < S; ++k) at.alpha[k][i] += c.torque_j[k] * inv_inertia[i];
      active += c.fn != 0.0 ? plane_contact_tag(n, p, i) : 0;
      total += c.fn;
    };
    int nonzero = 0, axis = 0;
    for (int d = 0; d < D; ++d)
      if (normal[d] != 0.0) ++nonzero, axis = d;
    if (nonzero == 1 && !Kind::frozen) {
      // Axis-aligned (the usual box): for finite positions the other terms of
      // the gap are ±0, so one coordinate decides apart; `contact` re-tests in full.
      const double* xa = at.x[axis];
      const double pa = point[axis], na = normal[axis];
      for (std::int32_t i = begin; i < end; ++i) {
        if (radius[i] - (xa[i] - pa) * na > 0) [[unlikely]]
          contact(i);
        else
          forget(i);
      }
    } else {
      for (std::int32_t i = begin; i < end; ++i) contact(i);
    }
    totals[p] = total;
  }
  return active;
}

#if defined(__SSE2__)
/// Two contacts at once in the two SSE2 lanes (x86-64 baseline). Every lane
/// does exactly the scalar operations of pair_contact_as and
/// tangential_force, in the same order, and takes the scalar code's branches
/// as selects between the results it would have computed, so the bits are
/// the scalar ones; the divider and the square roots, which dominate, issue
/// once for both contacts.
using V2 = double __attribute__((vector_size(16)));
using M2 = long long __attribute__((vector_size(16)));

inline V2 select(M2 mask, V2 a, V2 b) {
  return reinterpret_cast<V2>((mask & reinterpret_cast<M2>(a)) | (~mask & reinterpret_cast<M2>(b)));
}
inline V2 splat(double x) { return V2{x, x}; }
inline V2 lanes(double a, double b) { return V2{a, b}; }
inline V2 root(V2 x) { return _mm_sqrt_pd(x); }
inline V2 magnitude(V2 x) {  // std::fabs: the sign bit cleared
  return reinterpret_cast<V2>(reinterpret_cast<M2>(x) & M2{0x7fffffffffffffffLL, 0x7fffffffffffffffLL});
}

/// The linear laws with Coulomb friction, no rolling resistance, for two
/// touching pairs whose centres do not coincide (dist > 0 in both lanes).
/// Inputs and outputs per lane as pair_contact_as; xi advanced in place.
template <int D, bool NonTensile>
[[gnu::always_inline]] inline void frictional_pair_x2(const LawView<D>& m, const std::int32_t (&i)[2],
                                                      const std::int32_t (&j)[2], V2 K, V2 eta, const V2 (&dx)[D],
                                                      V2 dist, const V2 (&vi)[D], const V2 (&vj)[D],
                                                      const V2 (&wi)[spin_components(D)],
                                                      const V2 (&wj)[spin_components(D)], double h, V2 (&xi)[D],
                                                      V2 (&normal)[D], V2& fn, V2 (&ft)[D],
                                                      V2 (&torque_i)[spin_components(D)],
                                                      V2 (&torque_j)[spin_components(D)]) {
  constexpr int S = spin_components(D);
  const V2 zero = splat(0.0);
  const V2 ri = lanes(m.radius[i[0]], m.radius[i[1]]), rj = lanes(m.radius[j[0]], m.radius[j[1]]);
  const V2 reach = ri + rj;
  for (int d = 0; d < D; ++d) normal[d] = dx[d] / dist;
  V2 rate = zero;
  for (int d = 0; d < D; ++d) rate -= (vj[d] - vi[d]) * normal[d];
  const V2 m_eff = splat(1.0) / (lanes(m.inv_mass[i[0]], m.inv_mass[i[1]]) + lanes(m.inv_mass[j[0]], m.inv_mass[j[1]]));
  // normal_force: 0 unless δ > 0; K δ + η δ'; the non-tensile law never pulls.
  const V2 overlap = reach - dist;
  V2 force = K * overlap;
  force += eta * rate;
  if constexpr (NonTensile) force = select(force < zero, zero, force);  // std::max(force, 0.0)
  fn = select(overlap > zero, force, zero);
  V2 spin[S], turn[D], vt[D], vn = zero;
  for (int k = 0; k < S; ++k) spin[k] = ri * wi[k] + rj * wj[k];
  spin_cross<D>(spin, normal, turn);
  for (int d = 0; d < D; ++d) {
    vt[d] = vj[d] - vi[d] - turn[d];
    vn += vt[d] * normal[d];
  }
  for (int d = 0; d < D; ++d) vt[d] -= vn * normal[d];
  const V2 kt = splat(m.tangential_ratio) * K;
  const V2 eta_t = splat(2.0 * m.damping_ratio) * root(kt * m_eff);
  // tangential_force: the spring turned into the contact plane (its length kept).
  V2 along = zero, before = zero;
  for (int d = 0; d < D; ++d) {
    along += xi[d] * normal[d];
    before += xi[d] * xi[d];
  }
  {
    V2 turned[D], after = zero;
    for (int d = 0; d < D; ++d) {
      turned[d] = xi[d] - along * normal[d];
      after += turned[d] * turned[d];
    }
    const V2 keep = select(after > zero, root(before / after), zero);
    const M2 off_plane = along != zero;
    for (int d = 0; d < D; ++d) xi[d] = select(off_plane, turned[d] * keep, xi[d]);
  }
  V2 f2 = zero;
  const V2 step = splat(h);
  for (int d = 0; d < D; ++d) {
    xi[d] += step * vt[d];
    ft[d] = -kt * xi[d] - eta_t * vt[d];
    f2 += ft[d] * ft[d];
  }
  const V2 cap = splat(m.friction) * magnitude(fn);
  const M2 sliding = f2 > cap * cap;
  if (_mm_movemask_pd(reinterpret_cast<__m128d>(sliding)) != 0) {
    const V2 scale = cap / root(f2);
    for (int d = 0; d < D; ++d) {
      const V2 capped = ft[d] * scale;
      xi[d] = select(sliding, -(capped + eta_t * vt[d]) / kt, xi[d]);
      ft[d] = select(sliding, capped, ft[d]);
    }
  }
  V2 nf[S];
  moment<D>(normal, ft, nf);
  for (int k = 0; k < S; ++k) {
    torque_i[k] = -ri * nf[k];
    torque_j[k] = -rj * nf[k];
  }
}
#endif

/// Pairs [begin, end) of the list, in list order. As the frictionless
/// kernel (forces.hpp, pair_forces): listed pairs are screened in chunks
/// without branches, then only the touching ones are evaluated; a
/// contribution to a particle j >= split goes to the cross buffers (part 0 of
/// a split step).
template <int D, class Kind>
StepStatus granular_pairs(const DemModel<D>& m, DemState<D>& s, const DemWorkspace<D>& w, const Views<D>& at,
                          double h, bool keep,
                          std::int32_t begin, std::int32_t end, std::int32_t split, Columns<D> cross,
                          const std::array<double*, spin_components(D)>& cross_spin, std::uint64_t& active) {
  constexpr int S = spin_components(D);
  constexpr std::int32_t kChunk = 256;
  std::int32_t touching[kChunk];
  double kept_dx[D][kChunk], kept_dist2[kChunk];
  const LawView<D> law(m);
  const double* radius = law.radius;
  const double* inv_mass = law.inv_mass;
  const double* inv_inertia = law.inv_inertia;
  const std::int32_t* pi = s.pair_i.data();
  const std::int32_t* pj = s.pair_j.data();
  const double* pair_k = s.pair_stiffness.data();
  const double* pair_eta = s.pair_eta.data();
  const std::int32_t n = m.n;
  double* xi_of[D];
  for (int d = 0; d < D; ++d) xi_of[d] = s.pair_xi[d].data();
  StepStatus status = StepStatus::ok;
  for (std::int32_t c0 = begin; c0 < end; c0 += kChunk) {
    const std::int32_t c1 = std::min(end, c0 + kChunk);
    std::int32_t hits = 0;
    for (std::int32_t c = c0; c < c1; ++c) {
      const std::int32_t i = pi[c], j = pj[c];
      double dist2 = 0;
      for (int d = 0; d < D; ++d) {
        const double dx = at.x[d][j] - at.x[d][i];
        dist2 += dx * dx;
        kept_dx[d][hits] = dx;
      }
      const double reach = radius[i] + radius[j];
      bool on = dist2 < reach * reach;  // false for NaN
      if constexpr (Kind::frozen) on = pair_indicator<D>(m, s, c, w.mode_x, w.mode_v) > 0;  // the start's set
      if constexpr (Kind::friction)
        if (keep)  // apart: the contact forgets its spring
          for (int d = 0; d < D; ++d) xi_of[d][c] = on ? xi_of[d][c] : 0.0;
      touching[hits] = c;
      kept_dist2[hits] = dist2;
      hits += on ? 1 : 0;
    }
    std::int32_t k = 0;
#if defined(__SSE2__)
    if constexpr (Kind::friction && !Kind::rolling && Kind::law != ContactLaw::hertz && !Kind::frozen) {
      for (; k + 1 < hits; k += 2) {
        const std::int32_t ca = touching[k], cb = touching[k + 1];
        const std::int32_t ii[2] = {pi[ca], pi[cb]}, jj[2] = {pj[ca], pj[cb]};
        const V2 dist = root(V2{kept_dist2[k], kept_dist2[k + 1]});
        if (_mm_movemask_pd(reinterpret_cast<__m128d>(dist > splat(0.0))) != 3) break;  // coincident: scalar
        V2 dx[D], vi[D], vj[D], wi[S], wj[S], xi[D], normal[D], fn, ft[D], ti[S], tj[S];
        for (int d = 0; d < D; ++d) {
          dx[d] = V2{kept_dx[d][k], kept_dx[d][k + 1]};
          vi[d] = V2{at.v[d][ii[0]], at.v[d][ii[1]]};
          vj[d] = V2{at.v[d][jj[0]], at.v[d][jj[1]]};
          xi[d] = V2{xi_of[d][ca], xi_of[d][cb]};
        }
        for (int q = 0; q < S; ++q) {
          wi[q] = V2{at.spin[q][ii[0]], at.spin[q][ii[1]]};
          wj[q] = V2{at.spin[q][jj[0]], at.spin[q][jj[1]]};
        }
        frictional_pair_x2<D, Kind::law == ContactLaw::linear_nontensile>(
            law, ii, jj, V2{pair_k[ca], pair_k[cb]}, V2{pair_eta[ca], pair_eta[cb]}, dx, dist, vi, vj, wi, wj, h, xi,
            normal, fn, ft, ti, tj);
        // The contributions in list order: all of the first pair's, then the second's.
        for (int lane = 0; lane < 2; ++lane) {
          const std::int32_t c = lane == 0 ? ca : cb, i = ii[lane], j = jj[lane];
          const bool far = j >= split;
          const std::int32_t jt = far ? j - split : j;  // j's slot in its target column
          const double mi = inv_mass[i], mj = inv_mass[j], ii_ = inv_inertia[i], ij_ = inv_inertia[j];
          for (int d = 0; d < D; ++d) {
            if (keep) xi_of[d][c] = xi[d][lane];
            const double f = fn[lane] * normal[d][lane] + ft[d][lane];  // on j
            at.a[d][i] -= f * mi;
            (far ? cross[d] : at.a[d])[jt] += f * mj;
          }
          for (int q = 0; q < S; ++q) {
            at.alpha[q][i] += ti[q][lane] * ii_;
            (far ? cross_spin[q] : at.alpha[q])[jt] += tj[q][lane] * ij_;
          }
          active += fn[lane] != 0.0 ? pair_contact_tag(n, i, j) : 0;
        }
      }
    }
#endif
    for (; k < hits; ++k) {
      const std::int32_t c = touching[k];
      const std::int32_t i = pi[c], j = pj[c];
      double dx[D], vi[D], vj[D], wi[S], wj[S], xi[D];
      for (int d = 0; d < D; ++d) {
        dx[d] = kept_dx[d][k];
        vi[d] = at.v[d][i];
        vj[d] = at.v[d][j];
        xi[d] = Kind::friction ? xi_of[d][c] : 0.0;
      }
      for (int q = 0; q < S; ++q) {
        wi[q] = at.spin[q][i];
        wj[q] = at.spin[q][j];
      }
      const ContactResult<D> r = pair_contact_as<D, Kind>(law, i, j, pair_k[c], pair_eta[c], dx,
                                                          kept_dist2[k], vi, vj, wi, wj, h, xi);
      if (r.coincident) [[unlikely]]
        status |= StepStatus::coincident_centres;
      const bool far = j >= split;
      for (int d = 0; d < D; ++d) {
        if (Kind::friction && keep) xi_of[d][c] = xi[d];
        const double f = r.fn * r.normal[d] + r.ft[d];  // on j
        at.a[d][i] -= f * inv_mass[i];
        (far ? cross[d][j - split] : at.a[d][j]) += f * inv_mass[j];
      }
      for (int q = 0; q < S; ++q) {
        at.alpha[q][i] += r.torque_i[q] * inv_inertia[i];
        (far ? cross_spin[q][j - split] : at.alpha[q][j]) += r.torque_j[q] * inv_inertia[j];
      }
      active += r.fn != 0.0 ? pair_contact_tag(n, i, j) : 0;
    }
  }
  return status;
}

/// The host's contacts (DemDesc::external_contacts) at this evaluation, last,
/// on the whole state; their totals after the planes' in w.plane_force, so
/// that the step weighs them as it weighs the planes'.
template <int D>
[[gnu::noinline, gnu::cold]] std::uint64_t external_stage(const DemModel<D>& m, DemWorkspace<D>& w,
                                                          const Views<D>& at, double t, double h, bool keep) {
  if (w.external_rotating_contacts == nullptr) return 0;
  ExternalStage<D> stage;
  stage.time = t, stage.advance = h, stage.keep = keep;
  stage.x = at.x, stage.v = at.v, stage.spin = at.spin, stage.a = at.a, stage.alpha = at.alpha;
  return w.external_rotating_contacts(w.external_context, stage, w.plane_force.data() + m.plane_point.size());
}

/// Stage 3: a = g + F/m and α = M/I at the state (x, v, ω); the tangential
/// springs advanced by h from the stored ones (0: nothing accumulates, the
/// state's own forces). `keep`: the advanced springs become the stored ones
/// (false: an intermediate stage of a multistage step, which reads them only).
/// A model split in two parts (DemModel::parts) runs as the frictionless
/// kernel does: each part its particles' inputs and plane contacts, then part
/// 0 the pairs with i < split (contributions to particles of part 1 into the
/// cross buffers) and part 1 the others, then the cross buffers added in
/// particle order. The order of every sum is fixed by the model, so one and
/// two workers give the same bits.
template <int D, class Kind>
StepStatus granular_forces(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, const Views<D>& at, double t,
                           double h, bool keep) {
  constexpr int S = spin_components(D);
  const std::int32_t n = m.n;
  const int parts = m.parts > 1 ? 2 : 1;
  const std::int32_t split = parts == 2 ? m.split : n;
  const std::size_t planes = m.plane_point.size();
  std::uint64_t active[2] = {0, 0};  // sums of integers: the same total in any order
  for_parts(w.parallel, parts, [&](int part) {
    const std::int32_t begin = part == 0 ? 0 : split, end = part == 0 ? split : n;
    input_accelerations<D, true>(m, s, at.a, begin, end);
    for (int k = 0; k < S; ++k) {
      if (m.features.external_torques) {
        const double* torque = s.external_torque[k].data();
        for (std::int32_t i = begin; i < end; ++i) at.alpha[k][i] = torque[i] * m.inv_inertia[i];
      } else {
        std::fill(at.alpha[k] + begin, at.alpha[k] + end, 0.0);
      }
    }
    double* totals = parts == 1 ? w.plane_force.data() : w.plane_force_part.data() + part * planes;
    active[part] = granular_planes<D, Kind>(m, s, w, at, t, h, keep, begin, end, totals);
  });
  if (parts == 2)
    for (std::size_t p = 0; p < planes; ++p) w.plane_force[p] = w.plane_force_part[p] + w.plane_force_part[planes + p];
  std::uint64_t carried = active[0] + active[1];
  Columns<D> cross;
  std::array<double*, S> cross_spin;
  for (int d = 0; d < D; ++d) cross[d] = w.cross[d].data();
  for (int k = 0; k < S; ++k) cross_spin[k] = w.cross_spin[k].data();
  StepStatus part_status[2] = {StepStatus::ok, StepStatus::ok};
  if (parts == 1) {
    part_status[0] = granular_pairs<D, Kind>(m, s, w, at, h, keep, 0, s.pair_count, n, cross, cross_spin, active[0]);
  } else {
    // The list is sorted by i: part 0 owns the pairs with i < split.
    const std::int32_t* first = s.pair_i.data();
    const auto boundary = static_cast<std::int32_t>(std::lower_bound(first, first + s.pair_count, split) - first);
    for_parts(w.parallel, 2, [&](int part) {
      active[part] = 0;
      if (part == 0) {
        for (auto& c : w.cross) std::fill(c.begin(), c.end(), 0.0);
        for (auto& c : w.cross_spin) std::fill(c.begin(), c.end(), 0.0);
        part_status[0] = granular_pairs<D, Kind>(m, s, w, at, h, keep, 0, boundary, split, cross, cross_spin, active[0]);
      } else {
        part_status[1] =
            granular_pairs<D, Kind>(m, s, w, at, h, keep, boundary, s.pair_count, n, cross, cross_spin, active[1]);
      }
    });
    for (int d = 0; d < D; ++d)
      for (std::int32_t j = split; j < n; ++j) at.a[d][j] += cross[d][j - split];
    for (int k = 0; k < S; ++k)
      for (std::int32_t j = split; j < n; ++j) at.alpha[k][j] += cross_spin[k][j - split];
  }
  if (m.features.external_contacts) carried += external_stage<D>(m, w, at, t, h, keep);
  fold_contacts(w.contact_signature, carried + active[0] + active[1]);
  return part_status[0] | part_status[1];
}

}  // namespace

/// Stage 2: the grid's pair list rebuilt at x when stale. The records of the
/// old list (its tangential springs) follow their pair (i, j) into the new
/// one: both lists are sorted by (i, j), so one merge pass, in a fixed order.
/// A rebuild that hits a capacity restores the old list and its records.
template <int D>
StepStatus granular_broad_phase(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x) {
  if (m.features.broad_phase != BroadPhase::grid) return StepStatus::ok;
  if (s.pairs_valid) {
    bool moved[2] = {false, false};
    const int parts = m.parts > 1 ? 2 : 1;
    for_parts(w.parallel, parts, [&](int part) {
      moved[part] = moved_past_half_skin<D>(m, s, x, part == 0 ? 0 : m.split, part == 0 && parts == 2 ? m.split : m.n);
    });
    if (!moved[0] && !moved[1]) return StepStatus::ok;
  }
  const std::int32_t old_count = s.pair_count;
  for (std::int32_t c = 0; c < old_count; ++c) {
    w.old_pair_i[c] = s.pair_i[c];
    w.old_pair_j[c] = s.pair_j[c];
    for (int d = 0; d < D; ++d) w.old_pair_xi[d][c] = s.pair_xi[d][c];
  }
  const StepStatus built = build_pair_list<D>(m, s, w, x);
  if (built != StepStatus::ok) {
    for (std::int32_t c = 0; c < old_count; ++c) {
      s.pair_i[c] = w.old_pair_i[c];
      s.pair_j[c] = w.old_pair_j[c];
      for (int d = 0; d < D; ++d) s.pair_xi[d][c] = w.old_pair_xi[d][c];
      const PairParameters pp = pair_parameters(m, s.pair_i[c], s.pair_j[c]);
      s.pair_stiffness[c] = pp.stiffness;
      s.pair_eta[c] = pp.eta;
    }
    s.pair_count = old_count;
    s.pairs_valid = old_count > 0 || s.list_builds > 0 ? 1 : 0;
    return built;
  }
  std::int32_t o = 0;
  for (std::int32_t c = 0; c < s.pair_count; ++c) {
    const std::int32_t i = s.pair_i[c], j = s.pair_j[c];
    while (o < old_count && (w.old_pair_i[o] < i || (w.old_pair_i[o] == i && w.old_pair_j[o] < j))) ++o;
    const bool kept = o < old_count && w.old_pair_i[o] == i && w.old_pair_j[o] == j;
    for (int d = 0; d < D; ++d) s.pair_xi[d][c] = kept ? w.old_pair_xi[d][o] : 0.0;
  }
  return StepStatus::ok;
}

/// Stages 2 and 3 at one state: broad phase at its positions, then its forces
/// with the springs advanced by `offset` (kept or not), the contacts timed.
template <int D>
StepStatus evaluate_at(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, const Views<D>& at, double t,
                       double offset, bool keep) {
  const StepStatus built = granular_broad_phase<D>(m, s, w, at.x);
  if (has(built, kStepNotTaken)) return built;
  w.eval_time = t;
  const std::int64_t start = w.clock_ns != nullptr ? w.clock_ns() : 0;
  const StepStatus status =
      built | with_law<D>(
                  m, [&]<class Kind>(Kind) { return granular_forces<D, Kind>(m, s, w, at, t, offset, keep); },
                  w.mode_x[0] != nullptr);
  if (w.clock_ns != nullptr) w.profile.contacts_ns += w.clock_ns() - start;
  return status;
}

template <int D>
StepStatus granular_evaluate_current(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  Views<D> at;
  for (int d = 0; d < D; ++d) {
    at.x[d] = s.x[d].data();
    at.v[d] = s.v[d].data();
    at.a[d] = s.hist_a[s.history_head][d].data();
  }
  for (int k = 0; k < spin_components(D); ++k) {
    at.spin[k] = s.w[k].data();
    at.alpha[k] = s.hist_alpha[s.history_head][k].data();
  }
  const StepStatus status = evaluate_at<D>(m, s, w, at, s.time, 0.0, true);
  // The head slot's copies of the rates (the multistep history reads them).
  for (int d = 0; d < D; ++d) s.hist_v[s.history_head][d] = s.v[d];
  for (int k = 0; k < spin_components(D); ++k) s.hist_w[s.history_head][k] = s.w[k];
  return status;
}

namespace {

/// Runs f(begin, end) over the model's parts (particles [0, split) and
/// [split, n), or all in one part) through the host's workers.
template <int D, class F>
void over_parts(const DemModel<D>& m, DemWorkspace<D>& w, F&& f) {
  if (m.parts <= 1) return f(std::int32_t{0}, m.n);
  for_parts(w.parallel, 2, [&](int part) { f(part == 0 ? 0 : m.split, part == 0 ? m.split : m.n); });
}

/// Columns a one-step integrator advances: a coordinate q (position, or the
/// 2D angle; none for a 3D orientation, which is not tracked), its rate
/// q' (velocity, angular velocity) and the rate's rate q'' (acceleration,
/// angular acceleration), with the trial copies the step writes.
struct Column {
  const double* q;  ///< nullptr: no coordinate kept
  double* q1;
  const double* rate;
  double* rate_half;  ///< the kicked rate the evaluation sees
  double* rate1;
  const double* acc;  ///< at the step start
  double* acc1;       ///< at the trial state
  // RK4: the stage's coordinate, rate and acceleration, and the weighted sums.
  double *qs, *rs, *as, *sq, *sr;
  // ABM4: the history ring's rates and accelerations, newest (the head) first.
  const double* rate_hist[4];
  const double* acc_hist[4];
};

/// Which of the columns' copies an evaluation reads: an RK4 stage (qs, rs),
/// the kicked trial state of Verlet and symplectic Euler (q1, rate_half), or
/// the end of an RK4 step (q1, rate1). The acceleration goes to `as`, or acc1.
enum class Copy { stage, kicked, final };

template <int D>
Views<D> views_of(const Column* cols, Copy copy) {
  Views<D> at;
  for (int k = 0; k < D + spin_components(D); ++k) {
    const Column& c = cols[k];
    const double* rate = copy == Copy::stage ? c.rs : copy == Copy::kicked ? c.rate_half : c.rate1;
    double* acc = copy == Copy::stage ? c.as : c.acc1;
    if (k < D) {
      at.x[k] = copy == Copy::stage ? c.qs : c.q1;
      at.v[k] = rate;
      at.a[k] = acc;
    } else {
      at.spin[k - D] = rate;
      at.alpha[k - D] = acc;
    }
  }
  return at;
}

/// Classical RK4 over the columns (S3 at y_n + S2 h/2, as the frictionless
/// rk4), then f(y_n+1) into acc1. The stages read the stored springs advanced
/// by their own offset (h/2, h/2, h) without keeping them; the evaluation of
/// y_n+1 keeps its springs, advanced by h with y_n+1's sliding velocity.
/// The planes' impulse h/6 (F1 + 2F2 + 2F3 + F4) is left in w.plane_weighted.
/// The step starts at time t with the columns' (q, rate, acc) and the
/// planes' forces f0 there; finish false: without the evaluation of y_n+1
/// (abm4_events' trials and pieces, which decide first whether to keep them).
template <int D>
StepStatus rk4_columns(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, Column* cols, int count, double t,
                       double h, const double* f0, bool finish) {
  const std::int32_t n = m.n;
  const double half = 0.5 * h, sixth = h / 6.0;
  std::vector<double>& ledger = w.plane_weighted;
  for (int c = 0; c < count; ++c) {
    const Column& k = cols[c];
    for (std::int32_t i = 0; i < n; ++i) {
      k.sr[i] = k.acc[i];
      k.rs[i] = k.rate[i] + half * k.acc[i];
    }
    if (k.q != nullptr)
      for (std::int32_t i = 0; i < n; ++i) {
        k.sq[i] = k.rate[i];
        k.qs[i] = k.q[i] + half * k.rate[i];
      }
  }
  for (std::size_t p = 0; p < ledger.size(); ++p) ledger[p] = f0[p];
  StepStatus status = evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::stage), t + half, half, false);
  if (has(status, kStepNotTaken)) return status;
  for (std::size_t p = 0; p < ledger.size(); ++p) ledger[p] += 2.0 * w.plane_force[p];
  for (int stage = 3; stage <= 4; ++stage) {
    const double step = stage == 3 ? half : h;
    for (int c = 0; c < count; ++c) {
      const Column& k = cols[c];
      for (std::int32_t i = 0; i < n; ++i) {
        const double rate = k.rs[i], acc = k.as[i];
        if (k.q != nullptr) {
          k.sq[i] += 2.0 * rate;
          k.qs[i] = k.q[i] + step * rate;
        }
        k.sr[i] += 2.0 * acc;
        k.rs[i] = k.rate[i] + step * acc;
      }
    }
    status |= evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::stage), t + step, step, false);
    if (has(status, kStepNotTaken)) return status;
    if (stage == 3)
      for (std::size_t p = 0; p < ledger.size(); ++p) ledger[p] += 2.0 * w.plane_force[p];
  }
  for (std::size_t p = 0; p < ledger.size(); ++p) ledger[p] = sixth * (ledger[p] + w.plane_force[p]);
  for (int c = 0; c < count; ++c) {
    const Column& k = cols[c];
    for (std::int32_t i = 0; i < n; ++i) {
      if (k.q != nullptr) k.q1[i] = k.q[i] + sixth * (k.sq[i] + k.rs[i]);
      k.rate1[i] = k.rate[i] + sixth * (k.sr[i] + k.as[i]);
    }
  }
  if (finish) status |= evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::final), t + h, h, true);
  return status;
}

}  // namespace

/// One ABM4 PECE step over the columns (history complete), then f(y_n+1) into
/// acc1: the prediction's evaluation reads the stored springs advanced by h
/// without keeping them, the evaluation of y_n+1 keeps them. The planes'
/// impulse of the corrector, h/24 (9 F* + 19 F_n − 5 F_n−1 + F_n−2), is left
/// in w.plane_weighted.
template <int D>
StepStatus abm4_columns(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, Column* cols, int count,
                        bool finish) {
  const std::int32_t n = m.n;
  const double h = m.dt, c = h / 24.0, t = s.time;
  for (int k = 0; k < count; ++k) {
    const Column& col = cols[k];
    const double *r0 = col.rate_hist[0], *r1 = col.rate_hist[1], *r2 = col.rate_hist[2], *r3 = col.rate_hist[3];
    const double *a0 = col.acc_hist[0], *a1 = col.acc_hist[1], *a2 = col.acc_hist[2], *a3 = col.acc_hist[3];
    if (col.q != nullptr)
      for (std::int32_t i = 0; i < n; ++i) col.qs[i] = col.q[i] + c * (55.0 * r0[i] - 59.0 * r1[i] + 37.0 * r2[i] - 9.0 * r3[i]);
    for (std::int32_t i = 0; i < n; ++i) col.rs[i] = col.rate[i] + c * (55.0 * a0[i] - 59.0 * a1[i] + 37.0 * a2[i] - 9.0 * a3[i]);
  }
  StepStatus status = evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::stage), t + h, h, false);
  if (has(status, kStepNotTaken)) return status;
  const int f0 = s.history_head, f1 = (f0 + 3) & 3, f2 = (f0 + 2) & 3;
  for (std::size_t p = 0; p < w.plane_weighted.size(); ++p)
    w.plane_weighted[p] = c * (9.0 * w.plane_force[p] + 19.0 * s.hist_plane_force[f0][p] -
                               5.0 * s.hist_plane_force[f1][p] + s.hist_plane_force[f2][p]);
  for (int k = 0; k < count; ++k) {
    const Column& col = cols[k];
    const double *r0 = col.rate_hist[0], *r1 = col.rate_hist[1], *r2 = col.rate_hist[2];
    const double *a0 = col.acc_hist[0], *a1 = col.acc_hist[1], *a2 = col.acc_hist[2];
    if (col.q != nullptr)
      for (std::int32_t i = 0; i < n; ++i) col.q1[i] = col.q[i] + c * (9.0 * col.rs[i] + 19.0 * r0[i] - 5.0 * r1[i] + r2[i]);
    for (std::int32_t i = 0; i < n; ++i)
      col.rate1[i] = col.rate[i] + c * (9.0 * col.as[i] + 19.0 * a0[i] - 5.0 * a1[i] + a2[i]);
  }
  if (finish) status |= evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::final), t + h, h, true);
  return status;
}

namespace {

/// abm4_events over the columns: abm4 (its RK4 start steps while the history
/// fills) whose steps never straddle a change of the normal contact set, as
/// the frictionless step_abm4_events (integrators.cpp). The trial runs with
/// the contact set of the step start frozen (LawKind::frozen). If the set at
/// its end differs, the step is redone in RK4 pieces from the start of the
/// remaining interval (w.x0, v0, start_a and the rotation's start_w,
/// start_alpha, start_angle): bisection to 2^-48 of it finds the first
/// change, a piece lands just past it, and its plain evaluation advances and
/// keeps the tangential springs by the piece's length; the rest starts there.
/// The springs (first-order history, advanced once per piece) and the
/// stick-slip switches, which are no change of the set, limit the order
/// with friction (docs/dem.md, "Rotation and friction"). Leaves y_n+1 and its
/// accelerations where the other integrators do, the planes' impulse in
/// w.plane_weighted; `located`: the number of events (the history restarts).
template <int D>
StepStatus located_columns(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, Column* cols,
                           std::int32_t& located) {
  constexpr int S = spin_components(D);
  const double h = m.dt, t_n = s.time, t_end = s.time + h;
  located = 0;
  ConstColumns<D> x_n, v_n, x1, v1, x0, v0;
  auto bind = [&] {
    for (int d = 0; d < D; ++d) {
      x1[d] = w.x1[d].data();
      v1[d] = w.v1[d].data();
      x0[d] = w.x0[d].data();
      v0[d] = w.v0[d].data();
    }
  };
  for (int d = 0; d < D; ++d) {
    x_n[d] = s.x[d].data();
    v_n[d] = s.v[d].data();
  }
  bind();
  auto freeze = [&](ConstColumns<D> x, ConstColumns<D> v, double t) {
    w.mode_x = x;
    w.mode_v = v;
    w.mode_time = t;
  };
  auto thaw = [&] {
    w.mode_x = {};
    w.mode_v = {};
  };
  auto finite = [&](ConstColumns<D> x, ConstColumns<D> v) {
    double sum = 0;
    for (int d = 0; d < D; ++d) sum += zero_probe<2>({x[d], v[d]}, 0, m.n);
    return sum == 0.0;
  };
  freeze(x_n, v_n, t_n);
  StepStatus status = s.history_count == 4 ? abm4_columns<D>(m, s, w, cols, D + S, false)
                                           : rk4_columns<D>(m, s, w, cols, D + S, t_n, h,
                                                            s.hist_plane_force[s.history_head].data(), false);
  thaw();
  if (has(status, kStepNotTaken)) return status;
  // A non-finite trial is committed as it is (a NaN reads as "no contact").
  if (!finite(x1, v1) || !contact_set_changed<D>(m, s, t_n, x_n, v_n, t_end, x1, v1))
    return status | evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::final), t_end, h, true);

  // Event(s) inside the step: from the start of the remaining interval.
  for (int d = 0; d < D; ++d) {
    w.x0[d] = s.x[d];
    w.v0[d] = s.v[d];
    w.start_a[d] = s.hist_a[s.history_head][d];
  }
  for (int k = 0; k < S; ++k) {
    w.start_w[k] = s.w[k];
    w.start_alpha[k] = s.hist_alpha[s.history_head][k];
  }
  for (std::size_t k = 0; k < s.angle.size(); ++k) w.start_angle[k] = s.angle[k];
  w.plane_force0 = s.hist_plane_force[s.history_head];
  for (double& J : w.plane_step_impulse) J = 0.0;
  Column piece_cols[D + S];
  auto rebind = [&] {  // the columns from the start buffers (after every swap)
    bind();
    for (int k = 0; k < D + S; ++k) piece_cols[k] = cols[k];
    for (int d = 0; d < D; ++d) {
      piece_cols[d].q = w.x0[d].data(), piece_cols[d].rate = w.v0[d].data(), piece_cols[d].acc = w.start_a[d].data();
      piece_cols[d].q1 = w.x1[d].data(), piece_cols[d].rate1 = w.v1[d].data(), piece_cols[d].acc1 = w.a0[d].data();
    }
    for (int k = 0; k < S; ++k) {
      piece_cols[D + k].rate = w.start_w[k].data(), piece_cols[D + k].acc = w.start_alpha[k].data();
      piece_cols[D + k].rate1 = w.w1[k].data(), piece_cols[D + k].acc1 = w.alpha1[k].data();
    }
    if constexpr (D == 2) piece_cols[D].q = w.start_angle[0].data(), piece_cols[D].q1 = w.angle1[0].data();
  };
  double t0 = t_n, remaining = h;
  auto piece = [&](double length) {
    freeze(x0, v0, t0);
    const StepStatus st = rk4_columns<D>(m, s, w, piece_cols, D + S, t0, length, w.plane_force0.data(), false);
    thaw();
    return st;
  };
  for (;;) {
    rebind();
    status |= piece(remaining);
    if (has(status, kStepNotTaken)) return status;
    if (!contact_set_changed<D>(m, s, t0, x0, v0, t0 + remaining, x1, v1)) break;
    if (located == m.capacities.max_events_per_step) {
      status |= StepStatus::event_capacity;
      break;
    }
    const double hi = locate_contact_event(remaining, status, piece, [&](double length) {
      return contact_set_changed<D>(m, s, t0, x0, v0, t0 + length, x1, v1);
    });
    if (has(status, kStepNotTaken)) return status;
    // Land just past the event, where the new set holds; the springs advance by the piece.
    const double length = hi * remaining;
    status |= piece(length);
    if (has(status, kStepNotTaken)) return status;
    for (std::size_t p = 0; p < w.plane_step_impulse.size(); ++p) w.plane_step_impulse[p] += w.plane_weighted[p];
    status |= evaluate_at<D>(m, s, w, views_of<D>(piece_cols, Copy::final), t0 + length, length, true);
    if (has(status, kStepNotTaken)) return status;
    for (int d = 0; d < D; ++d) {
      w.x0[d].swap(w.x1[d]);
      w.v0[d].swap(w.v1[d]);
      w.start_a[d].swap(w.a0[d]);
    }
    for (int k = 0; k < S; ++k) {
      w.start_w[k].swap(w.w1[k]);
      w.start_alpha[k].swap(w.alpha1[k]);
    }
    for (std::size_t k = 0; k < s.angle.size(); ++k) w.start_angle[k].swap(w.angle1[k]);
    w.plane_force0 = w.plane_force;
    t0 += length;
    remaining -= length;
    ++located;
  }
  for (std::size_t p = 0; p < w.plane_step_impulse.size(); ++p)
    w.plane_weighted[p] = w.plane_step_impulse[p] + w.plane_weighted[p];
  return status | evaluate_at<D>(m, s, w, views_of<D>(piece_cols, Copy::final), t_end, remaining, true);
}

}  // namespace

template <int D>
StepStatus granular_step(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  constexpr int S = spin_components(D);
  const std::int32_t n = m.n;
  const double h = m.dt, half = 0.5 * m.dt;
  const bool verlet = m.integrator == DemIntegrator::verlet;
  StepStatus status = StepStatus::ok;
  w.mode_x = {};  // plain evaluations but in abm4_events' trials and pieces
  w.mode_v = {};
  if (s.history_count == 0) {
    status |= granular_evaluate_current<D>(m, s, w);
    if (has(status, kStepNotTaken)) return status;
    s.hist_plane_force[s.history_head] = w.plane_force;
    s.history_count = 1;
  }
  const double start_time = s.time;
  const bool moment_booked = m.energy_check.interval > 0;
  const double moment_start = moment_booked ? external_force_moment(m, s) : 0.0;
  const double planes_start = plane_work_sum(s);

  // The columns: translation, then rotation (the same updates).
  Column cols[D + S];
  for (int d = 0; d < D; ++d)
    cols[d] = {s.x[d].data(), w.x1[d].data(), s.v[d].data(), w.vs[d].data(), w.v1[d].data(),
               s.hist_a[s.history_head][d].data(), w.a0[d].data(), w.xs[d].data(), w.vs[d].data(),
               w.as[d].data(), w.sum_x[d].data(), w.sum_v[d].data(), {}, {}};
  for (int k = 0; k < S; ++k)
    cols[D + k] = {nullptr, nullptr, s.w[k].data(), w.w1[k].data(), w.w1[k].data(), s.hist_alpha[s.history_head][k].data(),
                   w.alpha1[k].data(), nullptr, w.ws[k].data(), w.alphas[k].data(), nullptr, w.sum_w[k].data(),
                   {}, {}};
  if constexpr (D == 2) {  // the angle turned: the coordinate of the 2D spin
    cols[D].q = s.angle[0].data();
    cols[D].q1 = w.angle1[0].data();
    cols[D].qs = w.angle_s[0].data();
    cols[D].sq = w.sum_angle[0].data();
  }
  // The history ring, newest first (ABM4 reads all four slots).
  for (int age = 0; age < 4; ++age) {
    const int slot = (s.history_head + 4 - age) & 3;
    for (int d = 0; d < D; ++d) {
      cols[d].rate_hist[age] = s.hist_v[slot][d].data();
      cols[d].acc_hist[age] = s.hist_a[slot][d].data();
    }
    for (int k = 0; k < S; ++k) {
      cols[D + k].rate_hist[age] = s.hist_w[slot][k].data();
      cols[D + k].acc_hist[age] = s.hist_alpha[slot][k].data();
    }
  }
  const bool events = m.integrator == DemIntegrator::abm4_events;
  const bool abm4 = m.integrator == DemIntegrator::abm4 && s.history_count == 4;
  // rk4, and abm4's three start steps.
  const bool rk4 = m.integrator == DemIntegrator::rk4 || (m.integrator == DemIntegrator::abm4 && !abm4);
  // The kicked rate: Verlet's translation keeps it apart (w.vs) from the final
  // one, its rotation kicks w1 in place; symplectic Euler's is final.
  if (!verlet)
    for (int d = 0; d < D; ++d) cols[d].rate_half = w.v1[d].data();

  std::int32_t located = 0;
  if (events) {
    // Stages 1-3 for the trial, every piece and y_n+1.
    status |= located_columns<D>(m, s, w, cols, located);
    if (has(status, kStepNotTaken)) return status;
  } else if (abm4) {
    // Stages 1-3 for the prediction and for y_n+1.
    status |= abm4_columns<D>(m, s, w, cols, D + S, true);
    if (has(status, kStepNotTaken)) return status;
  } else if (rk4) {
    // Stages 1-3 in each of the four RK4 stages and the evaluation of y_n+1.
    status |= rk4_columns<D>(m, s, w, cols, D + S, s.time, h, s.hist_plane_force[s.history_head].data(), true);
    if (has(status, kStepNotTaken)) return status;
  } else {
    // Stage 1: kick and drift. Verlet: q' ← q' + h/2 q''; symplectic Euler: q' ← q' + h q''; then q ← q + h q'.
    // Element by element: the model's parts (over_parts) give the same bits.
    const double kick = verlet ? half : h;
    over_parts(m, w, [&](std::int32_t begin, std::int32_t end) {
      for (const Column& c : cols) {
        for (std::int32_t i = begin; i < end; ++i) c.rate_half[i] = c.rate[i] + kick * c.acc[i];
        if (c.q != nullptr)
          for (std::int32_t i = begin; i < end; ++i) c.q1[i] = c.q[i] + h * c.rate_half[i];
      }
    });

    // Stages 2 and 3: broad phase and forces at the trial state (the dashpots
    // and the springs see the kicked rates, as in the frictionless Verlet).
    status |= evaluate_at<D>(m, s, w, views_of<D>(cols, Copy::kicked), s.time + h, h, true);
    if (has(status, kStepNotTaken)) return status;
    // Stage 4: Verlet's final kick q' ← q' + h/2 q''(trial).
    if (verlet)
      over_parts(m, w, [&](std::int32_t begin, std::int32_t end) {
        for (const Column& c : cols)
          for (std::int32_t i = begin; i < end; ++i) c.rate1[i] = c.rate_half[i] + half * c.acc1[i];
      });
  }

  // Stage 5: commit (swaps) and books.
  // The planes' impulse with the integrator's weights: Verlet h/2 (F_n + F_n+1),
  // Euler h F_n, RK4 and ABM4 their stages' (rk4_columns, abm4_columns).
  const double* force_start = s.hist_plane_force[s.history_head].data();
  for (std::size_t p = 0; p < s.plane_impulse.size(); ++p)
    s.plane_impulse[p] += rk4 || abm4 || events ? w.plane_weighted[p]
                          : verlet    ? half * (force_start[p] + w.plane_force[p])
                                      : h * force_start[p];
  // The new state, and its rates and accelerations into the next history slot.
  const int slot = (s.history_head + 1) & 3;
  for (int d = 0; d < D; ++d) {
    s.x[d].swap(w.x1[d]);
    s.v[d].swap(w.v1[d]);
    s.hist_a[slot][d].swap(w.a0[d]);
    s.hist_v[slot][d] = s.v[d];
  }
  for (int k = 0; k < S; ++k) {
    s.w[k].swap(w.w1[k]);
    s.hist_alpha[slot][k].swap(w.alpha1[k]);
    s.hist_w[slot][k] = s.w[k];
  }
  if constexpr (D == 2) s.angle[0].swap(w.angle1[0]);
  s.hist_plane_force[slot].swap(w.plane_force);
  s.history_head = slot;
  // An event restarts the history: it would span a kink of the right-hand side.
  s.history_count = located > 0 ? 1 : std::min(s.history_count + 1, 4);
  s.events_located += located;
  s.peak_events = std::max(s.peak_events, located);
  ++s.step;
  s.time = static_cast<double>(s.step) * m.dt;
  if (m.features.broad_phase != BroadPhase::grid) {
    ConstColumns<D> x;
    for (int d = 0; d < D; ++d) x[d] = s.x[d].data();
    s.network_omega2 = m.law == ContactLaw::hertz ? network_omega2<D, true>(m, s, w, x) : network_omega2<D>(m, s, w, x);
  }
  if (m.dt > m.stable_dt || m.dt * m.dt * s.network_omega2 > m.stable_factor * m.stable_factor * (1 + 1e-12))
    status |= StepStatus::unstable_time_step;
  // Finite: every column the step wrote, the springs and the step's inputs.
  // (zero_probe: 0 or NaN whatever the order of the sums, so parts may take it.)
  double probe = 0.0 * start_time + 0.0 * s.energy.reference + 0.0 * s.energy.work;
  double per_part[2] = {0, 0};
  const int head = s.history_head;
  over_parts(m, w, [&](std::int32_t begin, std::int32_t end) {
    double sum = 0;
    for (int d = 0; d < D; ++d)
      sum += zero_probe<3>({s.x[d].data(), s.v[d].data(), s.hist_a[head][d].data()}, begin, end);
    for (int k = 0; k < S; ++k) sum += zero_probe<2>({s.w[k].data(), s.hist_alpha[head][k].data()}, begin, end);
    for (const auto& c : s.angle) sum += zero_probe<1>({c.data()}, begin, end);
    per_part[begin == 0 ? 0 : 1] = sum;  // part 1 starts at split >= 1
  });
  probe += per_part[0] + per_part[1];
  std::array<const double*, D> springs;
  for (int d = 0; d < D; ++d) springs[d] = s.pair_xi[d].data();
  probe += zero_probe<D>(springs, 0, s.pair_count);
  for (std::size_t p = 0; p < s.plane_offset.size(); ++p) {
    for (int d = 0; d < D; ++d) springs[d] = s.plane_xi[d].data() + p * static_cast<std::size_t>(n);
    probe += zero_probe<D>(springs, 0, n);
  }
  for (std::size_t p = 0; p < s.plane_offset.size(); ++p)
    probe += 0.0 * s.plane_offset[p] + 0.0 * s.plane_speed[p] + 0.0 * s.plane_impulse[p];
  if (!(probe == 0.0)) status |= StepStatus::non_finite;
  const double moment_end = moment_booked ? external_force_moment(m, s) : 0.0;
  s.energy.work += (moment_end - moment_start) + (plane_work_sum(s) - planes_start);
  if (energy_check_due(m.energy_check, s.step)) energy_check(s.energy, m.energy_check, energy_totals(m, s));
  if (s.energy.exceeded != 0) status |= StepStatus::energy_growth;
  return status;
}

#define XFDEM_INSTANTIATE(D)                                                                                       \
  template StepStatus granular_step<D>(const DemModel<D>&, DemState<D>&, DemWorkspace<D>&);                        \
  template StepStatus granular_evaluate_current<D>(const DemModel<D>&, DemState<D>&, DemWorkspace<D>&);            \
  template ContactResult<D> pair_contact<D>(const DemModel<D>&, std::int32_t, std::int32_t, double, double,        \
                                            const double (&)[D], double, const double (&)[D], const double (&)[D], \
                                            const double*, const double*, double, double (&)[D]);                  \
  template ContactResult<D> plane_contact<D>(const DemModel<D>&, std::int32_t, std::size_t, double, double,        \
                                             const double (&)[D], const double*, double, double (&)[D]);        \
  template ContactResult<D> wall_contact<D>(const DemModel<D>&, std::int32_t, const WallContact<D>&, double,        \
                                            const double (&)[D], const double*, double, double (&)[D]);
XFDEM_INSTANTIATE(2)
XFDEM_INSTANTIATE(3)
#undef XFDEM_INSTANTIATE

}  // namespace xfdem::dem_detail
