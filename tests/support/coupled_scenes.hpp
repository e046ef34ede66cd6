// The coupled validation scenes (scenes/case*.json) as kernel descriptions, and
// helpers the coupling tests share.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "xfdem/coupled.hpp"

namespace xfdem::testing {

inline CoupledDesc coupled_scene(const std::string& file, const std::vector<std::string>& overrides = {}) {
  const scene::Scene s = scene::load_scene(std::string(XFDEM_SOURCE_DIR) + "/scenes/" + file, overrides);
  CoupledDesc d;
  d.dem = std::get<DemDesc<1>>(s.dem);
  d.bar = *s.bar;
  d.dem_substeps = s.dem_substeps;
  return d;
}

/// ∫ ρ A v dx over the bar: v is linear on every piece between element
/// boundaries and the interface, so the midpoint rule is exact.
inline double bar_momentum(const CoupledModel& m, const CoupledState& s) {
  const BarDesc& b = m.bar.desc;
  std::vector<double> cuts;
  for (int e = 0; e <= b.elements; ++e) cuts.push_back(b.length * e / b.elements);
  if (b.interface) cuts.push_back(b.interface->position);
  std::sort(cuts.begin(), cuts.end());
  double p = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], c = cuts[k + 1];
    if (c - a <= 0) continue;
    p += (c - a) * bar_velocity(m.bar, s.bar, 0.5 * (a + c));
  }
  return b.density * b.area * p;
}

inline double particle_momentum(const CoupledModel& m, const CoupledState& s) {
  double p = 0;
  for (std::int32_t i = 0; i < m.dem.n; ++i) p += m.dem.mass[i] * s.dem.v[0][i];
  return p;
}

inline double total_energy(const CoupledModel& m, const CoupledState& s) {
  const CoupledEnergy e = coupled_energy(m, s);
  return e.kinetic + e.elastic + e.potential;
}

}  // namespace xfdem::testing
