// What the particle stepper's energy balance check weighs (DemState::energy),
// in O(n + pairs): the contacts between particles come from the pair list
// (every overlapping pair is on it while the list is current), not from every
// pair as the dem_energy() probe reads them.
#pragma once
#include "xfdem/dem.hpp"

namespace xfdem::dem_detail {

/// Run on the model's parts through `parallel` (the bits do not depend on it).
template <int D>
EnergyTotals energy_totals(const DemModel<D>& m, const DemState<D>& s, const ParallelFor& parallel = {});

/// Σ ½ k_i δ² over the particles touching plane p: what a host's move of the
/// plane puts into (or takes out of) its contacts, booked as work.
template <int D>
double plane_elastic_energy(const DemModel<D>& m, const DemState<D>& s, std::size_t p);

/// Σ over the planes of speed × impulse given: the work moving planes have
/// done since the impulses were last zeroed, up to a constant (the difference
/// over a step is that step's work, the speed being held over it). P > 0:
/// the step was instantiated for P planes (dem_detail::plane_count).
template <int P = 0, int D>
double plane_work_sum(const DemState<D>& s) {
  double sum = 0;
  const std::size_t planes = P > 0 ? static_cast<std::size_t>(P) : s.plane_speed.size();
  for (std::size_t p = 0; p < planes; ++p) sum += s.plane_speed[p] * s.plane_impulse[p];
  return sum;
}

/// Σ F·x over the particles, and Σ τ θ with external torques (2D): over a
/// step, with F and τ held, its difference is their work (0 without either).
template <int D>
double external_force_moment(const DemModel<D>& m, const DemState<D>& s) {
  double sum = 0;
  if (m.features.external_forces)
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = 0; i < m.n; ++i) sum += s.external_force[d][i] * s.x[d][i];
  if constexpr (D == 2)
    if (m.features.external_torques)
      for (std::int32_t i = 0; i < m.n; ++i) sum += s.external_torque[0][i] * s.angle[0][i];
  return sum;
}

}  // namespace xfdem::dem_detail
