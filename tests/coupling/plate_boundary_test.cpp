// The plate's boundary for disk contact: the outer edges as a closed chain
// (broken at a crack's mouth), the closest point of a disk against the
// brute-force distance to every segment, one contact with a continuous
// overlap across joints (flat and bent), a crack from a void (the void's
// boundary on each side of the crack, the faces outside the void), a crack
// across an inclusion (its faces only, split at the inclusion), and the
// spreading of a contact force to the plate's unknowns: for every rigid
// motion the generalised forces do the work the force does at the contact
// point (force and moment).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "xfdem/coupling/plate_boundary.hpp"
#include "support/plate_scenes.hpp"
#include "xfdem/plate.hpp"

using namespace xfdem;

namespace {

PlateDesc free_plate(int nx, int ny) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.min[0] = 0, d.min[1] = 0, d.max[0] = 2, d.max[1] = 1;
  d.cells[0] = nx, d.cells[1] = ny;
  d.dt = 1e-4;
  return d;
}

PlateDiscontinuity vertical_crack(double x) {
  PlateDiscontinuity q;
  q.name = "c1";
  q.kind = PlateDiscontinuity::Kind::crack;
  q.shape = PlateDiscontinuity::Shape::polyline;
  q.points = {{x, -0.2}, {x, 1.2}};
  return q;
}

PlateDiscontinuity circular_void(double x, double y, double r) {
  return xfdem::testing::circle(PlateDiscontinuity::Kind::hole, x, y, r);
}

struct Built {
  PlateModel model;
  PlateState state;
  PlateWorkspace workspace;
  PlateBoundary boundary;
  std::vector<double> positions;
};

void build(const PlateDesc& d, double radius, Built& b) {
  const BuildResult r = build_plate(d, b.model, b.state, b.workspace);
  ASSERT_TRUE(r.ok()) << r.message;
  const BuildResult rb = plate_boundary_build(b.model, radius, 0.1, b.boundary);
  ASSERT_TRUE(rb.ok()) << rb.message;
  b.positions.assign(2 * b.boundary.vertices.size(), 0.0);
  plate_boundary_positions(b.model, b.boundary, b.state.u.data(), b.state.time, b.positions.data());
}

/// The 4 × 2 free plate with a vertical crack through it (x = 1.05).
void build_cracked(Built& b) {
  PlateDesc d = free_plate(4, 2);
  d.discontinuities.push_back(vertical_crack(1.05));
  build(d, 0.05, b);
}

/// Distance from c to the segment [p, q] (closed form, by clamping).
double segment_distance(const double c[2], const double* p, const double* q) {
  const double e[2] = {q[0] - p[0], q[1] - p[1]};
  const double t = std::clamp(((c[0] - p[0]) * e[0] + (c[1] - p[1]) * e[1]) / (e[0] * e[0] + e[1] * e[1]), 0.0, 1.0);
  return std::hypot(c[0] - p[0] - t * e[0], c[1] - p[1] - t * e[1]);
}

}  // namespace

TEST(PlateBoundary, OuterEdgesAreOneClosedChainWithOutwardNormals) {
  Built b;
  build(free_plate(4, 2), 0.05, b);
  const PlateBoundary& pb = b.boundary;
  ASSERT_EQ(pb.segments.size(), 12u);  // 2 (nx + ny) cell edges
  ASSERT_EQ(pb.vertices.size(), 12u);  // closed: as many vertices as segments
  double perimeter = 0, area2 = 0;
  for (std::size_t s = 0; s < pb.segments.size(); ++s) {
    const PlateBoundarySegment& seg = pb.segments[s];
    EXPECT_EQ(pb.vertices[static_cast<std::size_t>(seg.a)].next, static_cast<int>(s));
    EXPECT_EQ(pb.vertices[static_cast<std::size_t>(seg.b)].prev, static_cast<int>(s));
    const double* a = pb.vertices[static_cast<std::size_t>(seg.a)].x;
    const double* c = pb.vertices[static_cast<std::size_t>(seg.b)].x;
    perimeter += std::hypot(c[0] - a[0], c[1] - a[1]);
    area2 += a[0] * c[1] - c[0] * a[1];
  }
  EXPECT_DOUBLE_EQ(perimeter, 6.0);
  EXPECT_DOUBLE_EQ(0.5 * area2, 2.0);  // counter-clockwise: material on the left
}

TEST(PlateBoundary, AVoidIsAClosedClockwiseLoopOnItsCircle) {
  // A void well inside: one loop of its own (material on the left walks it
  // clockwise) whose vertices lie on the cut cells' piecewise-linear level
  // set, within O(h²/r) of the circle.
  PlateDesc d = free_plate(16, 8);
  const double xc = 1.03, yc = 0.49, r = 0.27;
  d.discontinuities.push_back(circular_void(xc, yc, r));
  Built b;
  build(d, 0.05, b);
  const PlateBoundary& pb = b.boundary;
  double area2 = 0, off = 0;
  int loop = 0;
  for (std::size_t s = 48; s < pb.segments.size(); ++s) {  // after the 2 (16 + 8) outer edges
    const PlateBoundarySegment& seg = pb.segments[s];
    const double* a = pb.vertices[static_cast<std::size_t>(seg.a)].x;
    const double* c = pb.vertices[static_cast<std::size_t>(seg.b)].x;
    area2 += a[0] * c[1] - c[0] * a[1];
    off = std::max(off, std::fabs(std::hypot(a[0] - xc, a[1] - yc) - r));
    ++loop;
  }
  for (const PlateBoundaryVertex& v : pb.vertices) {
    EXPECT_GE(v.prev, 0);
    EXPECT_GE(v.next, 0);
  }
  const double h = 0.125;
  std::printf("void loop: %d segments, area %.5f (circle %.5f), vertices within %.3g m of the circle\n", loop,
              -0.5 * area2, M_PI * r * r, off);
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  EXPECT_LT(0.5 * area2, 0.0);                        // clockwise
  EXPECT_LT(off, h * h / r);
  EXPECT_NEAR(-0.5 * area2, M_PI * r * r, 0.5 * M_PI * h * h);  // perimeter × h²/(4r)
}

/// Signed areas (shoelace) of the boundary's closed chains, in the order of
/// their first vertex; 0 if a chain is open.
std::vector<double> loop_areas(const PlateBoundary& pb) {
  std::vector<char> seen(pb.vertices.size(), 0);
  std::vector<double> areas;
  for (std::size_t start = 0; start < pb.vertices.size(); ++start) {
    if (seen[start]) continue;
    double area2 = 0;
    std::size_t v = start;
    bool closed = true;
    do {
      seen[v] = 1;
      const int s = pb.vertices[v].next;
      if (s < 0) {
        closed = false;
        break;
      }
      const auto w = static_cast<std::size_t>(pb.segments[static_cast<std::size_t>(s)].b);
      area2 += pb.vertices[v].x[0] * pb.vertices[w].x[1] - pb.vertices[w].x[0] * pb.vertices[v].x[1];
      v = w;
    } while (v != start);
    areas.push_back(closed ? 0.5 * area2 : 0.0);
  }
  return areas;
}

TEST(PlateBoundary, AFreeCrackSplitsTheBoundaryIntoTwoLoopsAndItsMouthOpens) {
  // A straight crack through the plate: its level set is linear, so the faces
  // are the crack's line and the two pieces' loops enclose the two
  // trapezoids exactly.
  PlateDesc d = free_plate(8, 4);
  PlateDiscontinuity q = vertical_crack(0.0);
  q.points = {{0.93, -0.2}, {1.11, 1.2}};
  d.discontinuities.push_back(q);
  Built b;
  build(d, 0.05, b);
  const PlateBoundary& pb = b.boundary;
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  const std::vector<double> areas = loop_areas(pb);
  ASSERT_EQ(areas.size(), 2u);
  const double x0 = 0.93 + 0.18 * 0.2 / 1.4, x1 = 0.93 + 0.18 * 1.2 / 1.4;  // the crack at y = 0 and y = 1
  const double left = 0.5 * (x0 + x1);
  std::printf("two loops: areas %.15f and %.15f (trapezoids %.15f and %.15f)\n", areas[0], areas[1], left, 2 - left);
  EXPECT_NEAR(areas[0], left, 1e-14);
  EXPECT_NEAR(areas[1], 2.0 - left, 1e-14);
  // Open the crack (the x of every Heaviside unknown): the faces part.
  std::vector<double> u(static_cast<std::size_t>(b.model.dofs), 0.0);
  for (int n = 0; n < b.model.nodes; ++n)
    for (int s = 0; s < 2; ++s) {
      if (b.model.node_enrichment[static_cast<std::size_t>(2 * n + s)] < 0) continue;
      const int dof = b.model.enriched_dof[static_cast<std::size_t>(2 * (2 * n + s))];
      if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-3;
    }
  plate_boundary_positions(b.model, b.boundary, u.data(), 0.0, b.positions.data());
  double worst = 0;
  int faces = 0;
  for (const PlateBoundarySegment& s : pb.segments) {
    if (s.side > 0 || pb.vertices[static_cast<std::size_t>(s.a)].at.side > 0) continue;
    ++faces;
    // ψ = H − H(x_a) with H = ±1: the − face moves by −2·1e-3 relative to the
    // + face; each face's vertices move with their own side's field.
    for (const int v : {s.a, s.b}) {
      const auto k = static_cast<std::size_t>(v);
      const PlateBoundaryVertex& vx = pb.vertices[k];
      double du[2];
      plate_material_point_field(b.model, vx.at, u.data(), true, 0.0, du);
      PlateMaterialPoint other = vx.at;
      other.side = 1;
      double dp[2];
      plate_material_point_field(b.model, other, u.data(), true, 0.0, dp);
      worst = std::max(worst, std::fabs((dp[0] - du[0]) - 2e-3));
      EXPECT_EQ(b.positions[2 * k], vx.x[0] + du[0]);
    }
  }
  std::printf("- face segments %d, jump across the faces within %.3g m of 2e-3 m\n", faces, worst);
  EXPECT_GT(faces, 4);
  EXPECT_LT(worst, 1e-18);
}

