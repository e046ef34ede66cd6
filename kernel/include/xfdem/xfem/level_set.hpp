// Level sets of the plate's discontinuities (cracks as polylines, circles,
// polygons) and the geometry of a cut cell, done on triangles.
//
// Sign convention, defined once here and used everywhere: a level set φ is
// positive outside a circle or polygon and on the left of a crack polyline
// (its direction from the first point to the last), and a point with φ = 0
// belongs to the positive side (side_of(0) = +1). docs/xfem2d.md states it.
#pragma once
#include <array>
#include <vector>

namespace xfdem::xfem {

using Point2 = std::array<double, 2>;

/// +1 for φ ≥ 0, −1 otherwise: the one rule for the side of a point.
inline int side_of(double phi) { return phi >= 0.0 ? 1 : -1; }

/// Signed distance to a polyline, positive on its left. At a vertex the sign
/// is that of the wedge the point lies in (left of both segments when the
/// polyline turns left there, left of either when it turns right).
double polyline_level_set(const std::vector<Point2>& points, Point2 x);

/// Signed distance to a circle, negative inside.
double circle_level_set(Point2 centre, double radius, Point2 x);

/// Signed distance to a closed polygon (either orientation), negative inside
/// (crossing-number membership; a point on an edge is at distance 0).
double polygon_level_set(const std::vector<Point2>& polygon, Point2 x);

/// The closest point of a polyline to x, and the unit direction of its segment there.
void polyline_closest(const std::vector<Point2>& points, Point2 x, Point2& closest, Point2& direction);

/// True when closed segments [a, b] and [c, d] have a point in common.
bool segments_intersect(Point2 a, Point2 b, Point2 c, Point2 d);

/// True when two non-adjacent segments of the polyline (closed: also the last
/// and first points' segment) have a point in common.
bool polyline_self_intersects(const std::vector<Point2>& points, bool closed);

/// One piece of a triangle cut by the zero of a linear level set: a triangle
/// (vertices in the order they were given, positive orientation kept) and its side.
struct TrianglePiece {
  Point2 v[3];
  int side = 1;
};

/// Splits triangle t (level set values phi at its vertices, linear between)
/// along φ = 0 into at most three triangles, each wholly on one side. A
/// piece's side is decided by membership: the sign of the vertices of the
/// original triangle it holds (the cut points have φ = 0 by construction and
/// are not asked). A triangle with no vertex strictly on one side is wholly
/// on the other (all zero: +1). Returns the number of pieces written.
int split_triangle(const Point2 t[3], const double phi[3], TrianglePiece out[3]);

}  // namespace xfdem::xfem

namespace xfdem::xfem {

// ---- Near a crack tip ------------------------------------------------------
// The building blocks of tip enrichment and of the interaction integral: the
// tip's local frame, the four branch functions and the Williams near-tip
// fields. The plate does not use them yet (tips are refused).

/// A crack tip's local frame: the origin at the tip, local x along the crack's
/// direction at the tip pointing out of the crack (θ = 0 ahead of the tip, the
/// faces at θ = ±π), local y to its left.
struct TipFrame {
  Point2 origin{};
  double cos_a = 1.0, sin_a = 0.0;  ///< the local x axis in global coordinates
};

/// The frame of the first (at_end false) or last (at_end true) point of a
/// polyline of at least two distinct points. At the first point the local x
/// axis is the reverse of the first segment's direction, so local y is then
/// on the polyline's right.
TipFrame tip_frame(const std::vector<Point2>& points, bool at_end);

/// Fans a convex polygon (either orientation) from a point `tip` inside it or
/// on its boundary: each edge split into `splits` equal segments, each giving
/// a triangle (tip, a, b) with the tip always the first vertex, so a rule
/// collapsed at the first vertex (almost-polar) cancels the 1/r of the branch
/// functions' gradients; more splits narrow the angle each triangle spans. A
/// triangle of zero area (the tip on that edge) is skipped. Each piece gets
/// `side`. Writes at most n × splits pieces; returns the number written.
int fan_from_tip(const Point2* polygon, int n, Point2 tip, int splits, int side, TrianglePiece* out);

/// Polar coordinates (r, θ) of x in the tip frame, θ in (−π, π] (atan2).
void tip_polar(const TipFrame& frame, Point2 x, double& r, double& theta);

/// The four branch functions √r{sin(θ/2), cos(θ/2), sin(θ/2) sin θ,
/// cos(θ/2) sin θ} at x and their gradients in global coordinates
/// (grad[i] = {∂F_i/∂x, ∂F_i/∂y}). At the tip itself (r = 0) the values are 0
/// and the gradients are set to 0 (they are unbounded there; a quadrature
/// point never sits on the tip).
void branch_functions(const TipFrame& frame, Point2 x, double value[4], double grad[4][2]);

/// Kolosov's constant κ: 3 − 4ν in plane strain, (3 − ν)/(1 + ν) in plane stress.
inline double kolosov(double poisson, bool plane_strain) {
  return plane_strain ? 3.0 - 4.0 * poisson : (3.0 - poisson) / (1.0 + poisson);
}

/// The Williams (leading-term) near-tip fields of a straight crack with
/// stress intensity factors k1, k2 (Pa·√m), shear modulus mu and Kolosov's
/// κ, at polar coordinates (r > 0, θ) in the tip frame, all in the tip frame:
/// displacement u, its gradient grad_u[i][j] = ∂u_i/∂x_j, and stress
/// {σ_xx, σ_yy, σ_xy}.
struct WilliamsField {
  double u[2];
  double grad_u[2][2];
  double stress[3];
};
WilliamsField williams_field(double k1, double k2, double mu, double kappa, double r, double theta);

/// The integrand of the domain form of the interaction integral (Yau et al.
/// 1980; Moran and Shih 1987; as in Moës et al. 1999), all in the tip frame:
///   [σ_ij ∂u^aux_i/∂x_1 + σ^aux_ij ∂u_i/∂x_1 − σ_ij ε^aux_ij δ_1j] ∂q/∂x_j
/// for the actual stress {σ_xx, σ_yy, σ_xy} and displacement gradient, the
/// auxiliary Williams field and the gradient of the weight q (1 at the tip, 0
/// on the domain's outer boundary). Integrated over the domain it gives
/// I = 2 (K_I K_I^aux + K_II K_II^aux)/E*, E* = E in plane stress and
/// E/(1 − ν²) in plane strain (straight traction-free faces, no body force).
double interaction_integrand(const double stress[3], const double grad_u[2][2], const WilliamsField& aux,
                             const double grad_q[2]);

}  // namespace xfdem::xfem
