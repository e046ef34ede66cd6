// Independent references for the bar tests: the continuum modal series of a
// fixed-free bar under a tip force, the exact solution of the semi-discrete
// system (generalised eigenproblem + Duhamel per mode), and dense copies of the
// model's matrices. Nothing here calls the kernel's solvers or integrator.
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "xfdem/bar.hpp"
#include "xfdem/plate.hpp"

namespace xfdem::test {

/// Zero-initial-condition response q(t), q'(t) of q'' + ω² q = A sin(Ωt) for t ≤ T
/// (ΩT = π), 0 after, with ω ≠ Ω.
struct ModalResponse {
  double q, dq;
};
inline ModalResponse half_sine_mode(double omega, double amplitude, double duration, double t) {
  const double big = std::numbers::pi / duration;
  const double den = omega * omega - big * big;
  auto during = [&](double s) {
    return ModalResponse{amplitude * (std::sin(big * s) - big / omega * std::sin(omega * s)) / den,
                         amplitude * big * (std::cos(big * s) - std::cos(omega * s)) / den};
  };
  if (t <= duration) return during(t);
  const ModalResponse end = during(duration);
  const double s = t - duration;
  return {end.q * std::cos(omega * s) + end.dq / omega * std::sin(omega * s),
          -end.q * omega * std::sin(omega * s) + end.dq * std::cos(omega * s)};
}

/// Tip displacement of the continuum fixed-free bar [0, L] under a half-sine tip
/// force: u(L, t) = Σ_n φ_n(L)² q_n(t), φ_n = sin(κ_n x)/√(ρAL/2),
/// κ_n = (2n − 1)π/(2L), ω_n = c κ_n. The quasi-static part Σ φ_n(L)²/ω_n² = L/(EA)
/// is summed in closed form so that the remaining terms fall off like n⁻³.
inline double continuum_tip_displacement(double length, double e, double area, double rho, double amplitude,
                                         double duration, double t, int terms = 20000) {
  const double c = std::sqrt(e / rho);
  const double big = std::numbers::pi / duration;
  const double f_now = (t <= duration) ? amplitude * std::sin(big * t) : 0.0;
  double sum = f_now * length / (e * area);  // Σ φ² F(t)/ω², exact
  for (int n = terms; n >= 1; --n) {          // small terms first
    const double omega = c * (2.0 * n - 1.0) * std::numbers::pi / (2.0 * length);
    const double phi2 = 2.0 / (rho * area * length);
    sum += phi2 * (half_sine_mode(omega, amplitude, duration, t).q - f_now / (omega * omega));
  }
  return sum;
}

inline Eigen::MatrixXd dense(const xfem::SymmetricBand& band) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(band.size(), band.size());
  for (int i = 0; i < band.size(); ++i)
    for (int j = 0; j < band.size(); ++j) m(i, j) = band.get(i, j);
  return m;
}

/// Stiffness with the interface spring (tied, or unilateral taken closed).
inline Eigen::MatrixXd dense_stiffness(const BarModel& m, bool with_interface = true) {
  Eigen::MatrixXd k = dense(m.stiffness);
  if (with_interface && m.has_interface) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(m.dofs);
    for (int i = 0; i < m.gap_terms; ++i) g(m.gap_dof[i]) += m.gap_coeff[i];
    k += m.interface_stiffness * g * g.transpose();
  }
  return k;
}

/// Exact solution of M ü + K u = e_tip F(t) (no damping, zero initial state),
/// F the half sine, by modal superposition on the generalised eigenproblem.
class SemiDiscreteExact {
 public:
  SemiDiscreteExact(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness, int tip_dof, double amplitude,
                    double duration)
      : amplitude_(amplitude), duration_(duration) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(stiffness, mass);  // φᵀ M φ = 1
    omega_ = eig.eigenvalues().cwiseSqrt();
    modes_ = eig.eigenvectors();
    participation_ = modes_.row(tip_dof).transpose();
  }
  [[nodiscard]] Eigen::VectorXd displacement(double t) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(modes_.rows());
    for (int n = 0; n < omega_.size(); ++n)
      u += modes_.col(n) * participation_(n) * half_sine_mode(omega_(n), amplitude_, duration_, t).q;
    return u;
  }

 private:
  double amplitude_, duration_;
  Eigen::VectorXd omega_, participation_;
  Eigen::MatrixXd modes_;
};

/// The paper's rod (V2): E = 3e7 Pa, A = 0.4 m², ρ = 2000 kg/m³, L = 30 m, fixed base,
/// half-sine tip load −1e4 N over 0.25 s.
inline BarDesc v2_rod(int elements = 30, double dt = 1e-3) {
  BarDesc d;
  d.length = 30.0;
  d.youngs_modulus = 3e7;
  d.area = 0.4;
  d.density = 2000.0;
  d.elements = elements;
  d.dt = dt;
  d.tip_load = BarDesc::TipLoad::half_sine;
  d.tip_amplitude = -1e4;
  d.tip_duration = 0.25;
  return d;
}

/// The bar `bd` as a plate: a column one cell wide (1 m, thickness A) on
/// rollers, plane stress with ν = 0, the bar's elements as its cells, the tip
/// load as two point forces on the top corners; the bottom fixed in y, or
/// with Lysmer dashpots where the bar's base is absorbing.
inline PlateDesc column_of(const BarDesc& bd) {
  const bool absorbing = bd.base == BarDesc::Base::absorbing;
  PlateDesc d;
  d.plane = PlateDesc::Plane::stress;
  d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 1.0, d.max[1] = bd.length;
  d.cells[0] = 1, d.cells[1] = bd.elements;
  d.thickness = bd.area;
  d.youngs_modulus = bd.youngs_modulus;
  d.poisson_ratio = 0.0;
  d.density = bd.density;
  d.dt = bd.dt, d.beta = bd.beta, d.gamma = bd.gamma;
  d.supports.push_back({PlateEdge::left, {true, false}, false});
  d.supports.push_back({PlateEdge::right, {true, false}, false});
  d.supports.push_back({PlateEdge::bottom, {false, !absorbing}, absorbing});
  for (double x : {0.0, 1.0}) {
    PlateLoad f;
    f.kind = PlateLoad::Kind::point_force;
    f.at[0] = x, f.at[1] = bd.length;
    f.value[1] = 0.5 * bd.tip_amplitude;
    f.shape = PlateLoadShape::half_sine, f.duration = bd.tip_duration;
    d.loads.push_back(f);
  }
  return d;
}

}  // namespace xfdem::test
