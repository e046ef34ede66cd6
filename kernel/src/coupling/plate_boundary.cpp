// The plate's boundary for disk contact: construction, broad phase, closest
// point, and the spreading of a contact force by the shape functions
// (include/xfdem/coupling/plate_boundary.hpp).
#include "xfdem/coupling/plate_boundary.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "xfdem/xfem/level_set.hpp"

namespace xfdem {

namespace {

using Code = BuildResult::Code;

/// Corners of a cell in parent coordinates, counter-clockwise from the lower left.
constexpr double kXi[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEta[4] = {-1.0, -1.0, 1.0, 1.0};

/// Where the level set, linear from p0 at (xi0, eta0) to p1 at (xi1, eta1),
/// is zero: computed from the end at the smaller node, so that the two cells
/// that share a cell edge find the same point.
void crossing(double p0, double p1, double xi0, double eta0, double xi1, double eta1, int n0, int n1, double& xi,
              double& eta) {
  if (n1 < n0) {
    std::swap(p0, p1), std::swap(xi0, xi1), std::swap(eta0, eta1);
  }
  const double t = p0 / (p0 - p1);
  xi = xi0 + t * (xi1 - xi0);
  eta = eta0 + t * (eta1 - eta0);
}

/// A crossing of a void's boundary or a crack's face with an edge: a cell
/// edge (its two nodes, the smaller first) or a sub-triangle's inner edge
/// (cell, corner), the discontinuity whose zero line crosses it, and the
/// side whose material the vertex belongs to: the vertex every segment
/// through it shares. In a cell cut by a crack and a void, where the crack
/// meets the void's boundary inside sub-triangle t: (2, cell, t, crack, side).
///
/// A void's boundary through a node (its level set 0 there, as the plate's
/// tiny-cut rule makes every node within 1e-9 of a cell of it) is keyed by
/// the node: (3, node, −1, disc, side). Every crossing there (on either cell
/// edge through the node, on the inner edge from it to a cell's centre, or
/// the end of a cell edge the boundary runs along) is that one vertex, so the
/// boundary goes on from cell to cell through the node as one chain.
using EdgeKey = std::tuple<int, int, int, int, int>;  // (0, node, node, disc, side), (1, cell, corner, disc, side)

bool is_hole(const PlateModel& m, int disc) {
  return m.desc.discontinuities[static_cast<std::size_t>(disc)].kind == PlateDiscontinuity::Kind::hole;
}

EdgeKey node_key(int node, int disc) { return EdgeKey{3, node, -1, disc, 1}; }

double phi_at(const PlateModel& m, int disc, int node) {
  return m.node_phi[static_cast<std::size_t>(disc) * static_cast<std::size_t>(m.nodes) + static_cast<std::size_t>(node)];
}

/// The tip of crack `cut` that cell `cell` holds, or nullptr.
const PlateModel::Tip* tip_of_cell(const PlateModel& m, int cell, int cut) {
  if (m.cell_tip.empty()) return nullptr;
  const int t = m.cell_tip[static_cast<std::size_t>(cell)];
  if (t < 0 || m.tips[static_cast<std::size_t>(t)].crack != cut) return nullptr;
  return &m.tips[static_cast<std::size_t>(t)];
}

/// Parent point (xi, eta) of cell (i, j) in physical coordinates.
void physical_point(const PlateModel& m, int i, int j, double xi, double eta, double x[2]) {
  x[0] = m.desc.min[0] + m.cell_size[0] * (i + 0.5 * (1.0 + xi));
  x[1] = m.desc.min[1] + m.cell_size[1] * (j + 0.5 * (1.0 + eta));
}

/// Whether parent point (xi, eta) of cell (i, j) lies ahead of the tip: its
/// tangential level set (the distance along the tip's direction) positive.
bool ahead_of_tip(const PlateModel& m, const PlateModel::Tip& t, int i, int j, double xi, double eta) {
  double x[2];
  physical_point(m, i, j, xi, eta, x);
  return (x[0] - t.origin[0]) * t.cos_a + (x[1] - t.origin[1]) * t.sin_a > 0.0;
}

/// Appends the outer boundary's segments: edge() takes the cell edge from
/// local corner `from` to corner `to` of cell (i, j), walked with the material
/// on its left (one segment, or two where a discontinuity crosses it).
struct Walker {
  const PlateModel& m;
  PlateBoundary& out;
  std::map<EdgeKey, int>& crossings;
  int last = -1;   ///< the open chain's last vertex (−1: broken)
  int first = -1;  ///< the first vertex of the walk, if the chain never broke before it
  bool broke = false;

  int add_vertex(int i, int j, double xi, double eta, int side) {
    PlateBoundaryVertex v;
    physical_point(m, i, j, xi, eta, v.x);
    v.at = PlateMaterialPoint{{i, j}, xi, eta, side};
    out.vertices.push_back(v);
    return static_cast<int>(out.vertices.size()) - 1;
  }

  /// Where the outer chain breaks or starts again at a node on a void's
  /// boundary (the void reaches the domain's edge there), the chain's end is
  /// the node's vertex: the void's boundary (a cut cell's chord, or a cell
  /// edge it runs along) goes on from it.
  void register_node(int v) {
    if (m.cell_cut_by.empty()) return;
    const PlateMaterialPoint& at = out.vertices[static_cast<std::size_t>(v)].at;
    if (std::fabs(at.xi) != 1.0 || std::fabs(at.eta) != 1.0) return;
    const int node = (at.cell[1] + (at.eta > 0 ? 1 : 0)) * (m.desc.cells[0] + 1) + at.cell[0] + (at.xi > 0 ? 1 : 0);
    for (int k = 0; k < static_cast<int>(m.desc.discontinuities.size()); ++k)
      if (is_hole(m, k) && phi_at(m, k, node) == 0.0) crossings.emplace(node_key(node, k), v);
  }

  void add_segment(int i, int j, double xi0, double eta0, double xi1, double eta1, int side) {
    int a = last;
    if (a < 0) {
      a = add_vertex(i, j, xi0, eta0, side);
      register_node(a);
    }
    const int b = add_vertex(i, j, xi1, eta1, side);
    PlateBoundarySegment s;
    s.a = a, s.b = b, s.cell[0] = i, s.cell[1] = j;
    s.xi[0] = xi0, s.eta[0] = eta0, s.xi[1] = xi1, s.eta[1] = eta1, s.side = side;
    out.segments.push_back(s);
    const int k = static_cast<int>(out.segments.size()) - 1;
    out.vertices[static_cast<std::size_t>(a)].next = k;
    out.vertices[static_cast<std::size_t>(b)].prev = k;
    if (first < 0 && !broke) first = a;
    last = b;
  }

  void brk() {
    if (last >= 0) register_node(last);
    last = -1;
    broke = true;
  }

  /// A segment of a cut between two vertices already made, in cell (i, j)
  /// from (xi0, eta0) at a to (xi1, eta1) at b. False, adding nothing, when
  /// either end is already taken (the cut's boundary meets itself there).
  bool link(int a, int b, int i, int j, double xi0, double eta0, double xi1, double eta1, int side) {
    PlateBoundaryVertex& va = out.vertices[static_cast<std::size_t>(a)];
    PlateBoundaryVertex& vb = out.vertices[static_cast<std::size_t>(b)];
    if (va.next >= 0 || vb.prev >= 0) return false;
    PlateBoundarySegment seg;
    seg.a = a, seg.b = b, seg.cell[0] = i, seg.cell[1] = j, seg.side = side;
    seg.xi[0] = xi0, seg.eta[0] = eta0, seg.xi[1] = xi1, seg.eta[1] = eta1;
    out.segments.push_back(seg);
    va.next = vb.prev = static_cast<int>(out.segments.size()) - 1;
    return true;
  }

  void edge(int i, int j, int from, int to) {
    const int nx = m.desc.cells[0];
    const int cell = j * nx + i;
    const int cut = m.cell_cut_by.empty() ? -1 : m.cell_cut_by[static_cast<std::size_t>(cell)];
    const PlateModel::Tip* tip = cut >= 0 ? tip_of_cell(m, cell, cut) : nullptr;
    const double xi0 = kXi[from], eta0 = kEta[from], xi1 = kXi[to], eta1 = kEta[to];
    const int material = m.cell_material.empty() ? 0 : m.cell_material[static_cast<std::size_t>(cell)];
    if (material < 0) return brk();  // a hole's cell (a crack may run through it): no material on this edge
    if (cut < 0) return add_segment(i, j, xi0, eta0, xi1, eta1, 1);
    // The cutting level set is linear along a cell edge (an edge of a sub-triangle).
    auto node = [&](int corner) {
      const int di = (corner == 1 || corner == 2) ? 1 : 0, dj = corner >= 2 ? 1 : 0;
      return (j + dj) * (nx + 1) + (i + di);
    };
    const auto base = static_cast<std::size_t>(cut) * static_cast<std::size_t>(m.nodes);
    const double p0 = m.node_phi[base + static_cast<std::size_t>(node(from))];
    const double p1 = m.node_phi[base + static_cast<std::size_t>(node(to))];
    const int s0 = xfem::side_of(p0), s1 = xfem::side_of(p1);
    const PlateDiscontinuity::Kind kind = m.desc.discontinuities[static_cast<std::size_t>(cut)].kind;
    auto has_material = [&](int side) { return !(kind == PlateDiscontinuity::Kind::hole && side < 0); };
    // In a cell cut by a crack and an inclusion (a void with a crack is off
    // the domain's edge: build_plate refuses it), the edge is also split
    // where the inclusion's level set crosses it, as the plate splits it for
    // edge loads, so that each part lies in one material; the field is
    // continuous there and the chain goes on, on the same side of the crack.
    const int second = m.cell_second_cut.empty() ? -1 : m.cell_second_cut[static_cast<std::size_t>(cell)];
    double sxi = 0, seta = 0;
    bool split = false;
    if (second >= 0) {
      const auto sbase = static_cast<std::size_t>(second) * static_cast<std::size_t>(m.nodes);
      const double q0 = m.node_phi[sbase + static_cast<std::size_t>(node(from))];
      const double q1 = m.node_phi[sbase + static_cast<std::size_t>(node(to))];
      if (xfem::side_of(q0) != xfem::side_of(q1)) {
        crossing(q0, q1, xi0, eta0, xi1, eta1, node(from), node(to), sxi, seta);
        split = (sxi != xi0 || seta != eta0) && (sxi != xi1 || seta != eta1);
      }
    }
    // The part of the edge from (a_xi, a_eta) to (b_xi, b_eta) on side `side`,
    // split at the inclusion's crossing where that lies strictly inside it.
    auto part = [&](double a_xi, double a_eta, double b_xi, double b_eta, int side) {
      const double along = (sxi - a_xi) * (b_xi - a_xi) + (seta - a_eta) * (b_eta - a_eta);
      const double length2 = (b_xi - a_xi) * (b_xi - a_xi) + (b_eta - a_eta) * (b_eta - a_eta);
      if (split && along > 0 && along < length2) {
        add_segment(i, j, a_xi, a_eta, sxi, seta, side);
        add_segment(i, j, sxi, seta, b_xi, b_eta, side);
      } else {
        add_segment(i, j, a_xi, a_eta, b_xi, b_eta, side);
      }
    };
    if (s0 == s1) {
      if (!has_material(s0)) return brk();
      return part(xi0, eta0, xi1, eta1, s0);
    }
    // A void's boundary through an end of the edge (the level set 0 there):
    // the edge's material ends or starts at that node, whose vertex the void's
    // boundary shares (register_node); no segment of no length.
    if (kind == PlateDiscontinuity::Kind::hole && (p0 == 0.0 || p1 == 0.0)) return brk();
    double xim = 0, etam = 0;
    crossing(p0, p1, xi0, eta0, xi1, eta1, node(from), node(to), xim, etam);
    // In a tip's cell the level set crosses the edge also where the crack's
    // line runs on past the tip: there the edge is intact.
    if (tip != nullptr && ahead_of_tip(m, *tip, i, j, xim, etam)) return add_segment(i, j, xi0, eta0, xi1, eta1, 1);
    const int lo = std::min(node(from), node(to)), hi = std::max(node(from), node(to));
    if (has_material(s0)) {
      part(xi0, eta0, xim, etam, s0);
      crossings[EdgeKey{0, lo, hi, cut, s0}] = last;  // a void's boundary or a crack's face goes on from here
    }
    // A crack opens at the crossing: each face ends in a vertex of its own
    // side. An inclusion's field is continuous there: the chain goes on.
    if (kind != PlateDiscontinuity::Kind::inclusion) brk();
    if (has_material(s1)) {
      const std::size_t before = out.segments.size();
      part(xim, etam, xi1, eta1, s1);
      crossings[EdgeKey{0, lo, hi, cut, s1}] = out.segments[before].a;  // ... and ends here
    }
  }
};

/// The zero line of a cell's level set in one of its sub-triangles (the
/// level set is linear there: its values at the cell's corners and at the
/// centre, their mean).
struct Chord {
  double xi[2] = {0, 0}, eta[2] = {0, 0};  ///< its crossings of the triangle's edges (parent coordinates)
  EdgeKey key[2];                          ///< theirs (the side left to the caller)
  double g[2] = {0, 0};                    ///< the level set's gradient on the triangle (physical)
};

/// The chord of discontinuity `disc`'s level set (values phi at the corners
/// of cell `cell`, natural nodes `nodes`, and at its centre) in sub-triangle
/// t (corners t, t + 1 and the centre). False where it does not cross it.
/// The level set at a cell's centre, the mean of its corners'. A mean within
/// round-off of 0 (a line through the centre, whose corners' values cancel
/// to a few ulps) is 0, so that every inner edge's crossing is the centre
/// itself and shares its key (chord()); it moves the crossing by at most
/// 1e-12 of the half-diagonal.
double centre_value(const double phi[5], double sum) {
  const double scale = std::max(std::max(std::fabs(phi[0]), std::fabs(phi[1])), std::max(std::fabs(phi[2]), std::fabs(phi[3])));
  const double mean = 0.25 * sum;
  return std::fabs(mean) <= 1e-12 * scale ? 0.0 : mean;
}

bool chord(const PlateModel& m, int cell, const int nodes[4], const double phi[5], int t, int disc, Chord& c) {
  const int corner[3] = {t, (t + 1) % 4, 4};
  const double pxi[3] = {kXi[t], kXi[(t + 1) % 4], 0.0}, peta[3] = {kEta[t], kEta[(t + 1) % 4], 0.0};
  const bool hole = is_hole(m, disc);
  int points = 0;
  for (int e = 0; e < 3; ++e) {
    const int a = e, b = (e + 1) % 3;
    const double fa = phi[corner[a]], fb = phi[corner[b]];
    if (xfem::side_of(fa) == xfem::side_of(fb) || points == 2) continue;
    // Order the ends as the key does, so both cells (or triangles) agree.
    const bool outer = corner[a] < 4 && corner[b] < 4;
    const int ka = corner[a] < 4 ? nodes[corner[a]] : -1, kb = corner[b] < 4 ? nodes[corner[b]] : -1;
    if (hole && ((fa == 0.0 && corner[a] < 4) || (fb == 0.0 && corner[b] < 4))) {
      // Through a corner of the cell (its level set 0): the node's vertex.
      const int z = fa == 0.0 ? a : b;
      c.xi[points] = pxi[z], c.eta[points] = peta[z];
      c.key[points] = node_key(nodes[corner[z]], disc);
    } else if (outer) {
      crossing(fa, fb, pxi[a], peta[a], pxi[b], peta[b], ka, kb, c.xi[points], c.eta[points]);
      c.key[points] = EdgeKey{0, std::min(ka, kb), std::max(ka, kb), disc, 0};
    } else {
      // An inner edge: from its cell corner to the centre.
      const int cc = corner[a] < 4 ? a : b, z = corner[a] < 4 ? b : a;
      crossing(phi[corner[cc]], phi[4], pxi[cc], peta[cc], pxi[z], peta[z], 0, 1, c.xi[points], c.eta[points]);
      // A line through the cell's centre crosses every inner edge there: one
      // key (the centre, 4) for all of them, so the triangles' chords share
      // that vertex and a chord from the centre to itself has no length.
      c.key[points] = EdgeKey{1, cell, phi[4] == 0.0 ? 4 : corner[cc], disc, 0};
    }
    ++points;
  }
  if (points != 2) return false;
  // A void's boundary along the triangle's cell edge (both its corners on it,
  // the triangle void): traced from the cell with material across that edge
  // (plate_boundary_build), not here.
  if (hole && std::get<0>(c.key[0]) == 3 && std::get<0>(c.key[1]) == 3 && c.key[0] != c.key[1]) return false;
  // φ's gradient on the triangle (parent coordinates, then physical).
  const double x0 = pxi[0] - pxi[2], y0 = peta[0] - peta[2], x1 = pxi[1] - pxi[2], y1 = peta[1] - peta[2];
  const double r0 = phi[corner[0]] - phi[4], r1 = phi[corner[1]] - phi[4];
  const double det = x0 * y1 - x1 * y0;
  c.g[0] = (r0 * y1 - r1 * y0) / det / m.cell_size[0], c.g[1] = (x0 * r1 - x1 * r0) / det / m.cell_size[1];
  return true;
}

/// The end of a chord that a segment with side `side`'s material on its left
/// starts from: the direction with the material (φ ≥ 0) on the left is
/// (g_y, −g_x); a crack's − face runs the other way.
int chord_first(const PlateModel& m, const Chord& c, int side) {
  const double dx = (c.xi[1] - c.xi[0]) * m.cell_size[0], dy = (c.eta[1] - c.eta[0]) * m.cell_size[1];
  return (dx * c.g[1] - dy * c.g[0] >= 0) == (side > 0) ? 0 : 1;
}

/// A level set linear on sub-triangle t (values phi at the cell's corners
/// and centre) at parent point (xi, eta), as the plate evaluates it.
double on_triangle(const double phi[5], int t, double xi, double eta) {
  const int a = t, b = (t + 1) % 4;
  const double x0 = kXi[a], y0 = kEta[a], x1 = kXi[b], y1 = kEta[b];
  const double r0 = phi[a] - phi[4], r1 = phi[b] - phi[4];
  const double det = x0 * y1 - x1 * y0;
  return phi[4] + (r0 * y1 - r1 * y0) / det * xi + (x0 * r1 - x1 * r0) / det * eta;
}

inline double dot(const double a[2], const double b[2]) { return a[0] * b[0] + a[1] * b[1]; }

/// The vertices a contact's feature spans: an edge's two ends; a vertex, its
/// neighbours along the chain too. Returns their count (≤ 3).
int feature_vertices(const PlateBoundary& b, const PlateBoundaryContact& c, int out[3]) {
  if (c.vertex < 0) {
    const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(c.segment)];
    out[0] = s.a, out[1] = s.b;
    return 2;
  }
  const PlateBoundaryVertex& v = b.vertices[static_cast<std::size_t>(c.vertex)];
  int n = 0;
  out[n++] = c.vertex;
  if (v.prev >= 0) out[n++] = b.segments[static_cast<std::size_t>(v.prev)].a;
  if (v.next >= 0) out[n++] = b.segments[static_cast<std::size_t>(v.next)].b;
  return n;
}

/// Whether two contacts' features are one piece of boundary: they share a
/// vertex, or a vertex's neighbour along its chain.
bool joined(const PlateBoundary& b, const PlateBoundaryContact& x, const PlateBoundaryContact& y) {
  int vx[3], vy[3];
  const int nx = feature_vertices(b, x, vx), ny = feature_vertices(b, y, vy);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      if (vx[i] == vy[j]) return true;
  return false;
}

}  // namespace

BuildResult plate_boundary_build(const PlateModel& m, double max_radius, double allowance, PlateBoundary& out) {
  if (!m.built || m.desc.analysis != PlateDesc::Analysis::dynamic)
    return BuildResult::failure(Code::invalid_argument, "continuum: the plate is not built as a %s analysis", "dynamic");
  if (!(std::isfinite(max_radius) && max_radius > 0))
    return BuildResult::failure(Code::invalid_argument, "dem.particles: the largest radius %g is not positive",
                                max_radius);
  if (!(std::isfinite(allowance) && allowance > 0))
    return BuildResult::failure(Code::invalid_argument, "boundary_allowance: %g is not a positive length", allowance);
  out = PlateBoundary{};
  const int nx = m.desc.cells[0], ny = m.desc.cells[1];
  std::map<EdgeKey, int> crossings;
  Walker w{m, out, crossings};
  auto meets_itself = [](int cut, const PlateDiscontinuity& q, int i, int j) {
    return BuildResult::failure(Code::invalid_argument,
                                "continuum.discontinuities.%d: the boundary of '%s' meets itself in cell (%d, %d) (refine the mesh)",
                                cut, q.name.c_str(), i, j);
  };
  for (int i = 0; i < nx; ++i) w.edge(i, 0, 0, 1);             // bottom, left to right
  for (int j = 0; j < ny; ++j) w.edge(nx - 1, j, 1, 2);        // right, upwards
  for (int i = nx - 1; i >= 0; --i) w.edge(i, ny - 1, 2, 3);   // top, right to left
  for (int j = ny - 1; j >= 0; --j) w.edge(0, j, 3, 0);        // left, downwards
  // Close the loop where the walk ends where it started, unbroken there.
  if (w.last >= 0 && w.first >= 0) {
    PlateBoundaryVertex& end = out.vertices[static_cast<std::size_t>(w.last)];
    const PlateBoundaryVertex& start = out.vertices[static_cast<std::size_t>(w.first)];
    if (end.x[0] == start.x[0] && end.x[1] == start.x[1] && start.prev < 0) {
      const int seg = end.prev;
      out.segments[static_cast<std::size_t>(seg)].b = w.first;
      out.vertices[static_cast<std::size_t>(w.first)].prev = seg;
      out.vertices.pop_back();  // the duplicate was the last vertex added
    }
  }
  // Void boundaries and free crack faces: in every sub-triangle of a cell cut
  // by a void, the zero line of the cutting level set (linear there) is one
  // segment, oriented with the material (φ ≥ 0) on its left; a free crack's
  // line is two, one per face, each with its side's material on its left.
  // Crossings are shared by edge and side, so the segments chain into loops,
  // or into the outer chain where they reach the domain's edge.
  //
  // A void's boundary along a cell edge (both its nodes on it, φ = 0, so that
  // no cell is cut there: the cells on one side are inside the void, those on
  // the other have material up to the edge): the edge is a segment where the
  // part of the cell on one side that touches it has material and the part
  // on the other has none (a cell inside the void, or the void's sub-triangle
  // of a cell it cuts). It is traced from the cell with material, in the cell
  // order, as that cell's edge walked with the cell on its left, between the
  // vertices of its two nodes, which the cut cells' chords ending there share.
  const auto nd = m.desc.discontinuities.size();
  auto centre_phi = [&](int disc, int ci, int cj) {
    double phi[5], mean = 0;
    for (int a = 0; a < 4; ++a) {
      const int di = (a == 1 || a == 2) ? 1 : 0, dj = a >= 2 ? 1 : 0;
      mean += (phi[a] = phi_at(m, disc, (cj + dj) * (nx + 1) + ci + di));
    }
    return centre_value(phi, mean);
  };
  // Whether cell (ci, cj) has no material beside its edge whose nodes are on
  // void k's boundary: inside the void, or cut by it with the sub-triangle
  // on that edge void (its centre's level set negative).
  auto void_beside = [&](int ci, int cj, int k) {
    const auto c = static_cast<std::size_t>(cj * nx + ci);
    if (m.cell_material[c] < 0) {
      // Some node inside void k; or every node on its boundary (a void one
      // cell wide on node lines, whose cells the plate makes void by the
      // exact level set at their centre: docs/xfem2d.md, "Thinner than the mesh").
      bool all_on = true;
      for (int a = 0; a < 4; ++a) {
        const int di = (a == 1 || a == 2) ? 1 : 0, dj = a >= 2 ? 1 : 0;
        const double p = phi_at(m, k, (cj + dj) * (nx + 1) + ci + di);
        if (p < 0.0) return true;
        all_on = all_on && p == 0.0;
      }
      return all_on;
    }
    const bool cut_by_k = m.cell_cut_by[c] == k || m.cell_second_cut[c] == k;
    return cut_by_k && centre_phi(k, ci, cj) < 0.0;
  };
  auto void_edges = [&](int i, int j, const int nodes[4]) {
    const auto cell = static_cast<std::size_t>(j * nx + i);
    const int cut = m.cell_cut_by[cell], second = m.cell_second_cut[cell];
    for (int a = 0; a < 4; ++a) {
      const int b = (a + 1) % 4;
      const int ni = i + (a == 1 ? 1 : a == 3 ? -1 : 0), nj = j + (a == 0 ? -1 : a == 2 ? 1 : 0);
      if (ni < 0 || nj < 0 || ni >= nx || nj >= ny) continue;  // the domain's edge: the outer walk's
      for (int k = 0; k < static_cast<int>(nd); ++k) {
        if (!is_hole(m, k) || phi_at(m, k, nodes[a]) != 0.0 || phi_at(m, k, nodes[b]) != 0.0) continue;
        if (!void_beside(ni, nj, k)) continue;
        const PlateDiscontinuity& q = m.desc.discontinuities[static_cast<std::size_t>(k)];
        auto refuse = [&] {
          return BuildResult::failure(Code::invalid_argument,
                                      "continuum.discontinuities.%d: the boundary of '%s' runs along an edge of cell "
                                      "(%d, %d), which '%s' cuts there in a way this build does not trace (move it off "
                                      "the mesh line)",
                                      k, q.name.c_str(), i, j,
                                      m.desc.discontinuities[static_cast<std::size_t>(cut)].name.c_str());
        };
        auto vertex = [&](int node, int corner, int side) {
          const EdgeKey key = node_key(node, k);
          const auto found = crossings.find(key);
          return found != crossings.end() ? found->second
                                          : (crossings[key] = w.add_vertex(i, j, kXi[corner], kEta[corner], side));
        };
        if (cut >= 0 && is_hole(m, cut)) {
          // This cell's sub-triangle on the edge: material where the void
          // cutting the cell has its level set ≥ 0 on all of it.
          const bool material = second < 0 && phi_at(m, cut, nodes[a]) >= 0.0 && phi_at(m, cut, nodes[b]) >= 0.0 &&
                                centre_phi(cut, i, j) >= 0.0;
          if (!material && second < 0 && cut == k) break;  // void on both sides: no boundary
          if (!material) return refuse();
        } else if (cut >= 0) {
          // A crack or an inclusion cuts this cell (and no second one, nor a
          // tip: refused): the edge is split where its level set crosses it,
          // each part on its side, as the outer walk splits an outer edge. A
          // crack's crossing is a vertex of each side, keyed as the crack's
          // faces key it there, so a free crack's face and the void's edge
          // chain through it (a tied or unilateral crack's chain ends there,
          // as at a mouth); an inclusion's, one vertex (its field is
          // continuous).
          if (second >= 0 || tip_of_cell(m, static_cast<int>(cell), cut) != nullptr) return refuse();
          const double p0 = phi_at(m, cut, nodes[a]), p1 = phi_at(m, cut, nodes[b]);
          const int s0 = xfem::side_of(p0), s1 = xfem::side_of(p1);
          const bool crack = m.desc.discontinuities[static_cast<std::size_t>(cut)].kind == PlateDiscontinuity::Kind::crack;
          if (s0 != s1 && (p0 == 0.0 || p1 == 0.0)) {
            if (crack) return refuse();  // a crack through the edge's node
            const int side = p0 == 0.0 ? s1 : s0;  // an inclusion through it: the edge on the other side
            if (!w.link(vertex(nodes[a], a, side), vertex(nodes[b], b, side), i, j, kXi[a], kEta[a], kXi[b], kEta[b], side))
              return meets_itself(k, q, i, j);
            break;
          }
          if (s0 == s1) {
            if (!w.link(vertex(nodes[a], a, s0), vertex(nodes[b], b, s0), i, j, kXi[a], kEta[a], kXi[b], kEta[b], s0))
              return meets_itself(k, q, i, j);
            break;
          }
          double xm = 0, em = 0;
          crossing(p0, p1, kXi[a], kEta[a], kXi[b], kEta[b], nodes[a], nodes[b], xm, em);
          const int lo = std::min(nodes[a], nodes[b]), hi = std::max(nodes[a], nodes[b]);
          auto at_crossing = [&](int side) {
            const EdgeKey key{0, lo, hi, cut, side};
            const auto found = crossings.find(key);
            return found != crossings.end() ? found->second : (crossings[key] = w.add_vertex(i, j, xm, em, side));
          };
          const int va = vertex(nodes[a], a, s0);
          const int m0 = crack ? at_crossing(s0) : w.add_vertex(i, j, xm, em, s0);
          const int m1 = crack ? at_crossing(s1) : m0;
          const int vb = vertex(nodes[b], b, s1);
          if (!w.link(va, m0, i, j, kXi[a], kEta[a], xm, em, s0) || !w.link(m1, vb, i, j, xm, em, kXi[b], kEta[b], s1))
            return meets_itself(k, q, i, j);
          break;
        }
        const int va = vertex(nodes[a], a, 1), vb = vertex(nodes[b], b, 1);
        if (!w.link(va, vb, i, j, kXi[a], kEta[a], kXi[b], kEta[b], 1)) return meets_itself(k, q, i, j);
        break;
      }
    }
    return BuildResult::success();
  };
  bool any_hole = false;
  for (int k = 0; k < static_cast<int>(nd); ++k) any_hole = any_hole || is_hole(m, k);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int cell = j * nx + i;
      if (any_hole && m.cell_material[static_cast<std::size_t>(cell)] >= 0) {
        int corners[4];
        for (int a = 0; a < 4; ++a) {
          const int di = (a == 1 || a == 2) ? 1 : 0, dj = a >= 2 ? 1 : 0;
          corners[a] = (j + dj) * (nx + 1) + (i + di);
        }
        const BuildResult r = void_edges(i, j, corners);
        if (!r.ok()) return r;
      }
      const int cut = m.cell_cut_by.empty() ? -1 : m.cell_cut_by[static_cast<std::size_t>(cell)];
      if (cut < 0 || m.cell_material[static_cast<std::size_t>(cell)] < 0) continue;  // uncut, or all void
      const PlateDiscontinuity& q = m.desc.discontinuities[static_cast<std::size_t>(cut)];
      const bool hole = q.kind == PlateDiscontinuity::Kind::hole;
      // A free crack's two faces; tied or unilateral faces are held together.
      const bool faces = q.kind == PlateDiscontinuity::Kind::crack && q.faces == PlateDiscontinuity::Faces::free;
      const int hv = m.cell_second_cut.empty() ? -1 : m.cell_second_cut[static_cast<std::size_t>(cell)];
      if (!hole && !faces && hv < 0) continue;
      int nodes[4];
      for (int a = 0; a < 4; ++a) {
        const int di = (a == 1 || a == 2) ? 1 : 0, dj = a >= 2 ? 1 : 0;
        nodes[a] = (j + dj) * (nx + 1) + (i + di);
      }
      const auto base = static_cast<std::size_t>(cut) * static_cast<std::size_t>(m.nodes);
      double phi[5], mean = 0;
      for (int a = 0; a < 4; ++a) mean += (phi[a] = m.node_phi[base + static_cast<std::size_t>(nodes[a])]);
      phi[4] = centre_value(phi, mean);
      // The plate's flat saddle takes the exact centre value: trace the same sub-triangles.
      plate_flat_centre(m, cut, i, j, phi[4]);
      // The vertex of a key (its side set to key_side), made at (xi, eta) on
      // side `side` by the first segment through it.
      auto vertex = [&](EdgeKey key, int key_side, double xi, double eta, int side) {
        std::get<4>(key) = key_side;
        const auto found = crossings.find(key);
        return found != crossings.end() ? found->second : (crossings[key] = w.add_vertex(i, j, xi, eta, side));
      };
      if (hv >= 0) {
        // A crack from a void or across an inclusion (no tip reaches the
        // cell, and a void's is off the domain's edge: build_plate refuses
        // these). The second level set is linear on each sub-triangle, as the
        // plate splits the pieces by it.
        //
        // A void: the material is where its level set is ≥ 0; the crack's
        // faces are its line clipped there as the plate clips them, from
        // where it meets the void's boundary (P, a vertex of each side); the
        // void's boundary is split at P into a piece on each side of the
        // crack, each on its side's functions, so that the side's face and
        // void piece chain through P. The crack's line inside the void has no
        // material on either side: no segment.
        //
        // An inclusion: material on both sides of its boundary, which is no
        // contact surface; the crack's faces are its whole line, each face on
        // its side's functions (the inclusion's ridge among them), split at P
        // where the line crosses the inclusion's boundary, so that each
        // segment lies in one material (plate_boundary_segment_material).
        const auto vbase = static_cast<std::size_t>(hv) * static_cast<std::size_t>(m.nodes);
        double vphi[5], vmean = 0;
        for (int a = 0; a < 4; ++a) vmean += (vphi[a] = m.node_phi[vbase + static_cast<std::size_t>(nodes[a])]);
        vphi[4] = centre_value(vphi, vmean);
        plate_flat_centre(m, hv, i, j, vphi[4]);
        const PlateDiscontinuity& qv = m.desc.discontinuities[static_cast<std::size_t>(hv)];
        const bool second_void = qv.kind == PlateDiscontinuity::Kind::hole;
        for (int t = 0; t < 4; ++t) {
          Chord cc, cv;
          const bool crack_here = chord(m, cell, nodes, phi, t, cut, cc);
          const bool void_here = second_void && chord(m, cell, nodes, vphi, t, hv, cv);
          // The crack's chord outside the void: parameters s[0] … s[1] along it.
          double s[2] = {0.0, 1.0};
          bool face = false;
          int clipped = -1;  // the end moved to P (−1: none)
          double ps = -1;    // an inclusion's P: its parameter along the chord (−1: none)
          if (crack_here) {
            const double vs0 = on_triangle(vphi, t, cc.xi[0], cc.eta[0]), vs1 = on_triangle(vphi, t, cc.xi[1], cc.eta[1]);
            if (!second_void) {
              face = true;
              if ((vs0 < 0.0) != (vs1 < 0.0)) {
                const double at = vs0 / (vs0 - vs1);
                if (at > 0.0 && at < 1.0) ps = at;
              }
            } else if (!(vs0 < 0.0 && vs1 < 0.0)) {
              if (vs0 < 0.0) s[0] = vs0 / (vs0 - vs1);
              if (vs1 < 0.0) s[1] = vs0 / (vs0 - vs1);
              face = s[1] > s[0];
              if (face && (vs0 < 0.0 || vs1 < 0.0)) clipped = vs0 < 0.0 ? 0 : 1;
            }
          }
          double exi[2], eeta[2];  // the clipped chord's ends
          for (int e = 0; e < 2; ++e) {
            if (e == clipped) {
              exi[e] = cc.xi[0] + s[e] * (cc.xi[1] - cc.xi[0]);
              eeta[e] = cc.eta[0] + s[e] * (cc.eta[1] - cc.eta[0]);
            } else {
              exi[e] = cc.xi[e], eeta[e] = cc.eta[e];  // an edge's crossing, as the cells around find it
            }
          }
          const EdgeKey at_p{2, cell, t, cut, 0};
          if (face && faces)
            for (const int side : {1, -1}) {
              const int first = chord_first(m, cc, side);
              int ends[2];
              for (int e = 0; e < 2; ++e) {
                const int k = e == 0 ? first : 1 - first;
                ends[e] = vertex(k == clipped ? at_p : cc.key[k], side, exi[k], eeta[k], side);
              }
              if (ends[0] == ends[1]) continue;
              if (ps < 0.0) {
                if (!w.link(ends[0], ends[1], i, j, exi[first], eeta[first], exi[1 - first], eeta[1 - first], side))
                  return meets_itself(cut, q, i, j);
                continue;
              }
              const double pxi = cc.xi[0] + ps * (cc.xi[1] - cc.xi[0]), peta = cc.eta[0] + ps * (cc.eta[1] - cc.eta[0]);
              const int p = vertex(at_p, side, pxi, peta, side);
              if (!w.link(ends[0], p, i, j, exi[first], eeta[first], pxi, peta, side) ||
                  !w.link(p, ends[1], i, j, pxi, peta, exi[1 - first], eeta[1 - first], side))
                return meets_itself(cut, q, i, j);
            }
          if (!void_here) continue;
          const int first = chord_first(m, cv, 1), other = 1 - first;
          // The crack's side of each end of the void's chord (its key's side
          // is the void's material side, +1, as in the cells the void alone cuts).
          const double f0 = on_triangle(phi, t, cv.xi[first], cv.eta[first]);
          const double f1 = on_triangle(phi, t, cv.xi[other], cv.eta[other]);
          if (clipped < 0) {
            // The void's chord does not meet the crack's line outside the
            // void in this triangle: one piece, on the side of its middle.
            const int side = xfem::side_of(on_triangle(phi, t, 0.5 * (cv.xi[0] + cv.xi[1]), 0.5 * (cv.eta[0] + cv.eta[1])));
            const int a = vertex(cv.key[first], 1, cv.xi[first], cv.eta[first], side);
            const int b = vertex(cv.key[other], 1, cv.xi[other], cv.eta[other], side);
            if (a != b && !w.link(a, b, i, j, cv.xi[first], cv.eta[first], cv.xi[other], cv.eta[other], side))
              return meets_itself(hv, qv, i, j);
            continue;
          }
          // Split at P: each piece on the side of its far end (an end on the
          // crack's line to round-off takes the side opposite the other's).
          int s0 = xfem::side_of(f0), s1 = xfem::side_of(f1);
          if (s0 == s1) {
            if (std::fabs(f0) < std::fabs(f1))
              s0 = -s1;
            else
              s1 = -s0;
          }
          const double pxi = exi[clipped], peta = eeta[clipped];
          const int a0 = vertex(cv.key[first], 1, cv.xi[first], cv.eta[first], s0);
          const int p0 = vertex(at_p, s0, pxi, peta, s0);
          if (!w.link(a0, p0, i, j, cv.xi[first], cv.eta[first], pxi, peta, s0)) return meets_itself(hv, qv, i, j);
          const int p1 = vertex(at_p, s1, pxi, peta, s1);
          const int b1 = vertex(cv.key[other], 1, cv.xi[other], cv.eta[other], s1);
          if (!w.link(p1, b1, i, j, pxi, peta, cv.xi[other], cv.eta[other], s1)) return meets_itself(hv, qv, i, j);
        }
        continue;
      }
      if (const PlateModel::Tip* tip = tip_of_cell(m, cell, cut)) {
        // A tip's cell, fanned from the tip as the plate integrates it: each
        // face is the straight crack from where it enters the cell (the
        // level set's crossing of that edge behind the tip, the point the
        // cell behind finds) to the tip, where the two faces meet.
        int edge = -1;
        double exi = 0, eeta = 0;
        for (int a = 0; a < 4 && edge < 0; ++a) {
          const int b = (a + 1) % 4;
          if (xfem::side_of(phi[a]) == xfem::side_of(phi[b])) continue;
          crossing(phi[a], phi[b], kXi[a], kEta[a], kXi[b], kEta[b], nodes[a], nodes[b], exi, eeta);
          if (!ahead_of_tip(m, *tip, i, j, exi, eeta)) edge = a;
        }
        if (edge < 0) continue;  // the crack enters at a node on no sign change: no faces here
        const int lo = std::min(nodes[edge], nodes[(edge + 1) % 4]), hi = std::max(nodes[edge], nodes[(edge + 1) % 4]);
        const double txi = 2.0 * (tip->origin[0] - m.desc.min[0]) / m.cell_size[0] - 2.0 * i - 1.0;
        const double teta = 2.0 * (tip->origin[1] - m.desc.min[1]) / m.cell_size[1] - 2.0 * j - 1.0;
        const int apex = w.add_vertex(i, j, txi, teta, 1);
        out.vertices[static_cast<std::size_t>(apex)].tip = true;
        // The tip frame's left (local y > 0) is the + side at the polyline's last point.
        const int left = tip->at_end ? 1 : -1;
        for (const int side : {1, -1}) {
          const auto found = crossings.find(EdgeKey{0, lo, hi, cut, side});
          const int entry = found != crossings.end() ? found->second
                                                     : (crossings[EdgeKey{0, lo, hi, cut, side}] = w.add_vertex(i, j, exi, eeta, side));
          // With its side's material on the left: towards the tip on the left side.
          const bool inward = side == left;
          const bool linked = inward ? w.link(entry, apex, i, j, exi, eeta, txi, teta, side)
                                     : w.link(apex, entry, i, j, txi, teta, exi, eeta, side);
          if (!linked) return meets_itself(cut, q, i, j);
        }
        continue;
      }
      for (int t = 0; t < 4; ++t) {
        Chord c;
        if (!chord(m, cell, nodes, phi, t, cut, c)) continue;
        // The + side's segment runs with its material (φ ≥ 0) on the left; a
        // crack's − face runs the other way over the same line.
        for (const int side : {1, -1}) {
          if (side < 0 && !faces) break;
          const int first = chord_first(m, c, side);
          int ends[2];
          for (int e = 0; e < 2; ++e) {
            const int k = e == 0 ? first : 1 - first;
            ends[e] = vertex(c.key[k], side, c.xi[k], c.eta[k], side);
          }
          if (ends[0] == ends[1]) continue;  // the line through a corner: no length
          if (!w.link(ends[0], ends[1], i, j, c.xi[first], c.eta[first], c.xi[1 - first], c.eta[1 - first], side))
            return meets_itself(cut, q, i, j);
        }
      }
    }
  // Chains: from each segment not yet named, back to its chain's first
  // segment (or round its loop), then forwards naming every one by it.
  for (std::size_t k = 0; k < out.segments.size(); ++k) {
    if (out.segments[k].chain >= 0) continue;
    int head = static_cast<int>(k);
    for (int before = out.vertices[static_cast<std::size_t>(out.segments[k].a)].prev;
         before >= 0 && before != static_cast<int>(k);
         before = out.vertices[static_cast<std::size_t>(out.segments[static_cast<std::size_t>(before)].a)].prev)
      head = before;
    for (int seg = head; seg >= 0 && out.segments[static_cast<std::size_t>(seg)].chain < 0;
         seg = out.vertices[static_cast<std::size_t>(out.segments[static_cast<std::size_t>(seg)].b)].next)
      out.segments[static_cast<std::size_t>(seg)].chain = head;
  }
  // Which segments the plate's field is linear along: an edge (constant ξ or
  // η) of a cell with only its four bilinear functions.
  for (PlateBoundarySegment& s : out.segments) {
    PlatePointBasis basis;
    const bool along_edge = s.xi[0] == s.xi[1] || s.eta[0] == s.eta[1];
    s.linear = along_edge &&
               plate_point_basis(m, s.cell[0], s.cell[1], 0.5 * (s.xi[0] + s.xi[1]), 0.5 * (s.eta[0] + s.eta[1]),
                                 s.side, basis, 0.0) &&  // the basis's count only: no held value read
               basis.count == 4;
  }
  // Bins: the domain grown by the reach, bins at least a reach wide.
  out.allowance = allowance;
  out.reach = max_radius + allowance;
  const double h = std::max({m.cell_size[0], m.cell_size[1], 2.0 * out.reach});
  out.bin_size = h;
  for (int c = 0; c < 2; ++c) {
    out.origin[c] = m.desc.min[c] - out.reach;
    out.bins[c] = static_cast<int>(std::ceil((m.desc.max[c] - m.desc.min[c] + 2.0 * out.reach) / h)) + 1;
  }
  const auto nbins = static_cast<std::size_t>(out.bins[0]) * static_cast<std::size_t>(out.bins[1]);
  std::vector<int> count(nbins + 1, 0);
  auto for_bins = [&](const PlateBoundarySegment& s, auto&& visit) {
    const PlateBoundaryVertex& a = out.vertices[static_cast<std::size_t>(s.a)];
    const PlateBoundaryVertex& b = out.vertices[static_cast<std::size_t>(s.b)];
    int lo[2], hi[2];
    for (int c = 0; c < 2; ++c) {
      lo[c] = std::max(0, static_cast<int>(std::floor((std::min(a.x[c], b.x[c]) - out.reach - out.origin[c]) / h)));
      hi[c] = std::min(out.bins[c] - 1,
                       static_cast<int>(std::floor((std::max(a.x[c], b.x[c]) + out.reach - out.origin[c]) / h)));
    }
    for (int bj = lo[1]; bj <= hi[1]; ++bj)
      for (int bi = lo[0]; bi <= hi[0]; ++bi) visit(static_cast<std::size_t>(bj) * out.bins[0] + bi);
  };
  for (const PlateBoundarySegment& s : out.segments) for_bins(s, [&](std::size_t k) { ++count[k + 1]; });
  for (std::size_t k = 0; k < nbins; ++k) count[k + 1] += count[k];
  out.bin_start = count;
  out.bin_items.assign(static_cast<std::size_t>(count[nbins]), 0);
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (std::size_t k = 0; k < out.segments.size(); ++k)
    for_bins(out.segments[k], [&](std::size_t bin) { out.bin_items[static_cast<std::size_t>(fill[bin]++)] = static_cast<int>(k); });
  return BuildResult::success();
}

