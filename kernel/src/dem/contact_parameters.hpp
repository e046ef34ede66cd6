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

template <int D>
PairParameters pair_parameters(const DemModel<D>& m, std::int32_t i, std::int32_t j) {
  const double ki = m.stiffness[i], kj = m.stiffness[j];
  const double K = ki * kj / (ki + kj);
  const double m_eff = m.mass[i] * m.mass[j] / (m.mass[i] + m.mass[j]);
  return {K, 2.0 * m.damping_ratio * std::sqrt(K * m_eff)};
}

}  // namespace xfdem::dem_detail
