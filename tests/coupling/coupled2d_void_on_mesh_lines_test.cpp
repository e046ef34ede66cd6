// A void whose boundary lies on the mesh's lines (docs/coupled2d.md, "A
// void's boundary on the mesh's lines"): a side on a node row or column has
// its nodes at φ = 0 (the plate's tiny-cut rule, docs/xfem2d.md), so no cell
// is cut there; the cells on one side are inside the void, those on the
// other have material up to the edge. The contact boundary is then the cell
// edges between them, chained with the cut cells' segments through the
// nodes on the void's boundary. Before, the tracer found no segment there (a
// disk fell through the void's floor, F = 0 at every step) or refused the
// plate ("the boundary of 'v' meets itself in cell (8, 3)"): a chord ending
// at a node on the boundary was keyed by the cell edge it lay on, so the
// neighbouring cell's chord from that node was another vertex, and a
// sub-triangle's chord from the node to itself (no length) was linked in
// the wrong direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/coupled2d_scenes.hpp"
#include "support/plate_scenes.hpp"
#include "xfdem/coupled2d.hpp"
#include "xfdem/coupling/plate_boundary.hpp"
#include "xfdem/plate.hpp"

using namespace xfdem;
using xfdem::testing::disk;

namespace {

using Points = std::vector<std::array<double, 2>>;

PlateDiscontinuity polygon_void(const Points& points) {
  return xfdem::testing::polygon(PlateDiscontinuity::Kind::hole, points, "v");
}

/// The 2 m × 1 m plate of the scenes (E = 2 GPa), held at its bottom.
PlateDesc plate_with(const PlateDiscontinuity& q, int nx, int ny) {
  PlateDesc p = xfdem::testing::plate(2e9, 2, 1, nx, ny);
  p.supports.push_back({PlateEdge::bottom, {true, true}, false});
  p.discontinuities.push_back(q);
  return p;
}

struct Traced {
  PlateModel model;
  PlateState state;
  PlateWorkspace workspace;
  PlateBoundary boundary;
};

void trace(const PlateDesc& d, Traced& t) {
  const BuildResult r = build_plate(d, t.model, t.state, t.workspace);
  ASSERT_TRUE(r.ok()) << r.message;
  const BuildResult rb = plate_boundary_build(t.model, 0.05, 0.01, t.boundary);
  ASSERT_TRUE(rb.ok()) << rb.message;
}

/// Signed areas of the closed chains (shoelace), in the order of their first
/// vertex; fails the test where a chain is open or a segment has no length.
std::vector<double> closed_loops(const PlateBoundary& pb) {
  std::vector<double> areas;
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  for (const PlateBoundarySegment& s : pb.segments) {
    const double* a = pb.vertices[static_cast<std::size_t>(s.a)].x;
    const double* b = pb.vertices[static_cast<std::size_t>(s.b)].x;
    EXPECT_GT(std::hypot(b[0] - a[0], b[1] - a[1]), 1e-6);
  }
  std::vector<char> seen(pb.vertices.size(), 0);
  for (std::size_t start = 0; start < pb.vertices.size(); ++start) {
    if (seen[start]) continue;
    double area2 = 0;
    std::size_t v = start;
    do {
      seen[v] = 1;
      const int s = pb.vertices[v].next;
      if (s < 0 || pb.vertices[v].prev < 0) {
        ADD_FAILURE() << "an open chain at vertex " << v;
        return areas;
      }
      const auto w = static_cast<std::size_t>(pb.segments[static_cast<std::size_t>(s)].b);
      area2 += pb.vertices[v].x[0] * pb.vertices[w].x[1] - pb.vertices[w].x[0] * pb.vertices[v].x[1];
      v = w;
    } while (v != start);
    areas.push_back(0.5 * area2);
  }
  return areas;
}

/// Twice the signed area of a polygon (counter-clockwise positive).
double polygon_area(const Points& p) {
  double a2 = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const auto& u = p[k];
    const auto& w = p[(k + 1) % p.size()];
    a2 += u[0] * w[1] - w[0] * u[1];
  }
  return 0.5 * a2;
}