int plate_boundary_segment_material(const PlateModel& m, const PlateBoundarySegment& s) {
  const int nx = m.desc.cells[0];
  const auto cell = static_cast<std::size_t>(s.cell[1] * nx + s.cell[0]);
  const int material = m.cell_material.empty() ? 0 : m.cell_material[cell];
  const int cut = m.cell_cut_by.empty() ? -1 : m.cell_cut_by[cell];
  if (cut < 0) return material;
  const PlateDiscontinuity::Kind kind = m.desc.discontinuities[static_cast<std::size_t>(cut)].kind;
  if (kind == PlateDiscontinuity::Kind::inclusion) return s.side < 0 ? 1 + cut : material;
  const int second = m.cell_second_cut.empty() ? -1 : m.cell_second_cut[cell];
  if (second < 0 || m.desc.discontinuities[static_cast<std::size_t>(second)].kind != PlateDiscontinuity::Kind::inclusion)
    return material;
  // The inclusion's level set, linear on the sub-triangle that holds the
  // segment's middle (the segment is split where it crosses zero).
  const double xi = 0.5 * (s.xi[0] + s.xi[1]), eta = 0.5 * (s.eta[0] + s.eta[1]);
  const int t = eta <= -std::fabs(xi) ? 0 : xi >= std::fabs(eta) ? 1 : eta >= std::fabs(xi) ? 2 : 3;
  const auto base = static_cast<std::size_t>(second) * static_cast<std::size_t>(m.nodes);
  double phi[5], mean = 0;
  for (int a = 0; a < 4; ++a) {
    const int di = (a == 1 || a == 2) ? 1 : 0, dj = a >= 2 ? 1 : 0;
    mean += (phi[a] = m.node_phi[base + static_cast<std::size_t>((s.cell[1] + dj) * (nx + 1) + s.cell[0] + di)]);
  }
  phi[4] = centre_value(phi, mean);  // as the tracer split the segment
  return xfem::side_of(on_triangle(phi, t, xi, eta)) < 0 ? 1 + second : material;
}