// A straight crack through the cells' centres (a horizontal one at a row's
// middle, a vertical one at a column's middle: what a user writes first) is
// traced as for any other line: two closed loops whose areas are the two
// rectangles exactly, no segment of zero length, and the faces part when the
// crack opens. It was refused ("the boundary of 'c1' meets itself"): the
// chords of the sub-triangles met at the centre through different keys.
TEST(PlateBoundary, ACrackThroughTheCellsCentresIsTwoRectangles) {
  struct Line {
    double p[2][2];
    double below;  // the area below (left of) the line
  };
  const Line lines[] = {{{{-0.2, 0.375}, {2.2, 0.375}}, 2.0 * 0.375}, {{{1.125, -0.2}, {1.125, 1.2}}, 1.125}};
  for (const Line& line : lines) {
    PlateDesc d = free_plate(8, 4);  // cells 0.25 × 0.25: centres at 0.125 + 0.25 k
    PlateDiscontinuity q = vertical_crack(0.0);
    q.points = {{line.p[0][0], line.p[0][1]}, {line.p[1][0], line.p[1][1]}};
    d.discontinuities.push_back(q);
    Built b;
    build(d, 0.05, b);
    const PlateBoundary& pb = b.boundary;
    EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
    for (const PlateBoundarySegment& sg : pb.segments) {
      const PlateBoundaryVertex& va = pb.vertices[static_cast<std::size_t>(sg.a)];
      const PlateBoundaryVertex& vb = pb.vertices[static_cast<std::size_t>(sg.b)];
      EXPECT_GT(std::hypot(vb.x[0] - va.x[0], vb.x[1] - va.x[1]), 1e-3);  // whole pieces of a cell's width
    }
    std::vector<double> areas = loop_areas(pb);
    ASSERT_EQ(areas.size(), 2u);
    std::sort(areas.begin(), areas.end());
    std::printf("crack (%g, %g)-(%g, %g): loops %.15f and %.15f\n", line.p[0][0], line.p[0][1], line.p[1][0],
                line.p[1][1], areas[0], areas[1]);
    EXPECT_NEAR(areas[0], std::min(line.below, 2.0 - line.below), 1e-14);
    EXPECT_NEAR(areas[1], std::max(line.below, 2.0 - line.below), 1e-14);
    // Open the crack: the faces part by the jump of the Heaviside unknowns.
    std::vector<double> u(static_cast<std::size_t>(b.model.dofs), 0.0);
    for (int n = 0; n < b.model.nodes; ++n)
      for (int sd = 0; sd < 2; ++sd) {
        if (b.model.node_enrichment[static_cast<std::size_t>(2 * n + sd)] < 0) continue;
        for (int c = 0; c < 2; ++c) {
          const int dof = b.model.enriched_dof[static_cast<std::size_t>(2 * (2 * n + sd) + c)];
          if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-3;
        }
      }
    // The faces: the segments on the crack's line, one set per side, each as
    // long as the line inside the plate; each face's vertices part by the jump.
    const bool horizontal = line.p[0][1] == line.p[1][1];
    double length[2] = {0, 0}, worst = 0;
    for (const PlateBoundarySegment& sg : pb.segments) {
      const PlateBoundaryVertex& va = pb.vertices[static_cast<std::size_t>(sg.a)];
      const PlateBoundaryVertex& vb = pb.vertices[static_cast<std::size_t>(sg.b)];
      const int c = horizontal ? 1 : 0;
      if (va.x[c] != line.p[0][c] || vb.x[c] != line.p[0][c]) continue;  // not on the crack's line
      length[sg.side > 0 ? 0 : 1] += std::hypot(vb.x[0] - va.x[0], vb.x[1] - va.x[1]);
      for (const PlateBoundaryVertex* vx : {&va, &vb}) {
        PlateMaterialPoint minus = vx->at, plus = vx->at;
        minus.side = -1, plus.side = 1;
        double du[2], dp[2];
        plate_material_point_field(b.model, minus, u.data(), true, 0.0, du);
        plate_material_point_field(b.model, plus, u.data(), true, 0.0, dp);
        for (int k = 0; k < 2; ++k) worst = std::max(worst, std::fabs((dp[k] - du[k]) - 2e-3));
      }
    }
    const double inside = horizontal ? 2.0 : 1.0;
    std::printf("- faces %.15f and %.15f m long (the line: %g m), jump within %.3g m of 2e-3 m\n", length[0],
                length[1], inside, worst);
    EXPECT_NEAR(length[0], inside, 1e-14);
    EXPECT_NEAR(length[1], inside, 1e-14);
    EXPECT_LT(worst, 1e-18);
  }
}

TEST(PlateBoundary, ClosestPointMatchesTheDistanceToEverySegment) {
  PlateDesc d = free_plate(10, 6);
  d.discontinuities.push_back(vertical_crack(0.55));
  d.discontinuities.push_back(circular_void(1.32, 0.52, 0.3));
  Built b;
  const double radius = 0.07;
  build(d, radius, b);
  // Bend the boundary a little (a smooth field), so that joints are not flat.
  for (std::size_t v = 0; v < b.boundary.vertices.size(); ++v) {
    const double x = b.boundary.vertices[v].x[0], y = b.boundary.vertices[v].x[1];
    b.positions[2 * v] += 0.004 * std::sin(3 * y + x);
    b.positions[2 * v + 1] += 0.004 * std::cos(5 * x);
  }
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ux(-0.1, 2.1), uy(-0.1, 1.1);
  int touching = 0, voids = 0, blended = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double c[2] = {ux(rng), uy(rng)};
    // Outside the material only (inside, contact is not defined by the
    // closest point): beyond the bent outer boundary (it moves by at most
    // 0.004 m), or well inside the void (its cut-cell boundary is within
    // about h²/(8r) = 0.01 m of the circle).
    const bool in_void = std::hypot(c[0] - 1.32, c[1] - 0.52) < 0.3 - 0.03;
    if (!in_void && c[0] > -0.01 && c[0] < 2.01 && c[1] > -0.01 && c[1] < 1.01) continue;
    voids += in_void ? 1 : 0;
    double nearest = INFINITY;
    for (const PlateBoundarySegment& s : b.boundary.segments)
      nearest = std::min(nearest, segment_distance(c, &b.positions[2 * static_cast<std::size_t>(s.a)],
                                                   &b.positions[2 * static_cast<std::size_t>(s.b)]));
    PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
    const int n = plate_boundary_contacts(b.boundary, b.positions.data(), c, radius, contacts);
    if (nearest >= radius) {
      EXPECT_EQ(n, 0) << c[0] << " " << c[1];
      continue;
    }
    // Points outside but beside the crack's mouth or a corner: the deepest
    // contact is the nearest point of the boundary.
    ASSERT_GE(n, 1) << c[0] << " " << c[1] << " nearest " << nearest;
    ++touching;
    EXPECT_NEAR(contacts[0].overlap, radius - nearest, 1e-14);
    const double arm = std::hypot(c[0] - contacts[0].point[0], c[1] - contacts[0].point[1]);
    if (contacts[0].partner < 0) {
      EXPECT_NEAR(arm, nearest, 1e-14);
    } else {
      // Near a concave joint's bisector: the blend of the two feet, on the
      // disk's side of the corner (between them), no farther than the nearest.
      ++blended;
      EXPECT_LE(arm, nearest + 1e-14);
      EXPECT_GT(contacts[0].partner_weight, 0.0);
      EXPECT_LE(contacts[0].partner_weight, 0.5);
    }
  }
  std::printf("contacts checked against the brute-force distance: %d (centres in the void: %d, blended at a "
              "concave joint: %d)\n",
              touching, voids, blended);
  EXPECT_GT(touching, 500);
  EXPECT_GT(voids, 500);
}

