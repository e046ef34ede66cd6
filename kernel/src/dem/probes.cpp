// Read-only measurements of a DEM state, for the tools and tests.
#include <cmath>

#include "dem/contact_law.hpp"
#include "dem/contact_parameters.hpp"
#include "dem/energy_books.hpp"
#include "dem/forces.hpp"
#include "dem/granular.hpp"

namespace xfdem {
namespace {

template <int D>
double plane_overlap(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::size_t p, double* rate) {
  const auto point = dem_detail::plane_point_at(m, s, p, s.time);
  double gap = 0, r = s.plane_speed[p];
  for (int d = 0; d < D; ++d) {
    gap += (s.x[d][i] - point[d]) * m.plane_normal[p][d];
    r -= s.v[d][i] * m.plane_normal[p][d];
  }
  if (rate) *rate = r;
  return m.radius[i] - gap;
}

template <int D>
double pair_overlap(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::int32_t j, double* rate) {
  double dx[D], dist = 0;
  for (int d = 0; d < D; ++d) {
    dx[d] = s.x[d][j] - s.x[d][i];
    dist += dx[d] * dx[d];
  }
  dist = std::sqrt(dist);
  double r = 0;
  for (int d = 0; d < D; ++d) r -= (s.v[d][j] - s.v[d][i]) * (dist > 0 ? dx[d] / dist : (d == 0 ? 1.0 : 0.0));
  if (rate) *rate = r;
  return m.radius[i] + m.radius[j] - dist;
}

template <int D>
double contact_force(const DemModel<D>& m, double K, double eta, double overlap, double rate) {
  return dem_detail::normal_force(m.law == ContactLaw::linear_nontensile, K, eta, overlap, rate);
}

/// hertz: E*, G* of particle i against plane p (a rigid wall adds nothing).
template <int D>
double plane_e_star(const DemModel<D>& m, std::int32_t i, std::size_t p) {
  return 1.0 / (m.hertz_inv_e[i] + m.plane_inv_e[p]);
}
template <int D>
double plane_g_star(const DemModel<D>& m, std::int32_t i, std::size_t p) {
  return 1.0 / (m.hertz_inv_g[i] + m.plane_inv_g[p]);
}

/// Particle i's ½ m v² (+ ½ I ω² when it rotates) and its −m g·x (datum x = 0).
struct ParticleEnergy {
  double kinetic, potential;
};
template <int D>
ParticleEnergy particle_energy(const DemModel<D>& m, const DemState<D>& s, std::int32_t i) {
  double v2 = 0, gx = 0;
  for (int d = 0; d < D; ++d) {
    v2 += s.v[d][i] * s.v[d][i];
    gx += m.gravity[d] * s.x[d][i];
  }
  double kinetic = 0.5 * m.mass[i] * v2;
  if constexpr (D > 1)
    if (m.features.rotation) {
      double w2 = 0;
      for (const auto& c : s.w) w2 += c[i] * c[i];
      kinetic += 0.5 * w2 / m.inv_inertia[i];
    }
  return {kinetic, -(m.mass[i] * gx)};
}

/// Σ ½ k_t |ξ|² over the tangential springs of the contact records (rotating
/// models; 0 otherwise): planes' of particles [begin, end), pairs [pair_begin, pair_end).
template <int D>
double tangential_springs(const DemModel<D>& m, const DemState<D>& s, std::int32_t begin, std::int32_t end,
                          std::int32_t pair_begin, std::int32_t pair_end) {
  if constexpr (D == 1) {
    return 0.0;
  } else {
  if (!m.features.rotation || m.friction == 0) return 0.0;
  double sum = 0;
  const double* plane_xi[D];
  const double* pair_xi[D];
  for (int d = 0; d < D; ++d) {
    plane_xi[d] = s.plane_xi[d].data();
    pair_xi[d] = s.pair_xi[d].data();
  }
  // hertz: the Mindlin spring kept as a force has no potential (its stiffness
  // changes with the overlap, so ½ |F|²/S_t would grow as a contact unloads
  // with F held): the books leave it out, and so count a lower bound of the
  // energy in motion; a gain past the start is still a gain.
  if (m.law == ContactLaw::hertz) return 0.0;
  // Each spring counted up to the Coulomb cap of its contact's normal spring
  // now (tangential_energy).
  auto cap = [&](double K, double overlap) { return overlap > 0 ? m.friction * K * overlap : 0.0; };
  for (std::size_t p = 0; p < m.plane_point.size(); ++p)
    for (std::int32_t i = begin; i < end; ++i)
      sum += dem_detail::tangential_energy<D>(m.tangential_ratio * m.stiffness[i], plane_xi,
                                              p * static_cast<std::size_t>(m.n) + static_cast<std::size_t>(i),
                                              cap(m.stiffness[i], plane_overlap(m, s, i, p, nullptr)));
  for (std::int32_t k = pair_begin; k < pair_end; ++k)
    sum += dem_detail::tangential_energy<D>(m.tangential_ratio * s.pair_stiffness[k], pair_xi, static_cast<std::size_t>(k),
                                            cap(s.pair_stiffness[k], pair_overlap(m, s, s.pair_i[k], s.pair_j[k], nullptr)));
  return sum;
  }
}

}  // namespace

template <int D>
DemEnergy dem_energy(const DemModel<D>& m, const DemState<D>& s) {
  DemEnergy e;
  for (std::int32_t i = 0; i < m.n; ++i) {
    const ParticleEnergy pe = particle_energy(m, s, i);
    e.kinetic += pe.kinetic;
    e.potential += pe.potential;
    for (std::size_t p = 0; p < m.plane_point.size(); ++p) {
      const double overlap = plane_overlap(m, s, i, p, nullptr);
      if (overlap > 0)
        e.elastic += m.law == ContactLaw::hertz ? dem_detail::hertz_energy(plane_e_star(m, i, p), m.radius[i], overlap)
                                                : dem_detail::spring_energy(m.stiffness[i], overlap);
    }
  }
  if constexpr (D > 1)
    if (m.features.rotation) e.elastic += tangential_springs(m, s, 0, m.n, 0, s.pair_count);
  // Every pair, not the pair list: the list may be stale between steps, and a
  // probe is not on the hot path.
  for (std::int32_t i = 0; i < m.n; ++i)
    for (std::int32_t j = i + 1; j < m.n; ++j) {
      const double overlap = pair_overlap(m, s, i, j, nullptr);
      if (overlap > 0) e.elastic += dem_detail::pair_spring_energy(m, i, j, dem_detail::pair_parameters(m, i, j).stiffness, overlap);
    }
  return e;
}

namespace dem_detail {

/// Σ ½ k_i δ² over particles [begin, end) touching plane p (its point taken once).
template <int D>
double plane_elastic_energy(const DemModel<D>& m, const DemState<D>& s, std::size_t p, std::int32_t begin,
                            std::int32_t end) {
  const std::array<double, D> point = plane_point_at(m, s, p, s.time);
  const auto& normal = m.plane_normal[p];
  double elastic = 0;
  for (std::int32_t i = begin; i < end; ++i) {
    double gap = 0;
    for (int d = 0; d < D; ++d) gap += (s.x[d][i] - point[d]) * normal[d];
    const double overlap = m.radius[i] - gap;
    if (overlap > 0)
      elastic += m.law == ContactLaw::hertz ? hertz_energy(plane_e_star(m, i, p), m.radius[i], overlap)
                                            : spring_energy(m.stiffness[i], overlap);
  }
  return elastic;
}

template <int D>
double plane_elastic_energy(const DemModel<D>& m, const DemState<D>& s, std::size_t p) {
  return plane_elastic_energy(m, s, p, 0, m.n);
}

template <int D>
EnergyTotals energy_totals(const DemModel<D>& m, const DemState<D>& s, const ParallelFor& parallel) {
  // The model's two parts (particles split at m.split, the pair list at its
  // middle), summed part 0 then part 1 whoever runs them: the same bits on one
  // worker or two.
  struct Sums {
    double kinetic = 0, elastic = 0, potential = 0, potential_magnitude = 0;
  } sums[2];
  const int parts = m.parts > 1 ? 2 : 1;
  for_parts(parallel, parts, [&](int part) {
    const std::int32_t begin = part == 0 ? 0 : m.split, end = parts == 1 || part == 1 ? m.n : m.split;
    const std::int32_t pair_begin = part == 0 ? 0 : s.pair_count / 2;
    const std::int32_t pair_end = parts == 1 || part == 1 ? s.pair_count : s.pair_count / 2;
    Sums& sum = sums[part];
    for (std::int32_t i = begin; i < end; ++i) {
      const ParticleEnergy pe = particle_energy(m, s, i);
      sum.kinetic += pe.kinetic;
      sum.potential += pe.potential;
      sum.potential_magnitude += std::fabs(pe.potential);
    }
    for (std::size_t p = 0; p < m.plane_point.size(); ++p) sum.elastic += plane_elastic_energy(m, s, p, begin, end);
    for (std::int32_t k = pair_begin; k < pair_end; ++k) {
      const std::int32_t i = s.pair_i[k], j = s.pair_j[k];
      double dist2 = 0;
      for (int d = 0; d < D; ++d) dist2 += (s.x[d][j] - s.x[d][i]) * (s.x[d][j] - s.x[d][i]);
      const double reach = m.radius[i] + m.radius[j];
      if (dist2 >= reach * reach) continue;
      const double overlap = reach - std::sqrt(dist2);
      sum.elastic += pair_spring_energy(m, i, j, s.pair_stiffness[k], overlap);
    }
    if constexpr (D > 1)
      if (m.features.rotation) sum.elastic += tangential_springs(m, s, begin, end, pair_begin, pair_end);
  });
  const double in_motion = (sums[0].kinetic + sums[1].kinetic) + (sums[0].elastic + sums[1].elastic);
  const double potential = sums[0].potential + sums[1].potential;
  return {in_motion + potential, in_motion, in_motion + (sums[0].potential_magnitude + sums[1].potential_magnitude)};
}

}  // namespace dem_detail

template <int D>
void dem_restart_energy_ledger(const DemModel<D>& m, DemState<D>& s) {
  energy_restart(s.energy, dem_detail::energy_totals(m, s));
}

template <int D>
double dem_pair_force(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::int32_t j) {
  if (i < 0 || j < 0 || i >= m.n || j >= m.n || i == j) return NAN;
  double rate = 0;
  const double overlap = pair_overlap(m, s, i, j, &rate);
  const dem_detail::PairParameters pp = dem_detail::pair_parameters(m, i, j);
  if (m.law == ContactLaw::hertz)
    return dem_detail::hertz_contact(pp.stiffness, pp.eta, m.radius[i] * m.radius[j] / (m.radius[i] + m.radius[j]),
                                     1.0 / (m.inv_mass[i] + m.inv_mass[j]), m.hertz_damping, overlap, rate)
        .fn;
  return contact_force(m, pp.stiffness, pp.eta, overlap, rate);
}

template <int D>
double dem_plane_force(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::int32_t p) {
  if (i < 0 || i >= m.n || p < 0 || p >= static_cast<std::int32_t>(m.plane_point.size())) return NAN;
  double rate = 0;
  const double overlap = plane_overlap(m, s, i, static_cast<std::size_t>(p), &rate);
  if (m.law == ContactLaw::hertz) {
    const auto q = static_cast<std::size_t>(p);
    return dem_detail::hertz_contact(plane_e_star(m, i, q), plane_g_star(m, i, q), m.radius[i], m.mass[i],
                                     m.hertz_damping, overlap, rate)
        .fn;
  }
  return contact_force(m, m.stiffness[i], m.plane_eta[i], overlap, rate);
}

namespace {

/// The tangential force of a touching contact as the probes report it (see
/// dem.hpp): 2D along t = (−n_y, n_x), 3D its magnitude; n from the first to the second body.
template <int D>
double reported_tangential(const double (&n)[D], const double (&ft)[D]) {
  if constexpr (D == 2) return -n[1] * ft[0] + n[0] * ft[1];
  double f2 = 0;
  for (int d = 0; d < D; ++d) f2 += ft[d] * ft[d];
  return std::sqrt(f2);
}

}  // namespace

template <int D>
double dem_pair_tangential_force(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::int32_t j) {
  if (i < 0 || j < 0 || i >= m.n || j >= m.n || i == j) return NAN;
  if constexpr (D == 1) {
    return 0.0;
  } else {
    if (!m.features.rotation || m.friction == 0) return 0.0;
    const std::int32_t a = std::min(i, j), b = std::max(i, j);
    double dx[D], va[D], vb[D], xi[D] = {};
    ConstColumns<D> x;
    for (int d = 0; d < D; ++d) x[d] = s.x[d].data();
    const double dist2 = dem_detail::separation<D>(x, a, b, dx);
    const double reach = m.radius[a] + m.radius[b];
    if (!(dist2 < reach * reach)) return 0.0;
    // The stored spring of the pair's record (none: a contact the list has not seen yet).
    for (std::int32_t c = 0; c < s.pair_count; ++c)
      if (s.pair_i[c] == a && s.pair_j[c] == b)
        for (int d = 0; d < D; ++d) xi[d] = s.pair_xi[d][c];
    for (int d = 0; d < D; ++d) {
      va[d] = s.v[d][a];
      vb[d] = s.v[d][b];
    }
    double wa[spin_components(D)], wb[spin_components(D)];
    for (int k = 0; k < spin_components(D); ++k) {
      wa[k] = s.w[k][a];
      wb[k] = s.w[k][b];
    }
    const dem_detail::PairParameters pp = dem_detail::pair_parameters(m, a, b);
    const dem_detail::ContactResult<D> r =
        dem_detail::pair_contact<D>(m, a, b, pp.stiffness, pp.eta, dx, dist2, va, vb, wa, wb, 0.0, xi);
    // The law's n runs from a to b and its F_t acts on b; named the other way
    // round (i > j) both flip, and so does t: the reported value is the same.
    return reported_tangential<D>(r.normal, r.ft);
  }
}

template <int D>
double dem_plane_tangential_force(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, std::int32_t p) {
  if (i < 0 || i >= m.n || p < 0 || p >= static_cast<std::int32_t>(m.plane_point.size())) return NAN;
  if constexpr (D == 1) {
    return 0.0;
  } else {
    if (!m.features.rotation || m.friction == 0) return 0.0;
    const auto q = static_cast<std::size_t>(p);
    const double overlap = plane_overlap(m, s, i, q, nullptr);
    if (!(overlap > 0)) return 0.0;
    double vi[D], xi[D], wi[spin_components(D)];
    const std::size_t slot = q * static_cast<std::size_t>(m.n) + static_cast<std::size_t>(i);
    for (int d = 0; d < D; ++d) {
      vi[d] = s.v[d][i];
      xi[d] = s.plane_xi[d][slot];
    }
    for (int k = 0; k < spin_components(D); ++k) wi[k] = s.w[k][i];
    const dem_detail::ContactResult<D> r = dem_detail::plane_contact<D>(m, i, q, overlap, s.plane_speed[q], vi, wi, 0.0, xi);
    // The law's n runs from the plane to the particle and its F_t acts on the
    // particle; the probe's n runs from the particle to the plane and reports
    // the force on the plane: n, t and F_t all flip, the value does not.
    return reported_tangential<D>(r.normal, r.ft);
  }
}

template <int D>
double dem_angular_velocity(const DemModel<D>& m, const DemState<D>& s, std::int32_t i, int component) {
  if (i < 0 || i >= m.n || component < 0 || component >= spin_components(D)) return NAN;
  if (!m.features.rotation) return 0.0;
  return s.w[static_cast<std::size_t>(component)][static_cast<std::size_t>(i)];
}

template <int D>
double dem_momentum(const DemModel<D>& m, const DemState<D>& s, int component) {
  if (component < 0 || component >= D) return NAN;
  double p = 0.0;
  for (std::int32_t i = 0; i < m.n; ++i)
    p += m.mass[static_cast<std::size_t>(i)] * s.v[static_cast<std::size_t>(component)][static_cast<std::size_t>(i)];
  return p;
}

template <int D>
double dem_rotation(const DemModel<D>& m, const DemState<D>& s, std::int32_t i) {
  if (D != 2 || i < 0 || i >= m.n) return NAN;
  if (!m.features.rotation) return 0.0;
  if constexpr (D == 2) return s.angle[0][static_cast<std::size_t>(i)];
  return NAN;
}

#define XFDEM_INSTANTIATE(D)                                                                        \
  template DemEnergy dem_energy<D>(const DemModel<D>&, const DemState<D>&);                          \
  template EnergyTotals dem_detail::energy_totals<D>(const DemModel<D>&, const DemState<D>&, const ParallelFor&); \
  template double dem_detail::plane_elastic_energy<D>(const DemModel<D>&, const DemState<D>&, std::size_t); \
  template void dem_restart_energy_ledger<D>(const DemModel<D>&, DemState<D>&);                       \
  template double dem_pair_force<D>(const DemModel<D>&, const DemState<D>&, std::int32_t, std::int32_t); \
  template double dem_plane_force<D>(const DemModel<D>&, const DemState<D>&, std::int32_t, std::int32_t); \
  template double dem_pair_tangential_force<D>(const DemModel<D>&, const DemState<D>&, std::int32_t, std::int32_t); \
  template double dem_plane_tangential_force<D>(const DemModel<D>&, const DemState<D>&, std::int32_t, std::int32_t); \
  template double dem_angular_velocity<D>(const DemModel<D>&, const DemState<D>&, std::int32_t, int); \
  template double dem_rotation<D>(const DemModel<D>&, const DemState<D>&, std::int32_t);          \
  template double dem_momentum<D>(const DemModel<D>&, const DemState<D>&, int);
XFDEM_INSTANTIATE(1)
XFDEM_INSTANTIATE(2)
XFDEM_INSTANTIATE(3)
#undef XFDEM_INSTANTIATE

}  // namespace xfdem
