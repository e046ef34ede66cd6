#include "xfdem/plate.hpp"

#include <Eigen/Core>

#include "xfdem/xfem/level_set.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>

namespace xfdem {

namespace {

using Code = BuildResult::Code;

/// Bound on the stored entries of one profile matrix (8 bytes each).
constexpr double kMaxProfileEntries = 5.0e7;

bool positive_finite(double x) { return std::isfinite(x) && x > 0.0; }

BuildResult fail(const char* format, double value) { return BuildResult::failure(Code::invalid_argument, format, value); }

const char* edge_name(PlateEdge e) {
  switch (e) {
    case PlateEdge::left: return "left";
    case PlateEdge::right: return "right";
    case PlateEdge::bottom: return "bottom";
    case PlateEdge::top: return "top";
  }
  return "?";
}

bool valid_edge(PlateEdge e) { return static_cast<unsigned>(e) <= 3u; }

// Node coordinate i of nc cells on [lo, hi]: the last node is exactly hi.
double node_coord(double lo, double hi, int i, int nc) { return i == nc ? hi : lo + (hi - lo) * i / nc; }

/// The cell holding coordinate x along one axis (on a cell edge: the smaller
/// index) and the parent coordinate in it; false when x is farther than 1e-9
/// of a cell outside [lo, hi].
bool locate_axis(double lo, double hi, int nc, double x, int& cell, double& xi) {
  const double h = (hi - lo) / nc;
  if (!(x >= lo - 1e-9 * h && x <= hi + 1e-9 * h)) return false;
  cell = std::clamp(static_cast<int>(std::ceil((x - lo) / h)) - 1, 0, nc - 1);
  const double x0 = node_coord(lo, hi, cell, nc), x1 = node_coord(lo, hi, cell + 1, nc);
  xi = std::clamp(2.0 * (x - x0) / (x1 - x0) - 1.0, -1.0, 1.0);
  return true;
}

// Parent coordinates of the element's nodes, counter-clockwise from the lower left.
constexpr double kXi[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEta[4] = {-1.0, -1.0, 1.0, 1.0};

/// Natural indices of cell (i, j)'s nodes, counter-clockwise from the lower left.
void cell_nodes(int nx, int i, int j, int out[4]) {
  out[0] = j * (nx + 1) + i;
  out[1] = out[0] + 1;
  out[2] = out[1] + nx + 1;
  out[3] = out[0] + nx + 1;
}

bool all_finite(const std::vector<double>& f) {
  double acc = 0.0;
  for (double x : f) acc += 0.0 * x;
  return acc == 0.0;
}

using xfem::Point2;
using Disc = PlateDiscontinuity;

/// The level set of discontinuity k at x (crack: the polyline with its end
/// segments extended far beyond the domain, so that every point of the domain
/// has its side from a segment, never from beyond an end).
double level_set(const Disc& q, const std::vector<Point2>& extended, Point2 x) {
  switch (q.shape) {
    case Disc::Shape::polyline: return xfem::polyline_level_set(extended, x);
    case Disc::Shape::circle: return xfem::circle_level_set({q.centre[0], q.centre[1]}, q.radius, x);
    case Disc::Shape::polygon: return xfem::polygon_level_set(q.points, x);
  }
  return 0.0;
}

/// The crack's polyline with both end segments extended by the domain's diagonal.
std::vector<Point2> extended_polyline(const PlateDesc& d, const Disc& q) {
  std::vector<Point2> p = q.points;
  if (q.shape != Disc::Shape::polyline || p.size() < 2) return p;
  const double reach = 2.0 * std::hypot(d.max[0] - d.min[0], d.max[1] - d.min[1]);
  auto extend = [&](Point2 from, Point2 to) {
    const double len = std::hypot(to[0] - from[0], to[1] - from[1]);
    return Point2{to[0] + reach * (to[0] - from[0]) / len, to[1] + reach * (to[1] - from[1]) / len};
  };
  p.front() = extend(q.points[1], q.points[0]);
  p.back() = extend(q.points[q.points.size() - 2], q.points.back());
  return p;
}

/// Clips closed segment [a, b] to the box [lo, hi] (Liang-Barsky): the
/// parameter range [t0, t1] inside; false when it misses the box. `open`: the
/// open box (a segment along a face misses it).
bool clip_segment(const double lo[2], const double hi[2], Point2 a, Point2 b, bool open, double& t0, double& t1) {
  t0 = 0.0, t1 = 1.0;
  for (int c = 0; c < 2; ++c) {
    const double delta = b[c] - a[c];
    if (delta == 0.0) {
      if (open ? !(a[c] > lo[c] && a[c] < hi[c]) : !(a[c] >= lo[c] && a[c] <= hi[c])) return false;
      continue;
    }
    double l = (lo[c] - a[c]) / delta, h = (hi[c] - a[c]) / delta;
    if (l > h) std::swap(l, h);
    t0 = std::max(t0, l);
    t1 = std::min(t1, h);
  }
  return open ? t0 < t1 : t0 <= t1;
}

/// Closed segment [a, b] meets the open domain: some point of it strictly inside.
bool segment_enters_domain(const PlateDesc& d, Point2 a, Point2 b) {
  double t0 = 0.0, t1 = 0.0;
  return clip_segment(d.min, d.max, a, b, true, t0, t1);
}

/// Where the straight segment from a tip (origin) towards prev leaves the box
/// lo–hi, in the box's parent coordinates (a point within 1e-12 of an edge on
/// it); false if the segment ends inside the box (the crack bends there).
bool tip_exit(const double lo[2], const double hi[2], Point2 origin, Point2 prev, double exit[2]) {
  double t0 = 0.0, t1 = 0.0;
  if (!clip_segment(lo, hi, origin, prev, false, t0, t1) || !(t1 < 1.0)) return false;
  for (int c = 0; c < 2; ++c) {
    const double x = origin[c] + t1 * (prev[c] - origin[c]);
    double p = 2.0 * (x - lo[c]) / (hi[c] - lo[c]) - 1.0;
    if (std::fabs(std::fabs(p) - 1.0) <= 1e-12) p = p > 0.0 ? 1.0 : -1.0;  // on the cell's edge exactly
    exit[c] = std::clamp(p, -1.0, 1.0);
  }
  return true;
}

/// The polyline (not extended) meets the box: its interior (open) or its closure.
bool polyline_meets_box(const std::vector<Point2>& p, const double lo[2], const double hi[2], bool open) {
  double t0 = 0.0, t1 = 0.0;
  for (std::size_t s = 0; s + 1 < p.size(); ++s)
    if (clip_segment(lo, hi, p[s], p[s + 1], open, t0, t1)) return true;
  return false;
}

/// The void whose interior holds x (its exact level set negative: no
/// material there), as its index in d.discontinuities, or -1. The one test
/// of "in a void" (crack ends, probes, point loads, prescribed nodes).
int void_at(const PlateDesc& d, Point2 x) {
  for (std::size_t k = 0; k < d.discontinuities.size(); ++k) {
    const PlateDiscontinuity& h = d.discontinuities[k];
    if (h.kind == PlateDiscontinuity::Kind::hole && h.shape != PlateDiscontinuity::Shape::polyline &&
        level_set(h, h.points, x) < 0.0)
      return static_cast<int>(k);
  }
  return -1;
}

bool in_void(const PlateDesc& d, Point2 x) { return void_at(d, x) >= 0; }

/// The tiny-cut rule for tips: a tip within this fraction of a cell of a
/// cell's closed box touches the cell (as the tip's cell's "just behind the
/// tip" and the boundary refusal, 1e-6); a crack end within it of the
/// domain's boundary is on the boundary (not a tip).
constexpr double kTipTouch = 1e-6;

/// kTipTouch of a cell (of min(h_x, h_y)), in metres.
double tip_touch(const PlateDesc& d) {
  return kTipTouch * std::min((d.max[0] - d.min[0]) / d.cells[0], (d.max[1] - d.min[1]) / d.cells[1]);
}

/// Inside the domain by more than kTipTouch of a cell: an end nearer the
/// boundary than that is on it.
bool inside_past_touch(const PlateDesc& d, Point2 x) {
  const double tol = tip_touch(d);
  return x[0] - d.min[0] > tol && d.max[0] - x[0] > tol && x[1] - d.min[1] > tol && d.max[1] - x[1] > tol;
}

PlateCrackEnd crack_end_kind(const PlateDesc& d, const PlateDiscontinuity& q, bool at_end) {
  const Point2 end = at_end ? q.points.back() : q.points.front();
  if (!inside_past_touch(d, end)) return PlateCrackEnd::on_boundary;
  return in_void(d, end) ? PlateCrackEnd::in_void : PlateCrackEnd::tip;
}

/// A crack end inside the domain by more than kTipTouch of a cell and not
/// inside a void is a tip (an end inside a void has no material about it;
/// one within kTipTouch of a cell of the boundary is on it).
bool end_is_tip(const PlateDesc& d, const PlateDiscontinuity& q, bool at_end) {
  return crack_end_kind(d, q, at_end) == PlateCrackEnd::tip;
}

bool crack_has_tip(const PlateDesc& d, const PlateDiscontinuity& q) {
  return q.kind == PlateDiscontinuity::Kind::crack && q.points.size() >= 2 && (end_is_tip(d, q, false) || end_is_tip(d, q, true));
}

/// The crack cuts only the cells its polyline enters (not its extension):
/// some end is inside the domain (a tip, or an end inside a void; an end
/// within kTipTouch of a cell of the boundary is on it).
bool crack_is_bounded(const PlateDesc& d, const PlateDiscontinuity& q) {
  return q.kind == PlateDiscontinuity::Kind::crack && q.points.size() >= 2 &&
         (inside_past_touch(d, q.points.front()) || inside_past_touch(d, q.points.back()));
}

/// Interiors of two regions (circle or polygon) share a point.
bool regions_overlap(const Disc& a, const Disc& b) {
  auto point_of = [](const Disc& q) {
    return q.shape == Disc::Shape::circle ? Point2{q.centre[0], q.centre[1]} : q.points[0];
  };
  auto phi = [](const Disc& q, Point2 x) {
    return q.shape == Disc::Shape::circle ? xfem::circle_level_set({q.centre[0], q.centre[1]}, q.radius, x)
                                          : xfem::polygon_level_set(q.points, x);
  };
  if (a.shape == Disc::Shape::circle && b.shape == Disc::Shape::circle)
    return std::hypot(a.centre[0] - b.centre[0], a.centre[1] - b.centre[1]) < a.radius + b.radius;
  if (a.shape == Disc::Shape::polygon && b.shape == Disc::Shape::polygon) {
    const std::size_t n = a.points.size(), m = b.points.size();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < m; ++j)
        if (xfem::segments_intersect(a.points[i], a.points[(i + 1) % n], b.points[j], b.points[(j + 1) % m])) return true;
    return phi(a, point_of(b)) < 0.0 || phi(b, point_of(a)) < 0.0;
  }
  const Disc& circle = a.shape == Disc::Shape::circle ? a : b;
  const Disc& polygon = a.shape == Disc::Shape::circle ? b : a;
  // The polygon's signed distance at the centre: inside, or nearer than the radius.
  return xfem::polygon_level_set(polygon.points, {circle.centre[0], circle.centre[1]}) < circle.radius;
}

void fill_elasticity(PlateDesc::Plane plane, double e, double nu, double dm[3][3]) {
  if (plane == PlateDesc::Plane::stress) {
    const double f = e / (1.0 - nu * nu);
    dm[0][0] = dm[1][1] = f;
    dm[0][1] = dm[1][0] = f * nu;
    dm[2][2] = f * 0.5 * (1.0 - nu);
  } else {
    const double f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    dm[0][0] = dm[1][1] = f * (1.0 - nu);
    dm[0][1] = dm[1][0] = f * nu;
    dm[2][2] = f * 0.5 * (1.0 - 2.0 * nu);
  }
  dm[0][2] = dm[2][0] = dm[1][2] = dm[2][1] = 0.0;
}

const char* kind_name(Disc::Kind k) {
  return k == Disc::Kind::crack ? "crack" : k == Disc::Kind::inclusion ? "inclusion" : "void";
}

BuildResult validate_discontinuities(const PlateDesc& d) {
  for (std::size_t k = 0; k < d.discontinuities.size(); ++k) {
    const Disc& q = d.discontinuities[k];
    for (std::size_t o = 0; o < k; ++o)
      if (d.discontinuities[o].name == q.name)
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.name: '%s' is also discontinuities.%zu's",
                                    k, q.name.c_str(), o);
    for (const auto& p : q.points)
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.points: must be finite", k);
    if (q.kind == Disc::Kind::crack) {
      if (q.shape != Disc::Shape::polyline)
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.points: a crack is a polyline", k);
      if (q.points.size() < 2)
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.points: a crack needs at least two points, got %zu", k,
                                    q.points.size());
      for (std::size_t i = 0; i + 1 < q.points.size(); ++i)
        if (q.points[i] == q.points[i + 1])
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%zu.points: points %zu and %zu are the same point", k, i, i + 1);
      if (xfem::polyline_self_intersects(q.points, false))
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.points: the polyline crosses itself", k);
      bool enters = false;
      for (std::size_t i = 0; i + 1 < q.points.size(); ++i) enters = enters || segment_enters_domain(d, q.points[i], q.points[i + 1]);
      if (!enters)
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.points: the crack '%s' does not enter the domain", k,
                                    q.name.c_str());
      if (q.faces != Disc::Faces::free)
        for (int c = 0; c < 2; ++c)
          if (!positive_finite(q.stiffness[c]))
            return BuildResult::failure(Code::invalid_argument,
                                        "discontinuities.%zu.stiffness: tied and unilateral faces need [k_normal, k_tangential] "
                                        "positive and finite (Pa/m), got %g",
                                        k, q.stiffness[c]);
      if (q.faces != Disc::Faces::free && q.faces != Disc::Faces::tied && q.faces != Disc::Faces::unilateral)
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.faces: must be free, tied or unilateral", k);
      continue;
    }
    if (q.kind != Disc::Kind::inclusion && q.kind != Disc::Kind::hole)
      return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.type: must be crack, inclusion or void", k);
    if (q.shape == Disc::Shape::circle) {
      if (!std::isfinite(q.centre[0]) || !std::isfinite(q.centre[1]))
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.circle.centre: must be finite", k);
      if (!positive_finite(q.radius))
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.circle.radius: must be positive and finite (m), got %g", k,
                                    q.radius);
    } else if (q.shape == Disc::Shape::polygon) {
      if (q.points.size() < 3)
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.polygon: needs at least 3 points, got %zu",
                                    k, q.points.size());
      // A repeated vertex is not a crossing: name it (a polygon written closed
      // repeats its first vertex at the end).
      for (std::size_t i = 0, n = q.points.size(); i < n; ++i)
        if (q.points[i] == q.points[(i + 1) % n])
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%zu.polygon: vertex %zu repeats vertex %zu (a polygon closes "
                                      "itself; give each vertex once)",
                                      k, i + 1 == n ? i : i + 1, i + 1 == n ? std::size_t{0} : i);
      if (xfem::polyline_self_intersects(q.points, true))
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.polygon: crosses itself", k);
      double area = 0.0;
      for (std::size_t i = 0, j = q.points.size() - 1; i < q.points.size(); j = i++)
        area += q.points[j][0] * q.points[i][1] - q.points[i][0] * q.points[j][1];
      if (!(std::fabs(area) > 0.0))
        return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu.polygon: encloses no area", k);
    } else {
      return BuildResult::failure(Code::invalid_argument, "discontinuities.%zu: an %s is a circle or a polygon", k,
                                  kind_name(q.kind));
    }
    if (q.kind == Disc::Kind::inclusion) {
      const PlateMaterial& m = q.material;
      if (!positive_finite(m.youngs_modulus))
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.material.youngs_modulus: must be positive and finite (Pa), got %g",
                                    k, m.youngs_modulus);
      const bool strain = d.plane == PlateDesc::Plane::strain;
      if (!std::isfinite(m.poisson_ratio) || m.poisson_ratio <= -1.0 || m.poisson_ratio > 0.5 ||
          (strain && m.poisson_ratio == 0.5))
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.material.poisson_ratio: must be in (-1, 0.5%s, got %g", k,
                                    strain ? ") in plane strain" : "]", m.poisson_ratio);
      if (!positive_finite(m.density))
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu.material.density: must be positive and finite (kg/m^3), got %g",
                                    k, m.density);
    }
    // Inclusions and voids must not overlap one another.
    for (std::size_t o = 0; o < k; ++o) {
      const Disc& other = d.discontinuities[o];
      if (other.kind == Disc::Kind::crack) continue;
      if (regions_overlap(q, other))
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities.%zu: the %s '%s' overlaps the %s '%s' (discontinuities.%zu)", k,
                                    kind_name(q.kind), q.name.c_str(), kind_name(other.kind), other.name.c_str(), o);
    }
  }
  return BuildResult::success();
}

}  // namespace

// ---- element ----------------------------------------------------------------

void plate_element_matrices(double hx, double hy, const double elasticity[3][3], double thickness, double density,
                            double stiffness[64], double mass[64]) {
  using Mat8 = Eigen::Matrix<double, 8, 8>;
  Eigen::Matrix3d d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d(r, c) = elasticity[r][c];
  Mat8 k = Mat8::Zero(), m = Mat8::Zero();
  const double g = 1.0 / std::sqrt(3.0);
  const double det_j = 0.25 * hx * hy;  // weights 1
  for (int gp = 0; gp < 4; ++gp) {
    const double xi = gp == 0 || gp == 3 ? -g : g;
    const double eta = gp < 2 ? -g : g;
    Eigen::Matrix<double, 3, 8> b = Eigen::Matrix<double, 3, 8>::Zero();
    Eigen::Matrix<double, 4, 1> n;
    for (int a = 0; a < 4; ++a) {
      n(a) = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
      const double dx = 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * (2.0 / hx);
      const double dy = 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * (2.0 / hy);
      b(0, 2 * a) = dx;
      b(1, 2 * a + 1) = dy;
      b(2, 2 * a) = dy;
      b(2, 2 * a + 1) = dx;
    }
    k.noalias() += (thickness * det_j) * (b.transpose() * d * b);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 4; ++c) {
        const double mac = density * thickness * det_j * n(a) * n(c);
        m(2 * a, 2 * c) += mac;
        m(2 * a + 1, 2 * c + 1) += mac;
      }
  }
  // Exactly symmetric (the products above are, up to the order of a sum).
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) {
      stiffness[r * 8 + c] = r <= c ? k(r, c) : k(c, r);
      mass[r * 8 + c] = r <= c ? m(r, c) : m(c, r);
    }
}


// ---- cut cells: functions, sub-triangles, quadrature ---------------------------