void plate_material_point_field(const PlateModel& m, const PlateMaterialPoint& at, const double* field,
                                bool displacement, double time, double out[2]) {
  PlatePointBasis basis;
  out[0] = out[1] = 0.0;
  if (!plate_point_basis(m, at.cell[0], at.cell[1], at.xi, at.eta, at.side, basis, time)) return;
  for (int f = 0; f < basis.count; ++f)
    for (int c = 0; c < 2; ++c) {
      const int dof = basis.dof[f][c];
      out[c] += basis.n[f] * (dof >= 0 ? field[dof] : (displacement ? basis.held[f][c] : 0.0));
    }
}

void plate_boundary_positions(const PlateModel& m, const PlateBoundary& b, const double* u, double time,
                              double* positions) {
  const std::size_t nv = b.vertices.size();
  for (std::size_t k = 0; k < nv; ++k) {
    double d[2];
    plate_material_point_field(m, b.vertices[k].at, u, true, time, d);
    positions[2 * k] = b.vertices[k].x[0] + d[0];
    positions[2 * k + 1] = b.vertices[k].x[1] + d[1];
  }
}

bool plate_boundary_within_reach(const PlateBoundary& b, const double* positions) {
  const std::size_t nv = b.vertices.size();
  for (std::size_t k = 0; k < nv; ++k) {
    const double dx = positions[2 * k] - b.vertices[k].x[0], dy = positions[2 * k + 1] - b.vertices[k].x[1];
    if (!(dx * dx + dy * dy <= b.allowance * b.allowance)) return false;
  }
  return true;
}

