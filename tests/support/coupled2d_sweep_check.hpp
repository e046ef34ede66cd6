// The sweep's run and checks (tests/coupling/coupled2d_sweep_test.cpp and
// tests/long/coupled2d_long_test.cpp): see run_sweep.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/coupled2d_sweep.hpp"

namespace xfdem::testing {

/// Runs `count` variants of seed `seed` (up to `max_disks` disks each) and
/// checks after every step:
///  - the step says ok: no coupling_unstable, nothing else;
///  - a free plate (no gravity, no supports): the disks' momentum change plus
///    the impulse the plate received (the exchange's books) within 1e-13 of
///    the exchange, and the total momentum (the plate's ∫ρv, whose Newmark
///    solves add their round-off) within 1e-10 of Σ m|v| of its start;
///  - symplectic Euler, verlet or rk4, cut plates too: the exchange creates
///    no energy: the plate's work f̄·Δu minus the disks' work on the
///    boundary it saw, Σ −h F·V, within 1e-9 of Σ|W| (the window's
///    tolerance, 1e-10 of the force, with a margin). On a segment of a cut
///    or enriched cell the force goes to the segment's ends, which the
///    contact point moves with (plate_boundary_material_points). Printed
///    only with abm4 (its corrector weighs evaluations of the last window,
///    which saw that window's boundary motion: the books balance over the
///    run, not step by step);
///  - undamped, with rk4 or abm4: the scene's energy at contact-free
///    instants (nothing stored in any contact) never above its start by more
///    than 1e-12 of it. Verlet's and symplectic Euler's are printed only:
///    their own contacts, between disks too, gain or lose O(h²) and O(h) of
///    their energy when they close and open inside a substep (the DEM's,
///    with or without the plate).
inline void run_sweep(std::uint64_t seed, int count, int max_disks) {
  int built = 0, energy_checked = 0, momentum_checked = 0, work_checked = 0;
  long long blended = 0, windows = 0;
  int peak_passes = 0;
  double worst_work = 0, worst_momentum = 0, worst_rise = 0, worst_books = 0;
  for (int index = 0; index < count; ++index) {
    SweepVariant v = sweep_variant(seed, index, max_disks);
    Coupled2dWorld w;
    if (!build_sweep_variant(v, w)) continue;
    ++built;
    const Coupled2dDesc& d = v.desc;
    std::vector<double> positions(2 * w.model.boundary.vertices.size());
    bool touching = false;
    const double e0 = sweep_energy(w, positions, touching);
    double scale = 0;
    for (std::int32_t i = 0; i < w.model.dem.n; ++i)
      scale += w.model.dem.mass[i] * std::hypot(w.state.dem.v[0][i], w.state.dem.v[1][i]);
    const double p0[2] = {total_momentum(w.model, w.state, 0), total_momentum(w.model, w.state, 1)};
    double work_scale = 0, variant_work = 0, drift = 0, rise = -INFINITY, books = 0, exchange = 0;
    double disks0[2] = {0, 0};
    for (std::int32_t i = 0; i < w.model.dem.n; ++i)
      for (int axis = 0; axis < 2; ++axis) disks0[axis] += w.model.dem.mass[i] * w.state.dem.v[axis][i];
    bool hit = false;
    for (int step = 0; step < v.steps; ++step) {
      const double before[2] = {w.state.work_on_plate, w.state.work_by_particles};
      const StepStatus s = w.step();
      char said[256];
      ASSERT_EQ(s, StepStatus::ok) << "variant " << index << " step " << step << ": " << describe(s, said, sizeof(said));
      const double on_plate = w.state.work_on_plate - before[0], by_disks = w.state.work_by_particles - before[1];
      variant_work = std::max(variant_work, std::fabs(on_plate - by_disks));
      work_scale += std::fabs(on_plate);
      hit = hit || w.state.impulse_to_particles[0] != 0.0 || w.state.impulse_to_particles[1] != 0.0;
      if (v.free_plate)
        for (int axis = 0; axis < 2; ++axis) {
          drift = std::max(drift, std::fabs(total_momentum(w.model, w.state, axis) - p0[axis]));
          double disks = 0;
          for (std::int32_t i = 0; i < w.model.dem.n; ++i) disks += w.model.dem.mass[i] * w.state.dem.v[axis][i];
          books = std::max(books, std::fabs(disks - disks0[axis] + w.state.impulse_to_plate[axis]));
          exchange = std::max(exchange, std::fabs(w.state.impulse_to_plate[axis]));
        }
      if (v.undamped) {
        const double e = sweep_energy(w, positions, touching);
        if (!touching) rise = std::max(rise, e - e0);
      }
    }
    EXPECT_TRUE(hit) << "variant " << index << ": no disk reached the plate";
    if (d.dem.integrator != DemIntegrator::abm4) {
      ++work_checked;
      EXPECT_LE(variant_work, 1e-9 * work_scale) << "variant " << index;
      worst_work = std::max(worst_work, work_scale > 0 ? variant_work / work_scale : 0.0);
    }
    if (v.free_plate) {
      ++momentum_checked;
      EXPECT_LE(books, 1e-13 * exchange) << "variant " << index;
      EXPECT_LE(drift, 1e-10 * scale) << "variant " << index;
      worst_books = std::max(worst_books, exchange > 0 ? books / exchange : 0.0);
      worst_momentum = std::max(worst_momentum, drift / scale);
    }
    if (v.undamped && rise > -INFINITY &&
        (d.dem.integrator == DemIntegrator::rk4 || d.dem.integrator == DemIntegrator::abm4)) {
      ++energy_checked;
      EXPECT_LE(rise, 1e-12 * e0) << "variant " << index;
      worst_rise = std::max(worst_rise, rise / e0);
    }
    blended += w.state.blended_windows;
    windows += w.state.step;
    peak_passes = std::max(peak_passes, static_cast<int>(w.state.peak_passes));
    std::printf("  variant %2d: %-16s %2d disks, %2d substeps, dt %.2g s, E %.2g Pa, zeta %.2f, %s%s%s: %d steps, "
                "peak passes %d, blended windows %lld, work %.2g of %.2g J, books %.2g of %.2g N s, momentum drift %.2g "
                "of %.2g, energy rise %.2g of %.3g J\n",
                index, integrator_name(d.dem.integrator), w.model.dem.n, d.dem_substeps, d.plate.dt,
                d.plate.youngs_modulus, d.dem.damping_ratio, v.free_plate ? "free" : "held",
                d.plate.discontinuities.empty() ? "" : ", cut", v.undamped ? ", undamped" : "", v.steps,
                w.state.peak_passes, static_cast<long long>(w.state.blended_windows), variant_work, work_scale,
                books, exchange, drift, scale, rise > -INFINITY ? rise : 0.0, e0);
  }
  std::printf("sweep %llu: %d of %d variants built; %lld windows, %lld blended across a jump, peak passes %d; "
              "worst exchange work %.2g of sum |W| (%d plates, not abm4), books %.2g of the exchange and momentum drift "
              "%.2g of sum m|v| (%d free plates), energy rise %.2g of E0 at contact-free instants (%d undamped, rk4 "
              "and abm4)\n",
              static_cast<unsigned long long>(seed), built, count, windows, blended, peak_passes, worst_work,
              work_checked, worst_books, worst_momentum, momentum_checked, worst_rise, energy_checked);
  EXPECT_GE(built, count * 9 / 10);
}

}  // namespace xfdem::testing
