// The granular step (particles that rotate, with friction): see granular.cpp
// for its stages. The contact functions are the step's and the probes'.
#pragma once
#include <cstddef>
#include <cstdint>

#include "xfdem/dem.hpp"

namespace xfdem::dem_detail {

/// One touching contact under the law of dem/contact_law.hpp: its unit normal
/// (first body to second), the normal force (compressive positive), the
/// tangential force on the second body, and the torques on both.
template <int D>
struct ContactResult {
  double normal[D];
  double fn;
  double ft[D];
  double torque_i[spin_components(D)], torque_j[spin_components(D)];
  bool coincident;
};

/// Particles i and j touching (|dx|² = dist2 < (r_i + r_j)², dx = x_j − x_i),
/// pair stiffness K and dashpot η; the spring xi advanced by h (0: a probe).
template <int D>
ContactResult<D> pair_contact(const DemModel<D>& m, std::int32_t i, std::int32_t j, double K, double eta,
                              const double (&dx)[D], double dist2, const double (&vi)[D], const double (&vj)[D],
                              const double* wi, const double* wj, double h, double (&xi)[D]);

/// Particle i touching plane p with overlap δ > 0; the plane is the first
/// body (n its normal), moving at `speed` along it. Torques in torque_j.
template <int D>
ContactResult<D> plane_contact(const DemModel<D>& m, std::int32_t i, std::size_t p, double overlap, double speed,
                               const double (&vi)[D], const double* wi, double h, double (&xi)[D]);

/// One step of a rotating model (verlet, symplectic_euler, rk4 or abm4).
template <int D>
StepStatus granular_step(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w);

/// The acceleration and angular acceleration of the current state into the
/// head history slot and DemState::alpha (nothing accumulated): at build and
/// after a restart.
template <int D>
StepStatus granular_evaluate_current(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w);

}  // namespace xfdem::dem_detail
