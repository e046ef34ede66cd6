// Stable step of each integrator for one linear contact.
//
// A contact (any of them: plane or pair) is the oscillator
//   δ'' + 2ζω δ' + ω² δ = 0,   ω² = K / m_eff,
// and every integrator here is linear on it, so one step is a matrix G(ωh)
// (for the multistep method, the companion matrix of its characteristic
// polynomial). Its spectral radius ρ decides growth. Eq 21 of the paper,
// Δt < √(2m/K), is not the limit of any of them.
//
// "Stable step" here means: the largest ωh at which one undamped contact period,
// 2π/(ωh) steps, amplifies the free response by at most 1 %:
//   ρ(ωh)^(2π/(ωh)) <= 1.01.
// For the one-step methods this sits a hair above the strict limit ρ <= 1
// (ωh = 2 for Verlet and symplectic Euler with ζ = 0, 2√2 for RK4); for ABM4 it
// is needed because PECE ABM4 has no strict limit at ζ = 0: on the imaginary
// axis ρ = 1 + 0.16 (ωh)^6 + …, a slow growth at any step. docs/dem.md tabulates
// the values; tests/dem/stability_test.cpp measures them on the real stepper.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>

#include "xfdem/dem.hpp"

namespace xfdem {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// ρ of one step of a one-step method given as a real matrix.
template <int N>
double spectral_radius(const Eigen::Matrix<double, N, N>& g) {
  Eigen::EigenSolver<Eigen::Matrix<double, N, N>> solver(g, false);
  return solver.eigenvalues().cwiseAbs().maxCoeff();
}

/// ABM4 PECE on y' = λy with z = hλ: y_{n+1} = c0 y_n + c1 y_{n-1} + c2 y_{n-2} + c3 y_{n-3}.
double abm4_radius(std::complex<double> z) {
  const std::complex<double> a = z / 24.0;
  Eigen::Matrix<std::complex<double>, 4, 4> companion = Eigen::Matrix<std::complex<double>, 4, 4>::Zero();
  companion(0, 0) = 1.0 + 28.0 * a + 495.0 * a * a;
  companion(0, 1) = -5.0 * a - 531.0 * a * a;
  companion(0, 2) = a + 333.0 * a * a;
  companion(0, 3) = -81.0 * a * a;
  companion(1, 0) = companion(2, 1) = companion(3, 2) = 1.0;
  Eigen::ComplexEigenSolver<Eigen::Matrix<std::complex<double>, 4, 4>> solver(companion, false);
  return solver.eigenvalues().cwiseAbs().maxCoeff();
}

double rk4_radius(std::complex<double> z) {
  return std::abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
}

}  // namespace

double dem_amplification(DemIntegrator integrator, double zeta, double y) {
  // Scaled so that ω = 1 and h = y.
  const double h = y;
  auto accel = [zeta](double x, double v) { return -x - 2.0 * zeta * v; };
  switch (integrator) {
    case DemIntegrator::verlet: {
      // State (x, v, a_stored); a_stored = a(x_n, v_{n-1/2}).
      Eigen::Matrix3d g;
      for (int k = 0; k < 3; ++k) {
        double s[3] = {0, 0, 0};
        s[k] = 1;
        const double v_half = s[1] + 0.5 * h * s[2];
        const double x1 = s[0] + h * v_half;
        const double a1 = accel(x1, v_half);
        g(0, k) = x1;
        g(1, k) = v_half + 0.5 * h * a1;
        g(2, k) = a1;
      }
      return spectral_radius<3>(g);
    }
    case DemIntegrator::symplectic_euler: {
      Eigen::Matrix2d g;
      for (int k = 0; k < 2; ++k) {
        double s[2] = {0, 0};
        s[k] = 1;
        const double v1 = s[1] + h * accel(s[0], s[1]);
        g(0, k) = s[0] + h * v1;
        g(1, k) = v1;
      }
      return spectral_radius<2>(g);
    }
    case DemIntegrator::rk4:
    case DemIntegrator::abm4:
    case DemIntegrator::abm4_events: {
      // The eigenvalues of the first-order system: λ = −ζ ± i√(1−ζ²) (ζ < 1,
      // the pair's moduli are equal), or −ζ ± √(ζ²−1), both real (ζ ≥ 1: an
      // overdamped mode, such as a tangential spring whose dashpot also turns
      // the particle; the faster one decides).
      auto radius = [integrator](std::complex<double> z) {
        if (integrator == DemIntegrator::rk4) return rk4_radius(z);
        // abm4_events also takes RK4 steps (after every event): the worse of the two.
        // (RK4's own limit is the larger one, so this is ABM4's in practice.)
        return std::max(abm4_radius(z), rk4_radius(z));
      };
      if (zeta < 1.0) return radius(h * std::complex<double>(-zeta, std::sqrt(1.0 - zeta * zeta)));
      const double split = std::sqrt(zeta * zeta - 1.0);
      return std::max(radius(std::complex<double>(h * (-zeta - split), 0.0)),
                      radius(std::complex<double>(h * (-zeta + split), 0.0)));
    }
  }
  return 0;
}

