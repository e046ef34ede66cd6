// Pieces of the coupled 2D tests' scenes (tests/coupling/coupled2d*_test.cpp).
#pragma once
#include "xfdem/coupled2d.hpp"

namespace xfdem::testing {

inline ParticleDesc<2> disk(double mass, double radius, double stiffness, double x, double y, double vx, double vy) {
  ParticleDesc<2> p;
  p.mass = mass, p.radius = radius, p.stiffness = stiffness;
  p.position = {x, y};
  p.velocity = {vx, vy};
  return p;
}

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

/// A free plate 2 m × 1 m (E = 2 GPa), 8 × 4 cells, cut by a free crack across it.
inline PlateDesc cracked_free_plate() {
  PlateDesc p = plate(2e9, 2, 1, 8, 4);
  PlateDiscontinuity crack;
  crack.name = "c1";
  crack.kind = PlateDiscontinuity::Kind::crack;
  crack.shape = PlateDiscontinuity::Shape::polyline;
  crack.points = {{0.93, -0.2}, {1.11, 1.2}};
  p.discontinuities.push_back(crack);
  return p;
}

/// Total linear momentum along `axis`: the plate's and the disks'.
inline double total_momentum(const Coupled2dModel& m, const Coupled2dState& s, int axis) {
  double p = plate_momentum(m.plate, s.plate, axis);
  for (std::int32_t i = 0; i < m.dem.n; ++i) p += m.dem.mass[i] * s.dem.v[axis][i];
  return p;
}

}  // namespace xfdem::testing