// A concave joint of 10° (the top's vertex at x = 1 pulled down, its
// neighbours 0.1 m away held): the closest point changes edges at the
// bisector, where the normal jumped by the joint's angle (0.17 rad). Blended
// there, the normal turns continuously: by the joint's angle φ over the
// zone's width gap·tan(φ/2), 2/gap per metre on average, and at most 3/2 of
// that (the smoothstep's steepest slope); it is the bisector's on the
// bisector, and the overlap is still the closest point's.
TEST(PlateBoundary, ANormalThatTurnsContinuouslyAcrossAConcaveJoint) {
  Built b;
  const double radius = 0.1;
  build(free_plate(20, 2), radius, b);
  const double drop = 0.1 * std::tan(5.0 * std::acos(-1.0) / 180.0);
  for (std::size_t v = 0; v < b.boundary.vertices.size(); ++v)
    if (b.boundary.vertices[v].x[1] == 1.0 && std::fabs(b.boundary.vertices[v].x[0] - 1.0) < 1e-12)
      b.positions[2 * v + 1] -= drop;
  const double height = 1.0 - drop + 0.09;
  const int samples = 20001;
  const double step = 0.1 / (samples - 1);
  double worst_turn = 0, previous[2] = {0, 0}, largest_weight = 0, gap = radius;
  for (int k = 0; k < samples; ++k) {
    const double c[2] = {0.95 + step * k, height};
    PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
    ASSERT_EQ(plate_boundary_contacts(b.boundary, b.positions.data(), c, radius, contacts), 1) << c[0];
    const PlateBoundaryContact& ct = contacts[0];
    if (k > 0) worst_turn = std::max(worst_turn, std::hypot(ct.normal[0] - previous[0], ct.normal[1] - previous[1]));
    previous[0] = ct.normal[0], previous[1] = ct.normal[1];
    largest_weight = std::max(largest_weight, ct.partner_weight);
    gap = std::min(gap, radius - ct.overlap);
    if (k == samples / 2) {  // on the bisector
      EXPECT_EQ(ct.partner_weight, 0.5);
      EXPECT_NEAR(ct.normal[0], 0.0, 1e-15);
      EXPECT_NEAR(ct.normal[1], 1.0, 1e-15);
      EXPECT_NEAR(ct.overlap, radius - (height - (1.0 - drop)) * std::cos(5.0 * std::acos(-1.0) / 180.0), 1e-15);
    }
  }
  std::printf("concave joint of 10 deg: largest turn of the normal between samples %.3g rad (%.3g m apart; "
              "3/gap per metre: %.3g), largest partner weight %.2f\n",
              worst_turn, step, 3 * step / gap, largest_weight);
  EXPECT_EQ(largest_weight, 0.5);
  EXPECT_LT(worst_turn, 1.1 * 3 * step / gap);  // 10 % for the tan(φ/2) ≈ φ/2 and the gap's change
}

TEST(PlateBoundary, OneContactWithContinuousOverlapAcrossJoints) {
  Built b;
  const double radius = 0.1;
  build(free_plate(20, 2), radius, b);
  // A sag under the disk: the top's vertices pushed down by a smooth bump
  // (every joint under the disk concave) or up (convex).
  for (const double sign : {-1.0, 1.0}) {
    for (std::size_t v = 0; v < b.boundary.vertices.size(); ++v) {
      const double x = b.boundary.vertices[v].x[0], y = b.boundary.vertices[v].x[1];
      b.positions[2 * v] = x;
      b.positions[2 * v + 1] = y + (y == 1.0 ? sign * 1e-3 * std::exp(-std::pow((x - 1.0) / 0.3, 2)) : 0.0);
    }
    const double height = 1.0 + 0.095;
    double worst_jump = 0, previous = -1;
    int worst_count = 1;
    const int samples = 40001;
    for (int k = 0; k < samples; ++k) {
      const double c[2] = {0.5 + 1.0 * k / (samples - 1), height};
      PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
      const int n = plate_boundary_contacts(b.boundary, b.positions.data(), c, radius, contacts);
      worst_count = std::max(worst_count, n);
      ASSERT_GE(n, 1);
      if (previous >= 0) worst_jump = std::max(worst_jump, std::fabs(contacts[0].overlap - previous));
      previous = contacts[0].overlap;
    }
    // The step between samples is 2.5e-5 m; the surface's slope is below
    // 1e-3·2/0.3·e^{-1/2} ≈ 4e-3, so a continuous overlap moves by < 1e-7.
    std::printf("bump %+g: largest change of overlap between samples %.3g m, most contacts %d\n", sign, worst_jump,
                worst_count);
    EXPECT_LT(worst_jump, 1e-7);
    EXPECT_EQ(worst_count, 1);
  }
  // Exactly over a flat joint (the sag removed): one vertex contact whose
  // normal is the surface's.
  plate_boundary_positions(b.model, b.boundary, b.state.u.data(), b.state.time, b.positions.data());
  const double c[2] = {1.0, 1.05};
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  ASSERT_EQ(plate_boundary_contacts(b.boundary, b.positions.data(), c, radius, contacts), 1);
  EXPECT_GE(contacts[0].vertex, 0);
  EXPECT_EQ(contacts[0].normal[0], 0.0);
  EXPECT_EQ(contacts[0].normal[1], 1.0);
  EXPECT_NEAR(contacts[0].overlap, 0.05, 1e-15);
}

TEST(PlateBoundary, ACornerIsAVertexContactAlongTheDiagonal) {
  Built b;
  build(free_plate(4, 2), 0.1, b);
  const double c[2] = {2.03, 1.04};
  PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
  ASSERT_EQ(plate_boundary_contacts(b.boundary, b.positions.data(), c, 0.1, contacts), 1);
  EXPECT_GE(contacts[0].vertex, 0);
  EXPECT_NEAR(contacts[0].overlap, 0.1 - 0.05, 1e-15);
  // c − corner = (0.03, 0.04) from coordinates near 2: each carries 2.2e-16
  // of round-off, 1e-14 of the 0.05 m it is divided by.
  EXPECT_NEAR(contacts[0].normal[0], 0.6, 2e-14);
  EXPECT_NEAR(contacts[0].normal[1], 0.8, 2e-14);
}

TEST(PlateBoundary, SpreadForceCarriesTheForceAndItsMomentToTheUnknowns) {
  // A free plate with a crack (Heaviside-enriched nodes on both sides of it):
  // for each rigid motion w (two translations, a rotation about the origin),
  // with the enriched unknowns at zero, Σ f·w over the unknowns must be F·w
  // at the contact point's reference position.
  Built b;
  build_cracked(b);
  const PlateModel& m = b.model;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  double worst = 0;
  int enriched_touched = 0;
  for (std::size_t s = 0; s < b.boundary.segments.size(); ++s) {
    PlateBoundaryContact c;
    c.segment = static_cast<int>(s);
    c.t = uni(rng);
    const PlateMaterialPoint at = plate_boundary_material_point(b.boundary, c);
    const double force[2] = {uni(rng) - 0.5, uni(rng) - 0.5};
    std::vector<double> f(static_cast<std::size_t>(m.dofs), 0.0);
    plate_spread_force(m, at, force, f.data());
    const double px = m.desc.min[0] + m.cell_size[0] * (at.cell[0] + 0.5 * (1 + at.xi));
    const double py = m.desc.min[1] + m.cell_size[1] * (at.cell[1] + 0.5 * (1 + at.eta));
    double sum[3] = {0, 0, 0};
    for (int n = 0; n < m.nodes; ++n) {
      const double x = m.desc.min[0] + m.cell_size[0] * (n % (m.desc.cells[0] + 1));
      const double y = m.desc.min[1] + m.cell_size[1] * (n / (m.desc.cells[0] + 1));
      const int dx = m.node_dof[static_cast<std::size_t>(2 * n)], dy = m.node_dof[static_cast<std::size_t>(2 * n + 1)];
      sum[0] += f[static_cast<std::size_t>(dx)];
      sum[1] += f[static_cast<std::size_t>(dy)];
      sum[2] += x * f[static_cast<std::size_t>(dy)] - y * f[static_cast<std::size_t>(dx)];
    }
    for (const int e : m.enriched_dof)
      if (e >= 0 && f[static_cast<std::size_t>(e)] != 0.0) ++enriched_touched;
    const double moment = px * force[1] - py * force[0];
    worst = std::max({worst, std::fabs(sum[0] - force[0]), std::fabs(sum[1] - force[1]), std::fabs(sum[2] - moment)});
  }
  std::printf("largest error of force and moment: %.3g (N, N·m); enriched shares touched: %d\n", worst,
              enriched_touched);
  EXPECT_LT(worst, 1e-15);
  EXPECT_GT(enriched_touched, 0);  // the crack's cells do load their enriched unknowns
}