double dem_tangential_amplification(DemIntegrator integrator, double zeta, double y) {
  // Scaled so that ω_t = 1 and h = y: the sliding velocity u and the spring ξ,
  // u' = A(ξ, u) = −ξ − 2ζu. Verlet and symplectic Euler advance the spring
  // as their own drift (the kicked or the new velocity), so the mode is their
  // oscillator; RK4 and ABM4 read the spring advanced from ξ_n by each
  // evaluation's own offset and velocity and keep ξ_n+1 = ξ_n + h u_n+1 (the
  // first-order spring of docs/dem.md), which is a scheme of its own.
  const double h = y;
  auto accel = [zeta](double xi, double u) { return -xi - 2.0 * zeta * u; };
  auto rk4 = [&] {
    Eigen::Matrix2d g;  // state (u, ξ); the stored acceleration is A(ξ_n, u_n)
    for (int k = 0; k < 2; ++k) {
      const double u = k == 0 ? 1.0 : 0.0, xi = k == 1 ? 1.0 : 0.0;
      const double a1 = accel(xi, u);
      const double u2 = u + 0.5 * h * a1, a2 = accel(xi + 0.5 * h * u2, u2);
      const double u3 = u + 0.5 * h * a2, a3 = accel(xi + 0.5 * h * u3, u3);
      const double u4 = u + h * a3, a4 = accel(xi + h * u4, u4);
      const double u1 = u + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      g(0, k) = u1;
      g(1, k) = xi + h * u1;
    }
    return spectral_radius<2>(g);
  };
  switch (integrator) {
    case DemIntegrator::verlet:
    case DemIntegrator::symplectic_euler: return dem_amplification(integrator, zeta, y);
    case DemIntegrator::rk4: return rk4();
    case DemIntegrator::abm4:
    case DemIntegrator::abm4_events: {
      // PECE: state (u_n, ξ_n, A_n−1, A_n−2, A_n−3), A_n = A(ξ_n, u_n).
      Eigen::Matrix<double, 5, 5> g;
      for (int k = 0; k < 5; ++k) {
        double st[5] = {0, 0, 0, 0, 0};
        st[k] = 1.0;
        const double u = st[0], xi = st[1], a0 = accel(xi, u), am1 = st[2], am2 = st[3], am3 = st[4];
        const double c = h / 24.0;
        const double up = u + c * (55.0 * a0 - 59.0 * am1 + 37.0 * am2 - 9.0 * am3);
        const double ap = accel(xi + h * up, up);
        const double u1 = u + c * (9.0 * ap + 19.0 * a0 - 5.0 * am1 + am2);
        g(0, k) = u1;
        g(1, k) = xi + h * u1;
        g(2, k) = a0;
        g(3, k) = am1;
        g(4, k) = am2;
      }
      const double abm = spectral_radius<5>(g);
      // abm4_events also takes RK4 steps (after every event): the worse of the two.
      return integrator == DemIntegrator::abm4_events ? std::max(abm, rk4()) : abm;
    }
  }
  return 0;
}

namespace {

/// The largest acceptable ω·h of an amplification ρ(ω h): one undamped period,
/// 2π/(ω h) steps, grows the free response by at most 1 %.
template <class Rho>
double stable_factor(Rho rho_of) {
  auto acceptable = [&](double y) {
    const double rho = rho_of(y);
    return std::log(rho) * (2.0 * kPi / y) <= std::log(1.01);
  };
  // Scan upward for the first unacceptable ωh, then bisect.
  double lo = 1e-3, hi = lo;
  while (hi < 8.0 && acceptable(hi)) {
    lo = hi;
    hi += 1e-2;
  }
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (acceptable(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

double dem_stable_step_factor(DemIntegrator integrator, double zeta) {
  return stable_factor([&](double y) { return dem_amplification(integrator, zeta, y); });
}

double dem_tangential_stable_step_factor(DemIntegrator integrator, double zeta) {
  return stable_factor([&](double y) { return dem_tangential_amplification(integrator, zeta, y); });
}

}  // namespace xfdem
