// Pieces of the plate tests' scenes (tests/xfem, tests/coupling, tests/long).
#pragma once
#include <array>
#include <utility>
#include <vector>

#include "xfdem/plate.hpp"

namespace xfdem::testing {

/// A plane-strain plate [0, x] × [0, y] of nx × ny cells, ν = 0.3, ρ = 7800, dt = 1e-4 s.
inline PlateDesc plate(double e, double x, double y, int nx, int ny) {
  PlateDesc p;
  p.plane = PlateDesc::Plane::strain;
  p.youngs_modulus = e;
  p.poisson_ratio = 0.3;
  p.density = 7800.0;
  p.min[0] = 0, p.min[1] = 0, p.max[0] = x, p.max[1] = y;
  p.cells[0] = nx, p.cells[1] = ny;
  p.dt = 1e-4;
  return p;
}

/// A circular void or inclusion (an inclusion's material is left for the
/// caller), named "hole" or "inclusion" unless `name` is given.
inline PlateDiscontinuity circle(PlateDiscontinuity::Kind kind, double cx, double cy, double r,
                                 const char* name = nullptr) {
  PlateDiscontinuity q;
  q.name = name != nullptr ? name : kind == PlateDiscontinuity::Kind::hole ? "hole" : "inclusion";
  q.kind = kind;
  q.shape = PlateDiscontinuity::Shape::circle;
  q.centre[0] = cx, q.centre[1] = cy;
  q.radius = r;
  return q;
}

/// A polygonal void or inclusion (an inclusion's material is left for the
/// caller), named "hole" or "inclusion" unless `name` is given.
inline PlateDiscontinuity polygon(PlateDiscontinuity::Kind kind, std::vector<std::array<double, 2>> points,
                                  const char* name = nullptr) {
  PlateDiscontinuity q;
  q.name = name != nullptr ? name : kind == PlateDiscontinuity::Kind::hole ? "hole" : "inclusion";
  q.kind = kind;
  q.shape = PlateDiscontinuity::Shape::polygon;
  q.points = std::move(points);
  return q;
}

/// The cells a second discontinuity cuts beside a crack (PlateModel::cell_second_cut).
inline int cells_cut_by_both(const PlateModel& m) {
  int n = 0;
  for (int c : m.cell_second_cut) n += c >= 0 ? 1 : 0;
  return n;
}

}  // namespace xfdem::testing
