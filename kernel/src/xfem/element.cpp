#include "xfdem/xfem/element.hpp"

namespace xfdem::xfem {

PieceMatrices bar_piece_matrices(double ea, double rho_a, double x0, double x1, double a, double b) {
  const double h = x1 - x0;
  const double len = b - a;
  PieceMatrices out;
  // Constant strain: N0' = −1/h, N1' = 1/h over the piece.
  const double k = ea * len / (h * h);
  out.stiffness << k, -k, -k, k;
  // Simpson on [a, b]: exact for products of two linear functions. N0 is taken
  // from x1 and N1 from x0 so that a value near zero keeps its relative precision.
  const double m = 0.5 * (a + b);
  const double n0[3] = {(x1 - a) / h, (x1 - m) / h, (x1 - b) / h};
  const double n1[3] = {(a - x0) / h, (m - x0) / h, (b - x0) / h};
  const double w = rho_a * len / 6.0;
  auto simpson = [&](const double* f, const double* g) { return w * (f[0] * g[0] + 4.0 * f[1] * g[1] + f[2] * g[2]); };
  out.mass(0, 0) = simpson(n0, n0);
  out.mass(0, 1) = simpson(n0, n1);
  out.mass(1, 0) = out.mass(0, 1);
  out.mass(1, 1) = simpson(n1, n1);
  return out;
}

Mat4 phantom_transform() {
  // a0 = p0 − u0 (node 0 is below: H(φ0) = 0, the enrichment lives above);
  // a1 = u1 − p1 (node 1 is above: H(φ1) = 1, the enrichment lives below).
  Mat4 t = Mat4::Zero();
  t(0, 0) = 1.0;
  t(1, 0) = -1.0;
  t(1, 1) = 1.0;
  t(2, 2) = 1.0;
  t(3, 2) = 1.0;
  t(3, 3) = -1.0;
  return t;
}

EnrichedMatrices enriched_element_matrices(double ea, double rho_a, double x0, double x1, double xi) {
  // Below xi the enriched functions are (0, −N1); above they are (N0, 0). Each
  // side is a linear combination of N0, N1, so the 4x4 is assembled from the two
  // side integrals through the side's map from (u0, a0, u1, a1) to (N0, N1)
  // coefficients.
  const PieceMatrices lower = bar_piece_matrices(ea, rho_a, x0, x1, x0, xi);
  const PieceMatrices upper = bar_piece_matrices(ea, rho_a, x0, x1, xi, x1);
  Eigen::Matrix<double, 2, 4> below, above;
  below << 1, 0, 0, 0,  //
      0, 0, 1, -1;      // lower side: N0 u0 + N1 (u1 − a1)
  above << 1, 1, 0, 0,  //
      0, 0, 1, 0;       // upper side: N0 (u0 + a0) + N1 u1
  EnrichedMatrices out;
  out.stiffness = below.transpose() * lower.stiffness * below + above.transpose() * upper.stiffness * above;
  out.mass = below.transpose() * lower.mass * below + above.transpose() * upper.mass * above;
  const double h = x1 - x0;
  // [[u]](xi) = N0(xi) a0 + N1(xi) a1.
  out.jump << 0.0, (x1 - xi) / h, 0.0, (xi - x0) / h;
  return out;
}

}  // namespace xfdem::xfem
