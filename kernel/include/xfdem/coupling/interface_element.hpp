// Type c contact geometry: a particle against an interface element, the
// 2-node segment [x0, x1] of a continuum's boundary (paper eq 13–17, with the
// slips of shared/spec/paper-notes.md corrected). Header-only, allocation-free.
//
//   t   = (x_c − x0)·(x1 − x0) / ‖x1 − x0‖²        projection parameter (eq 15)
//   x_p = x0 + t (x1 − x0)                          contact point
//   g_n = ‖x_c − x_p‖                               gap (eq 13–14); contact while g_n < r (eq 18)
//   edge contact when δ < t < 1 − δ (eq 16), else vertex contact with the
//   nearer node (x_p is that node, all the force goes to it).
//
// In 1D a boundary is a point and the element degenerates to it:
// interface_contact_point() measures the gap along the boundary's outward
// normal, as the coupled stepper's driven plane does (a particle that has
// passed the point still gets pushed out).
#pragma once
#include <array>
#include <cmath>

namespace xfdem::coupling {

template <int D>
struct InterfaceContact {
  double t = 0;                    ///< projection parameter, clamped to the node for a vertex contact
  std::array<double, D> point{};   ///< contact point x_p on the element, m
  std::array<double, D> normal{};  ///< unit, from x_p towards the particle's centre
  double gap = 0;                  ///< g_n, m
  double overlap = 0;              ///< r − g_n, m (positive: in contact)
  bool vertex = false;             ///< vertex (node) contact rather than edge contact
  double weight[2] = {0, 0};       ///< standard shape functions N0, N1 at x_p: the share of each node
};

/// Contact of a sphere (centre, radius) with the segment [x0, x1]; `margin`
/// is the paper's δ of eq 16 (0: vertex only when the projection falls
/// outside the segment). A zero-length segment is a vertex of node 0.
template <int D>
InterfaceContact<D> interface_contact(const std::array<double, D>& centre, double radius,
                                      const std::array<double, D>& x0, const std::array<double, D>& x1,
                                      double margin = 0.0) {
  InterfaceContact<D> c;
  double len2 = 0, along = 0;
  for (int d = 0; d < D; ++d) {
    const double e = x1[d] - x0[d];
    len2 += e * e;
    along += (centre[d] - x0[d]) * e;
  }
  const double t = len2 > 0 ? along / len2 : 0.0;
  if (len2 > 0 && t > margin && t < 1.0 - margin) {
    c.t = t;
    c.weight[0] = 1.0 - t;
    c.weight[1] = t;
  } else {
    c.vertex = true;
    const int node = (len2 > 0 && t >= 0.5) ? 1 : 0;
    c.t = node;
    c.weight[node] = 1.0;
  }
  double gap2 = 0;
  for (int d = 0; d < D; ++d) {
    c.point[d] = x0[d] + c.t * (x1[d] - x0[d]);
    c.normal[d] = centre[d] - c.point[d];
    gap2 += c.normal[d] * c.normal[d];
  }
  c.gap = std::sqrt(gap2);
  if (c.gap > 0)
    for (int d = 0; d < D; ++d) c.normal[d] /= c.gap;
  c.overlap = radius - c.gap;
  return c;
}

/// The degenerate 1D element: the boundary point x0 with outward normal
/// `outward` (±1). The gap is signed along the normal, so a centre that has
/// passed the point has a gap below zero and an overlap above the radius.
inline InterfaceContact<1> interface_contact_point(double centre, double radius, double x0, double outward) {
  InterfaceContact<1> c;
  c.vertex = true;
  c.point = {x0};
  c.normal = {outward};
  c.gap = (centre - x0) * outward;
  c.overlap = radius - c.gap;
  c.weight[0] = 1.0;
  return c;
}

/// Eq 17 for an element whose nodes may be enriched: the share of a force at
/// x_p for each node's standard unknown (N_i(x_p)) and, when node i is
/// enriched, for its enriched unknown, N_i(x_p) [H(φ(x_p)) − H(φ(x_i))] with the
/// shifted Heaviside of paper-notes (H = 1 for φ ≥ 0). phi_p is the level set at
/// x_p, phi[i] at the nodes.
struct EnrichedShares {
  double standard[2];
  double enriched[2];
};
inline EnrichedShares enriched_shares(const double weight[2], double phi_p, const double phi[2]) {
  const auto heaviside = [](double phi_value) { return phi_value >= 0 ? 1.0 : 0.0; };
  EnrichedShares s{};
  for (int i = 0; i < 2; ++i) {
    s.standard[i] = weight[i];
    s.enriched[i] = weight[i] * (heaviside(phi_p) - heaviside(phi[i]));
  }
  return s;
}

}  // namespace xfdem::coupling
