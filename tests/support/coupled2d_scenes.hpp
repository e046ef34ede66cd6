// Pieces of the coupled 2D tests' scenes (tests/coupling/coupled2d*_test.cpp).
#pragma once
#include "support/plate_scenes.hpp"
#include "xfdem/coupled2d.hpp"

namespace xfdem::testing {

inline ParticleDesc<2> disk(double mass, double radius, double stiffness, double x, double y, double vx, double vy) {
  ParticleDesc<2> p;
  p.mass = mass, p.radius = radius, p.stiffness = stiffness;
  p.position = {x, y};
  p.velocity = {vx, vy};
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

/// A bed of n frictional disks (0.5 kg, r = 8 mm, k = 1e5 N/m, ζ = 0.2,
/// μ = 0.5, k_t = 0.8 k) in rows of 70, the lowest 0.2 mm above the top of a
/// 2 m × 0.5 m plate (E = 1e9 Pa, ρ = 2000, 40 × 10 cells) held at its bottom,
/// with a circular void and a free crack across it, all at rest under
/// gravity; symplectic Euler, 10 substeps (bench/bm_coupled2d.cpp).
inline Coupled2dDesc disk_bed_on_plate(int n) {
  Coupled2dDesc d;
  d.plate = plate(1e9, 2, 0.5, 40, 10);
  d.plate.density = 2000.0;
  d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
  d.plate.discontinuities.push_back(circle(PlateDiscontinuity::Kind::hole, 0.6, 0.25, 0.12));
  PlateDiscontinuity crack;
  crack.name = "crack";
  crack.kind = PlateDiscontinuity::Kind::crack;
  crack.shape = PlateDiscontinuity::Shape::polyline;
  crack.points = {{1.33, -0.1}, {1.41, 0.6}};
  d.plate.discontinuities.push_back(crack);
  d.dem.integrator = DemIntegrator::symplectic_euler;
  d.dem.gravity = {0.0, -9.81};
  d.dem.damping_ratio = 0.2;
  d.dem.friction = 0.5;
  d.dem.tangential_stiffness_ratio = 0.8;
  for (int k = 0; k < n; ++k) {
    const int i = k % 70, j = k / 70;
    d.dem.particles.push_back(
        disk(0.5, 0.008, 1e5, 0.11 + 0.0255 * i + 0.003 * (j % 2), 0.5082 + 0.017 * j, 0.0, 0.0));
  }
  d.dem_substeps = 10;
  return d;
}

/// A heavy disk (49.55 kg, r = 0.14 m, k = 2.1e5 N/m, ζ = 0.7) set at its
/// static overlap m g / k on the top of a soft plate (1.835 m × 0.993 m, 4 × 6
/// cells, E = 2.9e7 Pa, ν = 0.135, ρ = 2789, Newmark β = 0.49, γ = 0.9: the
/// plate comes to rest) held at its bottom, centred at x; frictionless unless
/// the caller adds friction; dt = 1.6e-3 s, 10 substeps. A node of the top
/// every L/4, so x = L/2 is its centre node and L/4 a node off the centre.
inline Coupled2dDesc disk_resting_on_soft_plate(DemIntegrator integrator, double x) {
  constexpr double L = 1.8352577124736102, H = 0.992878970453352;
  const double m = 49.55, r = 0.14, k = 2.1e5, g = 9.81;
  Coupled2dDesc d;
  d.plate = plate(2.9e7, L, H, 4, 6);
  d.plate.poisson_ratio = 0.135;
  d.plate.density = 2789.0;
  d.plate.beta = 0.49, d.plate.gamma = 0.9;
  d.plate.dt = 1.6e-3;
  d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
  d.dem.integrator = integrator;
  d.dem.damping_ratio = 0.7;
  d.dem.gravity = {0.0, -g};
  d.dem.particles.push_back(disk(m, r, k, x, H + r - m * g / k, 0.0, 0.0));
  d.dem_substeps = 10;
  return d;
}

/// Total linear momentum along `axis`: the plate's and the disks'.
inline double total_momentum(const Coupled2dModel& m, const Coupled2dState& s, int axis) {
  double p = plate_momentum(m.plate, s.plate, axis);
  for (std::int32_t i = 0; i < m.dem.n; ++i) p += m.dem.mass[i] * s.dem.v[axis][i];
  return p;
}

}  // namespace xfdem::testing
