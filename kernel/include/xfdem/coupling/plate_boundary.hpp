// Type c contact in 2D: disks against the boundary of the plate (the part of
// it that has material on one side), as a list of straight segments between
// vertices, each vertex and each point of a segment a material point of the
// plate (a cell, parent coordinates, a side of the discontinuity cutting the
// cell), so that it moves with the plate's (enriched) field.
//
// Built once (plate_boundary_build, the only allocating call): the outer
// edges, walked counter-clockwise, one segment per cell edge with material,
// split where a discontinuity crosses it. A crack that reaches the edge
// breaks the chain there (each face's end is a vertex of its own side, so the
// mouth can open). Then the voids' boundaries: in each sub-triangle of a cell
// a void cuts, the zero line of the (there linear) level set, the material
// on its left; and a free crack's two faces, one per side, each with its
// side's material on its left. In a cell cut by a crack and a void (a crack
// from a hole), the material is where the void's level set (linear in each
// sub-triangle) is ≥ 0: the void's zero line split where the crack's meets
// it into a piece on each side of the crack (each on its side's functions),
// and the crack's faces only outside the void, each chained to its side's
// piece there; the crack's line inside the void has no material either
// side and is no contact surface. In a cell cut by a crack and an inclusion
// (material on both sides of the inclusion's boundary, which is no contact
// surface), a free crack's two faces, split where they cross the
// inclusion's level set (linear in each sub-triangle) so that each segment
// lies in one material; on the domain's edge the edge is split at both
// crossings. Crossings are shared by edge, discontinuity
// and side, so they close into loops, or join the outer chain where they
// reach the domain's edge (a crack through the plate: two loops). The broad phase is a fixed grid of bins over the
// domain: each segment is listed, in segment order, in every bin within
// `reach` of it, so a disk looks in one bin and meets its candidates in a
// fixed order.
//
// Contact of a disk (centre c, radius r) with the deformed boundary: the
// closest point on an edge (the centre's projection strictly inside it and on
// its outer side) or on a vertex (the centre in the vertex's Voronoi wedge:
// past the end of the segment before it and before the start of the segment
// after it, on the outer side of both). The tests that split edge from vertex
// use the same dot products on both sides of a joint, so every outer point
// belongs to at least one feature; a disk then keeps its deepest feature and
// any other whose normal is more than 60° from every one kept (a concave
// corner). On a flat or nearly flat surface that is one contact whose
// overlap is continuous as it moves from edge to vertex to edge: no bump at
// the joints.
#pragma once
#include <cstdint>
#include <vector>

#include "xfdem/plate.hpp"

