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

/// A wall that is not one of the model's planes (the coupled 2D stepper's
/// plate boundary): the contact's first body, with unit normal n (towards
/// the particle), its surface's speed along n, its contact point's velocity,
/// its spin (S components; nullptr: none), its hertz compliances (1 − ν²)/E
/// and 2(2 − ν)(1 + ν)/E (0: rigid) and the particle's arm to the contact point
/// (the plane's: its radius), for the contact point's velocity and the torque.
/// The rolling resistance is the one law of the planes and pairs
/// (rolling_torque): the torque that stops the relative rolling within `hold`
/// together with the contact's own tangential torque (capped at μ_r r |F_n|
/// as always), so that a particle whose sticking contact needs a couple (a
/// tilted normal under its weight) can rest; `hold` 0: the model's dt.
/// `inv_inertia`: the wall's 1/I for that torque (a plane's: 0), which turns
/// back under it as a pair's second particle does.
template <int D>
struct WallContact {
  double normal[D];
  double speed;
  double velocity[D];
  const double* spin;
  double inv_e, inv_g;
  double arm;
  double hold = 0;
  double inv_inertia = 0;
};

/// Particle i touching a wall with overlap δ > 0: the plane contact's law
/// (plane_contact is this with the plane's normal, speed · n and no spin),
/// the spring xi advanced by h. torque_j: the particle's torque; torque_i:
/// the couple on the wall (rolling resistance).
template <int D>
ContactResult<D> wall_contact(const DemModel<D>& m, std::int32_t i, const WallContact<D>& wall, double overlap,
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