namespace {

/// A concave joint: the disk's centre projects inside both edges, and the
/// deeper of the two (the closest point) changes sides at the joint's
/// bisector, turning the normal and moving the force from one edge's nodes
/// to the other's in one jump (which a window's fixed point cannot settle,
/// and which rocks a disk resting on it). Near the bisector the contact is
/// instead a blend of the two edges' feet: with s = gap_partner − gap_best
/// ≥ 0, the partner's weight w = ½(1 − smoothstep(s/ε)), ½ on the bisector
/// and 0 from s = ε on. ε = ½(1 − n_best·n_partner)·gap_best is below the s
/// at which the partner's foot leaves its edge (s = (1 − cos φ)|c − v| there,
/// φ the joint's angle, v its vertex), so the partner's weight is 0 before it
/// stops being a candidate: the contact is continuous everywhere, and on the
/// bisector its normal is the bisector's. The overlap stays the closest
/// point's (r − gap_best: continuous, since the two gaps are equal where the
/// deeper changes, and no higher than the surface). The point is the blend
/// p̄ = (1 − w) p_best + w p_partner and the normal is along c − p̄, so that
/// the force shared by the two feet in the same proportions has a moment
/// about the centre of −(c − p̄) × F: zero for a normal force, as for a
/// single contact (the disk's arm is then |c − p̄|).
template <typename ForEach>
void blend_concave_joint(const PlateBoundary& b, const double centre[2], double radius,
                         PlateBoundaryContact& best, ForEach&& for_each_candidate) {
  if (best.vertex >= 0) return;
  const PlateBoundarySegment& sb = b.segments[static_cast<std::size_t>(best.segment)];
  const double gap_best = radius - best.overlap;
  double weight = 0;
  PlateBoundaryContact partner;
  for_each_candidate([&](const PlateBoundaryContact& c) {
    if (c.vertex >= 0 || c.segment == best.segment) return;
    const PlateBoundarySegment& sc = b.segments[static_cast<std::size_t>(c.segment)];
    if (sc.a != sb.b && sc.b != sb.a) return;  // not across a joint of best's
    const double cosine = dot(c.normal, best.normal);
    if (cosine < 0.5) return;  // more than 60° apart: two contacts of a corner
    const double epsilon = 0.5 * (1.0 - cosine) * gap_best;
    const double s = best.overlap - c.overlap;
    if (!(epsilon > 0) || !(s < epsilon)) return;
    const double x = s / epsilon;
    const double w = 0.5 * (1.0 - x * x * (3.0 - 2.0 * x));
    if (w > weight) weight = w, partner = c;
  });
  if (!(weight > 0)) return;
  double point[2], gap[2];
  for (int a = 0; a < 2; ++a) {
    point[a] = (1.0 - weight) * best.point[a] + weight * partner.point[a];
    gap[a] = centre[a] - point[a];
  }
  const double length = std::sqrt(dot(gap, gap));
  if (!(length > 0)) return;
  best.point[0] = point[0], best.point[1] = point[1];
  best.normal[0] = gap[0] / length, best.normal[1] = gap[1] / length;
  best.partner = partner.segment;
  best.partner_t = partner.t;
  best.partner_weight = weight;
}

}  // namespace