namespace {

/// At most: 4 standard, 2 enrichment slots and 4 branch functions per node.
constexpr int kMaxCellFunctions = kPlateMaxPointFunctions;

/// The functions of one cell: standard N_a of its four nodes, then each
/// enrichment N_a ψ_k of its enriched nodes, then the branch functions
/// N_a (F_i − F_i(x_a)) of its tip-enriched nodes, with their unknowns.
struct CellView {
  int i = 0, j = 0, cell = 0;
  int en[4] = {};
  int cut = -1;       ///< the discontinuity cutting the cell, −1 none
  int material = 0;   ///< of the uncut cell / the cut cell's positive side (−1: none)
  int tip_cell = -1;  ///< the tip in the cell (−1 none): its pieces are fanned from the tip
  bool tip_functions = false;  ///< some node carries branch functions
  int touch_tip = -1;  ///< a cell other than the tip's that the tip touches (tiny-cut rule): fanned from it
  double touch_exit[2] = {2.0, 2.0};  ///< where the tip's crack leaves that cell (parent; off the cell: it does not cut it)
  int count = 0;      ///< functions
  int node[kMaxCellFunctions] = {};  ///< local node of function f
  int disc[kMaxCellFunctions] = {};  ///< −1: standard or branch; else the enriching discontinuity
  int tip[kMaxCellFunctions] = {};   ///< branch function: its tip (−1: not one)
  int branch[kMaxCellFunctions] = {};      ///< branch function: which of the four
  double branch_at_node[kMaxCellFunctions] = {};  ///< F_i(x_a), the shift
  int dof[kMaxCellFunctions][2] = {};       ///< unknown of (f, c), −1: held or absent
  double held[kMaxCellFunctions][2] = {};   ///< displacement of a held standard component (at make_view's time)
  double held_rate[2][kMaxCellFunctions][2] = {};  ///< its velocity [0] and acceleration [1] (moving ones; else 0)
  double phi[5] = {};        ///< the cutting discontinuity's level set at the nodes and the centre (cell_centre_phi)
  int second_cut = -1;         ///< a void or an inclusion cutting the cell with the crack `cut` (−1 none)
  bool second_inclusion = false;  ///< second_cut is an inclusion (its ridge on the cell's nodes, its material inside)
  double second_phi[5] = {};   ///< its level set at the nodes and the centre (cell_centre_phi)
  double x0[2] = {}, x1[2] = {};  ///< the cell's lower-left and upper-right corners, m
  bool plain = true;  ///< standard functions only, the plate's material, uncut (the fixed element matrices apply)
};

struct BasisAt {
  double n[kMaxCellFunctions], dx[kMaxCellFunctions], dy[kMaxCellFunctions];
};

xfem::TipFrame frame_of(const PlateModel::Tip& t) {
  return xfem::TipFrame{{t.origin[0], t.origin[1]}, t.cos_a, t.sin_a};
}

/// The physical point of parent point (xi, eta) of a cell.
inline Point2 physical(const CellView& v, double xi, double eta) {
  return {v.x0[0] + 0.5 * (1.0 + xi) * (v.x1[0] - v.x0[0]), v.x0[1] + 0.5 * (1.0 + eta) * (v.x1[1] - v.x0[1])};
}

inline double phi_at(const PlateModel& m, int k, int node) {
  return m.node_phi[static_cast<std::size_t>(k) * static_cast<std::size_t>(m.nodes) + static_cast<std::size_t>(node)];
}

/// A sub-triangle whose two nodes lie within this fraction of a cell (of
/// min(h_x, h_y)) of a void's or an inclusion's boundary, and whose centre
/// value is as near, is flat: see cell_centre_phi.
constexpr double kFlatCentreCells = 1e-6;

/// φ at the centre of a cell cut by discontinuity k (nodal values phi[4],
/// centre at x, cells of min size h): the mean of the nodal values (the
/// bilinear interpolant), except for a void or an inclusion when two
/// adjacent nodes and that mean all lie within kFlatCentreCells of a cell of
/// zero. There the boundary runs through both nodes and the other two sit on
/// opposite sides (a saddle, e.g. a polygon's corner at a node with one edge
/// along the cell's edge and the other cutting the cell from that corner):
/// the sub-triangle on that edge has φ_T ≈ 0 at all three corners, so the
/// mean's round-off sign put the whole sub-triangle (a quarter of the cell)
/// in or out of the material, and a shift of 1e-12 of a cell changed the
/// energy by percents. The exact level set at the centre (snapped to 0 within
/// 1e-9 of a cell, as nodes are) does not depend on such a shift. Cracks keep
/// the mean (their level set is linear in a cell away from a kink, and the
/// mean is then the exact value). docs/xfem2d.md, "Through nodes at a slant".
/// Beyond kFlatCentreCells the mean comes back: the switch is there, where
/// the boundary is that far off the nodes, no longer at a round-off's sign.
/// `flat` (if given) tells whether the exact value was taken.
double cell_centre_phi(const PlateDesc& d, int k, const double phi[4], Point2 x, double h, bool* flat_out = nullptr) {
  const double mean = 0.25 * (phi[0] + phi[1] + phi[2] + phi[3]);
  if (flat_out != nullptr) *flat_out = false;
  const PlateDiscontinuity& q = d.discontinuities[static_cast<std::size_t>(k)];
  if (q.kind == PlateDiscontinuity::Kind::crack) return mean;
  const double flat = kFlatCentreCells * h;
  if (!(std::fabs(mean) <= flat)) return mean;
  bool edge_on_zero = false;
  for (int a = 0; a < 4; ++a) edge_on_zero = edge_on_zero || (std::fabs(phi[a]) <= flat && std::fabs(phi[(a + 1) % 4]) <= flat);
  if (!edge_on_zero) return mean;
  if (flat_out != nullptr) *flat_out = true;
  const double exact = q.shape == PlateDiscontinuity::Shape::circle
                           ? xfem::circle_level_set({q.centre[0], q.centre[1]}, q.radius, x)
                           : xfem::polygon_level_set(q.points, x);
  return std::fabs(exact) <= 1e-9 * h ? 0.0 : exact;
}

/// A crack's Heaviside function whose other side, within its support, is a
/// corner cut off around one node within this fraction of a cell (of
/// min(h_x, h_y)) of the crack gets no unknown (docs/xfem2d.md, "Tiny cuts").
constexpr double kCornerSliverCells = 1e-6;

/// A node within this fraction of a cell (of min(h_x, h_y)) of a crack
/// without a tip is on it (φ = 0; docs/xfem2d.md, "Edge slivers").
constexpr double kCrackOnNodeCells = 1e-6;

/// A crack segment within kCrackOnNodeCells of a cell of an interior node row
/// (column) at both ends is put on it (docs/xfem2d.md, "Edge slivers"): its
/// ends take the row's coordinate, so the row's level set is 0 exactly and
/// the tip, its cell and the cells behind it agree on where the crack is.
/// Left alone, a crack 1e-16 … 1e-8 of a cell off a row cuts a strip that
/// thin off the cells along it, whose Heaviside unknowns the solve's
/// round-off sets (unilateral faces then chatter or gain energy). The crack
/// moves by at most kCrackOnNodeCells of a cell.
void put_cracks_on_near_node_lines(PlateDesc& d) {
  const double tol = kCrackOnNodeCells * std::min((d.max[0] - d.min[0]) / d.cells[0], (d.max[1] - d.min[1]) / d.cells[1]);
  for (PlateDiscontinuity& q : d.discontinuities) {
    if (q.kind != PlateDiscontinuity::Kind::crack || q.shape != PlateDiscontinuity::Shape::polyline) continue;
    for (int c = 0; c < 2; ++c) {
      const int n = d.cells[c];
      const double h = (d.max[c] - d.min[c]) / n;
      for (std::size_t s = 0; s + 1 < q.points.size(); ++s) {
        Point2& a = q.points[s];
        Point2& b = q.points[s + 1];
        if (std::fabs(a[1 - c] - b[1 - c]) <= tol) continue;  // not along the line: a crossing, left to the corner rule
        const double line_index = std::round((a[c] - d.min[c]) / h);
        if (!(line_index >= 1.0 && line_index <= n - 1.0)) continue;  // the domain's own edges are not moved onto
        const double line = node_coord(d.min[c], d.max[c], static_cast<int>(line_index), n);
        if (std::fabs(a[c] - line) <= tol && std::fabs(b[c] - line) <= tol) a[c] = b[c] = line;
      }
    }
  }
}

/// A crack end inside the domain within kTipTouch of a cell of its boundary
/// is on the boundary (docs/xfem2d.md, "Tiny cuts (the rule)"): it takes
/// the boundary's coordinate (both at a corner), so that the end is no tip
/// and the crack is the one that ends on the boundary to the bit, wherever
/// in that band it was written. Left alone, an end 1e-13 inside was a tip
/// and the answer jumped (an edge crack's energy by ×2.3). An end whose
/// neighbouring point is in the same band (a segment along the boundary) is
/// left alone. The end moves by at most kTipTouch of a cell.
void put_crack_ends_on_near_boundary(PlateDesc& d) {
  const double tol = tip_touch(d);
  for (PlateDiscontinuity& q : d.discontinuities) {
    if (q.kind != PlateDiscontinuity::Kind::crack || q.shape != PlateDiscontinuity::Shape::polyline ||
        q.points.size() < 2)
      continue;
    for (const bool at_end : {false, true}) {
      Point2& end = at_end ? q.points.back() : q.points.front();
      const Point2& next = at_end ? q.points[q.points.size() - 2] : q.points[1];
      if (!(end[0] >= d.min[0] && end[0] <= d.max[0] && end[1] >= d.min[1] && end[1] <= d.max[1])) continue;
      for (int c = 0; c < 2; ++c) {
        if (end[c] - d.min[c] <= tol && next[c] - d.min[c] > tol) end[c] = d.min[c];
        if (d.max[c] - end[c] <= tol && d.max[c] - next[c] > tol) end[c] = d.max[c];
      }
    }
  }
}

/// Side of a cell that discontinuity k does not cut: − when some node is
/// negative by more than kCornerSliverCells of a cell. A node nearer the
/// zero than that does not decide: a crack with a tip (whose level set is not
/// put to 0 at nodes) through a node leaves there a round-off sign, and a
/// cell that the crack only touches at that corner would take that sign's
/// side while all its material lies on its other nodes' side: its Heaviside
/// values then disagreed with those of the cut cells beside it, and a
/// uniform stress along a crack through nodes came out 30 % wrong
/// (docs/xfem2d.md, "Through nodes at a slant"). When every node is that
/// near, the strict signs decide.
int uncut_side(const PlateModel& m, int k, const int en[4]) {
  const double near = kCornerSliverCells * std::min(m.cell_size[0], m.cell_size[1]);
  bool far = false, far_negative = false, negative = false;
  for (int a = 0; a < 4; ++a) {
    const double p = phi_at(m, k, en[a]);
    negative = negative || p < 0.0;
    if (std::fabs(p) > near) far = true, far_negative = far_negative || p < 0.0;
  }
  return (far ? far_negative : negative) ? -1 : 1;
}

/// (kTipTouch: the tiny-cut rule for tips, above.)
bool tip_touches(const PlateModel& m, const PlateModel::Tip& t, const double lo[2], const double hi[2]) {
  const double tol = kTipTouch * std::min(m.cell_size[0], m.cell_size[1]);
  return t.origin[0] >= lo[0] - tol && t.origin[0] <= hi[0] + tol && t.origin[1] >= lo[1] - tol &&
         t.origin[1] <= hi[1] + tol;
}

/// Which field a coefficient is read from.
enum class Field : std::uint8_t { displacement, velocity, acceleration };

/// The displacement of moving held component h at t (its amplitude times its shape there).
inline double moving_displacement(const PlateModel& m, std::size_t h, double t) {
  return m.moving_amplitude[h] * plate_prescribed_shape(m, m.moving_prescribed[h], t);
}

/// The displacement of held natural component k at t.
inline double held_displacement(const PlateModel& m, std::size_t k, double t) {
  if (!m.node_moving.empty()) {
    const int h = m.node_moving[k];
    if (h >= 0) return moving_displacement(m, static_cast<std::size_t>(h), t);
  }
  return m.node_held[k];
}

/// The cell's functions and unknowns; held displacements at `time`, and with
/// `rates` the moving held components' velocity and acceleration from it.
void make_view(const PlateModel& m, int i, int j, CellView& v, double time = 0.0, const PlateState* rates = nullptr) {
  const int nx = m.desc.cells[0];
  v.i = i, v.j = j, v.cell = j * nx + i;
  cell_nodes(nx, i, j, v.en);
  const bool any = !m.cell_cut_by.empty();
  v.cut = any ? m.cell_cut_by[static_cast<std::size_t>(v.cell)] : -1;
  v.material = any ? m.cell_material[static_cast<std::size_t>(v.cell)] : 0;
  const PlateDesc& d = m.desc;
  v.x0[0] = node_coord(d.min[0], d.max[0], i, nx), v.x1[0] = node_coord(d.min[0], d.max[0], i + 1, nx);
  v.x0[1] = node_coord(d.min[1], d.max[1], j, d.cells[1]), v.x1[1] = node_coord(d.min[1], d.max[1], j + 1, d.cells[1]);
  v.count = 0;
  v.tip_cell = -1;
  v.tip_functions = false;
  v.touch_tip = -1;
  v.touch_exit[0] = v.touch_exit[1] = 2.0;
  for (int a = 0; a < 4; ++a) {
    const int f = v.count++;
    v.node[f] = a, v.disc[f] = -1, v.tip[f] = -1;
    for (int c = 0; c < 2; ++c) {
      const auto k = static_cast<std::size_t>(2 * v.en[a] + c);
      v.dof[f][c] = m.node_dof[k];
      v.held[f][c] = held_displacement(m, k, time);
      const int h = m.node_moving.empty() ? -1 : m.node_moving[k];
      v.held_rate[0][f][c] = h >= 0 && rates != nullptr ? rates->held_v[static_cast<std::size_t>(h)] : 0.0;
      v.held_rate[1][f][c] = h >= 0 && rates != nullptr ? rates->held_a[static_cast<std::size_t>(h)] : 0.0;
    }
  }
  if (any)
    for (int a = 0; a < 4; ++a)
      for (int s = 0; s < 2; ++s) {
        const int k = m.node_enrichment[static_cast<std::size_t>(2 * v.en[a] + s)];
        if (k < 0) continue;
        const int f = v.count++;
        v.node[f] = a, v.disc[f] = k, v.tip[f] = -1;
        for (int c = 0; c < 2; ++c) {
          v.dof[f][c] = m.enriched_dof[static_cast<std::size_t>(2 * (2 * v.en[a] + s) + c)];
          v.held[f][c] = 0.0;
          v.held_rate[0][f][c] = v.held_rate[1][f][c] = 0.0;
        }
      }
  if (!m.tips.empty()) {
    v.tip_cell = m.cell_tip[static_cast<std::size_t>(v.cell)];
    for (int a = 0; a < 4; ++a) {
      const int t = m.node_tip[static_cast<std::size_t>(v.en[a])];
      if (t < 0) continue;
      v.tip_functions = true;
      const Point2 xa = physical(v, kXi[a], kEta[a]);
      double value[4], grad[4][2];
      xfem::branch_functions(frame_of(m.tips[static_cast<std::size_t>(t)]), xa, value, grad);
      for (int b = 0; b < 4; ++b) {
        const int f = v.count++;
        v.node[f] = a, v.disc[f] = -1, v.tip[f] = t, v.branch[f] = b, v.branch_at_node[f] = value[b];
        for (int c = 0; c < 2; ++c) {
          v.dof[f][c] = m.tip_dof[static_cast<std::size_t>(8 * v.en[a] + 2 * b + c)];
          v.held[f][c] = 0.0;
          v.held_rate[0][f][c] = v.held_rate[1][f][c] = 0.0;
        }
      }
      const PlateModel::Tip& tip = m.tips[static_cast<std::size_t>(t)];
      if (v.tip_cell < 0 && (v.cut < 0 || v.cut == tip.crack) && tip_touches(m, tip, v.x0, v.x1)) v.touch_tip = t;
    }
  }
  v.plain = v.count == 4 && v.cut < 0 && v.material == 0;
  const Point2 centre = {0.5 * (v.x0[0] + v.x1[0]), 0.5 * (v.x0[1] + v.x1[1])};
  const double h = std::min(m.cell_size[0], m.cell_size[1]);
  if (v.cut >= 0) {
    for (int a = 0; a < 4; ++a) v.phi[a] = phi_at(m, v.cut, v.en[a]);
    v.phi[4] = cell_centre_phi(d, v.cut, v.phi, centre, h);
  }
  v.second_cut = m.cell_second_cut.empty() ? -1 : m.cell_second_cut[static_cast<std::size_t>(v.cell)];
  v.second_inclusion = v.second_cut >= 0 && d.discontinuities[static_cast<std::size_t>(v.second_cut)].kind ==
                                                 PlateDiscontinuity::Kind::inclusion;
  if (v.second_cut >= 0) {
    for (int a = 0; a < 4; ++a) v.second_phi[a] = phi_at(m, v.second_cut, v.en[a]);
    v.second_phi[4] = cell_centre_phi(d, v.second_cut, v.second_phi, centre, h);
  }
  if (v.touch_tip >= 0 && v.cut >= 0) {
    // The tip's crack cuts the cell it touches: where its straight tip segment
    // leaves the cell, as for the tip's cell (a bend inside: the plain split).
    const PlateModel::Tip& t = m.tips[static_cast<std::size_t>(v.touch_tip)];
    const std::vector<Point2>& pts = d.discontinuities[static_cast<std::size_t>(t.crack)].points;
    const Point2 origin = {t.origin[0], t.origin[1]};
    const Point2 prev = t.at_end ? pts[pts.size() - 2] : pts[1];
    if (!tip_exit(v.x0, v.x1, origin, prev, v.touch_exit)) v.touch_tip = -1;
  }
}

/// Sub-triangle t of a cell (parent coordinates): nodes t, t + 1 and the centre.
inline void sub_triangle(int t, Point2 out[3]) {
  out[0] = {kXi[t], kEta[t]};
  out[1] = {kXi[(t + 1) % 4], kEta[(t + 1) % 4]};
  out[2] = {0.0, 0.0};
}

/// The sub-triangle holding parent point (xi, eta).
inline int triangle_of(double xi, double eta) {
  if (eta <= -std::fabs(xi)) return 0;
  if (xi >= std::fabs(eta)) return 1;
  if (eta >= std::fabs(xi)) return 2;
  return 3;
}

/// The linear function on sub-triangle t with values f0, f1 at its nodes and
/// fc at the centre: value and parent-coordinate gradient at (xi, eta).
void linear_on_triangle(int t, double f0, double f1, double fc, double xi, double eta, double& value, double& g_xi,
                        double& g_eta) {
  const int a = t, b = (t + 1) % 4;
  const double x0 = kXi[a], y0 = kEta[a], x1 = kXi[b], y1 = kEta[b];
  const double r0 = f0 - fc, r1 = f1 - fc;
  const double det = x0 * y1 - x1 * y0;
  g_xi = (r0 * y1 - r1 * y0) / det;
  g_eta = (x0 * r1 - x1 * r0) / det;
  value = fc + g_xi * xi + g_eta * eta;
}

/// The cutting level set interpolated linearly on sub-triangle t (φ_T).
void phi_on_triangle(const CellView& v, int t, double xi, double eta, double& value, double& g_xi, double& g_eta) {
  linear_on_triangle(t, v.phi[t], v.phi[(t + 1) % 4], v.phi[4], xi, eta, value, g_xi, g_eta);
}

/// The cut side of a point of a cut cell (the one rule: φ = 0 counts as +).
int point_side(const CellView& v, double xi, double eta) {
  if (v.cut < 0) return 1;
  double value = 0.0, gx = 0.0, gy = 0.0;
  phi_on_triangle(v, triangle_of(xi, eta), xi, eta, value, gx, gy);
  return xfem::side_of(value);
}

/// The second discontinuity's level set interpolated linearly on sub-triangle t.
void second_phi_on_triangle(const CellView& v, int t, double xi, double eta, double& value, double& g_xi, double& g_eta) {
  linear_on_triangle(t, v.second_phi[t], v.second_phi[(t + 1) % 4], v.second_phi[4], xi, eta, value, g_xi, g_eta);
}

/// Every function of the cell and its gradient at (xi, eta), which lies in
/// sub-triangle `tri` on side `side` of the cutting discontinuity (by
/// membership, from the caller).
void evaluate(const PlateModel& m, const CellView& v, double xi, double eta, int tri, int side, BasisAt& out) {
  const double sx = 2.0 / m.cell_size[0], sy = 2.0 / m.cell_size[1];
  double n[4], dx[4], dy[4];
  for (int a = 0; a < 4; ++a) {
    n[a] = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
    dx[a] = 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * sx;
    dy[a] = 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * sy;
  }
  // The ridge of the cutting inclusion (Moës et al. 2003): ψ = Σ N_b |φ_b| − |φ_T|,
  // |φ_T| = side·φ_T on the piece.
  double ridge = 0.0, ridge_dx = 0.0, ridge_dy = 0.0;
  if (v.cut >= 0 && m.desc.discontinuities[static_cast<std::size_t>(v.cut)].kind == PlateDiscontinuity::Kind::inclusion) {
    double value = 0.0, gx = 0.0, gy = 0.0;
    phi_on_triangle(v, tri, xi, eta, value, gx, gy);
    ridge = -side * value;
    ridge_dx = -side * gx * sx;
    ridge_dy = -side * gy * sy;
    for (int b = 0; b < 4; ++b) {
      const double abs_phi = std::fabs(v.phi[b]);
      ridge += n[b] * abs_phi;
      ridge_dx += dx[b] * abs_phi;
      ridge_dy += dy[b] * abs_phi;
    }
  }
  // The ridge of an inclusion cutting the cell with a crack: the same, on the
  // point's side of the inclusion (by position: the ridge is continuous
  // across its zero, and a quadrature point off the zero by round-off only
  // carries a weight of that size).
  double ridge2 = 0.0, ridge2_dx = 0.0, ridge2_dy = 0.0;
  if (v.second_inclusion) {
    double value = 0.0, gx = 0.0, gy = 0.0;
    second_phi_on_triangle(v, tri, xi, eta, value, gx, gy);
    const double side2 = xfem::side_of(value);
    ridge2 = -side2 * value;
    ridge2_dx = -side2 * gx * sx;
    ridge2_dy = -side2 * gy * sy;
    for (int b = 0; b < 4; ++b) {
      const double abs_phi = std::fabs(v.second_phi[b]);
      ridge2 += n[b] * abs_phi;
      ridge2_dx += dx[b] * abs_phi;
      ridge2_dy += dy[b] * abs_phi;
    }
  }
  // The branch functions of the (at most four) tips of the cell's nodes at this point.
  int tips_here[4] = {-1, -1, -1, -1};
  double tip_value[4][4], tip_grad[4][4][2];
  if (v.tip_functions) {
    const Point2 x = physical(v, xi, eta);
    for (int f = 0; f < v.count; ++f) {
      if (v.tip[f] < 0) continue;
      int slot = 0;
      while (tips_here[slot] >= 0 && tips_here[slot] != v.tip[f]) ++slot;
      if (tips_here[slot] >= 0) continue;
      tips_here[slot] = v.tip[f];
      const PlateModel::Tip& t = m.tips[static_cast<std::size_t>(v.tip[f])];
      Point2 at = x;
      if (v.cut == t.crack) {
        // A point on the crack's line behind the tip (a face's point: a piece's
        // corner, the contact boundary's) takes its own side's limit θ = ±π,
        // not the one the round-off of its local y picks: moved, if need be,
        // to local y = ±max(|y|, 1e-15 of a cell), on its side.
        const double ox = x[0] - t.origin[0], oy = x[1] - t.origin[1];
        const double lx = t.cos_a * ox + t.sin_a * oy, ly = -t.sin_a * ox + t.cos_a * oy;
        const double h = std::min(m.cell_size[0], m.cell_size[1]);
        const double want = (side > 0) == t.at_end ? 1.0 : -1.0;  // the sign of local y on this side
        if (lx < 0.0 && std::fabs(ly) <= 1e-12 * h && !(ly * want > 0.0)) {
          const double shift = want * std::max(std::fabs(ly), 1e-15 * h) - ly;
          at = {x[0] - t.sin_a * shift, x[1] + t.cos_a * shift};
        }
      }
      xfem::branch_functions(frame_of(t), at, tip_value[slot], tip_grad[slot]);
    }
  }
  for (int f = 0; f < v.count; ++f) {
    const int a = v.node[f], k = v.disc[f];
    if (v.tip[f] >= 0) {
      // Shifted branch function: N_a (F_i − F_i(x_a)).
      int slot = 0;
      while (tips_here[slot] != v.tip[f]) ++slot;
      const int b = v.branch[f];
      const double psi = tip_value[slot][b] - v.branch_at_node[f];
      out.n[f] = n[a] * psi;
      out.dx[f] = dx[a] * psi + n[a] * tip_grad[slot][b][0];
      out.dy[f] = dy[a] * psi + n[a] * tip_grad[slot][b][1];
      continue;
    }
    if (k < 0) {
      out.n[f] = n[a], out.dx[f] = dx[a], out.dy[f] = dy[a];
      continue;
    }
    if (m.desc.discontinuities[static_cast<std::size_t>(k)].kind == PlateDiscontinuity::Kind::crack) {
      // Shifted Heaviside: ψ = H(x) − H(x_a), constant on each side.
      const int h = k == v.cut ? side : uncut_side(m, k, v.en);
      const double psi = static_cast<double>(h - xfem::side_of(phi_at(m, k, v.en[a])));
      out.n[f] = n[a] * psi, out.dx[f] = dx[a] * psi, out.dy[f] = dy[a] * psi;
    } else if (k == v.second_cut) {
      out.n[f] = n[a] * ridge2;
      out.dx[f] = dx[a] * ridge2 + n[a] * ridge2_dx;
      out.dy[f] = dy[a] * ridge2 + n[a] * ridge2_dy;
    } else if (k == v.cut) {
      out.n[f] = n[a] * ridge;
      out.dx[f] = dx[a] * ridge + n[a] * ridge_dx;
      out.dy[f] = dy[a] * ridge + n[a] * ridge_dy;
    } else {
      out.n[f] = out.dx[f] = out.dy[f] = 0.0;  // the ridge vanishes outside the cells it cuts
    }
  }
}

int material_of(const PlateModel& m, const CellView& v, int side);

/// The side a probe point takes: its own, except in the void part of a cell
/// cut by a hole, where it takes the material's (the cell's functions
/// extended): the exact boundary, by which a probe is checked, and the
/// piecewise-linear one of the cut cell differ by O(h²).
int material_side(const PlateModel& m, const CellView& v, double xi, double eta) {
  const int side = point_side(v, xi, eta);
  return material_of(m, v, side) < 0 && v.cut >= 0 ? 1 : side;
}

/// The material of a point of the cell on side `side` (−1: none, a hole).
int material_of(const PlateModel& m, const CellView& v, int side) {
  if (v.cut < 0 || side > 0) return v.material;
  switch (m.desc.discontinuities[static_cast<std::size_t>(v.cut)].kind) {
    case PlateDiscontinuity::Kind::inclusion: return 1 + v.cut;
    case PlateDiscontinuity::Kind::hole: return -1;
    case PlateDiscontinuity::Kind::crack: break;
  }
  return v.material;
}

/// The material at point (xi, eta) of the cell on side `side` of its cut:
/// material_of, but inside an inclusion that cuts the cell with a crack, the
/// inclusion's.
int material_at(const PlateModel& m, const CellView& v, double xi, double eta, int side) {
  if (v.second_inclusion) {
    double value = 0.0, gx = 0.0, gy = 0.0;
    second_phi_on_triangle(v, triangle_of(xi, eta), xi, eta, value, gx, gy);
    if (xfem::side_of(value) < 0) return 1 + v.second_cut;
  }
  return material_of(m, v, side);
}

// Gauss-Legendre, 5 points on [0, 1] (exact to degree 9).
constexpr double kGl5x[5] = {0.5 * (1.0 - 0.9061798459386640), 0.5 * (1.0 - 0.5384693101056831), 0.5,
                             0.5 * (1.0 + 0.5384693101056831), 0.5 * (1.0 + 0.9061798459386640)};
constexpr double kGl5w[5] = {0.5 * 0.2369268850561891, 0.5 * 0.4786286704993665, 0.5 * 0.5688888888888889,
                             0.5 * 0.4786286704993665, 0.5 * 0.2369268850561891};

/// Splits per edge of the tip cell's fan (bounds the angle of its triangles).
constexpr int kTipSplits = 3;
constexpr int kMaxPieces = 16;  // ≥ 4 × 3 split sub-triangles and 5 edges × kTipSplits fan triangles

/// The point a cell touched by a tip is fanned from (parent coordinates): the
/// tip, put on the cell's edge when within 1e-6 of a cell of it (kTipTouch)
/// or outside. A fan's triangles to the edge a tip sits ε from are slivers
/// whose 5-point rule keeps a point at distance ~ε below the tip, where
/// |∇F|² ~ 1/r: a sliver of area O(ε) would add O(1) to the stiffness, and
/// the answer would jump as ε → 0. On the edge, they vanish, and the fans of
/// the cells on both sides of a node row meet the same limit from either side.
Point2 fan_centre(const CellView& v, const PlateModel::Tip& t) {
  Point2 p{};
  for (int c = 0; c < 2; ++c) {
    const double x = 2.0 * (t.origin[c] - v.x0[c]) / (v.x1[c] - v.x0[c]) - 1.0;
    p[c] = std::fabs(x) >= 1.0 - 2.0 * kTipTouch ? (x > 0.0 ? 1.0 : -1.0) : x;
  }
  return p;
}

/// The triangles a cut cell, a tip cell or a cell with branch functions is
/// integrated on (parent coordinates), each with its side and sub-triangle.
/// A tip cell: fanned from the tip, its polygon through the point where the
/// crack leaves it, so that every triangle lies on one side of the (straight
/// in the cell) crack, the side of its centroid in the tip frame. Otherwise
/// the four sub-triangles, split along the cutting level set when cut.
int triangle_pieces(const PlateModel& m, const CellView& v, xfem::TrianglePiece out[kMaxPieces], int triangle[kMaxPieces]) {
  if (v.tip_cell >= 0 || v.touch_tip >= 0) {
    // A cell the tip touches but is not in (on or within 1e-6 of a cell of
    // its edge or corner) is fanned as the tip's own cell, from its point
    // nearest the tip: the limit of the tip cell's fan as the tip crosses
    // into it, so the answer does not jump with the side of the edge the tip
    // is on.
    const PlateModel::Tip& t = m.tips[static_cast<std::size_t>(v.tip_cell >= 0 ? v.tip_cell : v.touch_tip)];
    const Point2 tip = fan_centre(v, t);
    const Point2 exit = v.tip_cell >= 0 ? Point2{t.exit[0], t.exit[1]} : Point2{v.touch_exit[0], v.touch_exit[1]};
    Point2 poly[5];
    int n = 0;
    for (int a = 0; a < 4; ++a) {
      poly[n++] = {kXi[a], kEta[a]};
      const int b = (a + 1) % 4;
      // Edge a runs along ξ (a = 0, 2) or η (a = 1, 3); the exit point strictly between its corners.
      const bool along_xi = a % 2 == 0;
      const bool on_edge = along_xi ? exit[1] == kEta[a] && exit[0] > std::min(kXi[a], kXi[b]) && exit[0] < std::max(kXi[a], kXi[b])
                                    : exit[0] == kXi[a] && exit[1] > std::min(kEta[a], kEta[b]) && exit[1] < std::max(kEta[a], kEta[b]);
      if (on_edge) poly[n++] = exit;
    }
    const int count = xfem::fan_from_tip(poly, n, tip, kTipSplits, 1, out);
    for (int p = 0; p < count; ++p) {
      const double cx = (out[p].v[0][0] + out[p].v[1][0] + out[p].v[2][0]) / 3.0;
      const double cy = (out[p].v[0][1] + out[p].v[1][1] + out[p].v[2][1]) / 3.0;
      const Point2 x = physical(v, cx, cy);
      const double ly = -t.sin_a * (x[0] - t.origin[0]) + t.cos_a * (x[1] - t.origin[1]);
      // Local y is the positive (left) side at a last point, the negative at a first.
      out[p].side = (ly > 0.0) == t.at_end ? 1 : -1;
      triangle[p] = triangle_of(cx, cy);
    }
    return count;
  }
  int count = 0;
  for (int t = 0; t < 4; ++t) {
    Point2 tri[3];
    sub_triangle(t, tri);
    const double phi[3] = {v.cut >= 0 ? v.phi[t] : 1.0, v.cut >= 0 ? v.phi[(t + 1) % 4] : 1.0, v.cut >= 0 ? v.phi[4] : 1.0};
    const int made = xfem::split_triangle(tri, phi, out + count);
    for (int p = 0; p < made; ++p) triangle[count + p] = t;
    count += made;
  }
  return count;
}

/// The parts of a piece (side `piece.side` of the crack) of sub-triangle
/// `tri` of a cell a void or an inclusion cuts too: the piece split along
/// that one's level set, linear on the sub-triangle (values second_phi at its
/// nodes and the centre), each part's side of it in `second_side` (by
/// membership). Each part keeps the piece's crack side. Returns the number
/// of parts written (1–3).
int second_parts(const double second_phi[5], int tri, const xfem::TrianglePiece& piece, xfem::TrianglePiece out[3],
                 int second_side[3]) {
  double phi[3];
  const int b = (tri + 1) % 4;
  for (int c = 0; c < 3; ++c) {
    const Point2 x = piece.v[c];
    // The sub-triangle's own corners take their values exactly (the sign decides membership).
    if (x[0] == kXi[tri] && x[1] == kEta[tri]) {
      phi[c] = second_phi[tri];
    } else if (x[0] == kXi[b] && x[1] == kEta[b]) {
      phi[c] = second_phi[b];
    } else if (x[0] == 0.0 && x[1] == 0.0) {
      phi[c] = second_phi[4];
    } else {
      double gx = 0.0, gy = 0.0;
      linear_on_triangle(tri, second_phi[tri], second_phi[b], second_phi[4], x[0], x[1], phi[c], gx, gy);
    }
  }
  const int made = xfem::split_triangle(piece.v, phi, out);
  for (int p = 0; p < made; ++p) {
    second_side[p] = out[p].side;
    out[p].side = piece.side;
  }
  return made;
}

/// The material part of a piece of a cell a void cuts too (second_parts):
/// the parts on the void's negative side (inside it) dropped. Returns the
/// number of parts written (0–3).
int material_parts(const double second_phi[5], int tri, const xfem::TrianglePiece& piece, xfem::TrianglePiece out[3]) {
  xfem::TrianglePiece parts[3];
  int second_side[3];
  const int made = second_parts(second_phi, tri, piece, parts, second_side);
  int count = 0;
  for (int p = 0; p < made; ++p)
    if (second_side[p] >= 0) out[count++] = parts[p];
  return count;
}

/// Calls f(piece, sub-triangle, material) for each piece of a cell that holds
/// material: the pieces in a void are skipped, and in a cell a void cuts
/// too, a crack's piece is split to its parts outside the void; in a cell an
/// inclusion cuts too, to its parts outside (the crack side's material) and
/// inside (the inclusion's).
template <class F>
void for_each_material_piece(const PlateModel& m, const CellView& v, const xfem::TrianglePiece* pieces,
                             const int* triangle, int count, F&& f) {
  for (int p = 0; p < count; ++p) {
    const xfem::TrianglePiece& q = pieces[p];
    const int material = material_of(m, v, q.side);
    if (material < 0) continue;
    if (v.second_cut < 0) {
      f(q, triangle[p], material);
      continue;
    }
    if (v.second_inclusion) {
      xfem::TrianglePiece parts[3];
      int second_side[3];
      const int made = second_parts(v.second_phi, triangle[p], q, parts, second_side);
      for (int r = 0; r < made; ++r) f(parts[r], triangle[p], second_side[r] < 0 ? 1 + v.second_cut : material);
      continue;
    }
    xfem::TrianglePiece parts[3];
    const int made = material_parts(v.second_phi, triangle[p], q, parts);
    for (int r = 0; r < made; ++r) f(parts[r], triangle[p], material);
  }
}

// Gauss-Legendre, 7 points on [0, 1] (exact to degree 13).
constexpr double kGl7x[7] = {0.5 * (1.0 - 0.9491079123427585), 0.5 * (1.0 - 0.7415311855993945),
                             0.5 * (1.0 - 0.4058451513773972), 0.5,
                             0.5 * (1.0 + 0.4058451513773972), 0.5 * (1.0 + 0.7415311855993945),
                             0.5 * (1.0 + 0.9491079123427585)};
constexpr double kGl7w[7] = {0.5 * 0.1294849661688697, 0.5 * 0.2797053914892766, 0.5 * 0.3818300505051189,
                             0.5 * 0.4179591836734694, 0.5 * 0.3818300505051189, 0.5 * 0.2797053914892766,
                             0.5 * 0.1294849661688697};

/// The centre of a cell's polar rule (parent coordinates): the apex of the
/// fan of a tip's cell or of a cell the tip touches; otherwise the nearest
/// tip whose branch functions the cell carries (the others are integrated
/// as smooth functions).
Point2 polar_apex(const PlateModel& m, const CellView& v) {
  if (v.tip_cell >= 0 || v.touch_tip >= 0)
    return fan_centre(v, m.tips[static_cast<std::size_t>(v.tip_cell >= 0 ? v.tip_cell : v.touch_tip)]);
  Point2 best{};
  double best_d2 = INFINITY;
  for (int f = 0; f < v.count; ++f) {
    if (v.tip[f] < 0) continue;
    const PlateModel::Tip& t = m.tips[static_cast<std::size_t>(v.tip[f])];
    Point2 p{};
    for (int c = 0; c < 2; ++c) p[c] = 2.0 * (t.origin[c] - v.x0[c]) / (v.x1[c] - v.x0[c]) - 1.0;
    const double d2 = p[0] * p[0] + p[1] * p[1];
    if (d2 < best_d2) best_d2 = d2, best = p;
  }
  return best;
}

/// At most this many segments per run (the grading reaches a point 1e-11 of
/// the run's length from the line; beyond, the last segment takes the rest,
/// its part being that small).
constexpr int kMaxGradedSegments = 64;

/// Calls seg(t0, t1) for the segments of [0, 1] (a line's parameter) graded
/// away from tf, the foot of a point at distance dt from the line (both in
/// units of the parameter, in the physical metric): an integrand singular at
/// that point is analytic along the line but for the complex pair tf ± i dt.
/// The line is split at the foot; a segment at u from the foot is at most
/// grade × max(u, dt) long. With grade ½ the pair stays ≥ 4 half-lengths from
/// the segment's centre (Bernstein ellipse ρ ≥ 4.6; 7-point Gauss converges
/// there to ~1e-13 of its part); with grade 1, ρ ≥ 2.4.
/// (dt below 1e-9 counts as 1e-9: a point on the line grades to 1e-9 of it.)
template <class S>
void graded_segments(double tf, double dt_in, double grade, S&& seg) {
  const double dt = std::max(dt_in, 1e-9);
  for (int dir = 0; dir < 2; ++dir) {
    // Distances from the foot of the run's start and end: towards 1 over
    // [max(tf, 0), 1], towards 0 over [0, min(tf, 1)].
    double u = dir == 0 ? std::max(0.0, -tf) : std::max(0.0, tf - 1.0);
    const double end = dir == 0 ? 1.0 - tf : tf;
    for (int k = 0; k < kMaxGradedSegments && u < end; ++k) {
      const bool last = k + 1 == kMaxGradedSegments || u + grade * std::max(u, dt) >= end;
      const double w = last ? end : u + grade * std::max(u, dt);
      // The line's ends exact.
      if (dir == 0)
        seg(tf + u, last ? 1.0 : tf + w);
      else
        seg(last ? 0.0 : tf - w, tf - u);
      u = w;
    }
  }
}

/// The foot (parameter along p → q) of P on the line pq and P's distance
/// from it in units of the parameter, in the metric of a cell of sides
/// (hx, hy) (parent coordinates in, physical distances).
void foot_on_line(Point2 p, Point2 q, Point2 P, double hx, double hy, double& tf, double& dt) {
  const double px = (p[0] - P[0]) * hx, py = (p[1] - P[1]) * hy, ex = (q[0] - p[0]) * hx, ey = (q[1] - p[1]) * hy;
  const double len2 = ex * ex + ey * ey;
  tf = -(px * ex + py * ey) / len2;
  dt = std::fabs(px * ey - py * ex) / len2;
}

/// Points of the polar rule: radial and along-edge Gauss orders (5 or 7) and
/// the edges' grading (graded_segments).
struct PolarRule {
  int radial = 7, along = 7;
  double grade = 0.5;
};
/// The element matrices: 7 radial points (the mass's N_a F_i N_b F_j is of
/// degree 13 in s), edges graded by ½.
constexpr PolarRule kAssemblyRule{7, 7, 0.5};
/// The interaction integral (a probe, ~1e-3 of K from the mesh): 5 × 5 on
/// edges graded by 1.
constexpr PolarRule kProbeRule{5, 5, 1.0};

/// Calls g(xi, eta, weight) at the points of the polar rule of a triangle
/// (parent coordinates) about a point P (cell sides hx, hy): the triangle is
/// the signed sum of the triangles (P, p, q) over its edges pq (P need not
/// be inside it), each integrated in (s, b) with x = P + s² (p − P + b (q − p)),
/// Gauss in both (`rule`). With F ~ √r, ∇F ~ 1/√r and the Jacobian ~ r, every
/// integrand of the cell (products of the bilinear N_a, the branch functions
/// and their gradients, constants and linear functions) is a polynomial of
/// degree ≤ 13 in s on each ray from P: exact radially with 7 points. Along an edge it is
/// smooth but not polynomial, singular where P is (graded_segments). Edges
/// whose bit is set in `skip` are left out.
template <class G>
void polar_piece(const xfem::TrianglePiece& t, Point2 P, double hx, double hy, const PolarRule& rule, unsigned skip, G&& g) {
  const double* radial_x = rule.radial == 7 ? kGl7x : kGl5x;
  const double* radial_w = rule.radial == 7 ? kGl7w : kGl5w;
  const double* along_x = rule.along == 7 ? kGl7x : kGl5x;
  const double* along_w = rule.along == 7 ? kGl7w : kGl5w;
  const double area2 = (t.v[1][0] - t.v[0][0]) * (t.v[2][1] - t.v[0][1]) - (t.v[1][1] - t.v[0][1]) * (t.v[2][0] - t.v[0][0]);
  if (area2 == 0.0) return;
  const double orient = area2 > 0.0 ? 1.0 : -1.0;
  for (int e = 0; e < 3; ++e) {
    if (skip & (1u << e)) continue;
    const Point2 p = t.v[e], q = t.v[(e + 1) % 3];
    const double px = p[0] - P[0], py = p[1] - P[1], ex = q[0] - p[0], ey = q[1] - p[1];
    const double c = px * ey - py * ex;  // twice the signed area of (P, p, q)
    if (c == 0.0) continue;
    double tf = 0.0, dt = 0.0;
    foot_on_line(p, q, P, hx, hy, tf, dt);
    graded_segments(tf, dt, rule.grade, [&](double t0, double t1) {
      const double ax = px + t0 * ex, ay = py + t0 * ey;  // the segment's start from P
      const double sx = (t1 - t0) * ex, sy = (t1 - t0) * ey;
      const double cs = orient * c * (t1 - t0);
      for (int ib = 0; ib < rule.along; ++ib) {
        const double rx = ax + along_x[ib] * sx, ry = ay + along_x[ib] * sy;
        for (int is = 0; is < rule.radial; ++is) {
          const double s = radial_x[is], a = s * s;
          g(P[0] + a * rx, P[1] + a * ry, radial_w[is] * along_w[ib] * 2.0 * s * a * cs);
        }
      }
    });
  }
}

/// The polar rule of a piece is a signed sum of the triangles (P, p, q) over
/// its edges; where P lies far outside the piece compared with its size (a
/// sliver cut off near a node, a small piece far from the tip) those
/// triangles are much larger than the piece and their sum cancels: its
/// absolute round-off stays that of the triangles, so the integrals of
/// functions that live on the piece alone (the shifted Heaviside function of
/// a node across the crack from a sliver) are lost, and the mass and the
/// stiffness can come out indefinite. Such a piece (Σ|triangles| >
/// kPolarCancellation × its area) takes the collapsed Gauss rule on its own
/// area instead: positive weights; the piece is then either far from P
/// compared with its size (the rule's error far below round-off) or a sliver
/// whose share of the cell is about 1/kPolarCancellation or less.
constexpr double kPolarCancellation = 64.0;
bool polar_cancels(const xfem::TrianglePiece& t, Point2 P) {
  const double area2 = std::fabs((t.v[1][0] - t.v[0][0]) * (t.v[2][1] - t.v[0][1]) -
                                 (t.v[1][1] - t.v[0][1]) * (t.v[2][0] - t.v[0][0]));
  double sum = 0.0;
  for (int e = 0; e < 3; ++e) {
    const Point2 p = t.v[e], q = t.v[(e + 1) % 3];
    sum += std::fabs((p[0] - P[0]) * (q[1] - p[1]) - (p[1] - P[1]) * (q[0] - p[0]));
  }
  return sum > kPolarCancellation * area2;
}

/// Calls f(xi, eta, weight, tri, side, material) for the quadrature points of
/// the cell's material (weight in parent area: × hx hy / 4 for the physical;
/// negative weights occur in the polar rule's signed triangles).
/// An uncut cell: the 2 × 2 Gauss rule (exact for its functions). A cut cell
/// without branch functions: its four sub-triangles split along the linear
/// level set, each piece on its side by membership, a collapsed 5 × 5 Gauss
/// rule on each (exact to degree 8 in the piece: the ridge's products
/// included), weights from the piece's own area. A cell with branch
/// functions: the same pieces (a tip's cell or a cell the tip touches: its
/// fan), each by the polar rule about the tip (polar_piece).
template <class F>
void for_each_point(const PlateModel& m, const CellView& v, F&& f, const PolarRule& rule = kAssemblyRule) {
  if (v.cut < 0 && !v.tip_functions) {
    if (v.material < 0) return;
    const double g = 1.0 / std::sqrt(3.0);
    for (int gp = 0; gp < 4; ++gp) {
      const double xi = gp == 0 || gp == 3 ? -g : g, eta = gp < 2 ? -g : g;
      f(xi, eta, 1.0, triangle_of(xi, eta), 1, v.material);
    }
    return;
  }
  xfem::TrianglePiece pieces[kMaxPieces];
  int triangle[kMaxPieces];
  const int count = triangle_pieces(m, v, pieces, triangle);
  // The collapsed 5 × 5 Gauss rule on a piece (positive weights from its own area).
  auto integrate = [&](const xfem::TrianglePiece& q, int tri, int material) {
    const Point2 v0 = q.v[0], v1 = q.v[1], v2 = q.v[2];
    const double e1x = v1[0] - v0[0], e1y = v1[1] - v0[1];
    const double e2x = v2[0] - v1[0], e2y = v2[1] - v1[1];
    const double jac = std::fabs(e1x * e2y - e1y * e2x);  // twice the piece's area
    if (jac == 0.0) return;
    for (int ia = 0; ia < 5; ++ia)
      for (int ib = 0; ib < 5; ++ib) {
        const double a = kGl5x[ia], b = kGl5x[ib];
        const double xi = v0[0] + a * e1x + a * b * e2x, eta = v0[1] + a * e1y + a * b * e2y;
        f(xi, eta, kGl5w[ia] * kGl5w[ib] * a * jac, tri, q.side, material);
      }
  };
  if (v.tip_functions) {
    // Every piece of a cell with branch functions is integrated polar about
    // the tip (polar_piece).
    const Point2 apex = polar_apex(m, v);
    // The branch functions jump (θ = ±π) along the tip's straight line behind
    // it, which leaves the crack where the crack bends: beyond the bend it
    // runs through material, and a piece it crosses holds a jump that neither
    // rule integrates (Gauss across it; the mass is then no Gram matrix and may
    // be indefinite). Such a piece is split along that line, each part on one
    // side of it (ray[]: the sign of the tip's local y on it, 0 in cells
    // without a split) ("A bend near a tip", docs/xfem2d.md).
    xfem::TrianglePiece split[3 * kMaxPieces];
    int split_tri[3 * kMaxPieces];
    int ray[3 * kMaxPieces] = {};
    int parts = 0;
    bool any_split = false;
    {
      const double h = std::min(m.cell_size[0], m.cell_size[1]);
      const double tol = 1e-9 * h;
      int tip_here = -1;
      for (int g = 0; g < v.count && tip_here < 0; ++g)
        if (v.tip[g] >= 0) tip_here = v.tip[g];
      const PlateModel::Tip* t = tip_here >= 0 ? &m.tips[static_cast<std::size_t>(tip_here)] : nullptr;
      auto local = [&](Point2 q, double& lx, double& ly) {
        const Point2 x = physical(v, q[0], q[1]);
        const double ox = x[0] - t->origin[0], oy = x[1] - t->origin[1];
        lx = t->cos_a * ox + t->sin_a * oy, ly = -t->sin_a * ox + t->cos_a * oy;
      };
      for (int p = 0; p < count; ++p) {
        double lx[3] = {}, ly[3] = {};
        bool cross_behind = false;
        if (t != nullptr) {
          for (int c = 0; c < 3; ++c) local(pieces[p].v[c], lx[c], ly[c]);
          for (int c = 0; c < 3; ++c) {
            const int e = (c + 1) % 3;
            if ((ly[c] > tol && ly[e] < -tol) || (ly[c] < -tol && ly[e] > tol)) {
              const double a = ly[c] / (ly[c] - ly[e]);
              if (lx[c] + a * (lx[e] - lx[c]) < -tol) cross_behind = true;
            }
          }
        }
        if (!cross_behind) {
          split[parts] = pieces[p], split_tri[parts] = triangle[p];
          ++parts;
          continue;
        }
        any_split = true;
        xfem::TrianglePiece out[3];
        const int n = xfem::split_triangle(pieces[p].v, ly, out);
        for (int q = 0; q < n; ++q) {
          split[parts] = out[q];
          split[parts].side = pieces[p].side;
          split_tri[parts] = triangle[p];
          ray[parts] = out[q].side;  // split_triangle's side: the sign of ly there
          ++parts;
        }
      }
      if (any_split)
        for (int p = 0; p < parts; ++p) {
          if (ray[p] != 0) continue;
          const Point2 c{(split[p].v[0][0] + split[p].v[1][0] + split[p].v[2][0]) / 3.0,
                         (split[p].v[0][1] + split[p].v[1][1] + split[p].v[2][1]) / 3.0};
          double lx = 0.0, ly = 0.0;
          local(c, lx, ly);
          ray[p] = lx < 0.0 ? (ly >= 0.0 ? 1 : -1) : 0;
        }
    }
    // An edge two pieces share with opposite senses, where the integrand is
    // the same function on both (the same side, and the same sub-triangle
    // where an inclusion's ridge is), cancels in the signed sums: left out
    // of both (the pieces' inner edges; a third of the points of a whole cell).
    const bool ridge = v.cut >= 0 && m.desc.discontinuities[static_cast<std::size_t>(v.cut)].kind ==
                                         PlateDiscontinuity::Kind::inclusion;
    auto sense = [](const xfem::TrianglePiece& t) {
      const double a2 = (t.v[1][0] - t.v[0][0]) * (t.v[2][1] - t.v[0][1]) - (t.v[1][1] - t.v[0][1]) * (t.v[2][0] - t.v[0][0]);
      return a2 > 0.0 ? 1 : a2 < 0.0 ? -1 : 0;
    };
    // A piece whose signed triangles from the apex cancel to less than
    // 1/kPolarCancellation of their sizes (a sliver, or a small piece far from
    // the tip) is integrated by the collapsed Gauss rule on its own area
    // instead ("Tiny cuts at a tip", docs/xfem2d.md).
    bool own_rule[3 * kMaxPieces] = {};
    for (int p = 0; p < parts; ++p) own_rule[p] = polar_cancels(split[p], apex);
    unsigned skip[3 * kMaxPieces] = {};
    for (int p = 0; p < parts; ++p) {
      const int sp = sense(split[p]);
      if (sp == 0 || own_rule[p]) continue;
      for (int e = 0; e < 3; ++e) {
        if (skip[p] & (1u << e)) continue;
        const Point2 a = split[p].v[e], b = split[p].v[(e + 1) % 3];
        for (int r = p + 1; r < parts && !(skip[p] & (1u << e)); ++r) {
          if (own_rule[r] || split[r].side != split[p].side || ray[r] != ray[p] || (ridge && split_tri[r] != split_tri[p])) continue;
          const int sr = sense(split[r]);
          if (sr == 0) continue;
          for (int k = 0; k < 3; ++k) {
            if (skip[r] & (1u << k)) continue;
            const Point2 c = split[r].v[k], d = split[r].v[(k + 1) % 3];
            if ((c == b && d == a && sr == sp) || (c == a && d == b && sr == -sp)) {
              skip[p] |= 1u << e;
              skip[r] |= 1u << k;
              break;
            }
          }
        }
      }
    }
    for (int p = 0; p < parts; ++p) {
      const xfem::TrianglePiece& q = split[p];
      const int material = material_of(m, v, q.side);
      if (material < 0) continue;
      if (own_rule[p]) {
        integrate(q, split_tri[p], material);
        continue;
      }
      polar_piece(q, apex, m.cell_size[0], m.cell_size[1], rule, skip[p], [&](double xi, double eta, double w) { f(xi, eta, w, split_tri[p], q.side, material); });
    }
    return;
  }
  for_each_material_piece(m, v, pieces, triangle, count, integrate);
}

/// The cell of domain edge `edge` holding its e-th segment (along increasing
/// x or y), and the segment as a side of that cell: its sub-triangle and its
/// two corners (local nodes `from`, `to`, along increasing coordinate).
struct EdgeSegment {
  int ci = 0, cj = 0, tri = 0, from = 0, to = 0;
};
EdgeSegment edge_segment(const PlateDesc& d, PlateEdge edge, int e) {
  const int nx = d.cells[0], ny = d.cells[1];
  const bool vertical = edge == PlateEdge::left || edge == PlateEdge::right;
  EdgeSegment g;
  g.ci = vertical ? (edge == PlateEdge::left ? 0 : nx - 1) : e;
  g.cj = vertical ? e : (edge == PlateEdge::bottom ? 0 : ny - 1);
  g.tri = edge == PlateEdge::bottom ? 0 : edge == PlateEdge::right ? 1 : edge == PlateEdge::top ? 2 : 3;
  g.from = edge == PlateEdge::bottom ? 0 : edge == PlateEdge::right ? 1 : edge == PlateEdge::top ? 3 : 0;
  g.to = edge == PlateEdge::bottom ? 1 : edge == PlateEdge::right ? 2 : edge == PlateEdge::top ? 2 : 3;
  return g;
}

/// Calls f(xi, eta, side, material, length) at the quadrature points of a
/// cell's side on the domain's edge (v: the cell's view, g: the side): the
/// side split where the cutting level set crosses it, each piece on its side
/// by membership (its end off the zero), 3-point Gauss on each (exact to
/// degree 5: products of two of the cut cell's functions along it), the
/// material's part only; length is the point's weight in m² (× thickness).
/// `graded` with branch functions: 7-point Gauss on segments graded away from
/// the tip's foot on the side (the edge loads: their ∫ t N_a F_i).
template <class F>
void for_each_edge_point(const PlateModel& m, const CellView& v, const EdgeSegment& g, double h, bool graded, F&& f) {
  const double g3[3] = {0.5 * (1.0 - std::sqrt(0.6)), 0.5, 0.5 * (1.0 + std::sqrt(0.6))};
  const double w3[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
  double breaks[4] = {0.0, 1.0, 1.0, 1.0};
  int pieces = 1;
  if (v.cut >= 0) {
    const double pa = v.phi[g.from], pb = v.phi[g.to];
    if ((pa < 0.0 && pb > 0.0) || (pa > 0.0 && pb < 0.0)) {
      breaks[1] = pa / (pa - pb);
      pieces = 2;
    }
  }
  // An inclusion cutting the cell with a crack: the side split where its level set crosses it too.
  if (v.second_inclusion) {
    const double qa = v.second_phi[g.from], qb = v.second_phi[g.to];
    if ((qa < 0.0 && qb > 0.0) || (qa > 0.0 && qb < 0.0)) {
      const double sq = qa / (qa - qb);
      if (pieces == 1) {
        breaks[1] = sq, breaks[2] = 1.0;
      } else if (sq < breaks[1]) {
        breaks[2] = breaks[1], breaks[1] = sq;
      } else {
        breaks[2] = sq;
      }
      breaks[3] = 1.0;
      ++pieces;
    }
  }
  for (int pc = 0; pc < pieces; ++pc) {
    const double s0 = breaks[pc], s1 = breaks[pc + 1];
    if (!(s1 > s0)) continue;
    int side = 1;
    int material = 0;
    if (!v.second_inclusion) {
      if (v.cut >= 0) {
        const double pa = v.phi[g.from], pb = v.phi[g.to];
        side = pieces == 2 ? xfem::side_of(pc == 0 ? pa : pb) : (pa < 0.0 || pb < 0.0 ? -1 : 1);
      }
      material = material_of(m, v, side);
    } else {
      // Each piece's sides of the crack and of the inclusion: at its middle
      // when the level set crosses the side, else as the side's nodes.
      const double sm = 0.5 * (s0 + s1);
      auto side_along = [&](double fa, double fb) {
        if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0)) return xfem::side_of(fa + sm * (fb - fa));
        return fa < 0.0 || fb < 0.0 ? -1 : 1;
      };
      side = side_along(v.phi[g.from], v.phi[g.to]);
      material = side_along(v.second_phi[g.from], v.second_phi[g.to]) < 0 ? 1 + v.second_cut : material_of(m, v, side);
    }
    if (material < 0) continue;
    if (graded && v.tip_functions) {
      // Branch functions along the side: smooth but not polynomial, singular
      // at the tip; 7-point Gauss on segments graded away from its foot.
      const Point2 a = {kXi[g.from], kEta[g.from]}, b = {kXi[g.to], kEta[g.to]};
      double tf = 0.0, dt = 0.0;
      foot_on_line(a, b, polar_apex(m, v), m.cell_size[0], m.cell_size[1], tf, dt);
      graded_segments((tf - s0) / (s1 - s0), dt / (s1 - s0), 0.5, [&](double t0, double t1) {
        for (int qp = 0; qp < 7; ++qp) {
          const double sp = s0 + (t0 + kGl7x[qp] * (t1 - t0)) * (s1 - s0);
          const double xi = kXi[g.from] + sp * (kXi[g.to] - kXi[g.from]);
          const double eta = kEta[g.from] + sp * (kEta[g.to] - kEta[g.from]);
          f(xi, eta, side, material, kGl7w[qp] * (t1 - t0) * (s1 - s0) * h * m.desc.thickness);
        }
      });
      continue;
    }
    for (int qp = 0; qp < 3; ++qp) {
      const double sp = s0 + g3[qp] * (s1 - s0);
      const double xi = kXi[g.from] + sp * (kXi[g.to] - kXi[g.from]);
      const double eta = kEta[g.from] + sp * (kEta[g.to] - kEta[g.from]);
      f(xi, eta, side, material, w3[qp] * (s1 - s0) * h * m.desc.thickness);
    }
  }
}

}  // namespace