/// The largest distance between the vertices of two boundaries traced the
/// same way (the same segments, cells and sides, in the same order); +inf
/// where they differ in anything but the vertices' places.
double chain_distance(const PlateBoundary& x, const PlateBoundary& y) {
  if (x.segments.size() != y.segments.size() || x.vertices.size() != y.vertices.size()) return INFINITY;
  double worst = 0;
  for (std::size_t k = 0; k < x.segments.size(); ++k) {
    const PlateBoundarySegment& s = x.segments[k];
    const PlateBoundarySegment& t = y.segments[k];
    if (s.a != t.a || s.b != t.b || s.cell[0] != t.cell[0] || s.cell[1] != t.cell[1] || s.side != t.side ||
        s.chain != t.chain)
      return INFINITY;
  }
  for (std::size_t k = 0; k < x.vertices.size(); ++k)
    worst = std::max(worst, std::hypot(x.vertices[k].x[0] - y.vertices[k].x[0], x.vertices[k].x[1] - y.vertices[k].x[1]));
  return worst;
}

struct Geometry {
  const char* name;
  PlateDiscontinuity q;
  int nx, ny;
  double area;  // the void's area inside the plate (m²)
};

std::vector<Geometry> geometries() {
  const Points rect = {{0.8, 0.3}, {1.2, 0.3}, {1.2, 0.7}, {0.8, 0.7}};
  Points rect_cw(rect.rbegin(), rect.rend());
  const Points notch = {{0.5, 0.9}, {1.0, 0.9}, {1.0, 1.1}, {0.5, 1.1}};
  Points notch_cw(notch.rbegin(), notch.rend());
  const Points tri = {{0.83, 0.3}, {1.17, 0.3}, {1.0, 0.6}};
  const Points floor_off = {{0.8, 0.33}, {1.2, 0.33}, {1.2, 0.7}, {0.8, 0.7}};
  return {
      {"rectangle on node rows and columns, 20 x 10", polygon_void(rect), 20, 10, 0.16},
      {"the same, clockwise", polygon_void(rect_cw), 20, 10, 0.16},
      {"the same, 40 x 20", polygon_void(rect), 40, 20, 0.16},
      {"notch through the top edge", polygon_void(notch), 20, 10, 0.05},
      {"the notch, clockwise, 40 x 20", polygon_void(notch_cw), 40, 20, 0.05},
      {"triangle, base on a node row", polygon_void(tri), 20, 10, polygon_area(tri)},
      {"the triangle, 40 x 20", polygon_void(tri), 40, 20, polygon_area(tri)},
      {"sides on node columns, floor off the rows, 20 x 10", polygon_void(floor_off), 20, 10, 0.148},
      {"the same, 40 x 20", polygon_void(floor_off), 40, 20, 0.148},
      {"the same, 80 x 40", polygon_void(floor_off), 80, 40, 0.148},
      {"circle through four nodes, 20 x 10", xfdem::testing::circle(PlateDiscontinuity::Kind::hole, 1.0, 0.5, 0.2, "v"),
       20, 10, M_PI * 0.04},
      {"the circle, 40 x 20", xfdem::testing::circle(PlateDiscontinuity::Kind::hole, 1.0, 0.5, 0.2, "v"), 40, 20,
       M_PI * 0.04},
  };
}

/// The geometry moved by (dx, dy).
PlateDiscontinuity shifted(PlateDiscontinuity q, double dx, double dy) {
  for (auto& p : q.points) p[0] += dx, p[1] += dy;
  q.centre[0] += dx, q.centre[1] += dy;
  return q;
}

}  // namespace

