// Newmark GN22, kept apart from the physics (cf. MFEM's NewmarkSolver and
// SecondOrderTimeDependentOperator::ImplicitSolve).
//
// The integrator never sees a matrix. It predicts, asks the system for the new
// acceleration through one operation, and corrects:
//
//   ũ = u_n + Δt v_n + (1/2 − β) Δt² a_n,   ṽ = v_n + (1 − γ) Δt a_n
//   a_{n+1} = system.implicit_solve(fac0 = βΔt², fac1 = γΔt, t_{n+1}, ũ, ṽ)
//   u_{n+1} = ũ + βΔt² a_{n+1},             v_{n+1} = ṽ + γΔt a_{n+1}
//
// where implicit_solve returns k solving M k + C (ṽ + fac1 k) + K (ũ + fac0 k) = f(t_{n+1})
// (the equation of motion at t_{n+1}), i.e. (M + γΔt C + βΔt² K) k = f − C ṽ − K ũ.
// That matrix is βΔt² times the usual effective stiffness M/(βΔt²) + γC/(βΔt) + K,
// so the scheme is exactly the displacement form of eq 22-24; a linear system
// factors it once, a unilateral one runs its active-set loop inside.
// The initial acceleration is implicit_solve(0, 0, t_0, u_0, v_0): M a_0 = f(0) − K u_0 − C v_0.
#pragma once
#include <cmath>

#include "xfdem/status.hpp"

namespace xfdem::xfem {

struct NewmarkScheme {
  double beta = 0.25;   ///< β
  double gamma = 0.5;   ///< γ
  double dt = 0.0;      ///< Δt, s

  [[nodiscard]] double fac0() const { return beta * dt * dt; }
  [[nodiscard]] double fac1() const { return gamma * dt; }

  /// Accepted region: γ ≥ 1/2 and β ≥ (γ + 1/2)²/4, i.e. unconditionally stable
  /// for undamped linear systems (Hughes, "The Finite Element Method", ch. 9).
  /// γ = 1/2 is second order (β = 1/4: trapezoidal, energy-conserving); γ > 1/2
  /// damps high frequencies and is first order. Conditionally stable choices
  /// (β < (γ + 1/2)²/4, e.g. central differences) are rejected: their step limit
  /// depends on the highest frequency of the mesh, which a cut sliver drives to
  /// infinity.
  /// The bound on β is checked with a relative slack of 1e-12 so that the
  /// boundary itself, written in decimal (γ = 0.6, β = 0.3025), is accepted.
  [[nodiscard]] bool unconditionally_stable() const {
    return std::isfinite(beta) && std::isfinite(gamma) && gamma >= 0.5 &&
           beta >= 0.25 * (gamma + 0.5) * (gamma + 0.5) * (1.0 - 1e-12);
  }
};

/// One step n → n+1. `System` provides
///   StepStatus implicit_solve(double fac0, double fac1, double t, const double* u_pred,
///                             const double* v_pred, double* k) const;
///   int size() const;
/// u, v, a hold step n on entry and step n+1 on return; u_pred, v_pred are
/// scratch of the same size. `weighted_a` receives Σ weights_i a_i of the
/// acceleration the step starts from ([0]) and ends with ([1]), summed inside
/// the predictor's and the corrector's loops (for weights M·1 it is the net
/// force 1ᵀMa, whose Newmark average over the step is the momentum change).
/// With `zero_if_finite`, the corrector's loop also sums 0·u + 0·v + 0·a of
/// the new state into it: 0 if every entry is finite, NaN otherwise (the
/// caller's finiteness check, without another pass over the state).
/// Returns what implicit_solve returned. No allocation.
template <class System>
StepStatus newmark_step(const NewmarkScheme& scheme, const System& system, double t_next, double* u, double* v,
                        double* a, double* u_pred, double* v_pred, const double* weights, double weighted_a[2],
                        double* zero_if_finite = nullptr) {
  const int n = system.size();
  const double dt = scheme.dt;
  const double cu = (0.5 - scheme.beta) * dt * dt;
  const double cv = (1.0 - scheme.gamma) * dt;
  double start = 0.0, end = 0.0;
  for (int i = 0; i < n; ++i) {
    u_pred[i] = u[i] + dt * v[i] + cu * a[i];
    v_pred[i] = v[i] + cv * a[i];
    start += weights[i] * a[i];
  }
  const double fac0 = scheme.fac0();
  const double fac1 = scheme.fac1();
  const StepStatus status = system.implicit_solve(fac0, fac1, t_next, u_pred, v_pred, a);
  if (zero_if_finite == nullptr) {
    for (int i = 0; i < n; ++i) {
      u[i] = u_pred[i] + fac0 * a[i];
      v[i] = v_pred[i] + fac1 * a[i];
      end += weights[i] * a[i];
    }
  } else {
    double check = 0.0;
    for (int i = 0; i < n; ++i) {
      u[i] = u_pred[i] + fac0 * a[i];
      v[i] = v_pred[i] + fac1 * a[i];
      end += weights[i] * a[i];
      check += 0.0 * u[i] + 0.0 * v[i] + 0.0 * a[i];
    }
    *zero_if_finite = check;
  }
  weighted_a[0] = start;
  weighted_a[1] = end;
  return status;
}

}  // namespace xfdem::xfem