// ---- the one operation the integrator needs ---------------------------------

namespace {

/// The jump (the positive side of the crack's level set minus the negative)
/// of a tip's branch function √r sin(θ/2) on the crack behind it, over 2√r:
/// local y is the positive side at the polyline's last point.
inline double branch_jump_sign(const PlateModel::Tip& t) { return t.at_end ? 1.0 : -1.0; }

/// The terms of the jump [u] across crack k at parent point (xi, eta) of cell
/// `v`, with normal (gx, gy) towards the positive side: 2 N_a on each shifted
/// Heaviside unknown of the crack (ψ⁺ − ψ⁻ = 2 whatever the node's side),
/// ±2√r N_a on each √r sin(θ/2) unknown of a tip of the crack where the point
/// lies on the tip's line behind it (within 1e-9 of a cell; elsewhere, on a
/// bent crack, the branch functions are continuous across it). Held
/// unknowns (−1) are listed with their coefficients as the step skips them.
void face_terms(const PlateModel& m, const CellView& v, int k, double xi, double eta, double gx, double gy,
                PlateModel::FacePoint& fp) {
  fp.terms = 0;
  for (int f = 0; f < v.count; ++f) {
    double jump = 0.0;
    const int a = v.node[f];
    const double na = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
    if (v.disc[f] == k) {
      jump = 2.0 * na;
    } else if (v.tip[f] >= 0 && v.branch[f] == 0) {
      const PlateModel::Tip& t = m.tips[static_cast<std::size_t>(v.tip[f])];
      if (t.crack != k) continue;
      const Point2 x = physical(v, xi, eta);
      const double dx = x[0] - t.origin[0], dy = x[1] - t.origin[1];
      const double along = t.cos_a * dx + t.sin_a * dy, across = -t.sin_a * dx + t.cos_a * dy;
      if (!(along <= 0.0 && std::fabs(across) <= 1e-9 * std::min(m.cell_size[0], m.cell_size[1]))) continue;
      double r = 0.0, theta = 0.0;
      xfem::tip_polar(frame_of(t), x, r, theta);
      jump = branch_jump_sign(t) * 2.0 * std::sqrt(r) * na;
    } else {
      continue;
    }
    for (int c = 0; c < 2; ++c) {
      const int e = fp.terms++;
      fp.dof[e] = v.dof[f][c];
      fp.normal[e] = jump * (c == 0 ? gx : gy);
      fp.tangential[e] = jump * (c == 0 ? gy : -gx);
    }
  }
}

/// Makes a symmetric element stiffness k (nf × nf, the four standard
/// functions' x, y first, as make_view orders them) annihilate the two rigid
/// translations t (1 on the standard x, or y, unknowns, 0 on the enrichments)
/// to the round-off of one sum: k t = 0 exactly, but a sum over many
/// quadrature points (the polar rule's, signed ones among them) leaves each
/// row's sum over the translation's columns at their accumulated round-off,
/// and on a free, drifting plate −tᵀK u, the rate of its momentum, grows with
/// u. Each row's standard entries are set from the others in it, the same
/// entry on both sides of the diagonal: a change of round-off size.
template <class Mat>
void annihilate_translations(Mat& k, int nf) {
  for (int c = 0; c < 2; ++c) {
    // Enrichment rows: their last standard entry of component c closes the sum.
    for (int r = 8; r < nf; ++r) {
      const double s = k(r, c) + k(r, 2 + c) + k(r, 4 + c);
      k(r, 6 + c) = k(6 + c, r) = -s;
    }
    // The standard block's c–c part (symmetric): its diagonal closes each row.
    for (int a = 0; a < 4; ++a) {
      double s = 0.0;
      for (int b = 0; b < 4; ++b)
        if (b != a) s += k(2 * a + c, 2 * b + c);
      k(2 * a + c, 2 * a + c) = -s;
    }
  }
  // The x–y part B(a, b) = k(2a, 2b + 1) = k(2b + 1, 2a): its rows (the x rows
  // against t_y) and its columns (the y rows against t_x) both sum to 0; its
  // last row and column close them.
  for (int a = 0; a < 3; ++a) {
    const double s = k(2 * a, 1) + k(2 * a, 3) + k(2 * a, 5);
    k(2 * a, 7) = k(7, 2 * a) = -s;
  }
  for (int b = 0; b < 3; ++b) {
    const double s = k(0, 2 * b + 1) + k(2, 2 * b + 1) + k(4, 2 * b + 1);
    k(6, 2 * b + 1) = k(2 * b + 1, 6) = -s;
  }
  const double s = k(6, 1) + k(6, 3) + k(6, 5);
  k(6, 7) = k(7, 6) = -s;
}

}  // namespace

void plate_subtract_stiffness_product(const PlateModel& m, const double* x, double* y) {
  const double* ke = m.element_stiffness;
  const std::size_t plain = m.plain_cell_dof.size() / 8;
  for (std::size_t e = 0; e < plain; ++e) {
    const int* dof = m.plain_cell_dof.data() + 8 * e;
    double xe[8];
    for (int a = 0; a < 8; ++a) xe[a] = dof[a] >= 0 ? x[dof[a]] : 0.0;
    for (int a = 0; a < 8; ++a) {
      if (dof[a] < 0) continue;
      double s = 0.0;
      for (int b = 0; b < 8; ++b) s += ke[a * 8 + b] * xe[b];
      y[dof[a]] -= s;
    }
  }
  const std::size_t others = m.other_cell_matrix_start.size();
  for (std::size_t e = 0; e < others; ++e) {
    const int* dof = m.other_cell_dof.data() + m.other_cell_start[e];
    const int nf = m.other_cell_start[e + 1] - m.other_cell_start[e];
    const double* k = m.other_cell_matrix.data() + m.other_cell_matrix_start[e];
    for (int a = 0; a < nf; ++a) {
      if (dof[a] < 0) continue;
      double s = 0.0;
      for (int b = 0; b < nf; ++b)
        if (dof[b] >= 0) s += k[a * nf + b] * x[dof[b]];
      y[dof[a]] -= s;
    }
  }
  // Tied faces: w (k_n g_n n + k_t g_t t), g the jumps' coefficients (unilateral
  // points are not in K: the step adds those that are active).
  for (const PlateModel::FacePoint& fp : m.face_points) {
    if (fp.unilateral) continue;
    double gn = 0.0, gt = 0.0;
    for (int a = 0; a < fp.terms; ++a)
      if (fp.dof[a] >= 0) gn += fp.normal[a] * x[fp.dof[a]], gt += fp.tangential[a] * x[fp.dof[a]];
    for (int a = 0; a < fp.terms; ++a)
      if (fp.dof[a] >= 0)
        y[fp.dof[a]] -= fp.weight * (fp.k_normal * gn * fp.normal[a] + fp.k_tangential * gt * fp.tangential[a]);
  }
}

namespace detail {

/// The normal jump [u]·n of a face point.
inline double face_gap(const PlateModel::FacePoint& fp, const double* u) {
  double g = 0.0;
  for (int a = 0; a < fp.terms; ++a)
    if (fp.dof[a] >= 0) g += fp.normal[a] * u[fp.dof[a]];
  return g;
}

/// A += scale · w k_n g gᵀ of face point fp (g: its normal-jump coefficients).
inline void add_face_penalty(xfem::SymmetricBand& a, const PlateModel::FacePoint& fp, double scale) {
  for (int i = 0; i < fp.terms; ++i) {
    if (fp.dof[i] < 0) continue;
    for (int j = 0; j < fp.terms; ++j) {
      if (fp.dof[j] < 0 || fp.dof[j] > fp.dof[i]) continue;
      a.add(fp.dof[i], fp.dof[j], scale * fp.weight * fp.k_normal * fp.normal[i] * fp.normal[j]);
    }
  }
}

/// y −= w k_n g_p n_p for every point p in `set`, g_p = gap[p]: the face
/// springs' force on the unknowns at the gaps given.
inline void add_face_forces(const PlateModel& m, const char* set, const double* gap, double* y) {
  for (std::size_t p = 0; p < m.face_points.size(); ++p) {
    if (!set[p]) continue;
    const PlateModel::FacePoint& fp = m.face_points[p];
    const double force = fp.weight * fp.k_normal * gap[p];
    for (int a = 0; a < fp.terms; ++a)
      if (fp.dof[a] >= 0) y[fp.dof[a]] -= force * fp.normal[a];
  }
}

/// The step length of the damped Newton iteration on unilateral faces
/// (docs/xfem2d.md, "Unilateral faces"): the minimiser over (0, 1] of the
/// solve's convex energy along the Newton step d,
///   F(k) = ½ kᵀEk − bᵀk + Σ_p ½ w k_n min(g_p, 0)² / fac0   (g_p = gᵀ(x + fac0 k)),
/// a held point's spring acting whatever the sign (½ w k_n g_p²). Along d,
///   φ'(α) = s1 + α s2 + Σ_p w k_n m_p(gap_p + α dgap_p) dgap_p / fac0,
/// with s1 = dᵀ(Ek − b), s2 = dᵀEd ≥ 0 and each m_p non-decreasing, so φ' does
/// not decrease and bisection finds its zero (to the last bit of α).
inline double face_line_search(const PlateModel& m, const char* held, const double* gap, const double* dgap,
                               double fac0, double s1, double s2) {
  auto slope = [&](double alpha) {
    double sum = 0.0;
    for (std::size_t p = 0; p < m.face_points.size(); ++p) {
      const PlateModel::FacePoint& fp = m.face_points[p];
      if (!fp.unilateral) continue;
      double g = gap[p] + alpha * dgap[p];
      if (g > 0.0 && (held == nullptr || !held[p])) g = 0.0;
      sum += fp.weight * fp.k_normal * g * dgap[p];
    }
    return s1 + alpha * s2 + sum / fac0;
  };
  if (slope(1.0) <= 0.0) return 1.0;
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (slope(mid) > 0.0 ? hi : lo) = mid;
  }
  return hi;
}

/// y −= C x for the consistent blocks of the dashpots (PlateModel::absorb_*).
inline void subtract_absorb_product(const PlateModel& m, const double* x, double* y) {
  const std::size_t blocks = m.absorb_start.empty() ? 0 : m.absorb_start.size() - 1;
  for (std::size_t b = 0; b < blocks; ++b) {
    const int* dof = m.absorb_dof.data() + m.absorb_start[b];
    const int n = m.absorb_start[b + 1] - m.absorb_start[b];
    const double* c = m.absorb_matrix.data() + m.absorb_matrix_start[b];
    for (int r = 0; r < n; ++r) {
      double s = 0.0;
      for (int q = 0; q < n; ++q) s += c[r * n + q] * x[dof[q]];
      y[dof[r]] -= s;
    }
  }
}

/// y −= K_fh g(t) + M_fh a_h: what the moving held components push on the
/// unknowns (held_a: their accelerations).
inline void subtract_moving_push(const PlateModel& m, double t, const double* held_a, double* y) {
  const std::size_t moving = m.moving_component.size();
  for (std::size_t h = 0; h < moving; ++h) {
    const double g = moving_displacement(m, h, t), a = held_a[h];
    for (int e = m.moving_free_start[h]; e < m.moving_free_start[h + 1]; ++e) {
      const auto k = static_cast<std::size_t>(e);
      y[m.moving_free_dof[k]] -= m.moving_free_k[k] * g + m.moving_free_m[k] * a;
    }
  }
}

/// (M a + K u) on moving held component h's row of the whole plate (u, a the
/// unknowns, the held displacements at t, held_a the moving ones'
/// accelerations): the force the plate needs there, its support's reaction
/// plus the loads it takes.
inline double moving_row(const PlateModel& m, std::size_t h, const double* u, const double* a, double t,
                         const double* held_a) {
  double r = 0.0;
  for (int e = m.moving_free_start[h]; e < m.moving_free_start[h + 1]; ++e) {
    const auto k = static_cast<std::size_t>(e);
    const auto dof = static_cast<std::size_t>(m.moving_free_dof[k]);
    r += m.moving_free_k[k] * u[dof] + m.moving_free_m[k] * a[dof];
  }
  for (int e = m.moving_held_start[h]; e < m.moving_held_start[h + 1]; ++e) {
    const auto k = static_cast<std::size_t>(e);
    const auto comp = static_cast<std::size_t>(m.moving_held_component[k]);
    const int other = m.node_moving[comp];
    r += m.moving_held_k[k] * held_displacement(m, comp, t) +
         (other >= 0 ? m.moving_held_m[k] * held_a[static_cast<std::size_t>(other)] : 0.0);
  }
  return r;
}