int plate_boundary_contacts(const PlateBoundary& b, const double* positions, const double centre[2], double radius,
                            PlateBoundaryContact out[kPlateBoundaryMaxContacts]) {
  int bin[2];
  for (int c = 0; c < 2; ++c) {
    const double f = std::floor((centre[c] - b.origin[c]) / b.bin_size);
    if (!(f >= 0 && f < b.bins[c])) return 0;
    bin[c] = static_cast<int>(f);
  }
  const auto k = static_cast<std::size_t>(bin[1]) * static_cast<std::size_t>(b.bins[0]) + static_cast<std::size_t>(bin[0]);
  auto at = [&](int v) { return positions + 2 * v; };
  auto direction = [&](int s, double e[2]) {
    const PlateBoundarySegment& seg = b.segments[static_cast<std::size_t>(s)];
    e[0] = at(seg.b)[0] - at(seg.a)[0];
    e[1] = at(seg.b)[1] - at(seg.a)[1];
  };
  // Every feature in contact, in bin order: edges, then the vertices each
  // segment starts (a chain's last vertex with the segment it ends).
  auto for_each_candidate = [&](auto&& visit) {
    for (int q = b.bin_start[k]; q < b.bin_start[k + 1]; ++q) {
      const int s = b.bin_items[static_cast<std::size_t>(q)];
      const PlateBoundarySegment& seg = b.segments[static_cast<std::size_t>(s)];
      double e[2];
      direction(s, e);
      const double from_a[2] = {centre[0] - at(seg.a)[0], centre[1] - at(seg.a)[1]};
      const double from_b[2] = {centre[0] - at(seg.b)[0], centre[1] - at(seg.b)[1]};
      const double len2 = dot(e, e);
      // Edge: the projection strictly inside, the centre on the outer side.
      if (len2 > 0 && dot(from_a, e) > 0 && dot(from_b, e) < 0) {
        const double len = std::sqrt(len2);
        const double n[2] = {e[1] / len, -e[0] / len};
        const double gap = dot(from_a, n);
        if (gap > 0 && gap < radius) {
          PlateBoundaryContact c;
          c.segment = s;
          c.t = dot(from_a, e) / len2;
          c.point[0] = centre[0] - gap * n[0];
          c.point[1] = centre[1] - gap * n[1];
          c.normal[0] = n[0], c.normal[1] = n[1];
          c.overlap = radius - gap;
          visit(c);
        }
      }
      for (int end = 0; end < 2; ++end) {
        const int v = end == 0 ? seg.a : seg.b;
        const PlateBoundaryVertex& vx = b.vertices[static_cast<std::size_t>(v)];
        if (end == 1 && vx.next >= 0) continue;
        const double* d = end == 0 ? from_a : from_b;
        // The Voronoi wedge: past the end of the segment before (the same
        // product its edge test uses) and before the start of the one after,
        // and outside at least one of their lines (the wedge of a concave
        // vertex lies behind both: inside the material).
        bool inside = true, outside = false;
        for (int side = 0; side < 2 && inside; ++side) {
          const int t = side == 0 ? vx.prev : vx.next;
          if (t < 0) continue;
          double et[2];
          direction(t, et);
          const double along = dot(d, et);
          const double nt[2] = {et[1], -et[0]};
          inside = side == 0 ? along >= 0 : along <= 0;
          outside = outside || dot(d, nt) >= 0;
        }
        if (!inside || !outside) continue;
        const double gap = std::sqrt(dot(d, d));
        if (!(gap > 0 && gap < radius)) continue;
        PlateBoundaryContact c;
        c.segment = end == 0 ? vx.next : vx.prev;
        c.vertex = v;
        c.t = end == 0 ? 0.0 : 1.0;
        c.point[0] = at(v)[0], c.point[1] = at(v)[1];
        c.normal[0] = d[0] / gap, c.normal[1] = d[1] / gap;
        c.overlap = radius - gap;
        visit(c);
      }
    }
  };
  // The deepest feature (the first of equals), then the deepest of those more
  // than 60° from every one kept that it is joined to, until none is left.
  // Features of two separate pieces of boundary (a crack's two lips at its
  // mouth) are two contacts even where they face the same way: keeping only
  // the deeper would move the whole force from one lip to the other where
  // their depths cross, a jump in the plate's share that no force settles.
  int kept = 0;
  while (kept < kPlateBoundaryMaxContacts) {
    bool found = false;
    PlateBoundaryContact best;
    for_each_candidate([&](const PlateBoundaryContact& c) {
      for (int r = 0; r < kept; ++r)
        if (!(dot(c.normal, out[r].normal) < 0.5) && joined(b, c, out[r])) return;
      if (!found || c.overlap > best.overlap) best = c, found = true;
    });
    if (!found) break;
    blend_concave_joint(b, centre, radius, best, for_each_candidate);
    out[kept++] = best;
  }
  return kept;
}

