// The contact network's highest frequency, bounded from the contacts.
//
// The stable step the build checks (DemModel::stable_dt) is that of the
// stiffest single contact, ω² = K (1/m_i + 1/m_j). A particle pressed by
// several contacts at once vibrates faster: a column of equal spheres on a
// plane reaches ω² = 4K/m, twice the single contact's. With w_i = √m_i u_i,
//   (n·(u_i − u_j))² ≤ (1/m_i + 1/m_j) ((n·w_i)² + (n·w_j)²),
// so the Rayleigh quotient uᵀKu / uᵀMu of any mode is at most max_i λ_max(T_i),
//   T_i = Σ_pairs K_ij (1/m_i + 1/m_j) n_ij n_ijᵀ + Σ_planes (k_i/m_i) n_p n_pᵀ.
// T_i is bounded here by its largest absolute row sum. The bound equals the
// single contact's value when no particle has two contacts, and is exact for
// a chain and for cubic and face-centred lattices (where T_i is a multiple of
// the identity).
//
// A header, so that the small-system step inlines it (it runs after every step).
#pragma once
#include <cmath>

#include "dem/forces.hpp"

namespace xfdem::dem_detail {

namespace network {

/// Index of entry (r, c), r ≤ c, of a symmetric D × D matrix stored by rows.
template <int D>
constexpr int packed(int r, int c) {
  return r * D - r * (r - 1) / 2 + (c - r);
}

/// Adds weight · n nᵀ to the packed symmetric matrix t.
template <int D>
void add_outer(double* t, double weight, const double (&n)[D]) {
  for (int r = 0; r < D; ++r)
    for (int c = r; c < D; ++c) t[packed<D>(r, c)] += weight * n[r] * n[c];
}

}  // namespace network

/// Gershgorin bound on the squared highest frequency of the contacts touching
/// at positions x: listed pairs that overlap and planes a sphere reaches.
/// Hertz: K is the tangent stiffness S_n = 2 E* √(R* δ) at the contact's
/// current overlap (the pair list caches E*). N: particle_count; P: plane_count.
template <int D, bool Hertz = false, int N = 0, int P = 0>
[[gnu::always_inline]] inline double network_omega2(const DemModel<D>& m, const DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x) {
  constexpr int kEntries = D * (D + 1) / 2;
  const std::int32_t n = particle_count<N>(m);
  double* t = w.network_row.data();
  for (std::int64_t k = 0; k < std::int64_t{n} * kEntries; ++k) t[k] = 0.0;
  for (std::int32_t c = 0; c < s.pair_count; ++c) {
    const std::int32_t i = s.pair_i[c], j = s.pair_j[c];
    double dx[D];
    const double dist2 = separation<D>(x, i, j, dx);
    const double reach = m.radius[i] + m.radius[j];
    if (!(dist2 < reach * reach)) continue;
    double normal[D];
    const double dist = std::sqrt(dist2);
    for (int d = 0; d < D; ++d) normal[d] = dist > 0 ? dx[d] / dist : (d == 0 ? 1.0 : 0.0);
    double stiffness = s.pair_stiffness[c];
    if constexpr (Hertz) stiffness = 2.0 * stiffness * std::sqrt(m.radius[i] * m.radius[j] / reach * (reach - dist));
    const double omega2 = stiffness * (m.inv_mass[i] + m.inv_mass[j]);
    network::add_outer<D>(t + std::int64_t{i} * kEntries, omega2, normal);
    network::add_outer<D>(t + std::int64_t{j} * kEntries, omega2, normal);
  }
  const std::size_t planes = plane_count<P>(m.plane_point);
  for (std::size_t p = 0; p < planes; ++p) {
    const std::array<double, D> point = plane_point_at(m, s, p, s.time);
    double normal[D];
    for (int d = 0; d < D; ++d) normal[d] = m.plane_normal[p][d];
    for (std::int32_t i = 0; i < n; ++i) {
      double height = 0;
      for (int d = 0; d < D; ++d) height += (x[d][i] - point[d]) * normal[d];
      const double overlap = m.radius[i] - height;
      if (!(overlap > 0)) continue;
      double stiffness = m.stiffness[i];
      if constexpr (Hertz) stiffness = 2.0 / (m.hertz_inv_e[i] + m.plane_inv_e[p]) * std::sqrt(m.radius[i] * overlap);
      network::add_outer<D>(t + std::int64_t{i} * kEntries, stiffness * m.inv_mass[i], normal);
    }
  }
  double worst = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    const double* ti = t + std::int64_t{i} * kEntries;
    for (int r = 0; r < D; ++r) {
      double row = 0;
      for (int c = 0; c < D; ++c) row += std::fabs(ti[r <= c ? network::packed<D>(r, c) : network::packed<D>(c, r)]);
      worst = std::max(worst, row);
    }
  }
  return worst;
}

}  // namespace xfdem::dem_detail