/// The moving held components' part of the whole plate's xᵀMx (x the
/// unknowns' values, xh the moving components'): 2 x_hᵀM_hf x_f + x_hᵀM_hh x_h
/// (the constant held components' rates are 0).
inline double moving_mass_quadratic(const PlateModel& m, const double* x, const double* xh) {
  double q = 0.0;
  const std::size_t moving = m.moving_component.size();
  for (std::size_t h = 0; h < moving; ++h) {
    double row = 0.0;
    for (int e = m.moving_free_start[h]; e < m.moving_free_start[h + 1]; ++e) {
      const auto k = static_cast<std::size_t>(e);
      row += 2.0 * m.moving_free_m[k] * x[m.moving_free_dof[k]];
    }
    for (int e = m.moving_held_start[h]; e < m.moving_held_start[h + 1]; ++e) {
      const auto k = static_cast<std::size_t>(e);
      const int other = m.node_moving[static_cast<std::size_t>(m.moving_held_component[k])];
      if (other >= 0) row += m.moving_held_m[k] * xh[static_cast<std::size_t>(other)];
    }
    q += xh[h] * row;
  }
  return q;
}

class PlateOperator {
 public:
  PlateOperator(const PlateModel& model, PlateWorkspace& workspace, const char* held = nullptr)
      : m_(model), ws_(workspace), held_(held) {}
  [[nodiscard]] int size() const { return m_.dofs; }

  /// Solves (M + fac1 C + fac0 K) k = f(t) − C v − K x, with (fac0, fac1) either
  /// (0, 0) (M k = …: the initial acceleration) or the model's, factored at build.
  /// With unilateral faces K holds the penalties of the active points: the
  /// set starts from the points closing at the predictor x and is updated
  /// from the points closing at x + fac0 k until it repeats (re-factoring the
  /// effective matrix whenever the set differs from the factored one); after
  /// kMaxActiveSetIterations the last solve stands and the step says
  /// active_set_not_converged.
  StepStatus implicit_solve(double fac0, double fac1, double t, const double* x, const double* v, double* k) const {
    (void)fac1;
    const int n = m_.dofs;
    double* shape = ws_.shape_end.data();
    const int slots = static_cast<int>(ws_.shape_end.size());
    for (int s = 0; s < slots; ++s) shape[s] = plate_load_shape(m_, s - 1, t);
    double* base = m_.unilateral_points > 0 ? ws_.rhs.data() : k;
    for (int i = 0; i < n; ++i) base[i] = m_.held_force[static_cast<std::size_t>(i)];
    const std::size_t entries = m_.load_dof.size();
    for (std::size_t e = 0; e < entries; ++e) base[m_.load_dof[e]] += m_.load_value[e] * shape[m_.load_of[e] + 1];
    if (!ws_.external_force.empty())
      for (int i = 0; i < n; ++i) base[i] += ws_.external_force[static_cast<std::size_t>(i)];
    // The held components eliminated: the moving ones push −K_fh g(t) − M_fh a_h
    // (consistent mass couples them), a_h the accelerations the caller put
    // in the workspace (the step's, from Newmark's own update, or the state's).
    if (!m_.moving_component.empty()) subtract_moving_push(m_, t, ws_.held_accel.data(), base);
    plate_subtract_stiffness_product(m_, x, base);
    for (std::size_t d = 0; d < m_.damper_dof.size(); ++d) base[m_.damper_dof[d]] -= m_.damper_coeff[d] * v[m_.damper_dof[d]];
    subtract_absorb_product(m_, v, base);
    if (m_.unilateral_points == 0) {
      (fac0 == 0.0 ? m_.mass_factor : m_.effective_factor).solve(k, ws_.solve_work.data());
      return StepStatus::ok;
    }
    const std::size_t points = m_.face_points.size();
    for (std::size_t p = 0; p < points; ++p)
      ws_.active[p] = m_.face_points[p].unilateral && face_gap(m_.face_points[p], x) < 0.0 ? 1 : 0;
    if (held_ != nullptr && fac0 != 0.0)  // a redone step: the held points stay active
      for (std::size_t p = 0; p < points; ++p) ws_.active[p] |= held_[p];
    for (int iteration = 0; iteration < kMaxActiveSetIterations; ++iteration) {
      active_rhs(x, base, k);
      if (fac0 == 0.0) {  // M k = …: the acceleration does not move u
        m_.mass_factor.solve(k, ws_.solve_work.data());
        return StepStatus::ok;
      }
      solve_active(fac0, k);
      bool same = true;
      for (std::size_t p = 0; p < points; ++p) {
        if (!m_.face_points[p].unilateral) continue;
        // The gap at u_{n+1} = x + fac0 k.
        const PlateModel::FacePoint& fp = m_.face_points[p];
        double g = 0.0;
        for (int a = 0; a < fp.terms; ++a)
          if (fp.dof[a] >= 0) g += fp.normal[a] * (x[fp.dof[a]] + fac0 * k[fp.dof[a]]);
        const char now = g < 0.0 || (held_ != nullptr && held_[p] != 0) ? 1 : 0;
        if (now != ws_.active[p]) same = false;
        ws_.active[p] = now;
      }
      if (same) return StepStatus::ok;
    }
    return settle_by_line_search(fac0, x, base, k);
  }

  static constexpr int kMaxActiveSetIterations = 16;
  static constexpr int kMaxDampedIterations = 200;

 private:
  /// k = base − the active points' springs at the gaps of x.
  void active_rhs(const double* x, const double* base, double* k) const {
    for (int i = 0; i < m_.dofs; ++i) k[i] = base[i];
    for (std::size_t p = 0; p < m_.face_points.size(); ++p) {
      if (!ws_.active[p]) continue;
      const PlateModel::FacePoint& fp = m_.face_points[p];
      const double force = fp.weight * fp.k_normal * face_gap(fp, x);
      for (int a = 0; a < fp.terms; ++a)
        if (fp.dof[a] >= 0) k[fp.dof[a]] -= force * fp.normal[a];
    }
  }

  /// k ← (M_eff + fac0 Σ_active penalties)⁻¹ k, re-factoring only when the
  /// active set differs from the one factored last.
  void solve_active(double fac0, double* k) const {
    if (ws_.active != ws_.factored_active) {
      ws_.effective = m_.base_effective;
      for (std::size_t p = 0; p < m_.face_points.size(); ++p)
        if (ws_.active[p]) add_face_penalty(ws_.effective, m_.face_points[p], fac0);
      ws_.factor.factor(ws_.effective);
      ws_.factored_active = ws_.active;
    }
    ws_.factor.solve(k, ws_.solve_work.data());
  }

  /// The plain iteration above is Newton's method on the solve's convex,
  /// piecewise quadratic energy (each solve minimises it with the set of the
  /// last iterate), and undamped it can cycle between sets. From its last
  /// solve this continues it damped: the Newton point for the set of the
  /// current iterate, then the exact minimiser along the way to it
  /// (face_line_search), which lowers the energy at every iteration and so
  /// cannot cycle. It ends when the Newton point's set is the iterate's (the
  /// exact solution), when every point whose state still changes has a gap
  /// within its own rounding (a contact that neither pushes nor separates,
  /// which flips on round-off), or when the step along the way no longer
  /// moves the iterate (no descent the arithmetic can resolve).
  StepStatus settle_by_line_search(double fac0, const double* x, const double* base, double* k) const {
    const int n = m_.dofs;
    const std::size_t points = m_.face_points.size();
    double *kc = ws_.line_k.data(), *q = ws_.line_q.data(), *qn = ws_.line_qn.data();
    double *gap = ws_.line_gap.data(), *dgap = ws_.line_dgap.data();
    auto gap_at = [&](const PlateModel::FacePoint& fp, const double* kk) {
      double g = 0.0;
      for (int a = 0; a < fp.terms; ++a)
        if (fp.dof[a] >= 0) g += fp.normal[a] * (x[fp.dof[a]] + fac0 * kk[fp.dof[a]]);
      return g;
    };
    auto held = [&](std::size_t p) { return held_ != nullptr && held_[p] != 0; };
    ++ws_.damped_solves;
    // k solved the set factored last, so E k − b = −Σ_{that set} w k_n g_p(k) n_p.
    for (int i = 0; i < n; ++i) kc[i] = k[i], q[i] = 0.0;
    for (std::size_t p = 0; p < points; ++p) gap[p] = gap_at(m_.face_points[p], kc);
    add_face_forces(m_, ws_.factored_active.data(), gap, q);
    for (int iteration = 0; iteration < kMaxDampedIterations; ++iteration) {
      for (std::size_t p = 0; p < points; ++p)
        ws_.active[p] = m_.face_points[p].unilateral && (gap[p] < 0.0 || held(p)) ? 1 : 0;
      active_rhs(x, base, k);
      solve_active(fac0, k);
      bool same = true, round_off = true;
      for (std::size_t p = 0; p < points; ++p) {
        const PlateModel::FacePoint& fp = m_.face_points[p];
        const double g = dgap[p] = gap_at(fp, k);  // the Newton point's gap, for now
        if (!fp.unilateral) continue;
        const char now = g < 0.0 || held(p) ? 1 : 0;
        if (now != ws_.active[p]) {
          same = false;
          // The sign of a gap within its own rounding (64 ε of its terms) is not known.
          double terms = 0.0;
          for (int a = 0; a < fp.terms; ++a)
            if (fp.dof[a] >= 0) terms += std::fabs(fp.normal[a] * (x[fp.dof[a]] + fac0 * k[fp.dof[a]]));
          if (std::fabs(g) > 64.0 * DBL_EPSILON * terms) round_off = false;
        }
      }
      if (same || round_off) return StepStatus::ok;
      // E k_N − b = −Σ_active w k_n g_p(k_N) n_p, so E d = qn − q.
      for (int i = 0; i < n; ++i) qn[i] = 0.0;
      add_face_forces(m_, ws_.active.data(), dgap, qn);
      for (std::size_t p = 0; p < points; ++p) dgap[p] -= gap[p];  // the change along the step
      double s1 = 0.0, s2 = 0.0;
      for (int i = 0; i < n; ++i) {
        const double d = k[i] - kc[i];
        s1 += d * q[i];
        s2 += d * (qn[i] - q[i]);
      }
      const double alpha = face_line_search(m_, held_, gap, dgap, fac0, s1, s2);
      bool moved = false;
      for (int i = 0; i < n; ++i) {
        const double next = kc[i] + alpha * (k[i] - kc[i]);
        moved = moved || next != kc[i];
        kc[i] = next;
        q[i] += alpha * (qn[i] - q[i]);
      }
      if (!moved) {  // no descent the arithmetic can see: the iterate is the minimiser to round-off
        for (int i = 0; i < n; ++i) k[i] = kc[i];
        return StepStatus::ok;
      }
      for (std::size_t p = 0; p < points; ++p) gap[p] = gap_at(m_.face_points[p], kc);
    }
    for (int i = 0; i < n; ++i) k[i] = kc[i];
    return StepStatus::active_set_not_converged;
  }

  const PlateModel& m_;
  PlateWorkspace& ws_;
  const char* held_;  ///< non-null: the active set of every solve (a redone step)
};

}  // namespace detail

// ---- validation ---------------------------------------------------------------

BuildResult validate_plate(const PlateDesc& d) {
  for (int c = 0; c < 2; ++c) {
    if (!std::isfinite(d.min[c])) return fail("domain.min: must be finite, got %g", d.min[c]);
    if (!std::isfinite(d.max[c])) return fail("domain.max: must be finite, got %g", d.max[c]);
    if (!(d.max[c] - d.min[c] > 0.0))
      return BuildResult::failure(Code::invalid_argument, "domain.max: must exceed domain.min in %s (%g <= %g)",
                                  c == 0 ? "x" : "y", d.max[c], d.min[c]);
    if (d.cells[c] < 1)
      return BuildResult::failure(Code::invalid_argument, "cells: must be at least 1 in %s, got %d", c == 0 ? "x" : "y",
                                  d.cells[c]);
  }
  {
    // Each of the four profile matrices (M, K, and the factors) stores about
    // 2 nodes × (2 min(nx, ny) + 4) entries: bound it (a scene must not be
    // able to ask for terabytes).
    const double nodes = static_cast<double>(d.cells[0] + 1) * static_cast<double>(d.cells[1] + 1);
    const double entries = 2.0 * nodes * (2.0 * std::min(d.cells[0], d.cells[1]) + 4.0);
    if (entries > kMaxProfileEntries)
      return BuildResult::failure(Code::capacity,
                                  "cells: %d x %d needs about %.3g stored entries per matrix, more than this build's "
                                  "%.3g",
                                  d.cells[0], d.cells[1], entries, kMaxProfileEntries);
  }
  if (d.plane != PlateDesc::Plane::strain && d.plane != PlateDesc::Plane::stress)
    return BuildResult::failure(Code::invalid_argument, "plane: must be strain or stress, got %d", static_cast<int>(d.plane));
  if (!positive_finite(d.thickness)) return fail("thickness: must be positive and finite (m), got %g", d.thickness);
  if (!positive_finite(d.youngs_modulus))
    return fail("material.youngs_modulus: must be positive and finite (Pa), got %g", d.youngs_modulus);
  if (!std::isfinite(d.poisson_ratio) || d.poisson_ratio <= -1.0)
    return fail("material.poisson_ratio: must be finite and > -1, got %g", d.poisson_ratio);
  if (d.plane == PlateDesc::Plane::strain && d.poisson_ratio >= 0.5)
    return fail("material.poisson_ratio: must be < 0.5 in plane strain (incompressible material), got %g",
                d.poisson_ratio);
  if (d.plane == PlateDesc::Plane::stress && d.poisson_ratio > 0.5)
    return fail("material.poisson_ratio: must be <= 0.5, got %g", d.poisson_ratio);
  if (!positive_finite(d.density)) return fail("material.density: must be positive and finite (kg/m^3), got %g", d.density);
  for (int c = 0; c < 2; ++c)
    if (!std::isfinite(d.gravity[c])) return fail("gravity: must be finite, got %g", d.gravity[c]);
  const bool dynamic = d.analysis == PlateDesc::Analysis::dynamic;
  if (!dynamic && d.analysis != PlateDesc::Analysis::statics)
    return BuildResult::failure(Code::invalid_argument, "analysis: must be dynamic or static, got %d",
                                static_cast<int>(d.analysis));
  if (dynamic) {
    if (!positive_finite(d.dt)) return fail("dt: must be a positive finite time step (s), got %g", d.dt);
    if (!std::isfinite(d.gamma)) return fail("newmark.gamma: must be finite, got %g", d.gamma);
    if (!std::isfinite(d.beta)) return fail("newmark.beta: must be finite, got %g", d.beta);
    if (d.gamma < 0.5)
      return BuildResult::failure(Code::unstable_time_step, "newmark.gamma: must be >= 1/2 (stability), got %.17g",
                                  d.gamma);
    if (!xfem::NewmarkScheme{d.beta, d.gamma, d.dt}.unconditionally_stable())
      return BuildResult::failure(Code::unstable_time_step,
                                  "newmark.beta: must be >= (gamma + 1/2)^2 / 4 = %.17g for gamma = %.17g "
                                  "(unconditional stability), got %.17g",
                                  0.25 * (d.gamma + 0.5) * (d.gamma + 0.5), d.gamma, d.beta);
  }
  for (std::size_t s = 0; s < d.supports.size(); ++s) {
    const PlateSupport& sp = d.supports[s];
    if (!valid_edge(sp.edge))
      return BuildResult::failure(Code::invalid_argument, "supports.%zu.edge: must be left, right, bottom or top", s);
    if (sp.absorbing && !dynamic)
      return BuildResult::failure(Code::invalid_argument,
                                  "supports.%zu.absorbing: a static analysis has no dashpots (absorbing must be false)", s);
  }
  for (std::size_t p = 0; p < d.prescribed.size(); ++p)
    for (int c = 0; c < 2; ++c) {
      if (!std::isfinite(d.prescribed[p].at[c]))
        return BuildResult::failure(Code::invalid_argument, "prescribed.%zu.at: must be finite", p);
      if (!std::isfinite(d.prescribed[p].displacement[c]))
        return BuildResult::failure(Code::invalid_argument, "prescribed.%zu.displacement: must be finite", p);
    }
  for (std::size_t p = 0; p < d.prescribed.size(); ++p) {
    const PlatePrescribed& pr = d.prescribed[p];
    switch (pr.shape) {
      case PlatePrescribedShape::step:
        if (pr.duration != 0.0)
          return BuildResult::failure(Code::invalid_argument,
                                      "prescribed.%zu.duration: only a half_sine or ramp shape has a duration; must be "
                                      "0, got %g",
                                      p, pr.duration);
        break;
      case PlatePrescribedShape::half_sine:
      case PlatePrescribedShape::ramp:
        if (!dynamic)
          return BuildResult::failure(Code::invalid_argument,
                                      "prescribed.%zu.shape: a static analysis has no time; %s needs analysis dynamic "
                                      "(use step)",
                                      p, pr.shape == PlatePrescribedShape::ramp ? "ramp" : "half_sine");
        if (!positive_finite(pr.duration))
          return BuildResult::failure(Code::invalid_argument,
                                      "prescribed.%zu.duration: must be positive and finite (s), got %g", p, pr.duration);
        // The energy rule of unilateral faces redoes a step from its start
        // and compares energies that leave the moving nodes out.
        for (const PlateDiscontinuity& q : d.discontinuities)
          if (q.kind == PlateDiscontinuity::Kind::crack && q.faces == PlateDiscontinuity::Faces::unilateral)
            return BuildResult::failure(Code::invalid_argument,
                                        "prescribed.%zu.shape: a moving prescribed node is not supported with "
                                        "unilateral crack faces (use step)",
                                        p);
        break;
      default:
        return BuildResult::failure(Code::invalid_argument, "prescribed.%zu.shape: must be step, half_sine or ramp", p);
    }
  }
  for (std::size_t l = 0; l < d.loads.size(); ++l) {
    const PlateLoad& ld = d.loads[l];
    const char* what = ld.kind == PlateLoad::Kind::edge_traction ? "traction" : "force";
    if (ld.kind == PlateLoad::Kind::edge_traction) {
      if (!valid_edge(ld.edge))
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.edge: must be left, right, bottom or top", l);
    } else if (ld.kind == PlateLoad::Kind::point_force) {
      for (int c = 0; c < 2; ++c) {
        int cell = 0;
        double xi = 0.0;
        if (!locate_axis(d.min[c], d.max[c], d.cells[c], ld.at[c], cell, xi))
          return BuildResult::failure(Code::invalid_argument, "loads.%zu.at: (%g, %g) is outside the domain", l,
                                      ld.at[0], ld.at[1]);
      }
    } else {
      return BuildResult::failure(Code::invalid_argument, "loads.%zu: unknown kind %d", l, static_cast<int>(ld.kind));
    }
    for (int c = 0; c < 2; ++c)
      if (!std::isfinite(ld.value[c]))
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.%s: must be finite", l, what);
    switch (ld.shape) {
      case PlateLoadShape::none:
      case PlateLoadShape::step:
        if (ld.duration != 0.0)
          return BuildResult::failure(Code::invalid_argument,
                                      "loads.%zu.duration: only a half_sine load has a duration; must be 0, got %g", l,
                                      ld.duration);
        break;
      case PlateLoadShape::half_sine:
        if (!dynamic)
          return BuildResult::failure(Code::invalid_argument,
                                      "loads.%zu.shape: a static analysis has no time; half_sine needs analysis "
                                      "dynamic (use step)",
                                      l);
        if (!positive_finite(ld.duration))
          return BuildResult::failure(Code::invalid_argument, "loads.%zu.duration: must be positive and finite (s), got %g",
                                      l, ld.duration);
        break;
      default:
        return BuildResult::failure(Code::invalid_argument, "loads.%zu.shape: must be none, step or half_sine", l);
    }
  }
  if (d.max_dofs < 0) return BuildResult::failure(Code::invalid_argument, "max_dofs: must be >= 0, got %d", d.max_dofs);
  if (d.max_enriched_dofs < 0)
    return BuildResult::failure(Code::invalid_argument, "max_enriched_dofs: must be >= 0, got %d", d.max_enriched_dofs);
  if (d.max_cut_cells < 0)
    return BuildResult::failure(Code::invalid_argument, "max_cut_cells: must be >= 0, got %d", d.max_cut_cells);
  if (!std::isfinite(d.tip_radius) || d.tip_radius < 0.0)
    return fail("tip_enrichment.radius: must be finite and >= 0 (m; 0: the nodes of the tip's cell only), got %g",
                d.tip_radius);
  if (BuildResult r = validate_discontinuities(d); !r.ok()) return r;
  // A point force or a prescribed node inside a void would act on nothing.
  for (std::size_t l = 0; l < d.loads.size(); ++l)
    if (const PlateLoad& ld = d.loads[l]; ld.kind == PlateLoad::Kind::point_force)
      if (const int v = void_at(d, {ld.at[0], ld.at[1]}); v >= 0)
        return BuildResult::failure(Code::invalid_argument,
                                    "loads.%zu.at: (%g, %g) is inside void '%s': there is no material there", l,
                                    ld.at[0], ld.at[1], d.discontinuities[static_cast<std::size_t>(v)].name.c_str());
  for (std::size_t p = 0; p < d.prescribed.size(); ++p)
    if (const int v = void_at(d, {d.prescribed[p].at[0], d.prescribed[p].at[1]}); v >= 0)
      return BuildResult::failure(Code::invalid_argument,
                                  "prescribed.%zu.at: (%g, %g) is inside void '%s': there is no material there", p,
                                  d.prescribed[p].at[0], d.prescribed[p].at[1],
                                  d.discontinuities[static_cast<std::size_t>(v)].name.c_str());
  if (BuildResult r = validate_energy_check(d.energy_check); !r.ok()) return r;
  return BuildResult::success();
}

// ---- build --------------------------------------------------------------------

/// Whether the centre x of a cell all of whose nodes lie on the boundary of
/// void or inclusion q (φ = 0 there) is inside it: the exact level set at x,
/// snapped to 0 within 1e-9 of a cell (h) as nodes are, and the one sign rule
/// (a point on the zero is outside). docs/xfem2d.md, "Thinner than the mesh".
bool centre_inside(const PlateDiscontinuity& q, Point2 x, double h) {
  const double exact = q.shape == PlateDiscontinuity::Shape::circle
                           ? xfem::circle_level_set({q.centre[0], q.centre[1]}, q.radius, x)
                           : xfem::polygon_level_set(q.points, x);
  return xfem::side_of(std::fabs(exact) <= 1e-9 * h ? 0.0 : exact) < 0;
}

/// The level set bounding a cell's material as it is integrated: the void's
/// at the nodes and the centre (cell_centre_phi) where a void cuts the cell
/// (alone, or with a crack); +1 everywhere in a cell of material otherwise
/// (uncut, or cut by a crack or an inclusion: material on both sides), −1 in
/// a cell without material. Returns the void (−1: none).
int cell_material_phi(const PlateModel& m, int i, int j, double phi[5]) {
  const PlateDesc& d = m.desc;
  const int nx = d.cells[0];
  const auto cell = static_cast<std::size_t>(j * nx + i);
  const int cut = m.cell_cut_by[cell], second = m.cell_second_cut[cell];
  int hole = -1;
  if (second >= 0 && d.discontinuities[static_cast<std::size_t>(second)].kind == PlateDiscontinuity::Kind::hole)
    hole = second;
  else if (second < 0 && cut >= 0 && d.discontinuities[static_cast<std::size_t>(cut)].kind == PlateDiscontinuity::Kind::hole)
    hole = cut;
  int en[4];
  cell_nodes(nx, i, j, en);
  if (m.cell_material[cell] < 0) {  // no material: the void it lies in, for the message
    for (int a = 0; a < 5; ++a) phi[a] = -1.0;
    if (hole >= 0) return hole;
    for (std::size_t k = 0; k < d.discontinuities.size(); ++k) {
      if (d.discontinuities[k].kind != PlateDiscontinuity::Kind::hole) continue;
      bool in = true;
      for (int a = 0; a < 4; ++a) in = in && phi_at(m, static_cast<int>(k), en[a]) <= 0.0;
      if (in) return static_cast<int>(k);
    }
    return -1;
  }
  if (hole < 0) {
    for (int a = 0; a < 5; ++a) phi[a] = 1.0;
    return -1;
  }
  for (int a = 0; a < 4; ++a) phi[a] = phi_at(m, hole, en[a]);
  const Point2 centre = {0.5 * (node_coord(d.min[0], d.max[0], i, nx) + node_coord(d.min[0], d.max[0], i + 1, nx)),
                         0.5 * (node_coord(d.min[1], d.max[1], j, d.cells[1]) +
                                node_coord(d.min[1], d.max[1], j + 1, d.cells[1]))};
  phi[4] = cell_centre_phi(d, hole, phi, centre, std::min(m.cell_size[0], m.cell_size[1]));
  return hole;
}

/// The part of a segment where a linear φ (a at its start, b at its end) is
/// material (φ > 0; the whole segment when φ = 0 along it), as [lo, hi] in
/// its parameter; empty when lo ≥ hi.
void material_interval(double a, double b, double& lo, double& hi) {
  if (a == 0.0 && b == 0.0) { lo = 0.0, hi = 1.0; return; }
  if (a <= 0.0 && b <= 0.0) { lo = 1.0, hi = 0.0; return; }
  if (a >= 0.0 && b >= 0.0) { lo = 0.0, hi = 1.0; return; }
  const double r = a / (a - b);
  if (a > 0.0) lo = 0.0, hi = r;
  else lo = r, hi = 1.0;
}

/// A void thinner than the mesh (docs/xfem2d.md, "Thinner than the mesh"):
/// a node whose support's material falls into parts the void separates
/// ties them together through its shape functions (no enrichment copies a
/// void's node per part): a slot narrower than about two cells was bridged,
/// a strip across the plate held its far side. The material is taken as it
/// is integrated: the parts of the four sub-triangles of each cell, split
/// along the void's φ_T. Parts connect through a shared edge (two
/// sub-triangles of a cell: the one to the centre; neighbouring cells: their
/// common cell edge) with material of positive length on both sides, and
/// at a node of the mesh where φ ≥ 0 that both touch (a void's corner or
/// boundary through the node). Connections count within the node's support
/// grown by one cell on each side (4 × 4 cells): a polygon's acute corner
/// is thinner than the mesh near its tip, and the material on its two sides
/// meets within a cell beyond the support there; a slot or a strip is
/// separated farther than that. A node at least a cell inside a void is
/// not checked (below). Refused, naming the void and the node.
BuildResult refuse_void_bridges(const PlateModel& m) {
  const PlateDesc& d = m.desc;
  const int nx = d.cells[0], ny = d.cells[1];
  constexpr int kPatch = 4;  // cells a side: the support (the middle 2 × 2) and a ring of one cell
  constexpr int kParts = 4 * kPatch * kPatch;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      // Patch cell (px, py) is the mesh's (i − 2 + px, j − 2 + py); the support's are px, py ∈ {1, 2}.
      double phi[kPatch * kPatch][5];
      bool present[kPatch * kPatch] = {};
      int hole = -1;
      for (int q = 0; q < kPatch * kPatch; ++q) {
        const int px = q % kPatch, py = q / kPatch;
        const int ci = i - 2 + px, cj = j - 2 + py;
        if (ci < 0 || cj < 0 || ci >= nx || cj >= ny) continue;
        present[q] = true;
        const int h = cell_material_phi(m, ci, cj, phi[q]);
        const bool support = px >= 1 && px <= 2 && py >= 1 && py <= 2;
        if (support && hole < 0) hole = h;
      }
      if (hole < 0) continue;  // no void in the support: its material is whole
      // A node at least a cell inside a void: the void holds the disc of
      // radius one cell about it (two cells across), and its support's
      // material lies only in the corners beyond that disc, where its shape
      // function is below (1 − 1/√2)² = 0.086 (a node near a circle's centre).
      bool deep = false;
      const int node = j * (nx + 1) + i;
      const double cell = std::min(m.cell_size[0], m.cell_size[1]);
      for (std::size_t k = 0; k < d.discontinuities.size() && !deep; ++k)
        deep = d.discontinuities[k].kind == PlateDiscontinuity::Kind::hole &&
               phi_at(m, static_cast<int>(k), node) <= -(1.0 - 1e-9) * cell;
      if (deep) continue;
      // Part 4 q + t: sub-triangle t (nodes t, t + 1 and the centre) of patch cell q.
      int parent[kParts];
      bool has[kParts] = {};
      for (int s = 0; s < kParts; ++s) parent[s] = s;
      auto find = [&](int s) {
        while (parent[s] != s) s = parent[s] = parent[parent[s]];
        return s;
      };
      auto join = [&](int a, int b) { parent[find(a)] = find(b); };
      for (int q = 0; q < kPatch * kPatch; ++q) {
        if (!present[q]) continue;
        const double* p = phi[q];
        for (int t = 0; t < 4; ++t) {
          const double a = p[t], b = p[(t + 1) % 4], c = p[4];
          has[4 * q + t] = a > 0.0 || b > 0.0 || c > 0.0 || (a == 0.0 && b == 0.0 && c == 0.0);
        }
        for (int t = 0; t < 4; ++t) {  // t and t + 1 share the edge from node t + 1 to the centre
          const int u = (t + 1) % 4;
          double lo = 0.0, hi = 0.0;
          material_interval(p[u], p[4], lo, hi);
          if (has[4 * q + t] && has[4 * q + u] && lo < hi) join(4 * q + t, 4 * q + u);
        }
      }
      // Common cell edges: cell a's edge (sub-triangle ta, local nodes a0 → a1) is cell b's (tb, b0 → b1).
      auto edge = [&](int qa, int ta, int a0, int a1, int qb, int tb, int b0, int b1) {
        if (!present[qa] || !present[qb]) return;
        const int sa = 4 * qa + ta, sb = 4 * qb + tb;
        if (!has[sa] || !has[sb]) return;
        double alo = 0.0, ahi = 0.0, blo = 0.0, bhi = 0.0;
        material_interval(phi[qa][a0], phi[qa][a1], alo, ahi);
        material_interval(phi[qb][b0], phi[qb][b1], blo, bhi);
        if (std::max(alo, blo) < std::min(ahi, bhi)) join(sa, sb);
      };
      for (int py = 0; py < kPatch; ++py)
        for (int px = 0; px < kPatch; ++px) {
          const int q = py * kPatch + px;
          if (px + 1 < kPatch) edge(q, 1, 1, 2, q + 1, 3, 0, 3);        // right | left: bottom to top
          if (py + 1 < kPatch) edge(q, 2, 3, 2, q + kPatch, 0, 0, 1);   // top | bottom: left to right
        }
      // Parts that touch at a node of the mesh where φ ≥ 0.
      int at_node[(kPatch + 1) * (kPatch + 1)];
      for (int& g : at_node) g = -1;
      for (int q = 0; q < kPatch * kPatch; ++q) {
        if (!present[q]) continue;
        for (int t = 0; t < 4; ++t) {
          if (!has[4 * q + t]) continue;
          for (const int a : {t, (t + 1) % 4}) {
            if (phi[q][a] < 0.0) continue;
            const int gx = q % kPatch + (a == 1 || a == 2 ? 1 : 0), gy = q / kPatch + (a >= 2 ? 1 : 0);
            int& slot = at_node[gy * (kPatch + 1) + gx];
            if (slot < 0) slot = 4 * q + t;
            else join(slot, 4 * q + t);
          }
        }
      }
      // The support's parts: one piece?
      int first = -1;
      bool split = false;
      for (int py = 1; py <= 2 && !split; ++py)
        for (int px = 1; px <= 2 && !split; ++px)
          for (int t = 0; t < 4 && !split; ++t) {
            const int s = 4 * (py * kPatch + px) + t;
            if (!present[py * kPatch + px] || !has[s]) continue;
            if (first < 0) first = find(s);
            else split = find(s) != first;
          }
      if (!split) continue;
      return BuildResult::failure(Code::invalid_argument,
                                  "discontinuities.%d: the void '%s' is thinner than the mesh at the node (%g, %g): "
                                  "the material in the node's cells lies in pieces the void separates, which the "
                                  "node's shape functions would tie together; refine the mesh",
                                  hole, d.discontinuities[static_cast<std::size_t>(hole)].name.c_str(),
                                  node_coord(d.min[0], d.max[0], i, nx), node_coord(d.min[1], d.max[1], j, ny));
    }
  return BuildResult::success();
}

