// Element matrices of the 1D bar: the standard 2-node element, integrated over
// any part of its parent interval (so that a cut element is integrated exactly,
// one side at a time), and the paper's enriched 4x4 form (eq 25-26) for
// reference and tests.
//
// Units: ea = E·A in N, rho_a = ρ·A in kg/m, coordinates in m. Stiffness in N/m,
// mass in kg.
#pragma once
#include <Eigen/Core>

namespace xfdem::xfem {

using Mat2 = Eigen::Matrix<double, 2, 2>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Vec4 = Eigen::Matrix<double, 4, 1>;

struct PieceMatrices {
  Mat2 stiffness;  ///< ∫_a^b EA N_i' N_j' dx, N/m
  Mat2 mass;       ///< ∫_a^b ρA N_i N_j dx (consistent), kg
};

/// Matrices of the linear shape functions N0 = (x1 − x)/h, N1 = (x − x0)/h of the
/// parent element [x0, x1] (h = x1 − x0 > 0), integrated over [a, b] with
/// x0 ≤ a ≤ b ≤ x1. With [a, b] = [x0, x1] this is the standard element
/// (EA/h [1 −1; −1 1], ρAh/6 [2 1; 1 2]). The mass uses Simpson's rule, exact for
/// the quadratic integrand, and evaluates every N directly from its own end so
/// that a sliver piece loses no digits to cancellation.
PieceMatrices bar_piece_matrices(double ea, double rho_a, double x0, double x1, double a, double b);

struct EnrichedMatrices {
  Mat4 stiffness;  ///< N/m, dof order (u0, a0, u1, a1)
  Mat4 mass;       ///< kg, same order
  /// Jump of the displacement across the interface, [[u]] = jump · d (upper
  /// minus lower side), so that the tied penalty adds k · jump jumpᵀ.
  Vec4 jump;
};

/// The paper's enriched element (eq 9-10, 25-26): u = Σ N_i u_i + Σ N_i [H(φ) − H(φ_i)] a_i
/// on [x0, x1] cut at xi (x0 < xi ≤ x1, node 0 below the interface, node 1 on or
/// above it, H = 1 for φ ≥ 0). Integrals split at xi. Dof order (u0, a0, u1, a1).
/// The kernel does not assemble these directly (see phantom_transform()); they
/// are the reference the tests and docs compare against.
EnrichedMatrices enriched_element_matrices(double ea, double rho_a, double x0, double x1, double xi);

/// T with (u0, a0, u1, a1)ᵀ = T (u0, p0, u1, p1)ᵀ, where p0 = u0 + a0 is the upper
/// side's field extrapolated to node 0 and p1 = u1 − a1 the lower side's field
/// extrapolated to node 1 (the "phantom" values of Hansbo & Hansbo). Entries are
/// 0 and ±1, |det T| = 1: the kernel's unknowns span exactly the enriched space.
Mat4 phantom_transform();

}  // namespace xfdem::xfem