PlateMaterialPoint plate_boundary_material_point(const PlateBoundary& b, const PlateBoundaryContact& c) {
  if (c.vertex >= 0) return b.vertices[static_cast<std::size_t>(c.vertex)].at;
  const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(c.segment)];
  PlateMaterialPoint p;
  p.cell[0] = s.cell[0], p.cell[1] = s.cell[1], p.side = s.side;
  p.xi = s.xi[0] + c.t * (s.xi[1] - s.xi[0]);
  p.eta = s.eta[0] + c.t * (s.eta[1] - s.eta[0]);
  return p;
}

namespace {

/// One foot of a contact on segment `segment` at t, weighed by `weight`:
/// the point itself on a linear segment, else the segment's two ends.
int foot_points(const PlateBoundary& b, int segment, double t, double weight, PlateMaterialPoint* at, double* share) {
  const PlateBoundarySegment& s = b.segments[static_cast<std::size_t>(segment)];
  if (s.linear) {
    PlateBoundaryContact foot;
    foot.segment = segment;
    foot.t = t;
    at[0] = plate_boundary_material_point(b, foot);
    share[0] = weight;
    return 1;
  }
  at[0] = b.vertices[static_cast<std::size_t>(s.a)].at;
  at[1] = b.vertices[static_cast<std::size_t>(s.b)].at;
  share[0] = weight * (1.0 - t), share[1] = weight * t;
  return 2;
}

}  // namespace

