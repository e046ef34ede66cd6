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
