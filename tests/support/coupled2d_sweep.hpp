// Randomized coupled 2D scenes for the window's sweep
// (tests/coupling/coupled2d_sweep_test.cpp, tests/long/coupled2d_long_test.cpp):
// each variant drawn from a fixed seed, over wide ranges, run for a number of
// plate steps while its books are checked after every step.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "support/coupled2d_scenes.hpp"
#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"

namespace xfdem::testing {

/// splitmix64: the same numbers on every platform (std's distributions are not).
struct SweepRandom {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double a, double b) { return a + (b - a) * static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  int integer(int a, int b) { return a + static_cast<int>(next() % static_cast<std::uint64_t>(b - a + 1)); }
  bool coin(double p) { return uniform(0, 1) < p; }
};

struct SweepVariant {
  Coupled2dDesc desc;
  bool free_plate = false;  ///< no supports, no gravity: total momentum is kept
  bool undamped = false;    ///< ζ = 0 (and frictionless): nothing takes energy out
  int steps = 0;
};

/// Variant `index` of the sweep with seed `seed`: a plate of 1 to 12 × 1 to 6
/// cells, E from 1e7 to 1e11 Pa (log-uniform), free (no gravity) or held at
/// its bottom (under gravity), a circular void (possibly through its top) and
/// a free crack from its top, in some variants; 1 to `max_disks` disks of
/// 0.1–5 kg, r = 1–5 % of the plate's width, k = 1e4–1e7 N/m, in rows above
/// the top (and for a free plate also below its bottom), 0–2 mm from it,
/// moving at it at 0.1–3 m/s; ζ = 0 in a third of them, else 0–0.3; every
/// frictionless integrator; 1 to 20 substeps. time.dt is 1e-4 s, or shorter
/// where the coupled stable-step rule asks (build_coupled2d's refusal).
inline SweepVariant sweep_variant(std::uint64_t seed, int index, int max_disks) {
  SweepRandom r{seed * 0x100000001B3ull + static_cast<std::uint64_t>(index)};
  SweepVariant v;
  Coupled2dDesc& d = v.desc;
  const double lx = r.uniform(0.5, 2.0), ly = r.uniform(0.2, 1.0);
  d.plate = plate(r.log_uniform(1e7, 1e11), lx, ly, r.integer(1, 12), r.integer(1, 6));
  d.plate.density = r.uniform(1000, 8000);
  v.free_plate = r.coin(0.5);
  if (!v.free_plate) {
    d.plate.supports.push_back({PlateEdge::bottom, {true, true}, false});
    d.dem.gravity = {0.0, -9.81};
  }
  if (r.coin(0.5)) {
    // Drawn in this order (radius, x, y), so each seed keeps its scene.
    const double radius = r.uniform(0.1, 0.3) * std::min(lx, ly);
    const double x = r.uniform(0.25, 0.75) * lx;
    const double y = r.uniform(0.35, 1.05) * ly;  // above 1 - r/ly: a notch in the top
    d.plate.discontinuities.push_back(circle(PlateDiscontinuity::Kind::hole, x, y, radius));
  }
  if (r.coin(0.4)) {
    PlateDiscontinuity crack;
    crack.name = "crack";
    crack.kind = PlateDiscontinuity::Kind::crack;
    crack.shape = PlateDiscontinuity::Shape::polyline;
    const double x = r.uniform(0.1, 0.9) * lx;
    crack.points = {{x + r.uniform(-0.1, 0.1) * lx, r.coin(0.5) ? -0.2 * ly : r.uniform(0.3, 0.7) * ly},
                    {x, 1.2 * ly}};
    d.plate.discontinuities.push_back(crack);
  }
  static constexpr DemIntegrator kIntegrators[] = {DemIntegrator::abm4, DemIntegrator::rk4, DemIntegrator::verlet,
                                                   DemIntegrator::symplectic_euler};
  d.dem.integrator = kIntegrators[r.integer(0, 3)];
  v.undamped = r.coin(1.0 / 3.0);
  d.dem.damping_ratio = v.undamped ? 0.0 : r.uniform(0.0, 0.3);
  d.dem_substeps = r.integer(1, 20);
  const int n = r.integer(1, max_disks);
  const double rmax = r.uniform(0.01, 0.05) * lx;
  const double spacing = 2.2 * rmax, speed = r.uniform(0.1, 3.0);
  const int per_row = std::max(1, static_cast<int>((lx - spacing) / spacing));
  for (int k = 0; k < n; ++k) {
    const double radius = r.uniform(0.5, 1.0) * rmax;
    const int row = k / per_row, col = k % per_row;
    // A free plate also takes every third disk from below.
    const bool below = v.free_plate && k % 3 == 2;
    const double gap = r.uniform(0.0, 2e-3);
    const double x = 0.5 * spacing + col * spacing + r.uniform(-0.05, 0.05) * rmax;
    const double y = below ? -(radius + gap + row * spacing) : ly + radius + gap + row * spacing;
    const double vy = (below ? 1.0 : -1.0) * speed * r.uniform(0.5, 1.0);
    d.dem.particles.push_back(
        disk(r.log_uniform(0.1, 5.0), radius, r.log_uniform(1e4, 1e7), x, y, r.uniform(-0.2, 0.2) * speed, vy));
  }
  v.steps = r.integer(100, 300);
  return v;
}

/// Builds the variant, shortening time.dt (from 1e-4 s) to 0.9 of what the
/// coupled stable-step rule allows where it refuses; false if it still does not build.
inline bool build_sweep_variant(SweepVariant& v, Coupled2dWorld& w) {
  BuildResult r = w.build(v.desc);
  for (int attempt = 0; attempt < 6 && r.code == BuildResult::Code::unstable_time_step; ++attempt) {
    const double omega = w.model.coupling_omega;
    const double factor = dem_stable_step_factor(v.desc.dem.integrator, v.desc.dem.damping_ratio);
    double dt = 0.5 * v.desc.plate.dt;
    if (omega > 0) dt = std::min(dt, 0.9 * std::min(factor * v.desc.dem_substeps, kCoupledMaxOmegaDt) / omega);
    v.desc.plate.dt = dt;
    r = w.build(v.desc);
  }
  if (!r.ok()) std::printf("  not built: %s\n", r.message);
  return r.ok();
}

/// The scene's energy: the disks' (dem_energy: kinetic, potential, their
/// pair contacts' elastic), their contacts' ½ k δ² with the boundary, and the
/// plate's algorithmic (Newmark) energy; `touching` whether any contact is
/// closed.
inline double sweep_energy(const Coupled2dWorld& w, std::vector<double>& positions, bool& touching) {
  const Coupled2dModel& m = w.model;
  const Coupled2dState& s = w.state;
  plate_boundary_positions(m.plate, m.boundary, s.plate.u.data(), s.plate.time, positions.data());
  const DemEnergy d = dem_energy(m.dem, s.dem);
  double e = plate_algorithmic_energy(m.plate, s.plate) + d.kinetic + d.elastic + d.potential;
  touching = d.elastic > 0;
  for (std::int32_t i = 0; i < m.dem.n; ++i) {
    const double centre[2] = {s.dem.x[0][i], s.dem.x[1][i]};
    PlateBoundaryContact contacts[kPlateBoundaryMaxContacts];
    const int count = plate_boundary_contacts(m.boundary, positions.data(), centre, m.dem.radius[i], contacts);
    for (int c = 0; c < count; ++c) e += 0.5 * m.dem.stiffness[i] * contacts[c].overlap * contacts[c].overlap;
    touching = touching || count > 0;
  }
  return e;
}

}  // namespace xfdem::testing