// Every geometry builds (the floor off the rows and the circle were refused
// as "meets itself"), and its boundary is closed chains: the outer one
// counter-clockwise, the void's clockwise (or, for the notch, one loop with
// the outer edges), their areas the plate's less the void's. A polygon with
// every side on mesh lines is traced exactly (1e-14); the others to the
// cut cells' piecewise-linear geometry (within h²/r of a circle, πh²/2 of its
// area; a polygon's corners inside cut cells within h × its perimeter).
TEST(PlateBoundary, AVoidOnTheMeshLinesIsAClosedChain) {
  for (const Geometry& g : geometries()) {
    SCOPED_TRACE(g.name);
    Traced t;
    trace(plate_with(g.q, g.nx, g.ny), t);
    ASSERT_FALSE(HasFatalFailure());
    const std::vector<double> areas = closed_loops(t.boundary);
    double total = 0;
    int clockwise = 0;
    for (double a : areas) total += a, clockwise += a < 0 ? 1 : 0;
    bool through_top = false;
    for (const auto& p : g.q.points) through_top = through_top || p[1] > 1.0;
    const double h = 2.0 / g.nx;
    const bool exact = g.area == 0.16 || g.area == 0.05;
    double perimeter = 2 * M_PI * g.q.radius;
    if (g.q.shape == PlateDiscontinuity::Shape::polygon) {
      perimeter = 0;
      for (std::size_t k = 0; k < g.q.points.size(); ++k) {
        const auto& u = g.q.points[k];
        const auto& v = g.q.points[(k + 1) % g.q.points.size()];
        perimeter += std::hypot(v[0] - u[0], v[1] - u[1]);
      }
    }
    const double bound = exact ? 1e-14 : g.q.shape == PlateDiscontinuity::Shape::circle ? 0.5 * M_PI * h * h : h * perimeter;
    std::printf("%s: %zu segments, %zu loops, area %.6f m^2 (plate less void %.6f, off by %.2g)\n", g.name,
                t.boundary.segments.size(), areas.size(), total, 2.0 - g.area, std::fabs(total - (2.0 - g.area)));
    EXPECT_EQ(areas.size(), through_top ? 1u : 2u);
    EXPECT_EQ(clockwise, through_top ? 0 : 1);
    EXPECT_NEAR(total, 2.0 - g.area, bound);
    if (g.q.shape == PlateDiscontinuity::Shape::circle) {
      double off = 0;
      for (const PlateBoundaryVertex& v : t.boundary.vertices)
        if (v.x[0] > 0 && v.x[0] < 2 && v.x[1] > 0 && v.x[1] < 1)
          off = std::max(off, std::fabs(std::hypot(v.x[0] - 1.0, v.x[1] - 0.5) - 0.2));
      EXPECT_LT(off, h * h / 0.2);
    }
  }
}

// Moved by ±1e-12 of a cell along x or y, each geometry's nodes on its
// boundary stay on it (the tiny-cut rule's 1e-9 of a cell), so the boundary
// is traced the same way (the same segments in the same cells, sides and
// order) and its vertices move by the shift or a small multiple of it (a
// crossing inside a cut cell moves by the shift over the cosine of the
// boundary's angle with the edge it crosses).
TEST(PlateBoundary, AVoidOnTheMeshLinesMovedByATinyShiftIsTracedTheSameWay) {
  for (const Geometry& g : geometries()) {
    SCOPED_TRACE(g.name);
    Traced base;
    trace(plate_with(g.q, g.nx, g.ny), base);
    ASSERT_FALSE(HasFatalFailure());
    const double h = 2.0 / g.nx, delta = 1e-12 * h;
    double worst = 0;
    for (const double sx : {-1.0, 1.0})
      for (const int axis : {0, 1}) {
        Traced moved;
        trace(plate_with(shifted(g.q, axis == 0 ? sx * delta : 0.0, axis == 1 ? sx * delta : 0.0), g.nx, g.ny), moved);
        ASSERT_FALSE(HasFatalFailure());
        const double d = chain_distance(base.boundary, moved.boundary);
        ASSERT_TRUE(std::isfinite(d)) << "traced differently, shift " << sx << " along " << axis;
        worst = std::max(worst, d);
      }
    std::printf("%s: shifted by %.1e m, vertices within %.2g m (%.2g of the shift)\n", g.name, delta, worst,
                worst / delta);
    EXPECT_LE(worst, 10 * delta);
  }
}

