// The stability stress suite's scenes and runners, shared by the fast sweeps
// (tests/stress, label `stress`) and the deep runs (tests/long, label `long`).
//
// Every case is run step by step and ends in exactly one of two outcomes:
//   - bounded: no step raised a flag, and the total energy stayed within the
//     bound docs/stability.md states (E(t) ≤ E0 + W(t) + ε·A, where W is the
//     work done on the system and A the energy it has available to exchange);
//   - reported: the stepper (or the build) said what is wrong, with a status.
// A case that raised no flag and broke its bound is the defect the suite
// exists to find.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::stress {

/// What one run of a case did.
struct Outcome {
  bool built = true;           ///< false: the build refused the case (message kept)
  std::string build_message;
  StepStatus flags = StepStatus::ok;  ///< union of every step's flags
  std::int64_t first_flag_step = -1;  ///< first step that raised a flag
  std::int64_t steps = 0;             ///< steps taken
  double available = 0;        ///< A: the energy scale of the case (J)
  double worst_excess = 0;     ///< max over unflagged steps of (E − E0 − W)/A
  double peak_motion = 0;      ///< max over the run of (kinetic + elastic)/A (particle cases)
  bool finite = true;          ///< every energy along the run was finite

  [[nodiscard]] bool reported() const { return !built || flags != StepStatus::ok; }
  [[nodiscard]] bool bounded(double epsilon) const { return built && finite && worst_excess <= epsilon; }
};

inline std::string flag_text(StepStatus s) {
  char text[200];
  return describe(s, text, sizeof(text));
}

/// Steps `step()` `steps` times; `excess()` returns (E − E0 − W)/A after each
/// step. Stops at the first non-finite state (the flag is the outcome).
template <class Step, class Excess>
void run_case(Outcome& o, std::int64_t steps, Step&& step, Excess&& excess) {
  for (std::int64_t k = 0; k < steps; ++k) {
    const StepStatus s = step();
    ++o.steps;
    if (s != StepStatus::ok && o.first_flag_step < 0) o.first_flag_step = o.steps;
    o.flags |= s;
    const double e = excess();
    if (!std::isfinite(e)) {
      o.finite = false;
      break;
    }
    if (s == StepStatus::ok) o.worst_excess = std::max(o.worst_excess, e);
    if (has(s, StepStatus::non_finite)) break;
  }
}

// ---- particles: a column dropped on a plane -----------------------------------

/// Three unequal spheres stacked in a column (1D), the lowest 2 cm above a
/// plane, falling under gravity: impacts, rattling, and (damped) resting
/// contact, with pair and plane contacts of different stiffness and mass.
/// `stiffness_scale` multiplies every k.
inline DemDesc<1> column_scene(DemIntegrator integrator, double zeta, double stiffness_scale = 1.0) {
  DemDesc<1> d;
  d.gravity = {-9.81};
  d.damping_ratio = zeta;
  d.integrator = integrator;
  const double mass[3] = {1.0, 2.0, 0.5}, radius[3] = {0.05, 0.06, 0.04}, k[3] = {1e5, 2e5, 5e4};
  double x = 0.02;
  for (int i = 0; i < 3; ++i) {
    x += radius[i];
    d.particles.push_back({mass[i], radius[i], k[i] * stiffness_scale, {x}, {0.0}});
    x += radius[i] + 1e-3;  // a millimetre between neighbours
  }
  d.planes.push_back({{0.0}, {1.0}});
  return d;
}

/// The column's static equilibrium (each contact carrying the weight above it),
/// computed here from the contact laws, not by the stepper; its energy is the
/// least the column can have, so A = E0 − E_eq is what it can exchange.
inline double column_rest_energy(const DemDesc<1>& d) {
  const double g = -d.gravity[0];
  const std::size_t n = d.particles.size();
  double above = 0;
  for (const auto& p : d.particles) above += p.mass;
  double energy = 0, x = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = d.particles[i];
    const double force = above * g;  // on the contact below particle i
    // Plane contact: K = k_i; pair contact: k_i k_j/(k_i + k_j) (springs in series).
    const double k = i == 0 ? p.stiffness
                            : d.particles[i - 1].stiffness * p.stiffness / (d.particles[i - 1].stiffness + p.stiffness);
    const double overlap = force / k;
    x = i == 0 ? p.radius - overlap : x + d.particles[i - 1].radius + p.radius - overlap;
    energy += 0.5 * k * overlap * overlap + p.mass * g * x;
    above -= p.mass;
  }
  return energy;
}

