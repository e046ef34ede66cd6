// Stiffness and dashpot of a particle pair, computed in one place so that every
// path (all-pairs list, grid list, probes) rounds them identically.
#pragma once
#include <cmath>

#include "xfdem/dem.hpp"

namespace xfdem::dem_detail {

struct PairParameters {
  double stiffness;  ///< K = k_i k_j / (k_i + k_j), springs in series (N/m)
  double eta;        ///< 2 ζ √(K m_eff), m_eff = m_i m_j / (m_i + m_j) (N·s/m)
};

/// hertz: the pair list caches E* and G* instead
/// (1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j, 1/G* likewise).
template <int D>
PairParameters pair_parameters(const DemModel<D>& m, std::int32_t i, std::int32_t j) {
  if (m.law == ContactLaw::hertz)
    return {1.0 / (m.hertz_inv_e[i] + m.hertz_inv_e[j]), 1.0 / (m.hertz_inv_g[i] + m.hertz_inv_g[j])};
  const double ki = m.stiffness[i], kj = m.stiffness[j];
  const double K = ki * kj / (ki + kj);
  const double m_eff = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]);
  return {K, 2.0 * m.damping_ratio * std::sqrt(K * m_eff)};
}

}  // namespace xfdem::dem_detail