namespace {

/// A disk (m = 1 kg, r = 0.05 m, k = 1e6 N/m, ζ = 0.5) dropped from rest at
/// (x, y) in the plate with void q, symplectic Euler, 10 substeps; the plate
/// steel (E = 2e11 Pa) with numerical damping (γ = 0.6), as the resting disk
/// in a void of coupled2d_test.cpp.
Coupled2dDesc disk_in(const PlateDiscontinuity& q, int nx, int ny, double x, double y) {
  Coupled2dDesc d;
  d.plate = plate_with(q, nx, ny);
  d.plate.youngs_modulus = 2e11;
  d.plate.gamma = 0.6, d.plate.beta = 0.3025;
  d.dem.integrator = DemIntegrator::symplectic_euler;
  d.dem.damping_ratio = 0.5;
  d.dem.gravity = {0.0, -9.81};
  d.dem.particles.push_back(disk(1.0, 0.05, 1e6, x, y, 0.0, 0.0));
  d.dem_substeps = 10;
  return d;
}

}  // namespace

// A disk in a void whose floor is a node row (and in a notch through the
// top edge, its floor a node row, and at the bottom of a circle through a
// node) comes to rest on the floor and carries m g, as the resting disk in
// a void off the mesh lines does (coupled2d_test.cpp: position within 1e-6
// m, force within 1e-6 m g). Before, the contact force was 0 at every step
// and the disk fell through the floor into the material.
TEST(Coupled2d, ADiskRestingOnAVoidsFloorOnANodeRowCarriesItsWeight) {
  const double m = 1.0, g = 9.81, r = 0.05, k = 1e6;
  struct Case {
    const char* name;
    PlateDiscontinuity q;
    int nx, ny;
    double x, y;     // where the disk starts
    double rest_y;   // its centre at rest (floor + r − m g / k), NAN: not asserted
  };
  const Case cases[] = {
      {"rectangle, floor y = 0.3 on a node row", polygon_void({{0.8, 0.3}, {1.2, 0.3}, {1.2, 0.7}, {0.8, 0.7}}), 20, 10,
       1.0, 0.35, 0.3 + r - m * g / k},
      {"the same, clockwise, 40 x 20", polygon_void({{0.8, 0.3}, {0.8, 0.7}, {1.2, 0.7}, {1.2, 0.3}}), 40, 20, 1.0, 0.35,
       0.3 + r - m * g / k},
      {"notch through the top edge, floor y = 0.9", polygon_void({{0.5, 0.9}, {1.0, 0.9}, {1.0, 1.1}, {0.5, 1.1}}), 20,
       10, 0.75, 0.95, 0.9 + r - m * g / k},
      {"triangle, base y = 0.3 on a node row", polygon_void({{0.83, 0.3}, {1.17, 0.3}, {1.0, 0.6}}), 20, 10, 1.0, 0.36,
       0.3 + r - m * g / k},
      // The circle's lowest point (1, 0.3) is a node: the disk rests in the
      // V of the two chords that meet there, its weight along the bisector.
      {"circle through the node (1, 0.3)", xfdem::testing::circle(PlateDiscontinuity::Kind::hole, 1.0, 0.5, 0.2, "v"),
       20, 10, 1.0, 0.36, NAN},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Coupled2dWorld w;
    const BuildResult built = w.build(disk_in(c.q, c.nx, c.ny, c.x, c.y));
    ASSERT_TRUE(built.ok()) << built.message;
    double least = INFINITY;
    for (int step = 0; step < 10000; ++step) {
      ASSERT_EQ(w.step(), StepStatus::ok) << step;
      least = std::min(least, w.state.dem.x[1][0]);
    }
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, 0, f));
    const double speed = std::hypot(w.state.dem.v[0][0], w.state.dem.v[1][0]);
    std::printf("%s: after 1 s at (%.6f, %.6f) (lowest %.6f), F_y - m g = %.3g N of %.4g N, F_x = %.3g N, speed %.3g m/s\n",
                c.name, w.state.dem.x[0][0], w.state.dem.x[1][0], least, f[1] - m * g, m * g, f[0], speed);
    if (!std::isnan(c.rest_y)) {
      EXPECT_NEAR(w.state.dem.x[1][0], c.rest_y, 1e-6);
      EXPECT_GT(least, c.rest_y - 2 * r);  // never through the floor
    } else {
      EXPECT_GT(w.state.dem.x[1][0], 0.3);  // above the node at the circle's bottom
    }
    EXPECT_NEAR(w.state.dem.x[0][0], c.x, 1e-6);
    EXPECT_NEAR(f[1], m * g, 1e-6 * m * g);
    EXPECT_NEAR(f[0], 0.0, 1e-6 * m * g);
  }
}