inline double dem_total(const DemEnergy& e) { return e.kinetic + e.elastic + e.potential; }

/// The contact network's frequency bound for the resting column, from the
/// contact laws: per particle, the sum of K (1/m_i + 1/m_j) over its contacts
/// (k_i/m_i for the plane). For a chain this is the bound docs/stability.md
/// states; the stepper computes its own from the contacts it sees.
inline double column_network_omega(const DemDesc<1>& d) {
  const auto& p = d.particles;
  const std::size_t n = p.size();
  std::vector<double> row(n, 0.0);
  row[0] += p[0].stiffness / p[0].mass;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double K = p[i].stiffness * p[i + 1].stiffness / (p[i].stiffness + p[i + 1].stiffness);
    const double w2 = K * (1 / p[i].mass + 1 / p[i + 1].mass);
    row[i] += w2;
    row[i + 1] += w2;
  }
  return std::sqrt(*std::max_element(row.begin(), row.end()));
}

/// Runs a particle case at time step dt for `steps` steps, with the kernel's
/// energy check as `check` says.
inline Outcome run_dem_case(DemDesc<1> d, double dt, std::int64_t steps, const EnergyCheck& check = {}) {
  Outcome o;
  DemWorld<1> w;
  d.dt = dt;
  d.reject_unstable_dt = false;
  d.energy_check = check;
  const BuildResult r = w.build(d);
  if (!r.ok()) {
    o.built = false;
    o.build_message = r.message;
    return o;
  }
  const double e0 = dem_total(dem_energy(w.model, w.state));
  o.available = e0 - column_rest_energy(d);
  run_case(o, steps, [&] { return w.step(); },
           [&] {
             const DemEnergy e = dem_energy(w.model, w.state);
             o.peak_motion = std::max(o.peak_motion, (e.kinetic + e.elastic) / o.available);
             return (dem_total(e) - e0) / o.available;
           });
  return o;
}

}  // namespace xfdem::stress

namespace xfdem::stress {

/// A particle resting on the bar's top (tied interface or none, fixed base),
/// from statics: the rod, the interface spring and the contact carry m g in
/// series. Its energy is the least the coupled system can have.
inline double coupled_rest_energy(const CoupledDesc& d) {
  const auto& p = d.dem.particles.at(0);
  const BarDesc& b = d.bar;
  const double g = -d.dem.gravity[0], F = p.mass * g;
  double compliance = b.length / (b.youngs_modulus * b.area);
  if (b.interface) compliance += 1.0 / b.interface->stiffness;
  const double top = b.length - F * compliance;
  const double centre = top + p.radius - F / p.stiffness;
  return 0.5 * F * F * (compliance + 1.0 / p.stiffness) + p.mass * g * centre;
}

/// Runs a coupled case (one particle dropped on the bar) for `steps` steps,
/// with the kernel's energy check as `check` says.
inline Outcome run_coupled_case(CoupledDesc d, std::int64_t steps, bool reject, const EnergyCheck& check = {}) {
  Outcome o;
  d.energy_check = check;
  d.reject_unstable_coupling = reject;
  d.dem.reject_unstable_dt = reject;
  CoupledWorld w;
  const BuildResult r = w.build(d);
  if (!r.ok()) {
    o.built = false;
    o.build_message = r.message;
    return o;
  }
  const auto total = [&] {
    const CoupledEnergy e = coupled_energy(w.model, w.state);
    return e.kinetic + e.elastic + e.potential;
  };
  const double e0 = total();
  o.available = e0 - coupled_rest_energy(d);
  run_case(o, steps, [&] { return w.step(); }, [&] { return (total() - e0) / o.available; });
  return o;
}

}  // namespace xfdem::stress
