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

namespace xfdem::xfem {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TipFrame tip_frame(const std::vector<Point2>& points, bool at_end) {
  const std::size_t n = points.size();
  const Point2 tip = at_end ? points[n - 1] : points[0];
  const Point2 before = at_end ? points[n - 2] : points[1];
  const double dx = tip[0] - before[0], dy = tip[1] - before[1];
  const double len = std::hypot(dx, dy);
  return TipFrame{tip, dx / len, dy / len};
}

void tip_polar(const TipFrame& f, Point2 x, double& r, double& theta) {
  const double dx = x[0] - f.origin[0], dy = x[1] - f.origin[1];
  const double lx = f.cos_a * dx + f.sin_a * dy, ly = -f.sin_a * dx + f.cos_a * dy;
  r = std::hypot(lx, ly);
  theta = std::atan2(ly, lx);
}

void branch_functions(const TipFrame& f, Point2 x, double value[4], double grad[4][2]) {
  double r = 0.0, t = 0.0;
  tip_polar(f, x, r, t);
  const double s = std::sin(0.5 * t), c = std::cos(0.5 * t), st = std::sin(t), ct = std::cos(t);
  const double sr = std::sqrt(r);
  // F_i = √r g_i(θ); g_i and dg_i/dθ.
  const double g[4] = {s, c, s * st, c * st};
  const double dg[4] = {0.5 * c, -0.5 * s, 0.5 * c * st + s * ct, -0.5 * s * st + c * ct};
  for (int i = 0; i < 4; ++i) {
    value[i] = sr * g[i];
    if (r == 0.0) {
      grad[i][0] = grad[i][1] = 0.0;
      continue;
    }
    // ∂F/∂r = g/(2√r), (1/r)∂F/∂θ = g'/√r; local Cartesian, then rotate to global.
    const double fr = g[i] / (2.0 * sr), ft = dg[i] / sr;
    const double lx = fr * ct - ft * st, ly = fr * st + ft * ct;
    grad[i][0] = f.cos_a * lx - f.sin_a * ly;
    grad[i][1] = f.sin_a * lx + f.cos_a * ly;
  }
}

WilliamsField williams_field(double k1, double k2, double mu, double kappa, double r, double t) {
  const double s = std::sin(0.5 * t), c = std::cos(0.5 * t), st = std::sin(t), ct = std::cos(t);
  const double s3 = std::sin(1.5 * t), c3 = std::cos(1.5 * t);
  const double a = 1.0 / (2.0 * mu * std::sqrt(2.0 * kPi));
  // u_i = √r g_i(θ) (Anderson, Fracture Mechanics, table 2.2).
  const double gx = a * (k1 * c * (kappa - 1.0 + 2.0 * s * s) + k2 * s * (kappa + 1.0 + 2.0 * c * c));
  const double gy = a * (k1 * s * (kappa + 1.0 - 2.0 * c * c) - k2 * c * (kappa - 1.0 - 2.0 * s * s));
  const double dgx = a * (k1 * (-0.5 * s * (kappa - 1.0 + 2.0 * s * s) + 2.0 * s * c * c) +
                          k2 * (0.5 * c * (kappa + 1.0 + 2.0 * c * c) - 2.0 * s * s * c));
  const double dgy = a * (k1 * (0.5 * c * (kappa + 1.0 - 2.0 * c * c) + 2.0 * s * s * c) -
                          k2 * (-0.5 * s * (kappa - 1.0 - 2.0 * s * s) - 2.0 * s * c * c));
  const double sr = std::sqrt(r);
  WilliamsField w{};
  w.u[0] = sr * gx;
  w.u[1] = sr * gy;
  const double g[2] = {gx, gy}, dg[2] = {dgx, dgy};
  for (int i = 0; i < 2; ++i) {
    const double fr = g[i] / (2.0 * sr), ft = dg[i] / sr;
    w.grad_u[i][0] = fr * ct - ft * st;
    w.grad_u[i][1] = fr * st + ft * ct;
  }
  const double q = 1.0 / std::sqrt(2.0 * kPi * r);
  w.stress[0] = q * (k1 * c * (1.0 - s * s3) - k2 * s * (2.0 + c * c3));
  w.stress[1] = q * (k1 * c * (1.0 + s * s3) + k2 * s * c * c3);
  w.stress[2] = q * (k1 * s * c * c3 + k2 * c * (1.0 - s * s3));
  return w;
}


double interaction_integrand(const double sig[3], const double gu[2][2], const WilliamsField& aux, const double gq[2]) {
  const double* sa = aux.stress;
  // σ_ij ε^aux_ij with engineering shear: σ_xy (∂u^aux_x/∂y + ∂u^aux_y/∂x).
  const double w = sig[0] * aux.grad_u[0][0] + sig[1] * aux.grad_u[1][1] + sig[2] * (aux.grad_u[0][1] + aux.grad_u[1][0]);
  // P_1j = σ_ij ∂u^aux_i/∂x_1 + σ^aux_ij ∂u_i/∂x_1 − w δ_1j, for j = x, y.
  const double p1x = sig[0] * aux.grad_u[0][0] + sig[2] * aux.grad_u[1][0] + sa[0] * gu[0][0] + sa[2] * gu[1][0] - w;
  const double p1y = sig[2] * aux.grad_u[0][0] + sig[1] * aux.grad_u[1][0] + sa[2] * gu[0][0] + sa[1] * gu[1][0];
  return p1x * gq[0] + p1y * gq[1];
}


int fan_from_tip(const Point2* poly, int n, Point2 tip, int splits, int side, TrianglePiece* out) {
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const Point2 p = poly[i], q = poly[(i + 1) % n];
    if (cross(sub(p, tip), sub(q, tip)) == 0.0) continue;
    for (int k = 0; k < splits; ++k) {
      // The last segment ends exactly at q (no round-off gap between pieces).
      const double s0 = static_cast<double>(k) / splits;
      const Point2 a = {p[0] + s0 * (q[0] - p[0]), p[1] + s0 * (q[1] - p[1])};
      const double s1 = static_cast<double>(k + 1) / splits;
      const Point2 b = k + 1 == splits ? q : Point2{p[0] + s1 * (q[0] - p[0]), p[1] + s1 * (q[1] - p[1])};
      out[count] = TrianglePiece{{tip, k == 0 ? p : a, b}, side};
      ++count;
    }
  }
  return count;
}

}  // namespace xfdem::xfem