// A disk sliding over a crack's mouth whose lips are offset (one face moved
// 1e-3 m against the other): each lip's share of the contact, Σ δ n over the
// contacts on its piece of boundary, is continuous. Keeping only the deeper
// of two features that face the same way moved the whole contact from one
// lip to the other where their depths crossed, a jump of δ in each share.
TEST(PlateBoundary, ADiskOverACracksMouthTouchesBothLipsContinuously) {
  Built b;
  build_cracked(b);
  std::vector<double> u(static_cast<std::size_t>(b.model.dofs), 0.0);
  for (int n = 0; n < b.model.nodes; ++n) {
    if (b.model.node_enrichment[static_cast<std::size_t>(2 * n)] < 0) continue;
    const int dof = b.model.enriched_dof[static_cast<std::size_t>(2 * (2 * n) + 1)];
    if (dof >= 0) u[static_cast<std::size_t>(dof)] = 5e-4;  // the faces part by 1e-3 along y
  }
  plate_boundary_positions(b.model, b.boundary, u.data(), 0.0, b.positions.data());
  // The disk stays clear of the joints at x = 1 and 1.5 (the cut cell's
  // corners, where the lips' fields bend the edge: concave joints are not
  // smooth, above); the mouth is at x = 1.05.
  const double radius = 0.02, height = 1.0 + 0.018;
  const int samples = 40001;
  const double from = 1.025, span = 0.05, dx = span / (samples - 1);
  double worst = 0, previous[2][2] = {{0, 0}, {0, 0}};
  int chain_of_lip[2] = {-1, -1}, both = 0;
  for (int k = 0; k < samples; ++k) {
    const double c[2] = {from + span * k / (samples - 1), height};
    PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
    const int n = plate_boundary_contacts(b.boundary, b.positions.data(), c, radius, contacts);
    double share[2][2] = {{0, 0}, {0, 0}};
    for (int q = 0; q < n; ++q) {
      const int chain = b.boundary.segments[static_cast<std::size_t>(contacts[q].segment)].chain;
      int lip = chain == chain_of_lip[0] ? 0 : chain == chain_of_lip[1] ? 1 : -1;
      if (lip < 0) {
        lip = chain_of_lip[0] < 0 ? 0 : 1;
        ASSERT_LT(chain_of_lip[lip], 0) << "a third piece of boundary";
        chain_of_lip[lip] = chain;
      }
      for (int a = 0; a < 2; ++a) share[lip][a] += contacts[q].overlap * contacts[q].normal[a];
    }
    both += n == 2 ? 1 : 0;
    for (int lip = 0; lip < 2; ++lip)
      for (int a = 0; a < 2; ++a) {
        if (k > 0) worst = std::max(worst, std::fabs(share[lip][a] - previous[lip][a]));
        previous[lip][a] = share[lip][a];
      }
  }
  // Between samples δ moves by at most dx and n turns by at most dx/gap, so a
  // continuous share δ n moves by at most dx (1 + δ/gap) < 1.5 dx here.
  std::printf("disk over the mouth: largest change of a lip's share %.3g m per step of %.3g m; samples touching "
              "both lips %d\n",
              worst, dx, both);
  EXPECT_GT(both, 0);
  EXPECT_LT(worst, 1.5 * dx);
}

namespace {
// The free plate of 8 × 4 cells with a crack from below its bottom edge up
// to a tip at (xc, tip_y), 0.15 m below the top.
constexpr double xc = 1.1, tip_y = 0.85;
PlateDesc tipped_crack_plate() {
  PlateDesc d = free_plate(8, 4);
  PlateDiscontinuity q = vertical_crack(xc);
  q.points = {{xc, -0.2}, {xc, tip_y}};
  d.discontinuities.push_back(q);
  return d;
}
}  // namespace

// A crack from the bottom edge up to a tip 0.15 m below the top (cells of
// 0.25 m: the tip's cell reaches the top edge). The plate integrates the tip's
// cell fanned from the tip, the crack straight from where it enters the cell
// to the tip; the boundary's faces are the same line and stop at the tip,
// where they meet: one closed loop (the outer edges, broken at the bottom
// mouth, and the two faces), the top edge intact over the crack's line.
TEST(PlateBoundary, ACracksFacesStopAtItsTipAndTheEdgeBeyondItIsIntact) {
  Built b;
  build(tipped_crack_plate(), 0.05, b);
  const PlateBoundary& pb = b.boundary;
  ASSERT_EQ(b.model.tips.size(), 1u);
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  const std::vector<double> areas = loop_areas(pb);
  ASSERT_EQ(areas.size(), 1u);
  std::printf("one loop, area %.17g (the plate's 2; the faces enclose none)\n", areas[0]);
  EXPECT_NEAR(areas[0], 2.0, 1e-14);
  int tips = 0;
  double highest_face = 0;
  for (const PlateBoundaryVertex& v : pb.vertices) {
    if (v.tip) {
      ++tips;
      EXPECT_NEAR(v.x[0], xc, 1e-15);
      EXPECT_NEAR(v.x[1], tip_y, 1e-15);
    }
    // On the crack's line inside the plate: a face's vertex, never past the tip.
    if (std::fabs(v.x[0] - xc) < 1e-12 && v.x[1] > 0.0) highest_face = std::max(highest_face, v.x[1]);
  }
  EXPECT_EQ(tips, 1);
  EXPECT_NEAR(highest_face, tip_y, 1e-15);

  PlateBoundaryContact c[kPlateBoundaryMaxContacts];
  // A disk pressed on the top edge over the crack's line (0.15 m beyond the
  // tip, more than its radius): the intact surface, one contact, as it slides
  // across. Before the faces stopped at the tip, the edge broke there into two
  // lips and a disk over it touched both.
  const double r = 0.05, gap = 0.04;
  double worst = 0;
  int samples = 0;
  for (double x = 0.95; x <= 1.25; x += 0.001, ++samples) {
    const double centre[2] = {x, 1.0 + gap};
    const int n = plate_boundary_contacts(pb, b.positions.data(), centre, r, c);
    ASSERT_EQ(n, 1) << "x = " << x;
    EXPECT_NEAR(c[0].normal[1], 1.0, 1e-15);
    worst = std::max(worst, std::fabs(c[0].overlap - (r - gap)));
  }
  std::printf("top edge over the tip: %d samples, one contact each, overlap within %.3g m of %.3g m\n", samples, worst,
              r - gap);
  EXPECT_LT(worst, 1e-15);

  // A disk beside a face near the tip (its centre 0.03 m off the crack's
  // line, on either face's outer side), moved along it past the tip: the face
  // while its centre is beside it, then the tip's vertex: one contact, the
  // overlap r minus the distance to the face's segment (from where the crack
  // enters the tip's cell, y = 0.75, to the tip), continuous past the tip.
  const double entry[2] = {xc, 0.75}, tip[2] = {xc, tip_y};
  for (const double side : {1.0, -1.0}) {
    double err = 0, jump = 0, last = -1;
    int beyond = 0;
    for (double y = 0.76; y <= 0.94; y += 0.0005) {
      const double centre[2] = {xc + side * 0.03, y};
      const int n = plate_boundary_contacts(pb, b.positions.data(), centre, r, c);
      const double expected = std::max(0.0, r - segment_distance(centre, entry, tip));
      const double overlap = n > 0 ? c[0].overlap : 0.0;
      ASSERT_LE(n, 1) << "y = " << y;
      if (n == 1 && y < tip_y) {
        EXPECT_NEAR(c[0].normal[0], side, 1e-15);
      }
      if (n == 1 && y > tip_y) {
        ++beyond;
        EXPECT_TRUE(c[0].vertex >= 0 && pb.vertices[static_cast<std::size_t>(c[0].vertex)].tip);
      }
      err = std::max(err, std::fabs(overlap - expected));
      if (last >= 0) jump = std::max(jump, std::fabs(overlap - last));
      last = overlap;
    }
    std::printf("beside the %s face: overlap within %.3g m of r - distance to [entry, tip], largest change %.3g m "
                "per 0.5 mm step, %d samples on the tip past it\n",
                side > 0 ? "right" : "left", err, jump, beyond);
    EXPECT_LT(err, 1e-15);
    EXPECT_LE(jump, 0.0005 + 1e-15);  // continuous: by at most the step
    EXPECT_GT(beyond, 10);
  }
}