BuildResult build_plate(const PlateDesc& desc, PlateModel& model, PlateState& state, PlateWorkspace& workspace) {
  model = PlateModel{};
  state = PlateState{};
  workspace = PlateWorkspace{};
  if (BuildResult r = validate_plate(desc); !r.ok()) return r;
  model.desc = desc;
  put_crack_ends_on_near_boundary(model.desc);
  put_cracks_on_near_node_lines(model.desc);
  const PlateDesc& d = model.desc;
  const int nx = d.cells[0], ny = d.cells[1];
  const int nodes = (nx + 1) * (ny + 1);
  model.nodes = nodes;
  const double hx = (d.max[0] - d.min[0]) / nx, hy = (d.max[1] - d.min[1]) / ny;
  model.cell_size[0] = hx;
  model.cell_size[1] = hy;
  auto xs = [&](int i) { return node_coord(d.min[0], d.max[0], i, nx); };
  auto ys = [&](int j) { return node_coord(d.min[1], d.max[1], j, ny); };

  // ---- material ---------------------------------------------------------------
  double(&dm)[3][3] = model.elasticity;
  fill_elasticity(d.plane, d.youngs_modulus, d.poisson_ratio, dm);
  model.wave_speed[0] = std::sqrt(dm[0][0] / d.density);
  model.wave_speed[1] = std::sqrt(dm[2][2] / d.density);
  plate_element_matrices(hx, hy, dm, d.thickness, d.density, model.element_stiffness, model.element_mass);

  // ---- discontinuities: level sets, cut cells, enriched nodes -----------------
  const std::size_t ndisc = d.discontinuities.size();
  if (ndisc > 0) {
    auto add_material = [&](double e, double nu, double rho) {
      double dd[3][3];
      fill_elasticity(d.plane, e, nu, dd);
      std::array<double, 9> flat{};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) flat[static_cast<std::size_t>(3 * r + c)] = dd[r][c];
      model.material_elasticity.push_back(flat);
      model.material_density.push_back(rho);
    };
    add_material(d.youngs_modulus, d.poisson_ratio, d.density);
    for (const PlateDiscontinuity& q : d.discontinuities)
      add_material(q.material.youngs_modulus, q.material.poisson_ratio, q.material.density);
    model.node_phi.assign(ndisc * static_cast<std::size_t>(nodes), 0.0);
    for (std::size_t k = 0; k < ndisc; ++k) {
      const std::vector<Point2> ext = extended_polyline(d, d.discontinuities[k]);
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
          model.node_phi[k * static_cast<std::size_t>(nodes) + static_cast<std::size_t>(j * (nx + 1) + i)] =
              level_set(d.discontinuities[k], ext, {xs(i), ys(j)});
      // Tiny cuts of an inclusion or a void: a node within 1e-9 of a cell of
      // the boundary is on it (φ = 0). The ridge's support does not shrink
      // with the cut (its span jumps when a boundary crosses a node), so the
      // answer is kept continuous by moving the boundary by at most 1e-9 of
      // a cell, far below the O(h²) of its piecewise-linear geometry. A
      // crack without a tip: a node within kCrackOnNodeCells of a cell of it
      // is on it (docs/xfem2d.md, "Edge slivers"): no strip thinner than
      // that is cut off along a row of nodes.
      const bool crack = d.discontinuities[k].kind == PlateDiscontinuity::Kind::crack;
      if (!crack || !crack_has_tip(d, d.discontinuities[k])) {
        const double on = (crack ? kCrackOnNodeCells : 1e-9) * std::min(hx, hy);
        for (int n = 0; n < nodes; ++n) {
          double& p = model.node_phi[k * static_cast<std::size_t>(nodes) + static_cast<std::size_t>(n)];
          if (std::fabs(p) <= on) p = 0.0;
        }
      }
    }
    const auto ncells = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    model.cell_cut_by.assign(ncells, -1);
    model.cell_second_cut.assign(ncells, -1);
    model.cell_material.assign(ncells, 0);
    // ---- crack tips: the ends strictly inside the domain ----------------------
    std::vector<char> has_tip(ndisc, 0), bounded(ndisc, 0);
    for (std::size_t k = 0; k < ndisc; ++k) {
      const PlateDiscontinuity& q = d.discontinuities[k];
      bounded[k] = crack_is_bounded(d, q) ? 1 : 0;
      if (!crack_has_tip(d, q)) continue;
      has_tip[k] = 1;
      for (const bool at_end : {false, true}) {
        if (!end_is_tip(d, q, at_end)) continue;
        if (model.cell_tip.empty()) {
          model.cell_tip.assign(ncells, -1);
          model.node_tip.assign(static_cast<std::size_t>(nodes), -1);
        }
        const xfem::TipFrame f = xfem::tip_frame(q.points, at_end);
        PlateModel::Tip tip;
        tip.crack = static_cast<int>(k), tip.at_end = at_end;
        tip.origin[0] = f.origin[0], tip.origin[1] = f.origin[1], tip.cos_a = f.cos_a, tip.sin_a = f.sin_a;
        // The tip's cell: the one holding the crack just behind the tip (a tip on a cell edge or node is in the
        // closure of several).
        const double back = 1e-6 * std::min(hx, hy);
        int ci = 0, cj = 0;
        double xi = 0.0, eta = 0.0;
        if (!locate_axis(d.min[0], d.max[0], nx, f.origin[0] - back * f.cos_a, ci, xi) ||
            !locate_axis(d.min[1], d.max[1], ny, f.origin[1] - back * f.sin_a, cj, eta))
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%zu.points: the tip of '%s' at (%g, %g) is within 1e-6 of a "
                                      "cell of the boundary",
                                      k, q.name.c_str(), f.origin[0], f.origin[1]);
        const auto cell = static_cast<std::size_t>(cj * nx + ci);
        if (model.cell_tip[cell] >= 0)
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%zu.points: two crack tips in the cell (%d, %d); this build "
                                      "allows one tip per cell (refine the mesh)",
                                      k, ci, cj);
        // Where the crack leaves the tip's cell: along the tip's segment, which must leave it.
        const Point2 prev = at_end ? q.points[q.points.size() - 2] : q.points[1];
        const double lo[2] = {xs(ci), ys(cj)}, hi[2] = {xs(ci + 1), ys(cj + 1)};
        if (!tip_exit(lo, hi, f.origin, prev, tip.exit)) {
          if (q.points.size() == 2)  // the straight crack's other end is in the tip's cell too
            return BuildResult::failure(Code::invalid_argument,
                                        "discontinuities.%zu.points: the crack '%s' from (%g, %g) to (%g, %g) lies "
                                        "inside the cell (%d, %d); this build needs a crack to leave the cell of each "
                                        "tip (refine the mesh)",
                                        k, q.name.c_str(), q.points.front()[0], q.points.front()[1],
                                        q.points.back()[0], q.points.back()[1], ci, cj);
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%zu.points: the crack '%s' bends inside the cell holding its tip "
                                      "at (%g, %g); this build needs it straight there (refine the mesh)",
                                      k, q.name.c_str(), f.origin[0], f.origin[1]);
        }
        tip.cell = static_cast<int>(cell);
        model.cell_tip[cell] = static_cast<int>(model.tips.size());
        model.tips.push_back(tip);
      }
    }
    // Branch functions: the nodes of each tip's cell and of every cell the tip
    // touches (on or within 1e-6 of a cell of its edge or corner: the set does
    // not depend on the side of a node row or column the tip is on), and
    // (tip_radius > 0) every node within the radius.
    for (std::size_t t = 0; t < model.tips.size(); ++t) {
      const PlateModel::Tip& tip = model.tips[t];
      const double r2 = d.tip_radius * d.tip_radius;
      int en[4];
      cell_nodes(nx, tip.cell % nx, tip.cell / nx, en);
      for (int n = 0; n < nodes; ++n) {
        const int i = n % (nx + 1), j = n / (nx + 1);
        const double dx = xs(i) - tip.origin[0], dy = ys(j) - tip.origin[1];
        const double lo[2] = {xs(std::max(i - 1, 0)), ys(std::max(j - 1, 0))};
        const double hi[2] = {xs(std::min(i + 1, nx)), ys(std::min(j + 1, ny))};
        const bool own = n == en[0] || n == en[1] || n == en[2] || n == en[3] || tip_touches(model, tip, lo, hi);
        if (!own && !(d.tip_radius > 0.0 && dx * dx + dy * dy <= r2)) continue;
        int& slot = model.node_tip[static_cast<std::size_t>(n)];
        if (slot >= 0 && slot != static_cast<int>(t)) {
          const PlateModel::Tip& first = model.tips[static_cast<std::size_t>(slot)];
          const char* a = d.discontinuities[static_cast<std::size_t>(first.crack)].name.c_str();
          const char* b = d.discontinuities[static_cast<std::size_t>(tip.crack)].name.c_str();
          if (d.tip_radius > 0.0 && !own)
            return BuildResult::failure(Code::invalid_argument,
                                        "tip_enrichment.radius: the node at (%g, %g) is within reach of two crack tips "
                                        "(the %s of '%s' and the %s of '%s'; reduce the radius or refine the mesh)",
                                        xs(n % (nx + 1)), ys(n / (nx + 1)), first.at_end ? "end" : "start", a,
                                        tip.at_end ? "end" : "start", b);
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%d.points: the node at (%g, %g) belongs to the cells of two "
                                      "crack tips (the %s of '%s' and the %s of '%s'); this build gives a node the "
                                      "branch functions of one tip: refine the mesh",
                                      tip.crack, xs(n % (nx + 1)), ys(n / (nx + 1)), first.at_end ? "end" : "start", a,
                                      tip.at_end ? "end" : "start", b);
        }
        if (slot < 0) ++model.tip_nodes;
        slot = static_cast<int>(t);
      }
    }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        int en[4];
        cell_nodes(nx, i, j, en);
        const auto cell = static_cast<std::size_t>(j * nx + i);
        for (std::size_t k = 0; k < ndisc; ++k) {
          double lo = INFINITY, hi = -INFINITY;
          for (int a = 0; a < 4; ++a) {
            const double p = phi_at(model, static_cast<int>(k), en[a]);
            lo = std::min(lo, p), hi = std::max(hi, p);
          }
          const PlateDiscontinuity& q = d.discontinuities[k];
          // A crack with an end inside the domain (a tip, or an end in a void)
          // cuts only the cells its polyline enters (not its extension).
          const double clo[2] = {xs(i), ys(j)}, chi[2] = {xs(i + 1), ys(j + 1)};
          if (lo < 0.0 && hi > 0.0 && (!bounded[k] || polyline_meets_box(q.points, clo, chi, true))) {  // area on both sides
            const int other = model.cell_cut_by[cell];
            if (other >= 0) {
              // A crack and a void (a crack from a hole) or a crack and an inclusion
              // (a crack into or across it) may share a cell: the crack in
              // cell_cut_by, the other in cell_second_cut.
              const PlateDiscontinuity& o = d.discontinuities[static_cast<std::size_t>(other)];
              const bool pair = (q.kind == PlateDiscontinuity::Kind::crack) != (o.kind == PlateDiscontinuity::Kind::crack);
              if (!pair || model.cell_second_cut[cell] >= 0)
                return BuildResult::failure(Code::invalid_argument,
                                            "discontinuities.%zu: '%s' and '%s' cut the same cell (%d, %d); this build "
                                            "allows one discontinuity per cell, or one crack and one void or inclusion "
                                            "(refine the mesh or move them apart)",
                                            k, q.name.c_str(), o.name.c_str(), i, j);
              model.cell_cut_by[cell] = q.kind == PlateDiscontinuity::Kind::crack ? static_cast<int>(k) : other;
              model.cell_second_cut[cell] = q.kind == PlateDiscontinuity::Kind::crack ? other : static_cast<int>(k);
              continue;
            }
            model.cell_cut_by[cell] = static_cast<int>(k);
          } else if (q.kind != PlateDiscontinuity::Kind::crack &&
                     (lo < 0.0 || (lo == 0.0 && hi == 0.0 &&
                                   centre_inside(q, {0.5 * (xs(i) + xs(i + 1)), 0.5 * (ys(j) + ys(j + 1))},
                                                 std::min(hx, hy))))) {
            // Wholly inside; or every node on the boundary (φ = 0, a void or an
            // inclusion one cell wide between node lines) and the centre inside by
            // the exact level set (docs/xfem2d.md, "Thinner than the mesh").
            model.cell_material[cell] = q.kind == PlateDiscontinuity::Kind::hole ? -1 : 1 + static_cast<int>(k);
          }
        }
        if (model.cell_cut_by[cell] >= 0) ++model.cut_cells;
      }
    // Cells cut by a crack and a void: which sides of the crack hold material
    // (bit 1: +, bit 2: −), from the pieces as they are integrated; the crack's
    // part outside the void must be the crack itself (an end in the void whose
    // extension leaves the void in the same cell is refused), and neither a
    // tip's branch functions nor the domain's edge may reach the cell. Cells
    // cut by a crack and an inclusion: material on both sides of the crack
    // (on the domain's edge too); a tip's branch functions may not reach them.
    std::vector<unsigned char> void_sides(ncells, 0);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const auto cell = static_cast<std::size_t>(j * nx + i);
        const int hv = model.cell_second_cut[cell];
        if (hv < 0) continue;
        const int k = model.cell_cut_by[cell];
        const PlateDiscontinuity& q = d.discontinuities[static_cast<std::size_t>(k)];
        const char* crack = q.name.c_str();
        const char* hole = d.discontinuities[static_cast<std::size_t>(hv)].name.c_str();
        if (d.discontinuities[static_cast<std::size_t>(hv)].kind == PlateDiscontinuity::Kind::inclusion) {
          int en[4];
          cell_nodes(nx, i, j, en);
          bool tip_here = !model.cell_tip.empty() && model.cell_tip[cell] >= 0;
          for (int a = 0; a < 4 && !model.node_tip.empty(); ++a)
            tip_here = tip_here || model.node_tip[static_cast<std::size_t>(en[a])] >= 0;
          if (tip_here)
            return BuildResult::failure(Code::invalid_argument,
                                        "discontinuities.%d: a crack tip's branch functions reach the cell (%d, %d) that "
                                        "the crack '%s' and the inclusion '%s' both cut; this build needs a tip at least "
                                        "a cell from such a cell (refine the mesh or move the tip from the inclusion's "
                                        "boundary)",
                                        k, i, j, crack, hole);
          void_sides[cell] = 3;
          continue;
        }
        if (i == 0 || j == 0 || i == nx - 1 || j == ny - 1)
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%d: the crack '%s' and the void '%s' cut the cell (%d, %d) on "
                                      "the domain's edge; this build needs a cell they both cut inside the domain "
                                      "(refine the mesh or move them from the edge)",
                                      k, crack, hole, i, j);
        int en[4];
        cell_nodes(nx, i, j, en);
        bool tip_here = !model.cell_tip.empty() && model.cell_tip[cell] >= 0;
        for (int a = 0; a < 4 && !model.node_tip.empty(); ++a) tip_here = tip_here || model.node_tip[static_cast<std::size_t>(en[a])] >= 0;
        if (tip_here)
          return BuildResult::failure(Code::invalid_argument,
                                      "discontinuities.%d: a crack tip's branch functions reach the cell (%d, %d) that "
                                      "the crack '%s' and the void '%s' both cut; this build needs a tip at least a "
                                      "cell from such a cell (refine the mesh or move the tip from the void)",
                                      k, i, j, crack, hole);
        double phi[5] = {}, vphi[5] = {}, mc = 0.0;
        for (int a = 0; a < 4; ++a) {
          mc += (phi[a] = phi_at(model, k, en[a]));
          vphi[a] = phi_at(model, hv, en[a]);
        }
        phi[4] = 0.25 * mc;
        vphi[4] = cell_centre_phi(d, hv, vphi, {0.5 * (xs(i) + xs(i + 1)), 0.5 * (ys(j) + ys(j + 1))}, std::min(hx, hy));
        const std::vector<Point2> ext = extended_polyline(d, q);
        for (int t = 0; t < 4; ++t) {
          Point2 tri[3];
          sub_triangle(t, tri);
          const double tp[3] = {phi[t], phi[(t + 1) % 4], phi[4]};
          xfem::TrianglePiece pieces[3];
          const int made = xfem::split_triangle(tri, tp, pieces);
          for (int p = 0; p < made; ++p) {
            xfem::TrianglePiece parts[3];
            const int np = material_parts(vphi, t, pieces[p], parts);
            for (int r = 0; r < np; ++r) {
              const xfem::TrianglePiece& g = parts[r];
              const double a2 = (g.v[1][0] - g.v[0][0]) * (g.v[2][1] - g.v[0][1]) - (g.v[1][1] - g.v[0][1]) * (g.v[2][0] - g.v[0][0]);
              if (a2 != 0.0) void_sides[cell] |= g.side > 0 ? 1 : 2;
            }
          }
          // The crack's line in the sub-triangle (where φ_T crosses zero).
          Point2 seg[2];
          int found = 0;
          for (int e = 0; e < 3 && found < 2; ++e) {
            const int a = e, b = (e + 1) % 3;
            if (tp[a] == 0.0) seg[found++] = tri[a];
            if (found < 2 && ((tp[a] < 0.0 && tp[b] > 0.0) || (tp[a] > 0.0 && tp[b] < 0.0))) {
              const double sc = tp[a] / (tp[a] - tp[b]);
              seg[found++] = {tri[a][0] + sc * (tri[b][0] - tri[a][0]), tri[a][1] + sc * (tri[b][1] - tri[a][1])};
            }
          }
          if (found < 2) continue;
          // Its part outside the void (the void's φ_T ≥ 0), then its middle against the polyline.
          double vs[2];
          for (int c = 0; c < 2; ++c) {
            double gx = 0.0, gy = 0.0;
            linear_on_triangle(t, vphi[t], vphi[(t + 1) % 4], vphi[4], seg[c][0], seg[c][1], vs[c], gx, gy);
          }
          if (vs[0] < 0.0 && vs[1] < 0.0) continue;
          double s0 = 0.0, s1 = 1.0;
          if (vs[0] < 0.0) s0 = vs[0] / (vs[0] - vs[1]);
          if (vs[1] < 0.0) s1 = vs[0] / (vs[0] - vs[1]);
          if (!(s1 > s0)) continue;
          const double sm = 0.5 * (s0 + s1);
          const Point2 mid = {xs(i) + 0.5 * (1.0 + seg[0][0] + sm * (seg[1][0] - seg[0][0])) * hx,
                              ys(j) + 0.5 * (1.0 + seg[0][1] + sm * (seg[1][1] - seg[0][1])) * hy};
          Point2 on{}, on_ext{}, dir{};
          xfem::polyline_closest(q.points, mid, on, dir);
          xfem::polyline_closest(ext, mid, on_ext, dir);
          if (std::hypot(mid[0] - on[0], mid[1] - on[1]) > std::hypot(mid[0] - on_ext[0], mid[1] - on_ext[1]) + 1e-9 * std::min(hx, hy))
            return BuildResult::failure(Code::invalid_argument,
                                        "discontinuities.%d: the extension of the crack '%s' beyond its end in the void "
                                        "'%s' leaves the void in the cell (%d, %d); this build needs the crack's end "
                                        "deeper in the void or a finer mesh",
                                        k, crack, hole, i, j);
        }
      }
    if (model.cut_cells > d.max_cut_cells)
      return BuildResult::failure(Code::capacity, "max_cut_cells: the discontinuities cut %d cells, more than %d",
                                  model.cut_cells, d.max_cut_cells);
    // Enriched nodes. A crack's (shifted Heaviside): the node's support has
    // material on both sides. An inclusion's (ridge): the node is a corner of a
    // cell it cuts. A function that would vanish identically gets no unknown.
    model.node_enrichment.assign(static_cast<std::size_t>(2 * nodes), -1);
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int n = j * (nx + 1) + i;
        for (std::size_t k = 0; k < ndisc; ++k) {
          const PlateDiscontinuity& q = d.discontinuities[k];
          if (q.kind == PlateDiscontinuity::Kind::hole || !q.enrich) continue;
          if (has_tip[k]) {
            // A crack with a tip: no Heaviside on a node with branch functions of
            // its tip or with the tip strictly inside its support (not split by it).
            const int t = model.node_tip[static_cast<std::size_t>(n)];
            if (t >= 0 && model.tips[static_cast<std::size_t>(t)].crack == static_cast<int>(k)) continue;
            bool tip_inside = false;
            for (const PlateModel::Tip& tip : model.tips)
              tip_inside = tip_inside || (tip.crack == static_cast<int>(k) && tip.origin[0] > xs(std::max(i - 1, 0)) &&
                                          tip.origin[0] < xs(std::min(i + 1, nx)) && tip.origin[1] > ys(std::max(j - 1, 0)) &&
                                          tip.origin[1] < ys(std::min(j + 1, ny)));
            if (tip_inside) continue;
          }
          bool plus = false, minus = false, cut = false;
          // A crack's shifted Heaviside N_n (H − H(x_n)) lives on the other side
          // of the crack from the node. When that side holds a single node of
          // the support, within kCornerSliverCells of a cell of the crack, it is
          // a corner of size at most that cut off around that node: no unknown
          // ("Tiny cuts", docs/xfem2d.md).
          const bool node_plus = phi_at(model, static_cast<int>(k), n) >= 0.0;
          bool far_other = false, several_near = false;
          int near_node = -1;
          for (int cj = std::max(j - 1, 0); cj <= std::min(j, ny - 1); ++cj)
            for (int ci = std::max(i - 1, 0); ci <= std::min(i, nx - 1); ++ci) {
              const auto cell = static_cast<std::size_t>(cj * nx + ci);
              int en[4];
              cell_nodes(nx, ci, cj, en);
              if (model.cell_material[cell] < 0) continue;  // no material in the cell
              if (bounded[k]) {
                // Sides count only where the crack itself (not its extension) reaches the cell.
                const double clo[2] = {xs(ci), ys(cj)}, chi[2] = {xs(ci + 1), ys(cj + 1)};
                if (!polyline_meets_box(q.points, clo, chi, false)) continue;
              }
              for (int a = 0; a < 4; ++a) {
                const double pb = phi_at(model, static_cast<int>(k), en[a]);
                if ((pb >= 0.0) == node_plus) continue;
                if (std::fabs(pb) > kCornerSliverCells * std::min(hx, hy)) {
                  far_other = true;
                } else if (near_node < 0) {
                  near_node = en[a];
                } else if (near_node != en[a]) {
                  several_near = true;
                }
              }
              if (model.cell_second_cut[cell] == static_cast<int>(k)) {
                cut = true;  // an inclusion cutting the cell with a crack
              } else if (model.cell_cut_by[cell] == static_cast<int>(k) && model.cell_second_cut[cell] >= 0) {
                // Cut by a void too: only the sides with material outside it (both with an inclusion).
                cut = true;
                plus = plus || (void_sides[cell] & 1) != 0;
                minus = minus || (void_sides[cell] & 2) != 0;
              } else if (model.cell_cut_by[cell] == static_cast<int>(k)) {
                cut = plus = minus = true;
              } else {
                (uncut_side(model, static_cast<int>(k), en) > 0 ? plus : minus) = true;
              }
            }
          const bool corner_sliver = !far_other && near_node >= 0 && !several_near;
          const bool enrich = q.kind == PlateDiscontinuity::Kind::crack ? (plus && minus && !corner_sliver) : cut;
          if (!enrich) continue;
          const auto slot = static_cast<std::size_t>(2 * n);
          if (model.node_enrichment[slot] < 0) {
            model.node_enrichment[slot] = static_cast<int>(k);
          } else if (model.node_enrichment[slot + 1] < 0) {
            model.node_enrichment[slot + 1] = static_cast<int>(k);
          } else {
            return BuildResult::failure(Code::invalid_argument,
                                        "discontinuities.%zu: the node at (%g, %g) would be enriched by more than two "
                                        "discontinuities (they come within a cell of one another; refine the mesh)",
                                        k, xs(i), ys(j));
          }
        }
      }
  }

  // ---- constraints ----------------------------------------------------------
  // Nodes of an edge, in order along it.
  auto edge_nodes = [&](PlateEdge edge, auto&& visit) {
    switch (edge) {
      case PlateEdge::left:
        for (int j = 0; j <= ny; ++j) visit(j * (nx + 1), ys(j));
        break;
      case PlateEdge::right:
        for (int j = 0; j <= ny; ++j) visit(j * (nx + 1) + nx, ys(j));
        break;
      case PlateEdge::bottom:
        for (int i = 0; i <= nx; ++i) visit(i, xs(i));
        break;
      case PlateEdge::top:
        for (int i = 0; i <= nx; ++i) visit(ny * (nx + 1) + i, xs(i));
        break;
    }
  };
  const auto n2 = static_cast<std::size_t>(2 * nodes);
  std::vector<int> held(n2, 0);  // 0 free, 1 support, 2 prescribed
  std::vector<int> held_by(n2, -1);
  model.node_held.assign(n2, 0.0);
  for (std::size_t s = 0; s < d.supports.size(); ++s)
    edge_nodes(d.supports[s].edge, [&](int n, double) {
      for (int c = 0; c < 2; ++c)
        if (d.supports[s].fix[c] && held[static_cast<std::size_t>(2 * n + c)] == 0) {
          held[static_cast<std::size_t>(2 * n + c)] = 1;
          held_by[static_cast<std::size_t>(2 * n + c)] = static_cast<int>(s);
        }
    });
  for (std::size_t p = 0; p < d.prescribed.size(); ++p) {
    const PlatePrescribed& pr = d.prescribed[p];
    const int i = static_cast<int>(std::lround((pr.at[0] - d.min[0]) / hx));
    const int j = static_cast<int>(std::lround((pr.at[1] - d.min[1]) / hy));
    if (i < 0 || i > nx || j < 0 || j > ny || std::fabs(pr.at[0] - xs(i)) > 1e-9 * hx ||
        std::fabs(pr.at[1] - ys(j)) > 1e-9 * hy)
      return BuildResult::failure(Code::invalid_argument,
                                  "prescribed.%zu.at: (%g, %g) is not a node of the mesh (within 1e-9 of a cell)", p,
                                  pr.at[0], pr.at[1]);
    const int n = j * (nx + 1) + i;
    for (int c = 0; c < 2; ++c) {
      const auto k = static_cast<std::size_t>(2 * n + c);
      if (held[k] == 1 && pr.displacement[c] != 0.0)
        return BuildResult::failure(Code::invalid_argument,
                                    "prescribed.%zu.displacement: the node at (%g, %g) is held at 0 in %s by "
                                    "supports.%d (edge %s)",
                                    p, pr.at[0], pr.at[1], c == 0 ? "x" : "y", held_by[k],
                                    edge_name(d.supports[static_cast<std::size_t>(held_by[k])].edge));
      if (held[k] == 2 && model.node_held[k] != pr.displacement[c])
        return BuildResult::failure(Code::invalid_argument,
                                    "prescribed.%zu.displacement: the node at (%g, %g) is already prescribed by "
                                    "prescribed.%d with another value",
                                    p, pr.at[0], pr.at[1], held_by[k]);
      if (held[k] == 2 && pr.displacement[c] != 0.0) {
        const PlatePrescribed& first = d.prescribed[static_cast<std::size_t>(held_by[k])];
        if (first.shape != pr.shape || first.duration != pr.duration)
          return BuildResult::failure(Code::invalid_argument,
                                      "prescribed.%zu.shape: the node at (%g, %g) is already prescribed by "
                                      "prescribed.%d with another shape or duration",
                                      p, pr.at[0], pr.at[1], held_by[k]);
      }
      if (held[k] == 0) {
        held[k] = 2;
        held_by[k] = static_cast<int>(p);
        model.node_held[k] = pr.displacement[c];
      }
    }
  }
  // Components that move: prescribed with a shape other than step and a
  // nonzero amplitude (node_held keeps the amplitude d; the displacement at
  // t is d times the shape there).
  model.node_moving.clear();
  model.moving_component.clear();
  model.moving_prescribed.clear();
  model.moving_amplitude.clear();
  for (std::size_t k = 0; k < n2; ++k) {
    if (held[k] != 2 || model.node_held[k] == 0.0) continue;
    if (d.prescribed[static_cast<std::size_t>(held_by[k])].shape == PlatePrescribedShape::step) continue;
    if (model.node_moving.empty()) model.node_moving.assign(n2, -1);
    model.node_moving[k] = static_cast<int>(model.moving_component.size());
    model.moving_component.push_back(static_cast<int>(k));
    model.moving_prescribed.push_back(held_by[k]);
    model.moving_amplitude.push_back(model.node_held[k]);
  }

  // A void thinner than the mesh: a node whose support's material falls into
  // pieces not connected within the support would tie them together.
  if (ndisc > 0)
    if (BuildResult r = refuse_void_bridges(model); !r.ok()) return r;
  // A node whose support holds no material (wholly in a hole) has no unknowns.
  std::vector<char> has_material(static_cast<std::size_t>(nodes), 1);
  if (ndisc > 0)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        bool any = false;
        for (int cj = std::max(j - 1, 0); cj <= std::min(j, ny - 1); ++cj)
          for (int ci = std::max(i - 1, 0); ci <= std::min(i, nx - 1); ++ci)
            any = any || model.cell_material[static_cast<std::size_t>(cj * nx + ci)] >= 0;
        has_material[static_cast<std::size_t>(j * (nx + 1) + i)] = any ? 1 : 0;
      }
  // Supports hold the enrichment of their nodes in the fixed components too.
  std::vector<char> enriched_held(ndisc > 0 ? 2 * n2 : 0, 0);
  for (const PlateSupport& sp : d.supports)
    if (ndisc > 0)
      edge_nodes(sp.edge, [&](int n, double) {
        for (int sl = 0; sl < 2; ++sl)
          for (int c = 0; c < 2; ++c)
            if (sp.fix[c]) enriched_held[static_cast<std::size_t>(2 * (2 * n + sl) + c)] = 1;
      });
  const bool tips = !model.tips.empty();
  if (tips) model.tip_dof.assign(4 * n2, -1);

  // ---- unknowns: node by node along the shorter side (a narrow profile), ----
  // each node's enrichment right after its own components.
  model.node_dof.assign(n2, -1);
  if (ndisc > 0) model.enriched_dof.assign(2 * n2, -1);
  int next = 0;
  const bool rows = nx <= ny;
  for (int r = 0; r < nodes; ++r) {
    const int i = rows ? r % (nx + 1) : r / (ny + 1);
    const int j = rows ? r / (nx + 1) : r % (ny + 1);
    const int n = j * (nx + 1) + i;
    if (!has_material[static_cast<std::size_t>(n)]) continue;
    for (int c = 0; c < 2; ++c)
      if (held[static_cast<std::size_t>(2 * n + c)] == 0) model.node_dof[static_cast<std::size_t>(2 * n + c)] = next++;
    if (ndisc == 0) continue;
    for (int sl = 0; sl < 2; ++sl) {
      if (model.node_enrichment[static_cast<std::size_t>(2 * n + sl)] < 0) continue;
      for (int c = 0; c < 2; ++c) {
        const auto e = static_cast<std::size_t>(2 * (2 * n + sl) + c);
        if (enriched_held[e]) continue;
        model.enriched_dof[e] = next++;
        ++model.enriched_dofs;
      }
    }
    if (!tips || model.node_tip[static_cast<std::size_t>(n)] < 0) continue;
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 2; ++c) {
        // Held by a support in the components it fixes, as the Heaviside unknowns.
        if (!enriched_held.empty() && enriched_held[static_cast<std::size_t>(2 * (2 * n) + c)]) continue;
        model.tip_dof[static_cast<std::size_t>(8 * n + 2 * b + c)] = next++;
        ++model.enriched_dofs;
      }
  }
  model.dofs = next;
  if (model.enriched_dofs > d.max_enriched_dofs)
    return BuildResult::failure(Code::capacity,
                                "max_enriched_dofs: the discontinuities need %d enriched unknowns, more than %d",
                                model.enriched_dofs, d.max_enriched_dofs);
  if (d.max_dofs > 0 && model.dofs > d.max_dofs)
    return BuildResult::failure(Code::capacity, "max_dofs: the mesh needs %d unknowns, more than max_dofs = %d",
                                model.dofs, d.max_dofs);
  if (model.dofs == 0)
    return BuildResult::failure(Code::invalid_argument, "supports: every nodal displacement is held; nothing to solve");
  const int nd = model.dofs;
  const auto nds = static_cast<std::size_t>(nd);

  // ---- profile and assembly ---------------------------------------------------
  std::vector<int> first(nds);
  for (int k = 0; k < nd; ++k) first[static_cast<std::size_t>(k)] = k;
  CellView view;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      make_view(model, i, j, view);
      int lowest = std::numeric_limits<int>::max();
      for (int f = 0; f < view.count; ++f)
        for (int c = 0; c < 2; ++c)
          if (view.dof[f][c] >= 0) lowest = std::min(lowest, view.dof[f][c]);
      for (int f = 0; f < view.count; ++f)
        for (int c = 0; c < 2; ++c)
          if (view.dof[f][c] >= 0)
            first[static_cast<std::size_t>(view.dof[f][c])] = std::min(first[static_cast<std::size_t>(view.dof[f][c])], lowest);
    }
  model.mass.resize(nd, first);
  model.stiffness.resize(nd, first);
  model.held_force.assign(nds, 0.0);
  model.node_mass.assign(static_cast<std::size_t>(nodes), 0.0);
  if (ndisc > 0) model.enrichment_mass.assign(n2, 0.0);
  if (tips) model.tip_mass.assign(2 * n2, 0.0);
  const double det_j = 0.25 * hx * hy;
  constexpr int kMaxCellDofs = 2 * kMaxCellFunctions;
  using MatE = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCellDofs, kMaxCellDofs>;
  MatE ke_general, me_general;
  // (moving component, unknown or natural held component) → (K, M) entries.
  std::map<std::pair<int, int>, std::array<double, 2>> moving_free, moving_held;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      make_view(model, i, j, view);
      const int nf = 2 * view.count;
      const double* ke = model.element_stiffness;
      const double* me = model.element_mass;
      int stride = 8;
      if (!view.plain) {
        // Integrated on the cell's quadrature (sub-triangles when cut).
        ke_general.setZero(nf, nf);
        me_general.setZero(nf, nf);
        BasisAt basis;
        for_each_point(model, view, [&](double xi, double eta, double w, int tri, int side, int material) {
          evaluate(model, view, xi, eta, tri, side, basis);
          const std::array<double, 9>& dd = model.material_elasticity[static_cast<std::size_t>(material)];
          const double rho = model.material_density[static_cast<std::size_t>(material)];
          const double wt = w * det_j * d.thickness;
          Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxCellDofs> bm(3, nf);
          Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCellFunctions, 1> nv(view.count);
          bm.setZero();
          for (int f = 0; f < view.count; ++f) {
            bm(0, 2 * f) = basis.dx[f];
            bm(1, 2 * f + 1) = basis.dy[f];
            bm(2, 2 * f) = basis.dy[f];
            bm(2, 2 * f + 1) = basis.dx[f];
            nv(f) = basis.n[f];
          }
          Eigen::Matrix3d dmat;
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) dmat(r, c) = dd[static_cast<std::size_t>(3 * r + c)];
          ke_general.noalias() += wt * (bm.transpose() * dmat * bm);
          for (int f = 0; f < view.count; ++f) {
            for (int g = 0; g < view.count; ++g) {
              const double mfg = wt * rho * nv(f) * nv(g);
              me_general(2 * f, 2 * g) += mfg;
              me_general(2 * f + 1, 2 * g + 1) += mfg;
            }
            if (view.tip[f] >= 0) {
              model.tip_mass[static_cast<std::size_t>(4 * view.en[view.node[f]] + view.branch[f])] += wt * rho * nv(f);
            } else if (view.disc[f] < 0) {
              model.node_mass[static_cast<std::size_t>(view.en[view.node[f]])] += wt * rho * nv(f);
            } else {
              const int en = view.en[view.node[f]];
              const int sl = model.node_enrichment[static_cast<std::size_t>(2 * en)] == view.disc[f] ? 0 : 1;
              model.enrichment_mass[static_cast<std::size_t>(2 * en + sl)] += wt * rho * nv(f);
            }
          }
        });
        // Exactly symmetric.
        for (int r = 0; r < nf; ++r)
          for (int c = r + 1; c < nf; ++c) {
            ke_general(c, r) = ke_general(r, c);
            me_general(c, r) = me_general(r, c);
          }
        annihilate_translations(ke_general, nf);
        ke = ke_general.data();  // column-major = row-major for a symmetric matrix
        me = me_general.data();
        stride = nf;
      }
      for (int a = 0; a < nf; ++a) {
        const int ra = view.dof[a / 2][a % 2];
        if (ra < 0) continue;
        for (int b = 0; b <= a; ++b) {
          const int rb = view.dof[b / 2][b % 2];
          if (rb < 0) continue;
          model.stiffness.add(ra, rb, ke[a * stride + b]);
          model.mass.add(ra, rb, me[a * stride + b]);
        }
        for (int b = 0; b < nf; ++b)
          if (view.dof[b / 2][b % 2] < 0) {
            // A moving component's push depends on t: the step adds it (moving_free_*).
            if (b < 8 && !model.node_moving.empty() &&
                model.node_moving[static_cast<std::size_t>(2 * view.en[b / 2] + b % 2)] >= 0)
              continue;
            const double g = view.held[b / 2][b % 2];
            if (g != 0.0) model.held_force[static_cast<std::size_t>(ra)] -= ke[a * stride + b] * g;
          }
      }
      // The moving components' rows of K and M (the standard functions come
      // first, make_view), summed over the cells in cell order.
      if (!model.node_moving.empty())
        for (int a = 0; a < 8; ++a) {
          if (view.dof[a / 2][a % 2] >= 0) continue;
          const int h = model.node_moving[static_cast<std::size_t>(2 * view.en[a / 2] + a % 2)];
          if (h < 0) continue;
          for (int b = 0; b < nf; ++b) {
            const int rb = view.dof[b / 2][b % 2];
            const double kv = ke[a * stride + b], mv = me[a * stride + b];
            if (rb >= 0) {
              auto& e = moving_free[{h, rb}];
              e[0] += kv, e[1] += mv;
            } else if (b < 8) {
              auto& e = moving_held[{h, 2 * view.en[b / 2] + b % 2}];
              e[0] += kv, e[1] += mv;
            }
          }
        }
      // The element stiffness again, for the step's cell-by-cell K x.
      if (view.plain) {
        for (int a = 0; a < 8; ++a) model.plain_cell_dof.push_back(view.dof[a / 2][a % 2]);
      } else {
        if (model.other_cell_start.empty()) model.other_cell_start.push_back(0);
        model.other_cell_matrix_start.push_back(static_cast<int>(model.other_cell_matrix.size()));
        for (int a = 0; a < nf; ++a) model.other_cell_dof.push_back(view.dof[a / 2][a % 2]);
        model.other_cell_start.push_back(static_cast<int>(model.other_cell_dof.size()));
        for (int a = 0; a < nf; ++a)
          for (int b = 0; b < nf; ++b) model.other_cell_matrix.push_back(ke[a * stride + b]);
      }
      if (view.plain)
        // ρ t ∫ N_a dA: the x rows' sums of the element mass.
        for (int a = 0; a < 4; ++a) {
          double sum = 0.0;
          for (int b = 0; b < 4; ++b) sum += me[(2 * a) * 8 + 2 * b];
          model.node_mass[static_cast<std::size_t>(view.en[a])] += sum;
        }
    }
  {
    const std::size_t moving = model.moving_component.size();
    model.moving_free_start.assign(moving == 0 ? 0 : moving + 1, 0);
    model.moving_held_start.assign(moving == 0 ? 0 : moving + 1, 0);
    model.moving_free_dof.clear(), model.moving_free_k.clear(), model.moving_free_m.clear();
    model.moving_held_component.clear(), model.moving_held_k.clear(), model.moving_held_m.clear();
    for (const auto& [key, km] : moving_free) {  // ordered by (h, unknown)
      model.moving_free_dof.push_back(key.second);
      model.moving_free_k.push_back(km[0]);
      model.moving_free_m.push_back(km[1]);
      ++model.moving_free_start[static_cast<std::size_t>(key.first) + 1];
    }
    for (const auto& [key, km] : moving_held) {
      model.moving_held_component.push_back(key.second);
      model.moving_held_k.push_back(km[0]);
      model.moving_held_m.push_back(km[1]);
      ++model.moving_held_start[static_cast<std::size_t>(key.first) + 1];
    }
    for (std::size_t h = 0; h < moving; ++h) {
      model.moving_free_start[h + 1] += model.moving_free_start[h];
      model.moving_held_start[h + 1] += model.moving_held_start[h];
    }
  }

  // ---- tied or unilateral crack faces: penalty k [u]·[u] on the crack ---------
  if (ndisc > 0) {
    const double g3[3] = {0.5 * (1.0 - std::sqrt(0.6)), 0.5, 0.5 * (1.0 + std::sqrt(0.6))};
    const double w3[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    std::vector<std::vector<Point2>> extended(ndisc);
    for (std::size_t k = 0; k < ndisc; ++k) extended[k] = extended_polyline(d, d.discontinuities[k]);
    // One face point at parent (xi, eta) of the cell, normal (gx, gy) towards +.
    auto add_point = [&](const CellView& cell, int k, double xi, double eta, double gx, double gy, double weight) {
      const PlateDiscontinuity& q = d.discontinuities[static_cast<std::size_t>(k)];
      const bool unilateral = q.faces == PlateDiscontinuity::Faces::unilateral;
      PlateModel::FacePoint fp{};
      face_terms(model, cell, k, xi, eta, gx, gy, fp);
      fp.weight = weight;
      fp.k_normal = q.stiffness[0];
      fp.k_tangential = unilateral ? 0.0 : q.stiffness[1];
      fp.unilateral = unilateral;
      model.face_points.push_back(fp);
      if (unilateral) {
        ++model.unilateral_points;
        return;
      }
      for (int a = 0; a < fp.terms; ++a) {
        if (fp.dof[a] < 0) continue;
        for (int b = 0; b < fp.terms; ++b) {
          if (fp.dof[b] < 0 || fp.dof[b] > fp.dof[a]) continue;
          model.stiffness.add(fp.dof[a], fp.dof[b],
                              fp.weight * (fp.k_normal * fp.normal[a] * fp.normal[b] +
                                           fp.k_tangential * fp.tangential[a] * fp.tangential[b]));
        }
      }
    };
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        int en[4];
        cell_nodes(nx, i, j, en);
        if (model.cell_material[static_cast<std::size_t>(j * nx + i)] < 0) continue;
        bool viewed = false;
        for (std::size_t k = 0; k < ndisc; ++k) {
          const PlateDiscontinuity& q = d.discontinuities[k];
          if (q.kind != PlateDiscontinuity::Kind::crack || q.faces == PlateDiscontinuity::Faces::free) continue;
          if (!viewed) make_view(model, i, j, view), viewed = true;
          const int own_tip = view.tip_cell >= 0 && model.tips[static_cast<std::size_t>(view.tip_cell)].crack == static_cast<int>(k)
                                  ? view.tip_cell
                                  : -1;
          if (own_tip >= 0) {
            // The tip's cell: the straight crack from the tip to where it leaves
            // the cell, s = L t² from the tip and 5-point Gauss in t: the jump's
            // products (r, √r and 1 times N_a N_b, N linear in s) become
            // polynomials of degree ≤ 7 in t, integrated exactly.
            const PlateModel::Tip& t = model.tips[static_cast<std::size_t>(own_tip)];
            const double p0 = 2.0 * (t.origin[0] - view.x0[0]) / hx - 1.0, p1 = 2.0 * (t.origin[1] - view.x0[1]) / hy - 1.0;
            const double e0 = t.exit[0] - p0, e1 = t.exit[1] - p1;
            const double length = std::hypot(e0 * 0.5 * hx, e1 * 0.5 * hy);
            if (length == 0.0) continue;
            const double sign = branch_jump_sign(t);
            for (int qp = 0; qp < 5; ++qp) {
              const double tq = kGl5x[qp];
              add_point(view, static_cast<int>(k), p0 + tq * tq * e0, p1 + tq * tq * e1, -sign * t.sin_a, sign * t.cos_a,
                        d.thickness * 2.0 * length * tq * kGl5w[qp]);
            }
            continue;
          }
          double phi[5], mean = 0.0;
          for (int a = 0; a < 4; ++a) mean += (phi[a] = phi_at(model, static_cast<int>(k), en[a]));
          phi[4] = 0.25 * mean;
          // A face is counted once: by the sub-triangle on its negative side.
          for (int t = 0; t < 4; ++t) {
            Point2 tri[3];
            sub_triangle(t, tri);
            const double tp[3] = {phi[t], phi[(t + 1) % 4], phi[4]};
            Point2 seg[2];
            int found = 0;
            bool neg = false;
            for (double v : tp) neg = neg || v < 0.0;
            if (!neg) continue;
            for (int e = 0; e < 3 && found < 2; ++e) {
              const int a = e, b = (e + 1) % 3;
              if (tp[a] == 0.0) seg[found++] = tri[a];
              if (found < 2 && ((tp[a] < 0.0 && tp[b] > 0.0) || (tp[a] > 0.0 && tp[b] < 0.0))) {
                const double sc = tp[a] / (tp[a] - tp[b]);
                seg[found++] = {tri[a][0] + sc * (tri[b][0] - tri[a][0]), tri[a][1] + sc * (tri[b][1] - tri[a][1])};
              }
            }
            // A crossing or two vertices on the zero: either way two points.
            if (found < 2) continue;
            if (view.second_cut >= 0 && view.cut == static_cast<int>(k) &&
                d.discontinuities[static_cast<std::size_t>(view.second_cut)].kind == PlateDiscontinuity::Kind::hole) {
              // A cell the void cuts too: the faces outside the void only (its φ_T ≥ 0).
              double vs[2];
              for (int c = 0; c < 2; ++c) {
                double g0 = 0.0, g1 = 0.0;
                linear_on_triangle(t, view.second_phi[t], view.second_phi[(t + 1) % 4], view.second_phi[4], seg[c][0], seg[c][1],
                                   vs[c], g0, g1);
              }
              if (vs[0] < 0.0 && vs[1] < 0.0) continue;
              if (vs[0] < 0.0 || vs[1] < 0.0) {
                const double sc = vs[0] / (vs[0] - vs[1]);
                const Point2 cut = {seg[0][0] + sc * (seg[1][0] - seg[0][0]), seg[0][1] + sc * (seg[1][1] - seg[0][1])};
                seg[vs[0] < 0.0 ? 0 : 1] = cut;
              }
            }
            const double lx = (seg[1][0] - seg[0][0]) * 0.5 * hx, ly = (seg[1][1] - seg[0][1]) * 0.5 * hy;
            const double length = std::hypot(lx, ly);
            if (length == 0.0) continue;
            if (crack_is_bounded(d, q)) {
              // Only the crack, not its extension beyond a tip: the piece's middle is
              // (to round-off) as near the polyline as the extended one.
              const Point2 mid = physical(view, 0.5 * (seg[0][0] + seg[1][0]), 0.5 * (seg[0][1] + seg[1][1]));
              Point2 on{}, on_ext{}, dir{};
              xfem::polyline_closest(q.points, mid, on, dir);
              xfem::polyline_closest(extended[k], mid, on_ext, dir);
              if (std::hypot(mid[0] - on[0], mid[1] - on[1]) >
                  std::hypot(mid[0] - on_ext[0], mid[1] - on_ext[1]) + 1e-9 * std::min(hx, hy))
                continue;
            }
            // Normal: the gradient of the linear level set on this triangle (towards +).
            const double x0 = tri[0][0], y0 = tri[0][1], x1 = tri[1][0], y1 = tri[1][1];
            const double r0 = tp[0] - tp[2], r1 = tp[1] - tp[2], det = x0 * y1 - x1 * y0;
            double gx = (r0 * y1 - r1 * y0) / det * (2.0 / hx), gy = (x0 * r1 - x1 * r0) / det * (2.0 / hy);
            const double gl = std::hypot(gx, gy);
            gx /= gl, gy /= gl;
            // 3 Gauss points: exact for the Heaviside jumps' products (quadratic
            // along the piece); 5 where branch functions reach the cell (√r N_a N_b,
            // smooth there: the tip is not in the cell).
            const int points = view.tip_functions ? 5 : 3;
            for (int qp = 0; qp < points; ++qp) {
              const double gq = points == 5 ? kGl5x[qp] : g3[qp], wq = points == 5 ? kGl5w[qp] : w3[qp];
              const double xi = seg[0][0] + gq * (seg[1][0] - seg[0][0]);
              const double eta = seg[0][1] + gq * (seg[1][1] - seg[0][1]);
              add_point(view, static_cast<int>(k), xi, eta, gx, gy, d.thickness * length * wq);
            }
          }
        }
      }
  }

  // M r, r = 1 on the standard unknowns, 0 on the enriched: the net force 1ᵀMa.
  model.mass_row_sums.assign(nds, 0.0);
  {
    std::vector<double> ones(nds, 1.0);
    if (ndisc > 0)
      for (double& e2 : ones) e2 = 0.0;
    for (std::size_t k = 0; k < n2; ++k)
      if (model.node_dof[k] >= 0) ones[static_cast<std::size_t>(model.node_dof[k])] = 1.0;
    model.mass.multiply(ones.data(), model.mass_row_sums.data());
  }

  // ---- dashpots of absorbing edges --------------------------------------------
  // Lysmer: traction −ρc_p v_n − ρc_s v_t on the edge. On the standard unknowns
  // lumped (each node ∫ρc N_a over its segments: half of each plain segment);
  // a segment whose cell is cut, carries enrichment or another material is
  // integrated along its material part (for_each_edge_point) with that
  // material's ρc, and every product that involves an enrichment function
  // is kept consistent: a block of C per segment and component
  // (PlateModel::absorb_*), so that the enrichment of a crack or inclusion
  // reaching the edge is absorbed too.
  {
    std::vector<double> c_dof(nds, 0.0);
    model.absorb_start.assign(1, 0);
    model.absorb_matrix_start.assign(1, 0);
    for (const PlateSupport& sp : d.supports) {
      if (!sp.absorbing) continue;
      const bool vertical = sp.edge == PlateEdge::left || sp.edge == PlateEdge::right;
      const int normal = vertical ? 0 : 1;
      const int count = vertical ? ny : nx;
      const double h = vertical ? hy : hx;
      std::vector<char> plain(static_cast<std::size_t>(count), 1);
      for (int e2 = 0; e2 < count && ndisc > 0; ++e2) {
        const EdgeSegment g = edge_segment(d, sp.edge, e2);
        make_view(model, g.ci, g.cj, view);
        if (view.plain) continue;
        plain[static_cast<std::size_t>(e2)] = 0;
        // Points of the segment: every function there, the material's ρc per component.
        constexpr int kMaxEdgePoints = 6;
        double fn[kMaxEdgePoints][kMaxCellFunctions];
        double rho_c[kMaxEdgePoints][2];
        int points = 0;
        // The dashpots (an approximate boundary) keep the 3-point rule, branch
        // functions included: at most 6 points.
        for_each_edge_point(model, view, g, h, false, [&](double xi, double eta, int side, int material, double length) {
          BasisAt basis;
          evaluate(model, view, xi, eta, g.tri, side, basis);
          const std::array<double, 9>& dd = model.material_elasticity[static_cast<std::size_t>(material)];
          const double rho = model.material_density[static_cast<std::size_t>(material)];
          const double dn = dd[static_cast<std::size_t>(normal == 0 ? 0 : 4)];
          for (int c = 0; c < 2; ++c)
            rho_c[points][c] = length * std::sqrt(rho * (c == normal ? dn : dd[8]));
          for (int f = 0; f < view.count; ++f) fn[points][f] = basis.n[f];
          ++points;
        });
        for (int c = 0; c < 2; ++c) {
          int dofs[kMaxCellFunctions], funcs[kMaxCellFunctions], used = 0;
          bool enriched = false;
          for (int f = 0; f < view.count; ++f) {
            if (view.dof[f][c] < 0) continue;
            bool nonzero = false;
            for (int q = 0; q < points; ++q) nonzero = nonzero || fn[q][f] != 0.0;
            if (!nonzero) continue;
            if (f < 4) {  // the standard functions come first (make_view): lumped
              double lumped = 0.0;
              for (int q = 0; q < points; ++q) lumped += rho_c[q][c] * fn[q][f];
              c_dof[static_cast<std::size_t>(view.dof[f][c])] += lumped;
            } else {
              enriched = true;
            }
            dofs[used] = view.dof[f][c], funcs[used++] = f;
          }
          if (!enriched || !d.absorb_enrichment) continue;
          for (int r = 0; r < used; ++r) model.absorb_dof.push_back(dofs[r]);
          for (int r = 0; r < used; ++r)
            for (int q2 = 0; q2 < used; ++q2) {
              double sum = 0.0;
              if (funcs[r] >= 4 || funcs[q2] >= 4)
                for (int q = 0; q < points; ++q) sum += rho_c[q][c] * fn[q][funcs[r]] * fn[q][funcs[q2]];
              model.absorb_matrix.push_back(sum);
            }
          model.absorb_start.push_back(static_cast<int>(model.absorb_dof.size()));
          model.absorb_matrix_start.push_back(static_cast<int>(model.absorb_matrix.size()));
        }
      }
      int k = 0;
      edge_nodes(sp.edge, [&](int n, double) {
        // Half of each plain segment the node ends (k − 1 below it, k above).
        const double share =
            ((k > 0 && plain[static_cast<std::size_t>(k - 1)] ? 0.5 : 0.0) + (k < count && plain[static_cast<std::size_t>(k)] ? 0.5 : 0.0)) *
            h * d.thickness;
        ++k;
        if (share == 0.0) return;
        for (int c = 0; c < 2; ++c) {
          const int dof = model.node_dof[static_cast<std::size_t>(2 * n + c)];
          if (dof < 0) continue;
          c_dof[static_cast<std::size_t>(dof)] += d.density * model.wave_speed[c == normal ? 0 : 1] * share;
        }
      });
    }
    for (int k = 0; k < nd; ++k)
      if (c_dof[static_cast<std::size_t>(k)] != 0.0) {
        model.damper_dof.push_back(k);
        model.damper_coeff.push_back(c_dof[static_cast<std::size_t>(k)]);
      }
  }

  // ---- loads, flattened (slot −1: self weight) ---------------------------------
  {
    std::vector<double> f(nds, 0.0);
    std::vector<char> touched(nds, 0);
    auto flush = [&](int load) {
      for (int k = 0; k < nd; ++k)
        if (touched[static_cast<std::size_t>(k)]) {
          model.load_dof.push_back(k);
          model.load_of.push_back(load);
          model.load_value.push_back(f[static_cast<std::size_t>(k)]);
          f[static_cast<std::size_t>(k)] = 0.0;
          touched[static_cast<std::size_t>(k)] = 0;
        }
    };
    auto add = [&](int n, int c, double value) {
      const int dof = model.node_dof[static_cast<std::size_t>(2 * n + c)];
      if (dof < 0) return;
      f[static_cast<std::size_t>(dof)] += value;
      touched[static_cast<std::size_t>(dof)] = 1;
    };
    auto add_dof = [&](int dof, double value) {
      if (dof < 0) return;
      f[static_cast<std::size_t>(dof)] += value;
      touched[static_cast<std::size_t>(dof)] = 1;
    };
    // Every function of cell view at (xi, eta) on `side`, times a force.
    auto add_basis = [&](const CellView& v, double xi, double eta, int tri, int side, const double force[2]) {
      BasisAt basis;
      evaluate(model, v, xi, eta, tri, side, basis);
      for (int fn = 0; fn < v.count; ++fn)
        for (int c = 0; c < 2; ++c)
          if (basis.n[fn] != 0.0) add_dof(v.dof[fn][c], basis.n[fn] * force[c]);
    };
    if (d.self_weight) {
      for (int n = 0; n < nodes; ++n)
        for (int c = 0; c < 2; ++c)
          if (d.gravity[c] != 0.0) add(n, c, model.node_mass[static_cast<std::size_t>(n)] * d.gravity[c]);
      if (ndisc > 0)
        for (std::size_t e2 = 0; e2 < n2; ++e2)
          for (int c = 0; c < 2; ++c)
            if (d.gravity[c] != 0.0)
              add_dof(model.enriched_dof[2 * e2 + static_cast<std::size_t>(c)], model.enrichment_mass[e2] * d.gravity[c]);
      if (tips)
        for (std::size_t e2 = 0; e2 < 2 * n2; ++e2)
          for (int c = 0; c < 2; ++c)
            if (d.gravity[c] != 0.0)
              add_dof(model.tip_dof[2 * e2 + static_cast<std::size_t>(c)], model.tip_mass[e2] * d.gravity[c]);
      flush(-1);
    }
    for (std::size_t l = 0; l < d.loads.size(); ++l) {
      const PlateLoad& ld = d.loads[l];
      if (ld.kind == PlateLoad::Kind::edge_traction && ndisc > 0) {
        // Along each cell edge of the domain's edge (for_each_edge_point).
        const bool vertical = ld.edge == PlateEdge::left || ld.edge == PlateEdge::right;
        const int count = vertical ? ny : nx;
        const double h = vertical ? hy : hx;
        for (int e2 = 0; e2 < count; ++e2) {
          const EdgeSegment g = edge_segment(d, ld.edge, e2);
          make_view(model, g.ci, g.cj, view);
          for_each_edge_point(model, view, g, h, true, [&](double xi, double eta, int side, int, double length) {
            const double force[2] = {length * ld.value[0], length * ld.value[1]};
            add_basis(view, xi, eta, g.tri, side, force);
          });
        }
      } else if (ld.kind == PlateLoad::Kind::point_force && ndisc > 0) {
        int ci = 0, cj = 0;
        double xi = 0.0, eta = 0.0;
        locate_axis(d.min[0], d.max[0], nx, ld.at[0], ci, xi);
        locate_axis(d.min[1], d.max[1], ny, ld.at[1], cj, eta);
        make_view(model, ci, cj, view);
        const int side = point_side(view, xi, eta);
        if (material_at(model, view, xi, eta, side) >= 0) add_basis(view, xi, eta, triangle_of(xi, eta), side, ld.value);
      } else if (ld.kind == PlateLoad::Kind::edge_traction) {
        const bool vertical = ld.edge == PlateEdge::left || ld.edge == PlateEdge::right;
        const int count = vertical ? ny : nx;
        double prev = 0.0;
        int prev_node = -1, k = 0;
        edge_nodes(ld.edge, [&](int n, double s) {
          if (k > 0)
            for (int c = 0; c < 2; ++c) {
              const double half = 0.5 * (s - prev) * d.thickness * ld.value[c];
              add(prev_node, c, half);
              add(n, c, half);
            }
          (void)count;
          prev = s;
          prev_node = n;
          ++k;
        });
      } else {
        int ci = 0, cj = 0;
        double xi = 0.0, eta = 0.0;
        locate_axis(d.min[0], d.max[0], nx, ld.at[0], ci, xi);
        locate_axis(d.min[1], d.max[1], ny, ld.at[1], cj, eta);
        int en[4];
        cell_nodes(nx, ci, cj, en);
        for (int a = 0; a < 4; ++a) {
          const double na = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
          if (na == 0.0) continue;
          for (int c = 0; c < 2; ++c) add(en[a], c, na * ld.value[c]);
        }
      }
      flush(static_cast<int>(l));
    }
  }

  workspace.u_pred.assign(nds, 0.0);
  workspace.v_pred.assign(nds, 0.0);
  workspace.rhs.assign(nds, 0.0);
  workspace.solve_work.assign(nds, 0.0);
  // The pattern a factor must hold beyond its matrix's nonzeros: the
  // couplings of the unilateral face points, which a re-factor adds.
  std::vector<std::pair<int, int>> face_pairs;
  for (const PlateModel::FacePoint& fp : model.face_points)
    if (fp.unilateral)
      for (int a = 0; a < fp.terms; ++a)
        for (int b = 0; b < a; ++b)
          if (fp.dof[a] >= 0 && fp.dof[b] >= 0) face_pairs.emplace_back(fp.dof[a], fp.dof[b]);
  workspace.shape_start.assign(d.loads.size() + 1, 0.0);
  workspace.shape_end.assign(d.loads.size() + 1, 0.0);
  workspace.load_u_start.assign(model.load_dof.size(), 0.0);
  workspace.damper_u_start.assign(model.damper_dof.size(), 0.0);
  workspace.damper_v_start.assign(model.damper_dof.size(), 0.0);
  workspace.absorb_u_start.assign(model.absorb_dof.size(), 0.0);
  workspace.absorb_v_start.assign(model.absorb_dof.size(), 0.0);
  state.u.assign(nds, 0.0);
  state.v.assign(nds, 0.0);
  state.a.assign(nds, 0.0);
  // The moving held components start at rest (their shape's value at 0 is
  // 0); a jump of the shape's rate there is Newmark's to take, as at its kinks.
  state.held_v.assign(model.moving_component.size(), 0.0);
  state.held_a.assign(model.moving_component.size(), 0.0);
  workspace.held_accel.assign(model.moving_component.size(), 0.0);
  workspace.held_u_start.assign(model.moving_component.size(), 0.0);
  workspace.held_force_start.assign(model.moving_component.size(), 0.0);

  if (d.analysis == PlateDesc::Analysis::statics) {
    // K u = f with every load at its amplitude (shape step: 1; none: 0), by
    // the profile factor: one solve at build, and its round-off is what the
    // static closed-form tests were set against (the sparse factor's ordering
    // put a few of them past their 64 ε bars).
    xfem::BandLdlt& profile = model.stiffness_factor;
    auto factor_k = [&](const xfem::SymmetricBand& k) {
      return profile.factor(k) && profile.min_pivot() > 1e-12 * profile.max_pivot();
    };
    if (model.unilateral_points == 0 && !factor_k(model.stiffness))
      return BuildResult::failure(Code::invalid_argument,
                                  "supports: the plate is not held against rigid motion (its stiffness is singular); "
                                  "a static analysis needs supports or prescribed nodes that stop %s",
                                  "translation and rotation");
    double* u = state.u.data();
    auto solve = [&] {
      for (std::size_t k = 0; k < nds; ++k) u[k] = model.held_force[k];
      for (std::size_t e2 = 0; e2 < model.load_dof.size(); ++e2) {
        const int l = model.load_of[e2];
        const double s = l < 0 || d.loads[static_cast<std::size_t>(l)].shape == PlateLoadShape::step ? 1.0 : 0.0;
        u[model.load_dof[e2]] += model.load_value[e2] * s;
      }
      profile.solve(u);
    };
    if (model.unilateral_points == 0) {
      solve();
    } else {
      // Unilateral faces: start with every point closed, solve, open the
      // points whose faces separate (and close those that interpenetrate),
      // until the set repeats.
      const std::size_t points = model.face_points.size();
      std::vector<char> active(points, 0), updated(points, 0);
      for (std::size_t p = 0; p < points; ++p) active[p] = model.face_points[p].unilateral ? 1 : 0;
      bool settled = false;
      for (int iteration = 0; iteration < 64 && !settled; ++iteration) {
        xfem::SymmetricBand k_active = model.stiffness;
        for (std::size_t p = 0; p < points; ++p)
          if (active[p]) detail::add_face_penalty(k_active, model.face_points[p], 1.0);
        if (!factor_k(k_active))
          return BuildResult::failure(Code::invalid_argument,
                                      "supports: the plate is not held against rigid motion once its unilateral "
                                      "crack faces %s (its stiffness is singular)",
                                      "open");
        solve();
        // A gap within round-off of the displacements (1e-12 of the largest
        // unknown) keeps its point's state: faces that neither separate nor
        // interpenetrate (a load along the crack) would otherwise flip on the
        // last bits of the solve and never settle.
        double scale = 0.0;
        for (const double x : state.u) scale = std::max(scale, std::fabs(x));
        const double tol = 1e-12 * scale;
        for (std::size_t p = 0; p < points; ++p) {
          const double gap = detail::face_gap(model.face_points[p], u);
          updated[p] = !model.face_points[p].unilateral ? 0 : gap < -tol ? 1 : gap > tol ? 0 : active[p];
        }
        settled = updated == active;
        active.swap(updated);
      }
      // A set that cycles: the damped iteration of a dynamic step
      // (PlateOperator::settle_by_line_search), with fac0 = 1 and x = 0, from
      // the last solve, which solved the set now in `updated`.
      const int damped_cap = 200;
      int damped = 0;
      if (!settled) {
        std::vector<double> uc(state.u), q(nds, 0.0), qn(nds, 0.0), gap(points, 0.0), dgap(points, 0.0);
        for (std::size_t p = 0; p < points; ++p) gap[p] = detail::face_gap(model.face_points[p], uc.data());
        detail::add_face_forces(model, updated.data(), gap.data(), q.data());  // K u − f
        for (; damped < damped_cap && !settled; ++damped) {
          xfem::SymmetricBand k_active = model.stiffness;
          for (std::size_t p = 0; p < points; ++p)
            if (active[p]) detail::add_face_penalty(k_active, model.face_points[p], 1.0);
          if (!factor_k(k_active))
            return BuildResult::failure(Code::invalid_argument,
                                        "supports: the plate is not held against rigid motion once its unilateral "
                                        "crack faces %s (its stiffness is singular)",
                                        "open");
          solve();  // the Newton point for the iterate's set, into u
          double scale = 0.0;
          for (const double x : state.u) scale = std::max(scale, std::fabs(x));
          const double tol = 1e-12 * scale;
          for (std::size_t p = 0; p < points; ++p) {
            const double g = dgap[p] = detail::face_gap(model.face_points[p], u);  // the Newton point's gap, for now
            updated[p] = !model.face_points[p].unilateral ? 0 : g < -tol ? 1 : g > tol ? 0 : active[p];
          }
          settled = updated == active;
          if (settled) break;
          // K u_N − f = −Σ_active w k_n g_p(u_N) n_p, so K d = qn − q.
          std::fill(qn.begin(), qn.end(), 0.0);
          detail::add_face_forces(model, active.data(), dgap.data(), qn.data());
          for (std::size_t p = 0; p < points; ++p) dgap[p] -= gap[p];  // the change along the step
          double s1 = 0.0, s2 = 0.0;
          for (std::size_t i = 0; i < nds; ++i) {
            const double dir = u[i] - uc[i];
            s1 += dir * q[i];
            s2 += dir * (qn[i] - q[i]);
          }
          const double alpha = detail::face_line_search(model, nullptr, gap.data(), dgap.data(), 1.0, s1, s2);
          double scale_c = 0.0;
          for (std::size_t i = 0; i < nds; ++i) {
            uc[i] += alpha * (u[i] - uc[i]);
            q[i] += alpha * (qn[i] - q[i]);
            scale_c = std::max(scale_c, std::fabs(uc[i]));
          }
          // The iterate's set, by the same rule.
          for (std::size_t p = 0; p < points; ++p) {
            const double g = gap[p] = detail::face_gap(model.face_points[p], uc.data());
            updated[p] = !model.face_points[p].unilateral ? 0 : g < -1e-12 * scale_c ? 1 : g > 1e-12 * scale_c ? 0 : active[p];
          }
          active.swap(updated);
        }
      }
      if (!settled)
        return BuildResult::failure(Code::invalid_argument,
                                    "discontinuities: the unilateral faces' active set did not settle in %d solves "
                                    "(%d of them damped)",
                                    64 + damped, damped);
      workspace.damped_solves = damped > 0 ? 1 : 0;
    }
    model.built = true;
    if (!all_finite(state.u)) {
      model.built = false;
      return BuildResult::failure(Code::invalid_argument, "loads: the static solution is not finite");
    }
    state.energy = EnergyLedger{};
    return BuildResult::success();
  }

  // ---- dynamic: factor M and M + γΔt C + βΔt² K -------------------------------
  model.scheme = xfem::NewmarkScheme{d.beta, d.gamma, d.dt};
  model.mass_factor.analyse(model.mass, {});
  if (!model.mass_factor.factor(model.mass)) {
    // Mathematically the mass matrix is positive definite (a Gram matrix of
    // independent functions); in floating point it is not when enriched
    // functions are nearly dependent, which branch functions within a radius
    // over many (or elongated) cells are.
    if (d.tip_radius > 0.0)
      return BuildResult::failure(Code::invalid_argument,
                                  "tip_enrichment.radius: the mass matrix is not positive definite to working "
                                  "precision: the branch functions within %g of a tip, over cells of %g x %g, are "
                                  "nearly dependent (reduce the radius, or use cells closer to square)",
                                  d.tip_radius, (d.max[0] - d.min[0]) / d.cells[0], (d.max[1] - d.min[1]) / d.cells[1]);
    return BuildResult::failure(Code::invalid_argument,
                                "cells: the mass matrix is not positive definite to working precision (nearly "
                                "dependent enriched functions)");
  }
  {
    xfem::SymmetricBand eff = model.mass;
    const double fac0 = model.scheme.fac0(), fac1 = model.scheme.fac1();
    for (int i = 0; i < nd; ++i)
      for (int j = model.mass.first_column(i); j <= i; ++j) eff.add(i, j, fac0 * model.stiffness.get(i, j));
    for (std::size_t k = 0; k < model.damper_dof.size(); ++k)
      eff.add(model.damper_dof[k], model.damper_dof[k], fac1 * model.damper_coeff[k]);
    for (std::size_t b = 0; b + 1 < model.absorb_start.size(); ++b) {
      const int* dof = model.absorb_dof.data() + model.absorb_start[b];
      const int n = model.absorb_start[b + 1] - model.absorb_start[b];
      const double* c = model.absorb_matrix.data() + model.absorb_matrix_start[b];
      for (int r = 0; r < n; ++r)
        for (int q = 0; q < n; ++q)
          if (dof[q] <= dof[r] && c[r * n + q] != 0.0) eff.add(dof[r], dof[q], fac1 * c[r * n + q]);
    }
    model.effective_factor.analyse(eff, face_pairs);
    if (!model.effective_factor.factor(eff))
      return BuildResult::failure(Code::invalid_argument, "dt: the effective stiffness is not positive definite");
    if (model.unilateral_points > 0) {
      // The step re-factors eff + the active penalties into the workspace's
      // factor, whose storage is sized here (no face active).
      model.base_effective = eff;
      workspace.effective = eff;
      workspace.factor = model.effective_factor;
      workspace.active.assign(model.face_points.size(), 0);
      workspace.factored_active.assign(model.face_points.size(), 0);
      workspace.held.assign(model.face_points.size(), 0);
      workspace.u_start.assign(static_cast<std::size_t>(nd), 0.0);
      workspace.v_start.assign(static_cast<std::size_t>(nd), 0.0);
      workspace.a_start.assign(static_cast<std::size_t>(nd), 0.0);
      for (auto* v : {&workspace.line_k, &workspace.line_q, &workspace.line_qn})
        v->assign(static_cast<std::size_t>(nd), 0.0);
      workspace.line_gap.assign(model.face_points.size(), 0.0);
      workspace.line_dgap.assign(model.face_points.size(), 0.0);
    }
  }
  model.built = true;
  const StepStatus s = plate_initial_acceleration(model, state, workspace);
  if (s != StepStatus::ok) {
    model.built = false;
    return BuildResult::failure(Code::invalid_argument, "loads: the initial acceleration is not finite");
  }
  return BuildResult::success();
}