// No bump where the segments meet along the new chain: a disk (r = 0.05 m)
// slid along the floor and the left wall of the rectangle on the mesh lines,
// 0.04 m off them, across the nodes where their cell edges meet, has one
// contact at every sample, its overlap 0.01 m; slid down the left wall of the
// void whose floor is off the rows (the wall cell edges from y = 0.4, below
// that the cut cell's chord from the node (0.8, 0.4) to the floor, a
// concave joint of about 55°), its overlap changes by at most the step
// between samples (the distance to the boundary is 1-Lipschitz) and its
// normal turns continuously (blended across the joint, docs/coupled2d.md).
TEST(PlateBoundary, ADiskAlongAVoidOnTheMeshLinesMeetsNoBumpAtTheJoints) {
  const double radius = 0.05;
  {
    Traced t;
    trace(plate_with(polygon_void({{0.8, 0.3}, {1.2, 0.3}, {1.2, 0.7}, {0.8, 0.7}}), 20, 10), t);
    ASSERT_FALSE(HasFatalFailure());
    std::vector<double> positions(2 * t.boundary.vertices.size());
    plate_boundary_positions(t.model, t.boundary, t.state.u.data(), t.state.time, positions.data());
    double worst = 0;
    const int samples = 28001;
    for (int along = 0; along < 2; ++along)
      for (int k = 0; k < samples; ++k) {
        const double s = 0.36 + 0.28 * k / (samples - 1);
        const double c[2] = {along == 0 ? s + 0.5 : 0.84, along == 0 ? 0.34 : s};
        PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
        ASSERT_EQ(plate_boundary_contacts(t.boundary, positions.data(), c, radius, contacts), 1) << c[0] << " " << c[1];
        worst = std::max(worst, std::fabs(contacts[0].overlap - 0.01));
      }
    std::printf("along the floor and the wall on the mesh lines: one contact, overlap 0.01 m within %.2g m\n", worst);
    EXPECT_LT(worst, 1e-15);
  }
  Traced t;
  trace(plate_with(polygon_void({{0.8, 0.33}, {1.2, 0.33}, {1.2, 0.7}, {0.8, 0.7}}), 20, 10), t);
  ASSERT_FALSE(HasFatalFailure());
  std::vector<double> positions(2 * t.boundary.vertices.size());
  plate_boundary_positions(t.model, t.boundary, t.state.u.data(), t.state.time, positions.data());
  const int samples = 20001;
  const double top = 0.6, bottom = 0.38, step = (top - bottom) / (samples - 1);
  double worst_jump = 0, worst_turn = 0, previous = -1, normal[2] = {0, 0}, largest_weight = 0, gap = radius;
  int most = 0;
  for (int k = 0; k < samples; ++k) {
    const double c[2] = {0.84, top - step * k};
    PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
    const int n = plate_boundary_contacts(t.boundary, positions.data(), c, radius, contacts);
    ASSERT_GE(n, 1) << c[1];
    most = std::max(most, n);
    const PlateBoundaryContact& ct = contacts[0];
    if (previous >= 0) {
      worst_jump = std::max(worst_jump, std::fabs(ct.overlap - previous));
      worst_turn = std::max(worst_turn, std::hypot(ct.normal[0] - normal[0], ct.normal[1] - normal[1]));
    }
    previous = ct.overlap, normal[0] = ct.normal[0], normal[1] = ct.normal[1];
    largest_weight = std::max(largest_weight, ct.partner_weight);
    gap = std::min(gap, radius - ct.overlap);
  }
  std::printf("down the wall into the floor's cut cell: overlap changes by at most %.3g m per %.3g m step, the "
              "normal turns by at most %.3g rad per step (3 step/gap %.3g), largest partner weight %.2f, most "
              "contacts %d\n",
              worst_jump, step, worst_turn, 3 * step / gap, largest_weight, most);
  EXPECT_EQ(most, 1);
  EXPECT_LE(worst_jump, step * (1 + 1e-9));
  EXPECT_GT(largest_weight, 0.0);  // blended across the joint
  EXPECT_LT(worst_turn, 3 * step / gap);
}