// The same crack opened: Heaviside unknowns and the tip's first branch
// function (√r sin(θ/2), the one that jumps) along x. Each face moves with
// its own side's field up to the tip: the two faces' points at one place part
// by the crack's opening, which plate_crack_opening computes with the jump's
// sign explicitly (2 N_a a_a and ±2√r N_a b_a), not from a point's side.
TEST(PlateBoundary, NearATipEachFaceMovesWithItsOwnSide) {
  Built b;
  build(tipped_crack_plate(), 0.05, b);
  const PlateBoundary& pb = b.boundary;
  std::vector<double> u(static_cast<std::size_t>(b.model.dofs), 0.0);
  for (int n = 0; n < b.model.nodes; ++n) {
    for (int s = 0; s < 2; ++s) {
      if (b.model.node_enrichment[static_cast<std::size_t>(2 * n + s)] < 0) continue;
      const int dof = b.model.enriched_dof[static_cast<std::size_t>(2 * (2 * n + s))];
      if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-4;
    }
    if (b.model.node_tip[static_cast<std::size_t>(n)] < 0) continue;
    const int dof = b.model.tip_dof[static_cast<std::size_t>(8 * n)];  // F_1, x
    if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-4;
  }
  PlateState state = b.state;
  state.u = u;
  double worst = 0, largest = 0;
  int points = 0, near_tip = 0;
  for (const PlateBoundaryVertex& v : pb.vertices) {
    if (v.tip || v.at.side > 0 || !(v.x[1] > 0.0)) continue;  // the − face's points inside the plate
    PlateMaterialPoint plus = v.at;
    plus.side = 1;
    double up[2], um[2];
    plate_material_point_field(b.model, plus, u.data(), true, 0.0, up);
    plate_material_point_field(b.model, v.at, u.data(), true, 0.0, um);
    // The opening's normal is left of the polyline's direction (0, 1): (−1, 0).
    const double opening = plate_crack_opening(b.model, state, 0, v.x[0], v.x[1], 0);
    worst = std::max(worst, std::fabs(-(up[0] - um[0]) - opening));
    largest = std::max(largest, std::fabs(opening));
    ++points;
    if (v.x[1] > 0.5) ++near_tip;
  }
  std::printf("%d face points (%d within two cells of the tip): the faces part by the crack's opening to %.3g m "
              "(largest opening %.3g m)\n",
              points, near_tip, worst, largest);
  EXPECT_GE(near_tip, 2);
  EXPECT_GT(largest, 1e-5);
  EXPECT_LT(worst, 1e-15 * largest + 1e-19);
}

// The force a contact puts on the plate does the work of the contact point's
// motion: for any displacement increment Δu of the plate's unknowns
// (standard, Heaviside, branch), f·Δu = F·Δp, where f is F spread over
// plate_boundary_material_points and Δp the contact point's move as the
// contact sees it, on the straight segment between its moved ends
// (plate_boundary_positions). Without it the exchange creates energy: a disk
// bouncing off the top edge of a crack tip's cell left a free, undamped,
// frictionless plate with 5e-4 of the scene's energy more than it started
// with, at every Δt. The plate: the tipped crack above and a void.
TEST(PlateBoundary, AContactsForceDoesTheWorkOfItsPointsMotion) {
  Built b;
  PlateDesc d = tipped_crack_plate();
  d.discontinuities.push_back(circular_void(0.55, 0.45, 0.17));
  build(d, 0.05, b);
  const PlateModel& m = b.model;
  const PlateBoundary& pb = b.boundary;
  const auto dofs = static_cast<std::size_t>(m.dofs);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> zero(dofs, 0.0), du(dofs);
  for (double& x : du) x = 1e-3 * uni(rng);
  std::vector<double> p0(2 * pb.vertices.size()), p1(p0.size());
  plate_boundary_positions(m, pb, zero.data(), 0.0, p0.data());
  plate_boundary_positions(m, pb, du.data(), 0.0, p1.data());
  auto moved = [&](int vertex, int axis) {
    const auto k = static_cast<std::size_t>(2 * vertex + axis);
    return p1[k] - p0[k];
  };
  double worst = 0, largest = 0, point_spread_worst = 0;
  int nonlinear = 0, contacts = 0;
  for (std::size_t s = 0; s < pb.segments.size(); ++s) {
    const PlateBoundarySegment& seg = pb.segments[s];
    nonlinear += seg.linear ? 0 : 1;
    for (int trial = 0; trial < 3; ++trial) {
      PlateBoundaryContact c;
      c.segment = static_cast<int>(s);
      c.t = trial == 0 ? 0.0 : 0.5 * (1.0 + uni(rng));
      if (trial == 0) c.vertex = seg.a;  // a vertex contact
      const double force[2] = {uni(rng), uni(rng)};
      PlateMaterialPoint at[kPlateBoundaryMaxPoints];
      double share[kPlateBoundaryMaxPoints];
      const int points = plate_boundary_material_points(pb, c, at, share);
      std::vector<double> f(dofs, 0.0);
      for (int q = 0; q < points; ++q) {
        const double piece[2] = {share[q] * force[0], share[q] * force[1]};
        plate_spread_force(m, at[q], piece, f.data());
      }
      double work = 0;
      for (std::size_t k = 0; k < dofs; ++k) work += f[k] * du[k];
      double dp[2];
      for (int axis = 0; axis < 2; ++axis)
        dp[axis] = c.vertex >= 0 ? moved(c.vertex, axis) : (1.0 - c.t) * moved(seg.a, axis) + c.t * moved(seg.b, axis);
      const double expected = force[0] * dp[0] + force[1] * dp[1];
      worst = std::max(worst, std::fabs(work - expected));
      largest = std::max(largest, std::fabs(expected));
      ++contacts;
      if (c.vertex >= 0 || seg.linear) continue;
      // What spreading at the contact's own material point would give.
      std::vector<double> g(dofs, 0.0);
      plate_spread_force(m, plate_boundary_material_point(pb, c), force, g.data());
      double point_work = 0;
      for (std::size_t k = 0; k < dofs; ++k) point_work += g[k] * du[k];
      point_spread_worst = std::max(point_spread_worst, std::fabs(point_work - expected));
    }
  }
  std::printf("%d contacts on %zu segments (%d not linear): largest |f·du − F·dp| %.3g of %.3g J; spread at the "
              "point instead: %.3g J\n",
              contacts, pb.segments.size(), nonlinear, worst, largest, point_spread_worst);
  EXPECT_GT(nonlinear, 10);  // the void's chords, the crack's faces, the tip cell's edges
  // Δp is a difference of positions of about 1 m for moves of about 1e-3 m:
  // ε·1e3 of relative round-off, with a margin.
  EXPECT_LT(worst, 1e-12 * largest);
  EXPECT_GT(point_spread_worst, 1e-6 * largest);  // the identity is not one every spread meets
}