// ---- stepping -----------------------------------------------------------------

double plate_load_shape(const PlateModel& m, int load, double t) {
  if (load < 0) return 1.0;
  const PlateLoad& l = m.desc.loads[static_cast<std::size_t>(load)];
  switch (l.shape) {
    case PlateLoadShape::half_sine:
      return (t >= 0.0 && t <= l.duration) ? std::sin(std::numbers::pi * t / l.duration) : 0.0;
    case PlateLoadShape::step:
      return t >= 0.0 ? 1.0 : 0.0;
    case PlateLoadShape::none:
      break;
  }
  return 0.0;
}

double plate_prescribed_shape(const PlateModel& m, int prescribed, double t) {
  const PlatePrescribed& p = m.desc.prescribed[static_cast<std::size_t>(prescribed)];
  switch (p.shape) {
    case PlatePrescribedShape::half_sine:
      return (t >= 0.0 && t <= p.duration) ? std::sin(std::numbers::pi * t / p.duration) : 0.0;
    case PlatePrescribedShape::ramp:
      return t <= 0.0 ? 0.0 : t < p.duration ? t / p.duration : 1.0;
    case PlatePrescribedShape::step:
      break;
  }
  return t >= 0.0 ? 1.0 : 0.0;
}

StepStatus plate_initial_acceleration(const PlateModel& model, PlateState& state, PlateWorkspace& workspace) {
  if (!model.built || model.desc.analysis != PlateDesc::Analysis::dynamic) return StepStatus::not_built;
  // The moving held components' accelerations are the state's (same sizes: no allocation).
  std::copy(state.held_a.begin(), state.held_a.end(), workspace.held_accel.begin());
  const detail::PlateOperator op(model, workspace);
  op.implicit_solve(0.0, 0.0, state.time, state.u.data(), state.v.data(), state.a.data());
  const double e = plate_algorithmic_energy(model, state);
  energy_restart(state.energy, {e, e, e});
  StepStatus s = StepStatus::ok;
  if (!all_finite(state.u) || !all_finite(state.v) || !all_finite(state.a) || !std::isfinite(state.time))
    s |= StepStatus::non_finite;
  return s;
}