namespace {

/// The rectangle on the mesh lines with a crack from inside it (x = 1.07)
/// down through its floor (a node row) and the bottom edge, 20 × 10 cells:
/// the floor's cell edge in the crack's cell (10, 2) is split where the
/// crack crosses it.
PlateDesc void_with_crack(PlateDiscontinuity::Faces faces) {
  PlateDesc p = plate_with(polygon_void({{0.8, 0.3}, {1.2, 0.3}, {1.2, 0.7}, {0.8, 0.7}}), 20, 10);
  PlateDiscontinuity c;
  c.name = "c";
  c.kind = PlateDiscontinuity::Kind::crack;
  c.shape = PlateDiscontinuity::Shape::polyline;
  c.faces = faces;
  if (faces != PlateDiscontinuity::Faces::free) c.stiffness[0] = c.stiffness[1] = 1e13;
  c.points = {{1.07, 0.5}, {1.07, -0.1}};
  p.discontinuities.push_back(c);
  return p;
}

}  // namespace

// A crack from the void down through its floor on a node row: the floor's
// edge in the crack's cell is two segments, one on each side of the crack,
// meeting the free faces at their own side's vertex where the crack crosses
// the floor (two vertices at (1.07, 0.3)): one closed loop (the slot joins
// the void to the outer edge), of the plate's area less the void's. With
// tied faces there are no face segments and the two pieces end there (the
// chain open, as at a mouth).
TEST(PlateBoundary, ACrackFromAVoidOnTheMeshLinesSplitsTheFloorAtTheCrack) {
  Traced t;
  trace(void_with_crack(PlateDiscontinuity::Faces::free), t);
  ASSERT_FALSE(HasFatalFailure());
  const std::vector<double> areas = closed_loops(t.boundary);
  ASSERT_EQ(areas.size(), 1u);
  std::printf("crack from a void on the mesh lines: %zu segments, one loop of area %.15f m^2\n",
              t.boundary.segments.size(), areas[0]);
  EXPECT_NEAR(areas[0], 2.0 - 0.16, 1e-14);
  int pieces = 0, ends = 0;
  for (const PlateBoundarySegment& s : t.boundary.segments) {
    if (s.cell[0] != 10 || s.cell[1] != 2) continue;
    const double* a = t.boundary.vertices[static_cast<std::size_t>(s.a)].x;
    const double* b = t.boundary.vertices[static_cast<std::size_t>(s.b)].x;
    if (std::fabs(a[1] - 0.3) < 1e-12 && std::fabs(b[1] - 0.3) < 1e-12) {
      ++pieces;
      EXPECT_LT(b[0], a[0]);  // walked towards −x, the material below on the left
      EXPECT_EQ(std::fabs(a[0] - 1.07) < 1e-12 ? 1 : std::fabs(b[0] - 1.07) < 1e-12 ? 1 : 0, 1);
    }
  }
  for (const PlateBoundaryVertex& v : t.boundary.vertices)
    if (std::fabs(v.x[0] - 1.07) < 1e-12 && std::fabs(v.x[1] - 0.3) < 1e-12) ++ends;
  EXPECT_EQ(pieces, 2);
  EXPECT_EQ(ends, 2);  // one vertex of each side
  Traced tied;
  trace(void_with_crack(PlateDiscontinuity::Faces::tied), tied);
  ASSERT_FALSE(HasFatalFailure());
  int open = 0;
  for (const PlateBoundaryVertex& v : tied.boundary.vertices) open += (v.prev < 0) + (v.next < 0);
  EXPECT_EQ(open, 4);  // the floor's two pieces and the bottom edge's two lips, open at the crack
}