// A crack from a void: a rectangular void [0.8, 1.3] × [0.3, 0.7] and a
// straight crack from inside it (x = 1.07, in a column of cells and off its
// cells' centres) down through the bottom edge, on 16 × 8 cells (h = 0.125).
// Below the void's floor (the nearest of its sides there) both level sets
// are linear, so in the cell both cut, (8, 2) = [1, 1.125] × [0.25, 0.375],
// the traced segments are exactly: the floor y = 0.3 clipped to each side of
// the crack (in pieces where the cell's sub-triangles meet; the material
// below it on the left: walked towards −x), and the crack's two faces from
// the floor down to the cell's lower edge (the + face, x > 1.07, walked
// downwards; the − face upwards), each face chained to its side's piece of
// the floor at the point P where the crack leaves the void. No segment lies
// in the cells wholly inside the void that the crack runs through, or on the
// crack's line above the floor, and the boundary is one closed loop (the
// slot joins the void to the outer edge).
TEST(PlateBoundary, ACrackFromAVoidIsTheVoidsBoundaryOnEachSideAndTheFacesOutsideIt) {
  PlateDesc d = free_plate(16, 8);
  PlateDiscontinuity hole;
  hole.name = "hole";
  hole.kind = PlateDiscontinuity::Kind::hole;
  hole.shape = PlateDiscontinuity::Shape::polygon;
  hole.points = {{0.8, 0.3}, {1.3, 0.3}, {1.3, 0.7}, {0.8, 0.7}};
  d.discontinuities.push_back(hole);
  const double xc = 1.07, floor_y = 0.3, x0 = 1.0, x1 = 1.125, y0 = 0.25;  // the crack; the floor; the cell
  PlateDiscontinuity crack = vertical_crack(xc);
  crack.points = {{xc, 0.5}, {xc, -0.2}};  // downwards: its left (+ side) is x > xc
  d.discontinuities.push_back(crack);
  Built b;
  build(d, 0.05, b);
  ASSERT_EQ(b.model.cell_second_cut[2 * 16 + 8], 0);  // the cell both cut
  const PlateBoundary& pb = b.boundary;
  // In the cell: the floor's pieces (split where the cell's sub-triangles
  // meet) and the faces, each checked against the closed form; their lengths
  // summed per side and kind.
  double floor_length[2] = {0, 0}, face_length[2] = {0, 0}, worst = 0;
  int in_cell = 0, faces = 0;
  for (std::size_t k = 0; k < pb.segments.size(); ++k) {
    const PlateBoundarySegment& s = pb.segments[k];
    const PlateBoundaryVertex& va = pb.vertices[static_cast<std::size_t>(s.a)];
    const PlateBoundaryVertex& vb = pb.vertices[static_cast<std::size_t>(s.b)];
    // Nothing in the cells wholly inside the void, nothing on the crack's line above the floor.
    EXPECT_GE(b.model.cell_material[static_cast<std::size_t>(s.cell[1] * 16 + s.cell[0])], 0) << "segment " << k;
    if (std::fabs(va.x[0] - xc) < 1e-12 && std::fabs(vb.x[0] - xc) < 1e-12) {
      EXPECT_LE(std::max(va.x[1], vb.x[1]), floor_y + 1e-12) << "segment " << k << " on the crack's line";
    }
    if (s.cell[0] != 8 || s.cell[1] != 2) continue;
    ++in_cell;
    // A vertex made by this cell is on the segment's side (one on the cell's
    // edge may be the neighbour's point there, where the field is the same).
    for (const PlateBoundaryVertex* v : {&va, &vb})
      if (v->at.cell[0] == 8 && v->at.cell[1] == 2) {
        EXPECT_EQ(v->at.side, s.side) << "segment " << k;
      }
    const int side = s.side > 0 ? 1 : 0;
    if (std::fabs(va.x[1] - floor_y) < 1e-9 && std::fabs(vb.x[1] - floor_y) < 1e-9) {
      // A piece of the floor: on its side of the crack, walked towards −x.
      worst = std::max({worst, std::fabs(va.x[1] - floor_y), std::fabs(vb.x[1] - floor_y)});
      EXPECT_LT(vb.x[0], va.x[0]) << "segment " << k;
      if (s.side > 0) {
        EXPECT_GE(vb.x[0], xc - 1e-15) << "segment " << k;
      } else {
        EXPECT_LE(va.x[0], xc + 1e-15) << "segment " << k;
      }
      floor_length[side] += va.x[0] - vb.x[0];
    } else {
      // A face: on the crack's line, below the floor; the + face downwards.
      ++faces;
      worst = std::max({worst, std::fabs(va.x[0] - xc), std::fabs(vb.x[0] - xc)});
      EXPECT_EQ(vb.x[1] < va.x[1], s.side > 0) << "segment " << k;
      face_length[side] += std::fabs(vb.x[1] - va.x[1]);
    }
    // The segment's parent coordinates are its ends' points.
    for (int end = 0; end < 2; ++end) {
      const double px = x0 + (x1 - x0) * 0.5 * (1.0 + s.xi[end]), py = y0 + (x1 - x0) * 0.5 * (1.0 + s.eta[end]);
      const double* x = end == 0 ? va.x : vb.x;
      worst = std::max({worst, std::fabs(px - x[0]), std::fabs(py - x[1])});
    }
  }
  std::printf("crack from a void: %d segments in the cell both cut (%d faces); the floor's pieces %.17g m (−) and "
              "%.17g m (+), the faces %.17g m and %.17g m; off the closed form by %.3g m\n",
              in_cell, faces, floor_length[0], floor_length[1], face_length[0], face_length[1], worst);
  EXPECT_EQ(faces, 2);
  EXPECT_NEAR(floor_length[0], xc - x0, 1e-15);  // the floor from the cell's left edge to the crack
  EXPECT_NEAR(floor_length[1], x1 - xc, 1e-15);  // ... from the crack to the cell's right edge
  EXPECT_NEAR(face_length[0], floor_y - y0, 1e-15);  // each face from the cell's lower edge to the floor
  EXPECT_NEAR(face_length[1], floor_y - y0, 1e-15);
  EXPECT_LT(worst, 1e-15);
  // Each face goes on from its side's piece of the floor: one vertex per side
  // where the crack leaves the void.
  int p_plus = -1, p_minus = -1;
  for (std::size_t v = 0; v < pb.vertices.size(); ++v)
    if (std::hypot(pb.vertices[v].x[0] - xc, pb.vertices[v].x[1] - floor_y) < 1e-12)
      (pb.vertices[v].at.side > 0 ? p_plus : p_minus) = static_cast<int>(v);
  ASSERT_GE(p_plus, 0);
  ASSERT_GE(p_minus, 0);
  EXPECT_NE(p_plus, p_minus);
  for (const int p : {p_plus, p_minus}) {
    EXPECT_GE(pb.vertices[static_cast<std::size_t>(p)].prev, 0);
    EXPECT_GE(pb.vertices[static_cast<std::size_t>(p)].next, 0);
  }
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  EXPECT_EQ(loop_areas(pb).size(), 1u);               // one loop: the slot joins the void to the outer edge
  // Opening the crack (the x of every Heaviside unknown) parts the two sides'
  // pieces: each vertex moves with its own side's field, the − side's by
  // −2e-3 relative to the + side's.
  std::vector<double> u(static_cast<std::size_t>(b.model.dofs), 0.0);
  for (int n = 0; n < b.model.nodes; ++n)
    for (int s = 0; s < 2; ++s) {
      if (b.model.node_enrichment[static_cast<std::size_t>(2 * n + s)] != 1) continue;
      const int dof = b.model.enriched_dof[static_cast<std::size_t>(2 * (2 * n + s))];
      if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-3;
    }
  plate_boundary_positions(b.model, b.boundary, u.data(), 0.0, b.positions.data());
  const double jump = b.positions[2 * static_cast<std::size_t>(p_plus)] - b.positions[2 * static_cast<std::size_t>(p_minus)];
  std::printf("- opened by the Heaviside unknowns: the two sides' vertices where the crack leaves the void part by "
              "%.17g m (2e-3)\n",
              jump);
  // Each side's field sums at most 12 terms of at most 2e-3, each within
  // half an ulp (2.2e-19): the jump is 2e-3 within 5e-18.
  EXPECT_NEAR(jump, 2e-3, 5e-18);
}

// A crack from a void wherever it leaves it: 200 placements from a fixed
// seed (a circular void of radius 0.1–0.3 m about a point of [0.5, 1.5] ×
// [0.35, 0.65], a straight free crack from its centre out through the
// domain's edge in any direction, 16 × 8 cells). Each plate that builds
// (the plate refuses a cell both cut on the domain's edge) has a boundary
// whose chains all close into one loop (the crack joins the void's loop to
// the outer one) of the material's area to O(h²) (the void's polygon), and
// in every cell both cut the crack's faces lie outside the void.
TEST(PlateBoundary, ACrackFromAVoidClosesOneLoopWhereverItLeavesTheVoid) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int built = 0, cut_cells = 0;
  double worst_area = 0;
  for (int k = 0; k < 200; ++k) {
    const double r = 0.1 + 0.2 * u01(rng), xc = 0.5 + u01(rng), yc = 0.35 + 0.3 * u01(rng);
    const double a = 2.0 * M_PI * u01(rng);
    PlateDesc d = free_plate(16, 8);
    d.discontinuities.push_back(circular_void(xc, yc, r));
    PlateDiscontinuity crack = vertical_crack(0.0);
    crack.points = {{xc, yc}, {xc + 3.0 * std::cos(a), yc + 3.0 * std::sin(a)}};
    d.discontinuities.push_back(crack);
    PlateModel m;
    PlateState s;
    PlateWorkspace ws;
    if (!build_plate(d, m, s, ws).ok()) continue;
    ++built;
    PlateBoundary pb;
    const BuildResult rb = plate_boundary_build(m, 0.05, 0.1, pb);
    ASSERT_TRUE(rb.ok()) << "placement " << k << ": " << rb.message;
    EXPECT_EQ(pb.vertices.size(), pb.segments.size()) << "placement " << k;
    for (const PlateBoundaryVertex& v : pb.vertices) {
      EXPECT_GE(v.prev, 0) << "placement " << k;
      EXPECT_GE(v.next, 0) << "placement " << k;
    }
    const std::vector<double> areas = loop_areas(pb);
    EXPECT_EQ(areas.size(), 1u) << "placement " << k;
    const double h = 0.125;
    if (!areas.empty()) {
      worst_area = std::max(worst_area, std::fabs(areas[0] - (2.0 - M_PI * r * r)));
      EXPECT_NEAR(areas[0], 2.0 - M_PI * r * r, 0.5 * M_PI * h * h) << "placement " << k;  // as the void's loop
    }
    for (std::size_t c = 0; c < m.cell_second_cut.size(); ++c)
      if (m.cell_second_cut[c] >= 0) ++cut_cells;
    for (const PlateBoundarySegment& sg : pb.segments) {
      const std::size_t c = static_cast<std::size_t>(sg.cell[1] * 16 + sg.cell[0]);
      if (m.cell_second_cut[c] < 0) continue;
      const double* xa = pb.vertices[static_cast<std::size_t>(sg.a)].x;
      const double* xb = pb.vertices[static_cast<std::size_t>(sg.b)].x;
      const double mx = 0.5 * (xa[0] + xb[0]) - xc, my = 0.5 * (xa[1] + xb[1]) - yc;
      // Every segment's middle is on or outside the void's polygon, within
      // its distance h²/(8r) from the circle inside.
      EXPECT_GT(std::hypot(mx, my), r - h * h / r) << "placement " << k;
    }
  }
  std::printf("crack from a void: %d of 200 placements built, %d cells both cut; every chain closed, one loop each, "
              "area within %.3g m² of the plate's less the circle\n",
              built, cut_cells, worst_area);
  EXPECT_GE(built, 100);
}