StepStatus plate_start_acceleration(const PlateModel& model, PlateState& state, PlateWorkspace& workspace) {
  if (!model.built || model.desc.analysis != PlateDesc::Analysis::dynamic) return StepStatus::not_built;
  std::copy(state.held_a.begin(), state.held_a.end(), workspace.held_accel.begin());
  const detail::PlateOperator op(model, workspace);
  return op.implicit_solve(0.0, 0.0, state.time, state.u.data(), state.v.data(), state.a.data());
}

namespace {

/// Ê = ½vᵀMv + ½uᵀKu (tied faces in K) + Σ ½ w k_n min(g, 0)² over the
/// unilateral points + ½Δt²(β − γ/2) aᵀMa from the matrices (the energy
/// rule's measure; plate_algorithmic_energy() integrates the strains, equal
/// to round-off). Uses ws.rhs as scratch.
double step_energy(const PlateModel& m, const PlateState& s, PlateWorkspace& ws) {
  const int n = m.dofs;
  double* ku = ws.rhs.data();
  for (int i = 0; i < n; ++i) ku[i] = 0.0;
  plate_subtract_stiffness_product(m, s.u.data(), ku);
  double e = 0.5 * m.mass.quadratic(s.v.data());
  for (int i = 0; i < n; ++i) e -= 0.5 * s.u[static_cast<std::size_t>(i)] * ku[i];
  for (const PlateModel::FacePoint& fp : m.face_points)
    if (fp.unilateral) {
      const double g = std::min(detail::face_gap(fp, s.u.data()), 0.0);
      e += 0.5 * fp.weight * fp.k_normal * g * g;
    }
  const xfem::NewmarkScheme& k = m.scheme;
  const double c = k.beta - 0.5 * k.gamma;
  return e + (c == 0.0 ? 0.0 : 0.5 * k.dt * k.dt * c * m.mass.quadratic(s.a.data()));
}

/// Takes `excess` (J) out of the velocity relative to the plate's rigid
/// translation v̄ (the M-projection of v on a unit translation per
/// component): v ← v̄ + s (v − v̄), which keeps the momentum 1ᵀMv of each
/// component. Returns what it could not take (when the relative part's
/// kinetic energy is smaller). Uses ws.u_pred, ws.v_pred, ws.rhs as scratch.
double take_from_velocity(const PlateModel& m, PlateState& st, PlateWorkspace& ws, double excess) {
  const int n = m.dofs;
  double* t = ws.v_pred.data();
  double* mt = ws.u_pred.data();
  double mean[2] = {0.0, 0.0};  // v̄ = Σ_c mean[c] t_c
  double kinetic_mean = 0.0;
  for (int c = 0; c < 2; ++c) {
    for (int i = 0; i < n; ++i) t[i] = 0.0;
    for (std::size_t k = static_cast<std::size_t>(c); k < m.node_dof.size(); k += 2)
      if (m.node_dof[k] >= 0) t[m.node_dof[k]] = 1.0;
    m.mass.multiply(t, mt);
    double mass = 0.0, momentum = 0.0;
    for (int i = 0; i < n; ++i) mass += t[i] * mt[i], momentum += mt[i] * st.v[static_cast<std::size_t>(i)];
    if (mass > 0.0) mean[c] = momentum / mass, kinetic_mean += 0.5 * momentum * mean[c];
  }
  const double kinetic = 0.5 * m.mass.quadratic(st.v.data());
  const double relative = kinetic - kinetic_mean;
  if (!(relative > 0.0)) return excess;
  const double taken = std::min(excess, relative);
  const double scale = std::sqrt((relative - taken) / relative);
  double* bar = ws.rhs.data();
  for (int i = 0; i < n; ++i) bar[i] = 0.0;
  for (int c = 0; c < 2; ++c)
    for (std::size_t k = static_cast<std::size_t>(c); k < m.node_dof.size(); k += 2)
      if (m.node_dof[k] >= 0) bar[m.node_dof[k]] = mean[c];
  for (int i = 0; i < n; ++i) {
    double& v = st.v[static_cast<std::size_t>(i)];
    v = bar[i] + scale * (v - bar[i]);
  }
  return excess - taken;
}

}  // namespace

StepStatus plate_step(const PlateModel& model, PlateState& state, PlateWorkspace& ws) {
  if (!model.built || model.desc.analysis != PlateDesc::Analysis::dynamic) return StepStatus::not_built;
  const double t_n = static_cast<double>(state.step) * model.scheme.dt;
  const double t_next = static_cast<double>(state.step + 1) * model.scheme.dt;
  // Where the step starts, for the books of the work done over it.
  const std::size_t slots = ws.shape_start.size();
  for (std::size_t s = 0; s < slots; ++s) ws.shape_start[s] = plate_load_shape(model, static_cast<int>(s) - 1, t_n);
  const std::size_t entries = model.load_dof.size(), dampers = model.damper_dof.size();
  for (std::size_t e = 0; e < entries; ++e) ws.load_u_start[e] = state.u[static_cast<std::size_t>(model.load_dof[e])];
  for (std::size_t k = 0; k < dampers; ++k) {
    ws.damper_u_start[k] = state.u[static_cast<std::size_t>(model.damper_dof[k])];
    ws.damper_v_start[k] = state.v[static_cast<std::size_t>(model.damper_dof[k])];
  }
  for (std::size_t k = 0; k < model.absorb_dof.size(); ++k) {
    ws.absorb_u_start[k] = state.u[static_cast<std::size_t>(model.absorb_dof[k])];
    ws.absorb_v_start[k] = state.v[static_cast<std::size_t>(model.absorb_dof[k])];
  }
  // Moving held components: u_{n+1} = d g(t_{n+1}) is given, and Newmark's own
  // update gives the acceleration that reaches it from the predictor,
  // a_{n+1} = (u_{n+1} − ũ)/(βΔt²), and then v_{n+1} = ṽ + γΔt a_{n+1}: the
  // whole plate (held rows included) is one Newmark trajectory, so the
  // scheme's energy identity holds with their work booked below, and a kink
  // of g is an impulse Newmark delivers (docs/xfem2d.md).
  const std::size_t moving = model.moving_component.size();
  const double fac0 = model.scheme.fac0();
  for (std::size_t h = 0; h < moving; ++h) {
    const double dt = model.scheme.dt;
    const double u_n = moving_displacement(model, h, t_n);
    const double predicted = u_n + dt * state.held_v[h] + (0.5 - model.scheme.beta) * dt * dt * state.held_a[h];
    ws.held_u_start[h] = u_n;
    ws.held_force_start[h] =
        detail::moving_row(model, h, state.u.data(), state.a.data(), t_n, state.held_a.data());
    ws.held_accel[h] = (moving_displacement(model, h, t_next) - predicted) / fac0;
  }
  const bool rule = model.unilateral_points > 0;
  double energy_start = 0.0;
  if (rule) {
    ws.u_start = state.u, ws.v_start = state.v, ws.a_start = state.a;  // same sizes: no allocation
    energy_start = step_energy(model, state, ws);
  }
  const double g = model.scheme.gamma;
  // Work with the scheme's weights (x_γ = (1 − γ) x_n + γ x_{n+1}): exact in
  // the discrete energy identity of a linear system.
  auto step_work = [&]() {
    double work = 0.0;
    for (std::size_t e = 0; e < entries; ++e) {
      const auto slot = static_cast<std::size_t>(model.load_of[e] + 1);
      const double du = state.u[static_cast<std::size_t>(model.load_dof[e])] - ws.load_u_start[e];
      work += du * model.load_value[e] * ((1.0 - g) * ws.shape_start[slot] + g * ws.shape_end[slot]);
    }
    for (std::size_t k = 0; k < dampers; ++k) {
      const auto dof = static_cast<std::size_t>(model.damper_dof[k]);
      work -= model.damper_coeff[k] * (state.u[dof] - ws.damper_u_start[k]) *
              ((1.0 - g) * ws.damper_v_start[k] + g * state.v[dof]);
    }
    for (std::size_t b = 0; b + 1 < model.absorb_start.size(); ++b) {
      const auto first = static_cast<std::size_t>(model.absorb_start[b]);
      const int n = model.absorb_start[b + 1] - model.absorb_start[b];
      const double* c = model.absorb_matrix.data() + model.absorb_matrix_start[b];
      for (int r = 0; r < n; ++r) {
        const std::size_t er = first + static_cast<std::size_t>(r);
        const double du = state.u[static_cast<std::size_t>(model.absorb_dof[er])] - ws.absorb_u_start[er];
        double cv = 0.0;
        for (int q = 0; q < n; ++q) {
          const std::size_t eq = first + static_cast<std::size_t>(q);
          cv += c[r * n + q] * ((1.0 - g) * ws.absorb_v_start[eq] + g * state.v[static_cast<std::size_t>(model.absorb_dof[eq])]);
        }
        work -= du * cv;
      }
    }
    return work;
  };
  // A host's force, held over the step: its work f·Δu is the host's to book,
  // but the energy rule must not take it for a gain.
  auto host_work = [&]() {
    double w = 0.0;
    if (!ws.external_force.empty())
      for (std::size_t i = 0; i < state.u.size(); ++i) w += ws.external_force[i] * (state.u[i] - ws.u_start[i]);
    return w;
  };
  double net_force[2];
  StepStatus s = xfem::newmark_step(model.scheme, detail::PlateOperator(model, ws), t_next, state.u.data(),
                                    state.v.data(), state.a.data(), ws.u_pred.data(), ws.v_pred.data(),
                                    model.mass_row_sums.data(), net_force);
  double work = step_work();
  if (rule) {
    // The energy rule (docs/xfem2d.md): a step that gained energy while a
    // point opened is redone with the points active at its start held active
    // to its end (the others settle as before); each held point's spring then
    // acts at both ends, so the step's energy only falls, and the
    // acceleration is then recomputed with the set of u_{n+1} (the held
    // spring's pull ends with the step). What a step still gains (beyond its
    // work) is taken out of the velocity relative to the rigid motion.
    const std::size_t points = model.face_points.size();
    bool opened = false;
    for (std::size_t p = 0; p < points; ++p) {
      const PlateModel::FacePoint& fp = model.face_points[p];
      const bool was = fp.unilateral && detail::face_gap(fp, ws.u_start.data()) < 0.0;
      opened = opened || (was && !ws.active[p]);
      ws.held[p] = was ? 1 : 0;
    }
    if ((opened && step_energy(model, state, ws) > energy_start + work + host_work())) {
      state.u = ws.u_start, state.v = ws.v_start, state.a = ws.a_start;
      s = xfem::newmark_step(model.scheme, detail::PlateOperator(model, ws, ws.held.data()), t_next, state.u.data(),
                             state.v.data(), state.a.data(), ws.u_pred.data(), ws.v_pred.data(),
                             model.mass_row_sums.data(), net_force);
      s |= detail::PlateOperator(model, ws).implicit_solve(0.0, 0.0, t_next, state.u.data(), state.v.data(),
                                                           state.a.data());
      ++ws.held_steps;
      work = step_work();
    }
    const double excess = step_energy(model, state, ws) - (energy_start + work + host_work());
    if (excess > 0.0 && std::isfinite(excess)) {
      const double left = take_from_velocity(model, state, ws, excess);
      ws.energy_removed += excess - left;
      ws.energy_left += left;
      work = step_work();
    }
  }
  if (moving > 0) {
    const double dt = model.scheme.dt;
    for (std::size_t h = 0; h < moving; ++h) {
      state.held_v[h] += dt * ((1.0 - g) * state.held_a[h] + g * ws.held_accel[h]);
      state.held_a[h] = ws.held_accel[h];
    }
    // The moving nodes' work, Δu_h (M a + K u)_h with the scheme's weights:
    // what their supports and the loads on them put in.
    for (std::size_t h = 0; h < moving; ++h) {
      const double end = detail::moving_row(model, h, state.u.data(), state.a.data(), t_next, state.held_a.data());
      work += (moving_displacement(model, h, t_next) - ws.held_u_start[h]) *
              ((1.0 - g) * ws.held_force_start[h] + g * end);
    }
  }
  ws.last_external_impulse = model.scheme.dt * ((1.0 - g) * net_force[0] + g * net_force[1]);
  state.energy.work += work;
  state.step += 1;
  state.time = t_next;
  if (!all_finite(state.u) || !all_finite(state.v) || !all_finite(state.a) || !all_finite(state.held_v) ||
      !all_finite(state.held_a) || !std::isfinite(state.energy.work))
    s |= StepStatus::non_finite;
  if (energy_check_due(model.desc.energy_check, state.step)) {
    const double energy = plate_algorithmic_energy(model, state);
    energy_check(state.energy, model.desc.energy_check, {energy, energy, energy});
  }
  if (state.energy.exceeded != 0) s |= StepStatus::energy_growth;
  return s;
}

// ---- probes -------------------------------------------------------------------