namespace xfdem {

/// A point of the plate's material: cell (i, j), parent coordinates, side of
/// the discontinuity cutting the cell (+1 when uncut).
struct PlateMaterialPoint {
  int cell[2] = {0, 0};
  double xi = 0, eta = 0;
  int side = 1;
};

struct PlateBoundaryVertex {
  double x[2] = {0, 0};  ///< reference position, m
  PlateMaterialPoint at;
  int prev = -1, next = -1;  ///< the segments ending and starting here (−1: a chain's end)
  /// A crack's tip, where its two faces meet (in the tip's cell each face
  /// runs straight from where the crack enters the cell to the tip).
  bool tip = false;
};

/// From vertex a to vertex b with the material on the left (outward normal to
/// the right); the segment's points are those of one cell, parent coordinates
/// linear from a's to b's.
struct PlateBoundarySegment {
  int a = 0, b = 0;
  int cell[2] = {0, 0};
  double xi[2] = {0, 0}, eta[2] = {0, 0};  ///< at a and at b
  int side = 1;
  /// The chain of segments joined end to end it belongs to (a loop or an
  /// open chain), named by one of its segments: what a disk's tangential
  /// spring is kept by, so that it slides across joints with its history.
  int chain = -1;
  /// Whether the plate's field is linear along the segment (an edge of a cell
  /// with only its four bilinear functions): then a point's shape functions
  /// are its ends' blended, and a contact's force may be spread at the point
  /// itself. Elsewhere (a cut cell, enriched nodes) the field along the
  /// segment is not linear, while the contact sees the straight segment
  /// between its moved ends, so the force goes to the two ends
  /// (plate_boundary_material_points).
  bool linear = true;
};

struct PlateBoundary {
  std::vector<PlateBoundaryVertex> vertices;
  std::vector<PlateBoundarySegment> segments;
  /// Broad phase: bins of size bin_size from origin, bins[0] × bins[1];
  /// bin k lists segments bin_items[bin_start[k] … bin_start[k + 1]).
  double origin[2] = {0, 0};
  double bin_size = 0;
  int bins[2] = {0, 0};
  std::vector<int> bin_start, bin_items;
  /// A segment is listed in every bin within `reach` of it: the largest disk
  /// radius plus `allowance`, the displacement of the boundary the lists hold
  /// for (plate_boundary_within_reach checks it).
  double reach = 0, allowance = 0;
};

/// Builds the outer boundary, the voids' and the free cracks' faces (a crack
/// from a void's, a crack across an inclusion's too) of a built plate, with bins for disks up to
/// `max_radius` and boundary displacements up to `allowance` (m, > 0). Fails
/// (naming `what`) for an unbuilt or static plate; allocates.
BuildResult plate_boundary_build(const PlateModel& plate, double max_radius, double allowance, PlateBoundary& out);

/// The material segment s bounds: 0 the plate's, 1 + k inclusion k's (−1
/// none), as the plate takes it (its material_at): in a cell an inclusion
/// cuts alone, the inclusion's on its − side; in a cell a crack and an
/// inclusion cut, the inclusion's where the inclusion's level set, linear on
/// the sub-triangle, is negative at the segment's middle (the build splits a
/// segment where it crosses zero, so the whole segment is of that material);
/// else the cell's.
int plate_boundary_segment_material(const PlateModel& plate, const PlateBoundarySegment& segment);

/// The deformed position of every vertex (2 per vertex, x then y) at the
/// plate's displacement u (its unknowns) at time `time` (s: the held
/// displacements of prescribed nodes that move are their values then). No allocation.
void plate_boundary_positions(const PlateModel& plate, const PlateBoundary& boundary, const double* u, double time,
                              double* positions);

/// Whether every vertex is within the allowance of its reference position.
bool plate_boundary_within_reach(const PlateBoundary& boundary, const double* positions);

/// One contact of a disk with the boundary.
struct PlateBoundaryContact {
  int segment = -1;      ///< the segment of an edge contact, or the one whose material point is used
  int vertex = -1;       ///< the vertex of a vertex contact (−1: edge contact)
  double t = 0;          ///< parameter along the segment (0 at a, 1 at b) of the contact point
  double point[2] = {0, 0};   ///< contact point on the deformed boundary, m
  double normal[2] = {0, 0};  ///< unit, from the boundary towards the disk's centre
  double overlap = 0;         ///< r − gap, > 0
  /// At a concave joint, the edge across the joint when the centre is near
  /// the joint's bisector (−1: none): the contact is then the blend
  /// (1 − w)·this edge's foot + w·the partner's foot (`point` is the blend,
  /// `normal` along centre − point; `overlap` stays the closest point's), and
  /// the force is shared by the two material points in those proportions
  /// (plate_boundary_material_points).
  int partner = -1;
  double partner_t = 0;       ///< parameter along the partner segment of its foot
  double partner_weight = 0;  ///< w, in [0, ½]
};

/// Most contacts one disk can have: kept normals are more than 60° apart.
inline constexpr int kPlateBoundaryMaxContacts = 6;

/// The contacts of a disk with the boundary at the deformed vertex positions
/// `positions` (plate_boundary_positions), in a fixed order (deepest first).
/// Returns their count (≤ kPlateBoundaryMaxContacts). No allocation.
int plate_boundary_contacts(const PlateBoundary& boundary, const double* positions, const double centre[2],
                            double radius, PlateBoundaryContact out[kPlateBoundaryMaxContacts]);

/// The material point of a contact (the vertex's, or the segment's at t;
/// of a blended contact, its first edge's).
PlateMaterialPoint plate_boundary_material_point(const PlateBoundary& boundary, const PlateBoundaryContact& contact);

/// Adds the force `force` (N, x and y) acting at material point `at` to the
/// plate's generalised force vector f (one entry per unknown), spread by the
/// (enriched) shape functions there: for every rigid motion w of the plate,
/// Σ f·w = force·w(at), so the plate gets the force and its moment about any
/// point. Shares on held components (supports) go nowhere: the supports take
/// them. No allocation.
void plate_spread_force(const PlateModel& plate, const PlateMaterialPoint& at, const double force[2], double* f);

/// Most material points a contact's force is shared by: two feet of a
/// blended contact, each on a segment's two ends.
inline constexpr int kPlateBoundaryMaxPoints = 4;

/// Where a contact's force acts on the plate, and each point's share of it:
/// the points the contact's own kinematics moves with, so that the force's
/// work on the plate is the force times the contact point's velocity (the
/// exchange creates no energy). A vertex contact: the vertex (share 1). An
/// edge contact at t on a `linear` segment: the point at t (share 1; the
/// same as its ends at 1 − t and t there); on any other segment its two
/// ends, shares 1 − t and t, as the contact point is placed on the straight
/// segment between the moved ends. A blended contact: each foot so, weighed
/// by 1 − w and w. The shares sum to 1 and blend the points to the contact
/// point, so the plate gets the force and its moment about any point.
/// Returns the count (≤ kPlateBoundaryMaxPoints).
int plate_boundary_material_points(const PlateBoundary& boundary, const PlateBoundaryContact& contact,
                                   PlateMaterialPoint at[kPlateBoundaryMaxPoints],
                                   double share[kPlateBoundaryMaxPoints]);

/// The plate's field (displacement u with the held displacements at `time`,
/// s, or a rate with held components 0) at a material point. No allocation.
void plate_material_point_field(const PlateModel& plate, const PlateMaterialPoint& at, const double* field,
                                bool displacement, double time, double out[2]);

}  // namespace xfdem
