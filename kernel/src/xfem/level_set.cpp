#include "xfdem/xfem/level_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace xfdem::xfem {

namespace {

double cross(Point2 a, Point2 b) { return a[0] * b[1] - a[1] * b[0]; }
Point2 sub(Point2 a, Point2 b) { return {a[0] - b[0], a[1] - b[1]}; }

/// Parameter in [0, 1] of the point of segment [a, b] closest to x, and the squared distance.
double closest_on_segment(Point2 a, Point2 b, Point2 x, double& dist2) {
  const Point2 d = sub(b, a), r = sub(x, a);
  const double len2 = d[0] * d[0] + d[1] * d[1];
  const double t = len2 > 0.0 ? std::clamp((r[0] * d[0] + r[1] * d[1]) / len2, 0.0, 1.0) : 0.0;
  const double px = a[0] + t * d[0] - x[0], py = a[1] + t * d[1] - x[1];
  dist2 = px * px + py * py;
  return t;
}

int orientation(Point2 a, Point2 b, Point2 c) {
  const double v = cross(sub(b, a), sub(c, a));
  return v > 0.0 ? 1 : v < 0.0 ? -1 : 0;
}

bool on_segment(Point2 a, Point2 b, Point2 p) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= p[1] &&
         p[1] <= std::max(a[1], b[1]);
}

}  // namespace

double polyline_level_set(const std::vector<Point2>& p, Point2 x) {
  const std::size_t segments = p.size() - 1;
  double best = std::numeric_limits<double>::infinity(), best_t = 0.0;
  std::size_t best_s = 0;
  for (std::size_t s = 0; s < segments; ++s) {
    double d2 = 0.0;
    const double t = closest_on_segment(p[s], p[s + 1], x, d2);
    if (d2 < best) best = d2, best_t = t, best_s = s;
  }
  const double dist = std::sqrt(best);
  // The vertex the closest point is at, if it joins two segments.
  std::size_t vertex = 0;
  if (best_t == 0.0 && best_s > 0) vertex = best_s;
  if (best_t == 1.0 && best_s + 1 < segments) vertex = best_s + 1;
  bool left = false;
  if (vertex == 0) {
    left = cross(sub(p[best_s + 1], p[best_s]), sub(x, p[best_s])) >= 0.0;
  } else {
    const Point2 d1 = sub(p[vertex], p[vertex - 1]), d2 = sub(p[vertex + 1], p[vertex]), r = sub(x, p[vertex]);
    const bool l1 = cross(d1, r) >= 0.0, l2 = cross(d2, r) >= 0.0;
    left = cross(d1, d2) > 0.0 ? (l1 && l2) : (l1 || l2);
  }
  return left ? dist : -dist;
}

void polyline_closest(const std::vector<Point2>& p, Point2 x, Point2& closest, Point2& direction) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s + 1 < p.size(); ++s) {
    double d2 = 0.0;
    const double t = closest_on_segment(p[s], p[s + 1], x, d2);
    if (d2 < best) {
      best = d2;
      const Point2 d = sub(p[s + 1], p[s]);
      const double len = std::hypot(d[0], d[1]);
      closest = {p[s][0] + t * d[0], p[s][1] + t * d[1]};
      direction = {d[0] / len, d[1] / len};
    }
  }
}

double circle_level_set(Point2 centre, double radius, Point2 x) {
  return std::hypot(x[0] - centre[0], x[1] - centre[1]) - radius;
}

double polygon_level_set(const std::vector<Point2>& q, Point2 x) {
  const std::size_t n = q.size();
  double best = std::numeric_limits<double>::infinity();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    double d2 = 0.0;
    closest_on_segment(q[j], q[i], x, d2);
    best = std::min(best, d2);
    if ((q[i][1] > x[1]) != (q[j][1] > x[1]) &&
        x[0] < q[j][0] + (x[1] - q[j][1]) * (q[i][0] - q[j][0]) / (q[i][1] - q[j][1]))
      inside = !inside;
  }
  const double dist = std::sqrt(best);
  return inside && dist > 0.0 ? -dist : dist;
}

bool segments_intersect(Point2 a, Point2 b, Point2 c, Point2 d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
         (o4 == 0 && on_segment(c, d, b));
}

bool polyline_self_intersects(const std::vector<Point2>& p, bool closed) {
  const std::size_t n = p.size();
  const std::size_t segments = closed ? n : n - 1;
  for (std::size_t s = 0; s < segments; ++s)
    for (std::size_t r = s + 1; r < segments; ++r) {
      const bool adjacent = r == s + 1 || (closed && s == 0 && r == segments - 1);
      const Point2 a = p[s], b = p[(s + 1) % n], c = p[r], d = p[(r + 1) % n];
      if (!adjacent) {
        if (segments_intersect(a, b, c, d)) return true;
      } else {
        // Adjacent segments share a vertex; they cross only by folding back onto each other.
        const Point2 shared = r == s + 1 ? b : a;
        const Point2 u = r == s + 1 ? a : b, w = r == s + 1 ? d : c;
        if (orientation(shared, u, w) == 0 && (sub(u, shared)[0] * sub(w, shared)[0] + sub(u, shared)[1] * sub(w, shared)[1]) > 0.0)
          return true;
      }
    }
  return false;
}

int split_triangle(const Point2 t[3], const double phi[3], TrianglePiece out[3]) {
  bool pos = false, neg = false;
  for (int k = 0; k < 3; ++k) {
    pos = pos || phi[k] > 0.0;
    neg = neg || phi[k] < 0.0;
  }
  if (!pos || !neg) {
    for (int k = 0; k < 3; ++k) out[0].v[k] = t[k];
    out[0].side = neg ? -1 : 1;
    return 1;
  }
  auto cut = [&](int a, int b) {
    const double s = phi[a] / (phi[a] - phi[b]);  // phi[a], phi[b] of strictly opposite signs
    return Point2{t[a][0] + s * (t[b][0] - t[a][0]), t[a][1] + s * (t[b][1] - t[a][1])};
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if (phi[a] == 0.0) {  // the cut runs from vertex a to edge bc
      const Point2 p = cut(b, c);
      out[0] = {{t[a], t[b], p}, side_of(phi[b])};
      out[1] = {{t[a], p, t[c]}, side_of(phi[c])};
      return 2;
    }
  }
  // No vertex on the zero: the lone vertex a (its sign differs from b's and c's).
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if ((phi[a] > 0.0) != (phi[b] > 0.0) && (phi[a] > 0.0) != (phi[c] > 0.0)) {
      const Point2 p = cut(a, b), q = cut(a, c);
      out[0] = {{t[a], p, q}, side_of(phi[a])};
      out[1] = {{p, t[b], t[c]}, side_of(phi[b])};
      out[2] = {{p, t[c], q}, side_of(phi[b])};
      return 3;
    }
  }
  return 0;  // unreachable: pos and neg with no zero vertex leave one lone vertex
}

}  // namespace xfdem::xfem