namespace {

/// The state's array of a field.
inline const double* field_of(const PlateState& s, Field f) {
  return f == Field::displacement ? s.u.data() : f == Field::velocity ? s.v.data() : s.a.data();
}

/// The value of component c of natural node n in field f of the state (held
/// nodes: their displacement at the state's time; rates 0 unless moving).
inline double nodal(const PlateModel& m, const PlateState& s, Field f, int n, int c) {
  const auto k = static_cast<std::size_t>(2 * n + c);
  const int dof = m.node_dof[k];
  if (dof >= 0) return field_of(s, f)[dof];
  if (f == Field::displacement) return held_displacement(m, k, s.time);
  const int h = m.node_moving.empty() ? -1 : m.node_moving[k];
  if (h < 0) return 0.0;
  return (f == Field::velocity ? s.held_v : s.held_a)[static_cast<std::size_t>(h)];
}

/// The cell (i, j) holding (x, y) and the parent coordinates there; false for
/// an unbuilt model or a point outside the domain.
bool locate(const PlateModel& m, double x, double y, int& i, int& j, double& xi, double& eta) {
  const PlateDesc& d = m.desc;
  return m.built && locate_axis(d.min[0], d.max[0], d.cells[0], x, i, xi) &&
         locate_axis(d.min[1], d.max[1], d.cells[1], y, j, eta);
}

/// The value of function f's component c in field `which` (u: that array; held:
/// the view's held displacement or rate).
inline double coefficient(const CellView& v, const double* u, Field which, int f, int c) {
  const int dof = v.dof[f][c];
  if (dof >= 0) return u[dof];
  return which == Field::displacement ? v.held[f][c] : v.held_rate[which == Field::velocity ? 0 : 1][f][c];
}

double field_at(const PlateModel& m, const PlateState& st, Field which, double x, double y, int c) {
  const PlateDesc& d = m.desc;
  int i = 0, j = 0;
  double xi = 0.0, eta = 0.0;
  if (c < 0 || c > 1 || !locate(m, x, y, i, j, xi, eta)) return std::numeric_limits<double>::quiet_NaN();
  if (m.node_phi.empty()) {
    int en[4];
    cell_nodes(d.cells[0], i, j, en);
    double s = 0.0;
    for (int a = 0; a < 4; ++a)
      s += 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]) * nodal(m, st, which, en[a], c);
    return s;
  }
  CellView v;
  make_view(m, i, j, v, st.time, &st);
  const int side = material_side(m, v, xi, eta);
  if (material_at(m, v, xi, eta, side) < 0) return std::numeric_limits<double>::quiet_NaN();
  BasisAt basis;
  evaluate(m, v, xi, eta, triangle_of(xi, eta), side, basis);
  double s = 0.0;
  for (int fn = 0; fn < v.count; ++fn) s += basis.n[fn] * coefficient(v, field_of(st, which), which, fn, c);
  return s;
}

/// ε at a point of a cell from the basis there.
void strain_of(const CellView& v, const BasisAt& basis, const double* u, double eps[3]) {
  eps[0] = eps[1] = eps[2] = 0.0;
  for (int f = 0; f < v.count; ++f) {
    const double ux = coefficient(v, u, Field::displacement, f, 0), uy = coefficient(v, u, Field::displacement, f, 1);
    eps[0] += basis.dx[f] * ux;
    eps[1] += basis.dy[f] * uy;
    eps[2] += basis.dy[f] * ux + basis.dx[f] * uy;
  }
}

/// ε = (ε_xx, ε_yy, γ_xy) at parent point (xi, eta) of cell (i, j).
void strain_at(const PlateModel& m, const PlateState& s, int i, int j, double xi, double eta, double eps[3]) {
  int en[4];
  cell_nodes(m.desc.cells[0], i, j, en);
  eps[0] = eps[1] = eps[2] = 0.0;
  for (int a = 0; a < 4; ++a) {
    const double dx = 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * (2.0 / m.cell_size[0]);
    const double dy = 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * (2.0 / m.cell_size[1]);
    const double ux = nodal(m, s, Field::displacement, en[a], 0), uy = nodal(m, s, Field::displacement, en[a], 1);
    eps[0] += dx * ux;
    eps[1] += dy * uy;
    eps[2] += dy * ux + dx * uy;
  }
}

}  // namespace

double plate_displacement(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s, Field::displacement, x, y, c);
}
double plate_velocity(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s, Field::velocity, x, y, c);
}
double plate_acceleration(const PlateModel& m, const PlateState& s, double x, double y, int c) {
  return field_at(m, s, Field::acceleration, x, y, c);
}

double plate_stress(const PlateModel& m, const PlateState& s, double x, double y, int component) {
  int i = 0, j = 0;
  double xi = 0.0, eta = 0.0;
  if (component < 0 || component > 2 || !locate(m, x, y, i, j, xi, eta)) return std::numeric_limits<double>::quiet_NaN();
  double eps[3];
  if (m.node_phi.empty()) {
    strain_at(m, s, i, j, xi, eta, eps);
    const double(&dm)[3][3] = m.elasticity;
    return dm[component][0] * eps[0] + dm[component][1] * eps[1] + dm[component][2] * eps[2];
  }
  CellView v;
  make_view(m, i, j, v, s.time, &s);
  const int side = material_side(m, v, xi, eta);
  const int material = material_at(m, v, xi, eta, side);
  if (material < 0) return std::numeric_limits<double>::quiet_NaN();
  BasisAt basis;
  evaluate(m, v, xi, eta, triangle_of(xi, eta), side, basis);
  strain_of(v, basis, s.u.data(), eps);
  const std::array<double, 9>& dd = m.material_elasticity[static_cast<std::size_t>(material)];
  return dd[static_cast<std::size_t>(3 * component)] * eps[0] + dd[static_cast<std::size_t>(3 * component + 1)] * eps[1] +
         dd[static_cast<std::size_t>(3 * component + 2)] * eps[2];
}

double plate_crack_opening(const PlateModel& m, const PlateState& s, int crack, double x, double y, int component) {
  const PlateDesc& d = m.desc;
  int i = 0, j = 0;
  double xi = 0.0, eta = 0.0;
  if (crack < 0 || static_cast<std::size_t>(crack) >= d.discontinuities.size() ||
      d.discontinuities[static_cast<std::size_t>(crack)].kind != PlateDiscontinuity::Kind::crack || component < 0 ||
      component > 1 || !locate(m, x, y, i, j, xi, eta))
    return std::numeric_limits<double>::quiet_NaN();
  // [u] = Σ_a N_a (H⁺ − H⁻) a_a = 2 Σ_a N_a a_a over the crack's Heaviside unknowns.
  CellView v;
  make_view(m, i, j, v, s.time, &s);
  double jump[2] = {0.0, 0.0};
  for (int f = 0; f < v.count; ++f) {
    if (v.disc[f] != crack) continue;
    const int a = v.node[f];
    const double na = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
    for (int c = 0; c < 2; ++c) jump[c] += 2.0 * na * coefficient(v, s.u.data(), Field::displacement, f, c);
  }
  // Near a tip of this crack: of the four branch functions only F_1 = √r sin(θ/2) jumps, by 2√r
  // (upper minus lower in the tip's frame: the sign says which face is the positive one).
  for (int f = 0; f < v.count; ++f) {
    if (v.tip[f] < 0 || v.branch[f] != 0) continue;
    const PlateModel::Tip& tip = m.tips[static_cast<std::size_t>(v.tip[f])];
    if (tip.crack != crack) continue;
    double r = 0.0, theta = 0.0;
    xfem::tip_polar(frame_of(tip), {x, y}, r, theta);
    const int a = v.node[f];
    const double na = 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
    for (int c = 0; c < 2; ++c)
      jump[c] += branch_jump_sign(tip) * 2.0 * std::sqrt(r) * na * coefficient(v, s.u.data(), Field::displacement, f, c);
  }
  Point2 closest{}, dir{};
  xfem::polyline_closest(d.discontinuities[static_cast<std::size_t>(crack)].points, {x, y}, closest, dir);
  // Normal: left of the direction (towards the positive side).
  return component == 0 ? -dir[1] * jump[0] + dir[0] * jump[1] : dir[0] * jump[0] + dir[1] * jump[1];
}

bool plate_flat_centre(const PlateModel& m, int k, int i, int j, double& value) {
  if (!m.built || m.node_phi.empty() || k < 0 || static_cast<std::size_t>(k) >= m.desc.discontinuities.size() || i < 0 ||
      j < 0 || i >= m.desc.cells[0] || j >= m.desc.cells[1])
    return false;
  const PlateDesc& d = m.desc;
  int en[4];
  cell_nodes(d.cells[0], i, j, en);
  double phi[4];
  for (int a = 0; a < 4; ++a) phi[a] = phi_at(m, k, en[a]);
  const Point2 x = {0.5 * (node_coord(d.min[0], d.max[0], i, d.cells[0]) + node_coord(d.min[0], d.max[0], i + 1, d.cells[0])),
                    0.5 * (node_coord(d.min[1], d.max[1], j, d.cells[1]) + node_coord(d.min[1], d.max[1], j + 1, d.cells[1]))};
  bool flat = false;
  const double c = cell_centre_phi(d, k, phi, x, std::min(m.cell_size[0], m.cell_size[1]), &flat);
  if (flat) value = c;
  return flat;
}

int plate_cell_pieces(const PlateModel& m, int i, int j, PlateCellPiece out[kPlateMaxCellPieces]) {
  if (!m.built || i < 0 || j < 0 || i >= m.desc.cells[0] || j >= m.desc.cells[1]) return 0;
  CellView v;
  make_view(m, i, j, v);
  if (v.cut < 0 && v.tip_cell < 0) {
    if (v.material < 0) return 0;
    PlateCellPiece& p = out[0];
    p = PlateCellPiece{};
    p.corners = 4;
    for (int a = 0; a < 4; ++a) p.xi[a] = kXi[a], p.eta[a] = kEta[a];
    p.material = v.material;
    return 1;
  }
  // The cut (or tip) cell's pieces as for_each_point integrates them.
  xfem::TrianglePiece pieces[kMaxPieces];
  int triangle[kMaxPieces];
  const int n = triangle_pieces(m, v, pieces, triangle);
  int count = 0;
  auto add = [&](const xfem::TrianglePiece& q, int tri, int material) {
    const double e1x = q.v[1][0] - q.v[0][0], e1y = q.v[1][1] - q.v[0][1];
    const double e2x = q.v[2][0] - q.v[1][0], e2y = q.v[2][1] - q.v[1][1];
    if (e1x * e2y - e1y * e2x == 0.0 || count >= kPlateMaxCellPieces) return;
    PlateCellPiece& p = out[count++];
    p = PlateCellPiece{};
    p.corners = 3;
    for (int a = 0; a < 3; ++a) p.xi[a] = q.v[a][0], p.eta[a] = q.v[a][1];
    p.triangle = tri, p.side = q.side, p.material = material;
  };
  for_each_material_piece(m, v, pieces, triangle, n, add);  // add() stops at kPlateMaxCellPieces
  return count;
}

void plate_piece_fields(const PlateModel& m, const PlateState& s, int i, int j, const PlateCellPiece& piece, double xi,
                        double eta, double u[2], double v[2], double stress[3]) {
  CellView view;
  make_view(m, i, j, view, s.time, &s);
  BasisAt basis;
  evaluate(m, view, xi, eta, piece.triangle >= 0 ? piece.triangle : triangle_of(xi, eta), piece.side, basis);
  for (int c = 0; c < 2; ++c) {
    u[c] = v[c] = 0.0;
    for (int f = 0; f < view.count; ++f) {
      u[c] += basis.n[f] * coefficient(view, s.u.data(), Field::displacement, f, c);
      v[c] += basis.n[f] * coefficient(view, s.v.data(), Field::velocity, f, c);
    }
  }
  double eps[3];
  strain_of(view, basis, s.u.data(), eps);
  if (m.material_elasticity.empty()) {
    for (int r = 0; r < 3; ++r) stress[r] = m.elasticity[r][0] * eps[0] + m.elasticity[r][1] * eps[1] + m.elasticity[r][2] * eps[2];
    return;
  }
  const std::array<double, 9>& dd = m.material_elasticity[static_cast<std::size_t>(piece.material)];
  for (int r = 0; r < 3; ++r)
    stress[r] = dd[static_cast<std::size_t>(3 * r)] * eps[0] + dd[static_cast<std::size_t>(3 * r + 1)] * eps[1] +
                dd[static_cast<std::size_t>(3 * r + 2)] * eps[2];
}

bool plate_point_basis(const PlateModel& m, int i, int j, double xi, double eta, int side, PlatePointBasis& out,
                       double time) {
  out.count = 0;
  if (!m.built || i < 0 || j < 0 || i >= m.desc.cells[0] || j >= m.desc.cells[1]) return false;
  CellView view;
  make_view(m, i, j, view, time);
  BasisAt basis;
  evaluate(m, view, xi, eta, triangle_of(xi, eta), view.cut >= 0 ? side : 1, basis);
  out.count = view.count;
  for (int f = 0; f < view.count; ++f) {
    out.n[f] = basis.n[f];
    for (int c = 0; c < 2; ++c) out.dof[f][c] = view.dof[f][c], out.held[f][c] = view.held[f][c];
  }
  return true;
}

void plate_stress_intensity(const PlateModel& m, const PlateState& s, int crack, bool at_end, double radius, double k[2],
                            bool inertia) {
  k[0] = k[1] = std::numeric_limits<double>::quiet_NaN();
  const PlateModel::Tip* tip = nullptr;
  for (const PlateModel::Tip& t : m.tips)
    if (t.crack == crack && t.at_end == at_end) tip = &t;
  if (!m.built || tip == nullptr || !std::isfinite(radius) || !(radius > 0.0)) return;
  const PlateDesc& d = m.desc;
  inertia = inertia && d.analysis == PlateDesc::Analysis::dynamic;  // a static solution has ü = 0
  const int nx = d.cells[0], ny = d.cells[1];
  auto q_of = [&](int n) {
    const double dx = node_coord(d.min[0], d.max[0], n % (nx + 1), nx) - tip->origin[0];
    const double dy = node_coord(d.min[1], d.max[1], n / (nx + 1), ny) - tip->origin[1];
    return dx * dx + dy * dy <= radius * radius ? 1.0 : 0.0;
  };
  // q must vanish on the domain's boundary (the crack faces are traction free).
  for (int i = 0; i <= nx; ++i)
    if (q_of(i) != 0.0 || q_of(ny * (nx + 1) + i) != 0.0) return;
  for (int j = 0; j <= ny; ++j)
    if (q_of(j * (nx + 1)) != 0.0 || q_of(j * (nx + 1) + nx) != 0.0) return;
  const xfem::TipFrame frame = frame_of(*tip);
  const double c = tip->cos_a, sn = tip->sin_a;
  // The cells that can hold ∇q ≠ 0: those within the radius plus one cell of the tip.
  const int i0 = std::max(0, static_cast<int>(std::floor((tip->origin[0] - radius - d.min[0]) / m.cell_size[0])) - 1);
  const int i1 = std::min(nx - 1, static_cast<int>(std::ceil((tip->origin[0] + radius - d.min[0]) / m.cell_size[0])) + 1);
  const int j0 = std::max(0, static_cast<int>(std::floor((tip->origin[1] - radius - d.min[1]) / m.cell_size[1])) - 1);
  const int j1 = std::min(ny - 1, static_cast<int>(std::ceil((tip->origin[1] + radius - d.min[1]) / m.cell_size[1])) + 1);
  double integral[2] = {0.0, 0.0};
  double e_star = 0.0;
  CellView v;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      make_view(m, i, j, v, s.time, &s);
      double q[4];
      for (int a = 0; a < 4; ++a) q[a] = q_of(v.en[a]);
      // ∇q = 0 there, so the static terms vanish; the inertia term needs q = 0 too.
      const bool flat = q[0] == q[1] && q[1] == q[2] && q[2] == q[3];
      if (flat && (!inertia || q[0] == 0.0)) continue;
      const double area = 0.25 * m.cell_size[0] * m.cell_size[1];
      for_each_point(m, v, [&](double xi, double eta, double w, int tri, int side, int material) {
        BasisAt basis;
        evaluate(m, v, xi, eta, tri, side, basis);
        double gu[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
        for (int f = 0; f < v.count; ++f)
          for (int comp = 0; comp < 2; ++comp) {
            const double u = coefficient(v, s.u.data(), Field::displacement, f, comp);
            gu[comp][0] += basis.dx[f] * u;
            gu[comp][1] += basis.dy[f] * u;
          }
        const double* dd = m.material_elasticity[static_cast<std::size_t>(material)].data();
        const double eps[3] = {gu[0][0], gu[1][1], gu[0][1] + gu[1][0]};
        double sig[3];
        for (int r = 0; r < 3; ++r) sig[r] = dd[3 * r] * eps[0] + dd[3 * r + 1] * eps[1] + dd[3 * r + 2] * eps[2];
        double gq[2] = {0.0, 0.0}, qp = 0.0;
        for (int a = 0; a < 4; ++a) {
          qp += q[a] * 0.25 * (1.0 + xi * kXi[a]) * (1.0 + eta * kEta[a]);
          gq[0] += q[a] * 0.25 * kXi[a] * (1.0 + eta * kEta[a]) * (2.0 / m.cell_size[0]);
          gq[1] += q[a] * 0.25 * kEta[a] * (1.0 + xi * kXi[a]) * (2.0 / m.cell_size[1]);
        }
        // Into the tip frame: R = [[c, s], [−s, c]]; σ' = R σ Rᵀ, ∇u' = R ∇u Rᵀ, ∇q' = R ∇q.
        const double rm[2][2] = {{c, sn}, {-sn, c}};
        const double sg[2][2] = {{sig[0], sig[2]}, {sig[2], sig[1]}};
        double sl[2][2], gl[2][2];
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b) {
            sl[a][b] = gl[a][b] = 0.0;
            for (int p = 0; p < 2; ++p)
              for (int r = 0; r < 2; ++r) {
                sl[a][b] += rm[a][p] * sg[p][r] * rm[b][r];
                gl[a][b] += rm[a][p] * gu[p][r] * rm[b][r];
              }
          }
        const double sig_local[3] = {sl[0][0], sl[1][1], sl[0][1]};
        const double gq_local[2] = {c * gq[0] + sn * gq[1], -sn * gq[0] + c * gq[1]};
        double r = 0.0, theta = 0.0;
        xfem::tip_polar(frame, physical(v, xi, eta), r, theta);
        if (r == 0.0) return;
        // The material's E and ν from its D (plane strain: D00 = λ + 2μ, D01 = λ; plane stress likewise with λ*).
        const double mu = dd[8], lambda = dd[1];
        const double nu = d.plane == PlateDesc::Plane::strain ? lambda / (2.0 * (lambda + mu)) : lambda / (lambda + 2.0 * mu);
        const double e = 2.0 * mu * (1.0 + nu);
        const double kappa = xfem::kolosov(nu, d.plane == PlateDesc::Plane::strain);
        e_star = d.plane == PlateDesc::Plane::strain ? e / (1.0 - nu * nu) : e;
        // ρ ü in the tip frame (ü of the enriched field at the point).
        double acc_local[2] = {0.0, 0.0};
        if (inertia && qp != 0.0) {
          double acc[2] = {0.0, 0.0};
          for (int f = 0; f < v.count; ++f)
            for (int comp = 0; comp < 2; ++comp) acc[comp] += basis.n[f] * coefficient(v, s.a.data(), Field::acceleration, f, comp);
          const double rho = m.material_density[static_cast<std::size_t>(material)];
          acc_local[0] = rho * (c * acc[0] + sn * acc[1]);
          acc_local[1] = rho * (-sn * acc[0] + c * acc[1]);
        }
        for (int mode = 0; mode < 2; ++mode) {
          const xfem::WilliamsField aux = xfem::williams_field(mode == 0 ? 1.0 : 0.0, mode == 1 ? 1.0 : 0.0, mu, kappa, r, theta);
          double value = xfem::interaction_integrand(sig_local, gl, aux, gq_local);
          // The dynamic interaction integral's inertia term ρ ü_i ∂u^aux_i/∂x₁ q (docs/xfem2d.md).
          value += qp * (acc_local[0] * aux.grad_u[0][0] + acc_local[1] * aux.grad_u[1][0]);
          integral[mode] += w * area * value;
        }
      }, kProbeRule);
    }
  if (e_star == 0.0) return;  // q = 0 everywhere: no node within the radius
  // I = 2 (K_I K_I^aux + K_II K_II^aux) / E*.
  k[0] = 0.5 * e_star * integral[0];
  k[1] = 0.5 * e_star * integral[1];
}

int plate_point_region(const PlateDesc& d, double x, double y, double tolerance) {
  int ci = 0, cj = 0;
  double xi = 0.0, eta = 0.0;
  if (!locate_axis(d.min[0], d.max[0], d.cells[0], x, ci, xi) || !locate_axis(d.min[1], d.max[1], d.cells[1], y, cj, eta))
    return -1;
  bool on_crack = false;
  for (const PlateDiscontinuity& q : d.discontinuities) {
    if (q.kind == PlateDiscontinuity::Kind::crack) {
      on_crack = on_crack || std::fabs(xfem::polyline_level_set(q.points, {x, y})) <= tolerance;
      continue;
    }
    if (std::fabs(level_set(q, q.points, {x, y})) <= tolerance) return 1;
  }
  const int region = void_at(d, {x, y}) >= 0 ? 2 : 0;
  // A crack's line inside a void (a crack from a hole) has no material on
  // either side: a point there is in the void.
  return on_crack && region != 2 ? 1 : region;
}

int plate_void_at(const PlateDesc& d, double x, double y) { return void_at(d, {x, y}); }

PlateCrackEnd plate_crack_end(const PlateDesc& d, int crack, bool at_end) {
  return crack_end_kind(d, d.discontinuities[static_cast<std::size_t>(crack)], at_end);
}

PlateEnergy plate_energy(const PlateModel& m, const PlateState& s) {
  PlateEnergy e;
  if (!m.built) return e;
  e.kinetic = 0.5 * m.mass.quadratic(s.v.data());
  // The moving held nodes' velocity too (the whole plate's ½vᵀMv).
  if (!m.moving_component.empty()) e.kinetic += 0.5 * detail::moving_mass_quadratic(m, s.v.data(), s.held_v.data());
  // ½ t ∫ εᵀDε dA from the strains, cell by cell on the cell's quadrature: a
  // rigid motion has exactly zero strain, so no energy to lose in the
  // cancellation of uᵀKu.
  const double g = 1.0 / std::sqrt(3.0);
  const double w = 0.5 * m.desc.thickness * 0.25 * m.cell_size[0] * m.cell_size[1];
  const double(&dm)[3][3] = m.elasticity;
  double elastic = 0.0;
  CellView v;
  std::size_t other = 0;  // the cell's index among the non-plain ones (other_cell_*)
  for (int j = 0; j < m.desc.cells[1]; ++j)
    for (int i = 0; i < m.desc.cells[0]; ++i) {
      make_view(m, i, j, v, s.time, &s);
      if (v.plain) {
        for (int gp = 0; gp < 4; ++gp) {
          double eps[3];
          strain_at(m, s, i, j, gp == 0 || gp == 3 ? -g : g, gp < 2 ? -g : g, eps);
          double q = 0.0;
          for (int r = 0; r < 3; ++r) q += eps[r] * (dm[r][0] * eps[0] + dm[r][1] * eps[1] + dm[r][2] * eps[2]);
          elastic += w * q;
        }
        continue;
      }
      const std::size_t oc = other++;
      if (v.tip_functions) {
        // ½ u_eᵀ K_e u_e from the stored element stiffness (the polar rule's
        // quadratic form, without its many points), after removing from the
        // nodes' standard components the cell's rigid motion (their mean
        // translation and rotation about the centre): K_e annihilates it, and
        // without it nothing is lost to the cancellation of a drifting plate.
        const int nf = 2 * v.count;
        double ue[2 * kMaxCellFunctions];
        for (int a = 0; a < nf; ++a) ue[a] = coefficient(v, s.u.data(), Field::displacement, a / 2, a % 2);
        double t[2] = {0.0, 0.0}, num = 0.0, den = 0.0;
        for (int a = 0; a < 4; ++a) t[0] += 0.25 * ue[2 * a], t[1] += 0.25 * ue[2 * a + 1];
        for (int a = 0; a < 4; ++a) {
          const double dx = 0.5 * kXi[a] * m.cell_size[0], dy = 0.5 * kEta[a] * m.cell_size[1];
          num += dx * (ue[2 * a + 1] - t[1]) - dy * (ue[2 * a] - t[0]);
          den += dx * dx + dy * dy;
        }
        const double omega = num / den;
        for (int a = 0; a < 4; ++a) {
          const double dx = 0.5 * kXi[a] * m.cell_size[0], dy = 0.5 * kEta[a] * m.cell_size[1];
          ue[2 * a] -= t[0] - omega * dy;
          ue[2 * a + 1] -= t[1] + omega * dx;
        }
        const double* k = m.other_cell_matrix.data() + m.other_cell_matrix_start[oc];
        double q = 0.0;
        for (int a = 0; a < nf; ++a) {
          double row = 0.0;
          for (int b = 0; b < nf; ++b) row += k[a * nf + b] * ue[b];
          q += ue[a] * row;
        }
        elastic += 0.5 * q;
        continue;
      }
      for_each_point(m, v, [&](double xi, double eta, double wp, int tri, int side, int material) {
        BasisAt basis;
        evaluate(m, v, xi, eta, tri, side, basis);
        double eps[3];
        strain_of(v, basis, s.u.data(), eps);
        const std::array<double, 9>& dd = m.material_elasticity[static_cast<std::size_t>(material)];
        double q = 0.0;
        for (int r = 0; r < 3; ++r)
          q += eps[r] * (dd[static_cast<std::size_t>(3 * r)] * eps[0] + dd[static_cast<std::size_t>(3 * r + 1)] * eps[1] +
                         dd[static_cast<std::size_t>(3 * r + 2)] * eps[2]);
        elastic += w * wp * q;
      });
    }
  for (const PlateModel::FacePoint& fp : m.face_points) {
    double gn = 0.0, gt = 0.0;
    for (int a = 0; a < fp.terms; ++a)
      if (fp.dof[a] >= 0) {
        gn += fp.normal[a] * s.u[static_cast<std::size_t>(fp.dof[a])];
        gt += fp.tangential[a] * s.u[static_cast<std::size_t>(fp.dof[a])];
      }
    if (fp.unilateral) gn = std::min(gn, 0.0);  // only closing is resisted
    elastic += 0.5 * fp.weight * (fp.k_normal * gn * gn + fp.k_tangential * gt * gt);
  }
  e.elastic = elastic;
  if (m.desc.self_weight)
    for (int n = 0; n < m.nodes; ++n)
      for (int c = 0; c < 2; ++c) {
        e.potential -= m.node_mass[static_cast<std::size_t>(n)] * m.desc.gravity[c] * nodal(m, s, Field::displacement, n, c);
        if (!m.enrichment_mass.empty())
          for (int sl = 0; sl < 2; ++sl) {
            const int dof = m.enriched_dof[static_cast<std::size_t>(2 * (2 * n + sl) + c)];
            if (dof >= 0)
              e.potential -= m.enrichment_mass[static_cast<std::size_t>(2 * n + sl)] * m.desc.gravity[c] *
                             s.u[static_cast<std::size_t>(dof)];
          }
        if (!m.tip_mass.empty())
          for (int b = 0; b < 4; ++b) {
            const int dof = m.tip_dof[static_cast<std::size_t>(8 * n + 2 * b + c)];
            if (dof >= 0)
              e.potential -= m.tip_mass[static_cast<std::size_t>(4 * n + b)] * m.desc.gravity[c] * s.u[static_cast<std::size_t>(dof)];
          }
      }
  return e;
}

double plate_algorithmic_energy(const PlateModel& m, const PlateState& s) {
  if (!m.built) return 0.0;
  const PlateEnergy e = plate_energy(m, s);
  const xfem::NewmarkScheme& k = m.scheme;
  const double c = k.beta - 0.5 * k.gamma;
  if (c == 0.0) return e.kinetic + e.elastic;
  double ama = m.mass.quadratic(s.a.data());
  if (!m.moving_component.empty()) ama += detail::moving_mass_quadratic(m, s.a.data(), s.held_a.data());
  return e.kinetic + e.elastic + 0.5 * k.dt * k.dt * c * ama;
}

void plate_support_reaction(const PlateModel& m, const PlateState& s, double reaction[2]) {
  reaction[0] = reaction[1] = 0.0;
  if (!m.built) {
    reaction[0] = reaction[1] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  // The cells in the build's order (plain ones on element_stiffness, the others
  // on their stored matrix, other_cell_* in the same order): the standard
  // functions come first in a view, so rows 0 … 7 are the four nodes' x, y.
  CellView v;
  std::size_t other = 0;
  for (int j = 0; j < m.desc.cells[1]; ++j)
    for (int i = 0; i < m.desc.cells[0]; ++i) {
      make_view(m, i, j, v, s.time, &s);
      const int nf = v.plain ? 8 : 2 * v.count;
      const double* k = v.plain ? m.element_stiffness : m.other_cell_matrix.data() + m.other_cell_matrix_start[other++];
      bool held = false;
      for (int a = 0; a < 8; ++a) held = held || v.dof[a / 2][a % 2] < 0;
      if (!held) continue;
      double ue[2 * kMaxCellFunctions];
      for (int a = 0; a < nf; ++a) ue[a] = coefficient(v, s.u.data(), Field::displacement, a / 2, a % 2);
      for (int a = 0; a < 8; ++a) {
        if (v.dof[a / 2][a % 2] >= 0) continue;
        double row = 0.0;
        for (int b = 0; b < nf; ++b) row += k[a * nf + b] * ue[b];
        reaction[a % 2] += row;
      }
    }
}

double plate_momentum(const PlateModel& m, const PlateState& s, int component) {
  if (!m.built || component < 0 || component > 1) return std::numeric_limits<double>::quiet_NaN();
  double p = 0.0;
  for (int n = 0; n < m.nodes; ++n) {
    p += m.node_mass[static_cast<std::size_t>(n)] * nodal(m, s, Field::velocity, n, component);
    if (!m.enrichment_mass.empty())
      for (int sl = 0; sl < 2; ++sl) {
        const int dof = m.enriched_dof[static_cast<std::size_t>(2 * (2 * n + sl) + component)];
        if (dof >= 0) p += m.enrichment_mass[static_cast<std::size_t>(2 * n + sl)] * s.v[static_cast<std::size_t>(dof)];
      }
    if (!m.tip_mass.empty())
      for (int b = 0; b < 4; ++b) {
        const int dof = m.tip_dof[static_cast<std::size_t>(8 * n + 2 * b + component)];
        if (dof >= 0) p += m.tip_mass[static_cast<std::size_t>(4 * n + b)] * s.v[static_cast<std::size_t>(dof)];
      }
  }
  return p;
}

}  // namespace xfdem