// Two disks (0.5 kg, r = 0.02 m, k = 1e6 N/m) resting on that floor, one on
// each side of the free crack, both over the crack's cell: each carries
// m g, as on a floor off the mesh lines (coupled2d_crack_void_test.cpp).
TEST(Coupled2d, DisksOnAVoidsFloorOnANodeRowEitherSideOfACrackCarryTheirWeight) {
  Coupled2dDesc d;
  d.plate = void_with_crack(PlateDiscontinuity::Faces::free);
  d.plate.youngs_modulus = 2e11;
  d.plate.gamma = 0.6, d.plate.beta = 0.3025;
  d.dem.integrator = DemIntegrator::symplectic_euler;
  d.dem.damping_ratio = 0.5;
  d.dem.gravity = {0.0, -9.81};
  const double m = 0.5, g = 9.81, r = 0.02, k = 1e6;
  d.dem.particles.push_back(disk(m, r, k, 1.03, 0.3 + r + 0.002, 0.0, 0.0));
  d.dem.particles.push_back(disk(m, r, k, 1.095, 0.3 + r + 0.002, 0.0, 0.0));
  d.dem_substeps = 10;
  Coupled2dWorld w;
  const BuildResult built = w.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  for (int step = 0; step < 10000; ++step) ASSERT_EQ(w.step(), StepStatus::ok) << step;
  for (int i = 0; i < 2; ++i) {
    double f[2];
    ASSERT_TRUE(coupled2d_boundary_force(w.model, w.state, i, f));
    std::printf("disk %d beside the crack: at (%.6f, %.6f), F_y - m g = %.3g N of %.4g N, F_x = %.3g N\n", i,
                w.state.dem.x[0][i], w.state.dem.x[1][i], f[1] - m * g, m * g, f[0]);
    EXPECT_NEAR(w.state.dem.x[1][i], 0.3 + r - m * g / k, 1e-6);
    EXPECT_NEAR(f[1], m * g, 1e-6 * m * g);
    EXPECT_NEAR(f[0], 0.0, 1e-6 * m * g);
  }
}

// An inclusion (a circle of radius 0.07 about (1, 0.2)) cutting the cells
// under the floor on the node row, its boundary short of the floor: the
// floor's edges in those cells are segments on the inclusion's + side, the
// loop closed and of the void's area exactly (the inclusion's boundary is
// no contact surface).
TEST(PlateBoundary, AVoidsFloorOnANodeRowOverCellsAnInclusionCutsIsTraced) {
  PlateDesc p = plate_with(polygon_void({{0.8, 0.3}, {1.2, 0.3}, {1.2, 0.7}, {0.8, 0.7}}), 20, 10);
  PlateDiscontinuity inc = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, 1.0, 0.2, 0.07);
  inc.material = {5e9, 0.25, 3000};
  p.discontinuities.push_back(inc);
  Traced t;
  trace(p, t);
  ASSERT_FALSE(HasFatalFailure());
  const std::vector<double> areas = closed_loops(t.boundary);
  ASSERT_EQ(areas.size(), 2u);
  EXPECT_NEAR(areas[0] + areas[1], 2.0 - 0.16, 1e-14);
  int cut = 0;
  for (const PlateBoundarySegment& s : t.boundary.segments)
    if (t.model.cell_cut_by[static_cast<std::size_t>(s.cell[1] * 20 + s.cell[0])] == 1) {
      ++cut;
      EXPECT_EQ(s.side, 1);
    }
  EXPECT_EQ(cut, 2);  // the floor's edges over the cells (9, 2) and (10, 2)
}