// The same crack from the rectangular void with tied faces: no face is a
// contact surface, and the floor's two pieces end at their own vertices
// where the crack leaves the void (the chain broken there, as at a tied
// crack's mouth on the outer edge).
TEST(PlateBoundary, ATiedCrackFromAVoidLeavesTheFloorsPiecesOpenAtItsMouth) {
  PlateDesc d = free_plate(16, 8);
  PlateDiscontinuity hole;
  hole.name = "hole";
  hole.kind = PlateDiscontinuity::Kind::hole;
  hole.shape = PlateDiscontinuity::Shape::polygon;
  hole.points = {{0.8, 0.3}, {1.3, 0.3}, {1.3, 0.7}, {0.8, 0.7}};
  d.discontinuities.push_back(hole);
  const double xc = 1.07, floor_y = 0.3;
  PlateDiscontinuity crack = vertical_crack(xc);
  crack.points = {{xc, 0.5}, {xc, -0.2}};
  crack.faces = PlateDiscontinuity::Faces::tied;
  crack.stiffness[0] = crack.stiffness[1] = 1e12;
  d.discontinuities.push_back(crack);
  Built b;
  build(d, 0.05, b);
  const PlateBoundary& pb = b.boundary;
  int faces = 0, at_p = 0;
  for (const PlateBoundarySegment& s : pb.segments) {
    const double* xa = pb.vertices[static_cast<std::size_t>(s.a)].x;
    const double* xb = pb.vertices[static_cast<std::size_t>(s.b)].x;
    if (std::fabs(xa[0] - xc) < 1e-12 && std::fabs(xb[0] - xc) < 1e-12) ++faces;
  }
  for (const PlateBoundaryVertex& v : pb.vertices) {
    if (std::hypot(v.x[0] - xc, v.x[1] - floor_y) > 1e-12) continue;
    ++at_p;
    // The + piece ends there, the − piece starts there: one segment each.
    EXPECT_EQ(v.at.side > 0, v.prev >= 0 && v.next < 0);
    EXPECT_EQ(v.at.side < 0, v.next >= 0 && v.prev < 0);
  }
  std::printf("tied crack from a void: %d face segments, %d vertices where it leaves the void\n", faces, at_p);
  EXPECT_EQ(faces, 0);
  EXPECT_EQ(at_p, 2);
}

// A free crack across two inclusions (2 × 1 plate, 16 × 8 cells, h = 0.125):
// the crack y = 0.53 from edge to edge (its + side above), through a circle
// about (0.97, 0.48) of radius 0.26 inside the plate and through a circle
// about (−0.1, 0.42) of radius 0.2 that crosses the left edge at y = 0.5932
// inside the crack's cell (0, 4) there. An inclusion's boundary has material
// on both sides: it is no contact surface; in every cell both cut the traced
// segments off the outer edge are exactly the crack's two faces (on its
// line, each the cell's width, one per side with that side's material on
// its left), each split where it crosses the inclusion's piecewise-linear
// boundary, so that each segment lies in one material (off the circle by
// at most the interpolation's h²/r there). The left edge of the cell (0, 4)
// is split at both crossings, the chain broken at the crack's mouth: two
// loops, the plate's parts above and below the crack.
TEST(PlateBoundary, ACrackAcrossAnInclusionIsTracedByItsFacesOnly) {
  PlateDesc d = free_plate(16, 8);
  const double yc = 0.53, h = 0.125;
  PlateDiscontinuity crack = vertical_crack(0.0);
  crack.points = {{-1.0, yc}, {3.0, yc}};
  d.discontinuities.push_back(crack);
  const double centre[2][2] = {{0.97, 0.48}, {-0.1, 0.42}}, radius[2] = {0.26, 0.2};
  for (int k = 0; k < 2; ++k) {
    PlateDiscontinuity inc = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, centre[k][0], centre[k][1],
                                                    radius[k], k == 0 ? "inner" : "at_edge");
    inc.material = {5e10, 0.25, 3000};
    d.discontinuities.push_back(inc);
  }
  Built b;
  build(d, 0.05, b);
  const PlateModel& m = b.model;
  const PlateBoundary& pb = b.boundary;
  int both = 0;
  for (std::size_t c = 0; c < m.cell_second_cut.size(); ++c)
    if (m.cell_second_cut[c] >= 0) ++both;
  ASSERT_GE(m.cell_second_cut[4 * 16 + 0], 0);  // the edge's cell both cut
  ASSERT_GE(m.cell_second_cut[4 * 16 + 5], 0);  // and the inner circle's
  ASSERT_GE(m.cell_second_cut[4 * 16 + 9], 0);
  auto on_outer_edge = [](const double* xa, const double* xb) {
    for (int c = 0; c < 2; ++c)
      for (const double e : {0.0, c == 0 ? 2.0 : 1.0})
        if (xa[c] == e && xb[c] == e) return true;
    return false;
  };
  double face_length[16][2] = {}, worst_line = 0, worst_split = 0;
  int splits = 0, in_inclusion = 0;
  for (std::size_t k = 0; k < pb.segments.size(); ++k) {
    const PlateBoundarySegment& s = pb.segments[k];
    const double* xa = pb.vertices[static_cast<std::size_t>(s.a)].x;
    const double* xb = pb.vertices[static_cast<std::size_t>(s.b)].x;
    const std::size_t cell = static_cast<std::size_t>(s.cell[1] * 16 + s.cell[0]);
    if (on_outer_edge(xa, xb)) continue;
    // Off the outer edge, every segment is a face: on the crack's line.
    worst_line = std::max({worst_line, std::fabs(xa[1] - yc), std::fabs(xb[1] - yc)});
    if (m.cell_second_cut[cell] < 0) continue;
    ASSERT_EQ(s.cell[1], 4) << "segment " << k;
    EXPECT_EQ(xb[0] > xa[0], s.side > 0) << "segment " << k;  // the + face (material above) runs towards +x
    EXPECT_EQ(pb.vertices[static_cast<std::size_t>(s.a)].at.side, s.side) << "segment " << k;
    EXPECT_EQ(pb.vertices[static_cast<std::size_t>(s.b)].at.side, s.side) << "segment " << k;
    face_length[s.cell[0]][s.side > 0 ? 1 : 0] += std::fabs(xb[0] - xa[0]);
    // Its material against the circle of the inclusion cutting the cell.
    const int inc = m.cell_second_cut[cell] - 1;
    const int material = plate_boundary_segment_material(m, s);
    EXPECT_TRUE(material == 0 || material == 2 + inc) << "segment " << k;
    const double mid = std::hypot(0.5 * (xa[0] + xb[0]) - centre[inc][0], 0.5 * (xa[1] + xb[1]) - centre[inc][1]);
    const double band = h * h / radius[inc];
    if (std::fabs(mid - radius[inc]) > band) {
      EXPECT_EQ(material == 2 + inc, mid < radius[inc]) << "segment " << k;
    }
    in_inclusion += material > 0;
    // A split: a face's vertex made inside the cell off its sub-triangles'
    // edges (where the inclusion's zero line crosses the crack's).
    for (const double* x : {xa, xb}) {
      const double xi = 2.0 * (x[0] - s.cell[0] * h) / h - 1.0, eta = 2.0 * (x[1] - s.cell[1] * h) / h - 1.0;
      if (std::fabs(xi) < 1 - 1e-12 && std::fabs(std::fabs(xi) - std::fabs(eta)) > 1e-12 && s.side > 0 && x == xb) {
        ++splits;
        worst_split = std::max(worst_split, std::fabs(std::hypot(x[0] - centre[inc][0], x[1] - centre[inc][1]) -
                                                      radius[inc]) / band);
      }
    }
  }
  std::printf("crack across two inclusions: %d cells both cut; faces off the crack's line by %.3g m; %d face segments "
              "in an inclusion, %d splits on the + face, off the circle by %.3g of h^2/r\n",
              both, worst_line, in_inclusion, splits, worst_split);
  EXPECT_LT(worst_line, 1e-15);
  EXPECT_GE(splits, 3);  // where the crack enters and leaves the inner circle, and leaves the edge's
  EXPECT_LE(worst_split, 1.0);
  EXPECT_GT(in_inclusion, 0);
  for (int i = 0; i < 16; ++i) {
    if (m.cell_second_cut[static_cast<std::size_t>(4 * 16 + i)] < 0) continue;
    EXPECT_NEAR(face_length[i][0], h, 1e-15) << "cell (" << i << ", 4)";  // each face the cell's width
    EXPECT_NEAR(face_length[i][1], h, 1e-15) << "cell (" << i << ", 4)";
  }
  // The left edge of the cell (0, 4), walked downwards: to the inclusion's
  // crossing (its level set linear along the edge, from the lower node) in
  // the plate's material, on to the mouth in the inclusion's, both on the +
  // side; below the mouth the − side, in the inclusion's.
  const double p0 = m.node_phi[2 * static_cast<std::size_t>(m.nodes) + 4 * 17];
  const double p1 = m.node_phi[2 * static_cast<std::size_t>(m.nodes) + 5 * 17];
  const double y_inc = 0.5 + h * p0 / (p0 - p1);
  std::vector<const PlateBoundarySegment*> edge;
  for (const PlateBoundarySegment& s : pb.segments) {
    const double* xa = pb.vertices[static_cast<std::size_t>(s.a)].x;
    const double* xb = pb.vertices[static_cast<std::size_t>(s.b)].x;
    if (xa[0] == 0.0 && xb[0] == 0.0 && s.cell[1] == 4) edge.push_back(&s);
  }
  ASSERT_EQ(edge.size(), 3u);
  const double ends[4] = {0.625, y_inc, yc, 0.5};
  const int sides[3] = {1, 1, -1}, materials[3] = {0, 3, 3};
  double worst_edge = 0;
  for (int k = 0; k < 3; ++k) {
    worst_edge = std::max({worst_edge, std::fabs(pb.vertices[static_cast<std::size_t>(edge[k]->a)].x[1] - ends[k]),
                           std::fabs(pb.vertices[static_cast<std::size_t>(edge[k]->b)].x[1] - ends[k + 1])});
    EXPECT_EQ(edge[k]->side, sides[k]) << "edge part " << k;
    EXPECT_EQ(plate_boundary_segment_material(m, *edge[k]), materials[k]) << "edge part " << k;
  }
  EXPECT_LT(worst_edge, 1e-15);
  EXPECT_NE(edge[1]->b, edge[2]->a);  // the chain broken at the mouth: a vertex of each side
  EXPECT_EQ(edge[0]->b, edge[1]->a);  // continuous across the inclusion's boundary
  EXPECT_EQ(pb.vertices.size(), pb.segments.size());  // every chain closed
  const std::vector<double> areas = loop_areas(pb);
  ASSERT_EQ(areas.size(), 2u);
  std::printf("- left edge of the cell (0, 4) split at y = %.17g and %.17g, off by %.3g m; loops %.17g and %.17g m^2\n",
              y_inc, yc, worst_edge, areas[0], areas[1]);
  EXPECT_NEAR(std::min(areas[0], areas[1]), 2.0 * (1.0 - yc), 1e-14);
  EXPECT_NEAR(std::max(areas[0], areas[1]), 2.0 * yc, 1e-14);
  // Opening the crack (the x of every Heaviside unknown of the crack): every
  // pair of coincident face vertices of the two sides (where a face meets a
  // cell's or sub-triangle's edge, a split, the mouths) part by 2e-3, each
  // moving with its side's functions (the ridge's unknowns 0).
  std::vector<double> u(static_cast<std::size_t>(m.dofs), 0.0);
  for (int n = 0; n < m.nodes; ++n)
    for (int s = 0; s < 2; ++s) {
      if (m.node_enrichment[static_cast<std::size_t>(2 * n + s)] != 0) continue;
      const int dof = m.enriched_dof[static_cast<std::size_t>(2 * (2 * n + s))];
      if (dof >= 0) u[static_cast<std::size_t>(dof)] = 1e-3;
    }
  double worst_jump = 0;
  int pairs = 0;
  for (std::size_t v = 0; v < pb.vertices.size(); ++v)
    for (std::size_t w = 0; w < pb.vertices.size(); ++w) {
      const PlateBoundaryVertex& a = pb.vertices[v];
      const PlateBoundaryVertex& c = pb.vertices[w];
      if (a.at.side < 0 || c.at.side > 0 || a.x[0] != c.x[0] || a.x[1] != c.x[1]) continue;
      ++pairs;
      // The displacements (the positions add the reference x, whose ulp is 2.2e-16 m).
      double da[2], dc[2];
      plate_material_point_field(m, a.at, u.data(), true, 0.0, da);
      plate_material_point_field(m, c.at, u.data(), true, 0.0, dc);
      worst_jump = std::max(worst_jump, std::fabs(da[0] - dc[0] - 2e-3));
    }
  std::printf("- opened: %d pairs of face vertices part by 2e-3 m within %.3g m\n", pairs, worst_jump);
  EXPECT_GT(pairs, 16);
  // Each side's field sums at most 12 terms of at most 2e-3, each within half
  // an ulp (2.2e-19): within 5e-18.
  EXPECT_LT(worst_jump, 5e-18);
}