int plate_boundary_material_points(const PlateBoundary& b, const PlateBoundaryContact& c,
                                   PlateMaterialPoint at[kPlateBoundaryMaxPoints],
                                   double share[kPlateBoundaryMaxPoints]) {
  if (c.vertex >= 0) {
    at[0] = b.vertices[static_cast<std::size_t>(c.vertex)].at;
    share[0] = 1.0;
    return 1;
  }
  if (c.partner < 0) return foot_points(b, c.segment, c.t, 1.0, at, share);
  const int first = foot_points(b, c.segment, c.t, 1.0 - c.partner_weight, at, share);
  return first + foot_points(b, c.partner, c.partner_t, c.partner_weight, at + first, share + first);
}

void plate_spread_force(const PlateModel& m, const PlateMaterialPoint& at, const double force[2], double* f) {
  PlatePointBasis basis;
  // Shares on held components go nowhere: their displacement is not read.
  if (!plate_point_basis(m, at.cell[0], at.cell[1], at.xi, at.eta, at.side, basis, 0.0)) return;
  for (int q = 0; q < basis.count; ++q)
    for (int c = 0; c < 2; ++c)
      if (basis.dof[q][c] >= 0) f[basis.dof[q][c]] += basis.n[q] * force[c];
}

}  // namespace xfdem