// A free crack across an inclusion wherever it crosses it: 200 placements
// from a fixed seed (a circular inclusion of radius 0.1–0.3 m about a point
// of [0.5, 1.5] × [0.35, 0.65], a straight free crack through a point within
// r/2 of its centre in any direction, through the whole plate; 16 × 8
// cells). Each plate that builds has a boundary whose chains all close into
// two loops (the plate's two parts) of areas summing to the plate's (the
// shoelace sums some 100 products of coordinates ≤ 2, each within an ulp of
// 4.4e-16: 1e-13), and in every cell both cut every segment off the outer
// edge lies on the crack's line (a crossing's distance from it is the level
// set's round-off, a few 1e-16, and this distance's own of coordinates ≤ 2:
// 1e-14).
TEST(PlateBoundary, ACrackAcrossAnInclusionClosesTwoLoopsWhereverItCrossesIt) {
  std::mt19937_64 rng(20261130);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int built = 0, cut_cells = 0;
  double worst_area = 0, worst_line = 0;
  for (int k = 0; k < 200; ++k) {
    const double r = 0.1 + 0.2 * u01(rng), xc = 0.5 + u01(rng), yc = 0.35 + 0.3 * u01(rng);
    const double a = M_PI * u01(rng), off = 0.5 * r * (2.0 * u01(rng) - 1.0);
    const double px = xc - off * std::sin(a), py = yc + off * std::cos(a);  // a point of the crack's line
    PlateDesc d = free_plate(16, 8);
    PlateDiscontinuity crack = vertical_crack(0.0);
    crack.points = {{px - 4.0 * std::cos(a), py - 4.0 * std::sin(a)}, {px + 4.0 * std::cos(a), py + 4.0 * std::sin(a)}};
    d.discontinuities.push_back(crack);
    PlateDiscontinuity inc = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, xc, yc, r);
    inc.material = {5e10, 0.25, 3000};
    d.discontinuities.push_back(inc);
    PlateModel m;
    PlateState s;
    PlateWorkspace ws;
    if (!build_plate(d, m, s, ws).ok()) continue;
    ++built;
    PlateBoundary pb;
    const BuildResult rb = plate_boundary_build(m, 0.05, 0.1, pb);
    ASSERT_TRUE(rb.ok()) << "placement " << k << ": " << rb.message;
    EXPECT_EQ(pb.vertices.size(), pb.segments.size()) << "placement " << k;
    const std::vector<double> areas = loop_areas(pb);
    EXPECT_EQ(areas.size(), 2u) << "placement " << k;
    double total = 0;
    for (const double area : areas) total += area;
    worst_area = std::max(worst_area, std::fabs(total - 2.0));
    EXPECT_NEAR(total, 2.0, 1e-13) << "placement " << k;
    for (std::size_t c = 0; c < m.cell_second_cut.size(); ++c)
      if (m.cell_second_cut[c] >= 0) ++cut_cells;
    for (const PlateBoundarySegment& sg : pb.segments) {
      const std::size_t c = static_cast<std::size_t>(sg.cell[1] * 16 + sg.cell[0]);
      if (m.cell_second_cut[c] < 0) continue;
      const double* xa = pb.vertices[static_cast<std::size_t>(sg.a)].x;
      const double* xb = pb.vertices[static_cast<std::size_t>(sg.b)].x;
      bool edge = false;
      for (int q = 0; q < 2; ++q)
        for (const double e : {0.0, q == 0 ? 2.0 : 1.0}) edge = edge || (xa[q] == e && xb[q] == e);
      if (edge) continue;
      for (const double* x : {xa, xb})
        worst_line = std::max(worst_line, std::fabs((x[0] - px) * std::sin(a) - (x[1] - py) * std::cos(a)));
    }
  }
  std::printf("crack across an inclusion: %d of 200 placements built, %d cells both cut; every chain closed, two "
              "loops each, areas summing to the plate's within %.3g m^2; faces off the crack's line by %.3g m\n",
              built, cut_cells, worst_area, worst_line);
  EXPECT_GE(built, 100);
  EXPECT_LT(worst_line, 1e-14);
}
