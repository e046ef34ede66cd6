// The retaining-wall demonstration at its end (docs/coupled2d.md,
// "Demonstration", "Its end state"; label `long`): scenes/demo/retaining_wall.json
// read by the scene reader as `xfdem run` reads it and run to its end, t = 1 s
// (10 000 plate steps), unchanged. That end is not a settled state: the bed's
// lowest modes ring, weakly damped by the contacts' dashpots, so the floor's
// force swings by a fifth of the bed's weight, and the wall rings with them.
// What statics requires of a settled state is therefore printed against the
// bodies' momentum rates, and what holds at any instant is asserted, each side
// computed from its own source:
//  - the wall: its supports' reaction (plate_support_reaction, from the
//    plate's stress at the held nodes) plus the disks' force its unknowns
//    received (Coupled2dState::coupling_force) equals its free rows' inertia
//    Σ_f (M a)_f to round-off, component by component (at rest, statics'
//    R = −F); the part of the disks' force (their own account,
//    coupled2d_boundary_force) that fell on held components is at most the
//    forces of the disks that touch the base's cell;
//  - Coulomb: the disks' drag on the wall, the floor's friction and the back
//    plane's, each at most μ times the normal forces of the same contacts;
//  - the thrust on the wall positive;
//  - the crack's opening and stress intensity probes finite, and no window
//    taken at its smallest residual or ended in a blend across a jump.
// Printed: the kinetic energies against Σ m g r, the whole system's vertical
// and horizontal balance (supports, floor, back plane, weight; the wall has
// no self weight in this scene) against the disks' and the wall's momentum
// rates, the thrust's ratio to ½ γ H² against Rankine's active, Jaky's
// at-rest and the passive coefficients for φ = atan μ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "xfdem/coupled2d.hpp"

namespace xfdem {
namespace {

struct Books {
  double disk_kinetic = 0, plate_kinetic = 0;
  double reaction[2] = {0, 0};      ///< the supports' force on the wall (K u at the held rows)
  double received[2] = {0, 0};      ///< the disks' force on the wall's unknowns (coupling_force)
  double disks_on_wall[2] = {0, 0}; ///< −Σ coupled2d_boundary_force
  double floor[2] = {0, 0}, back[2] = {0, 0};  ///< the planes' forces on the disks
  double weight = 0;                 ///< Σ m g
  double base_share_bound = 0;       ///< Σ |F| of the disks that touch the wall's lowest cell
  /// Coulomb: Σ |F_t| and μ Σ |F_n| of the disks' contacts with the wall, the floor, the back plane.
  double wall_t = 0, wall_n = 0, floor_t = 0, floor_n = 0, back_t = 0, back_n = 0;
  double bed_top = 0;                ///< the mean top (y + r) of the 50 highest disks
};

Books books(const Coupled2dWorld& w, const Coupled2dDesc& d, double g, std::int32_t floor, std::int32_t back) {
  Books b;
  const auto& dem = w.state.dem;
  const double cell_y = w.model.plate.cell_size[1];
  for (std::int32_t i = 0; i < w.model.dem.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double m = d.dem.particles[k].mass, r = d.dem.particles[k].radius;
    const double vx = dem.v[0][k], vy = dem.v[1][k], om = dem.w[0][k];
    b.disk_kinetic += 0.5 * m * (vx * vx + vy * vy) + 0.5 * (0.5 * m * r * r) * om * om;
    b.weight += m * g;
    double f[2];
    coupled2d_boundary_force(w.model, w.state, i, f);
    b.disks_on_wall[0] -= f[0], b.disks_on_wall[1] -= f[1];
    if (dem.x[1][k] - r < cell_y) b.base_share_bound += std::hypot(f[0], f[1]);
    // The planes' forces on the disk: N along the plane's normal, and the
    // tangential probe's f_t (on the plane, along t = (−n_y, n_x), n from
    // the disk to the plane) reversed. Floor: normal (0, 1), t = (1, 0);
    // back plane: normal (−1, 0), t = (0, 1).
    const double fn = dem_plane_force(w.model.dem, dem, i, floor), ft = dem_plane_tangential_force(w.model.dem, dem, i, floor);
    const double bn = dem_plane_force(w.model.dem, dem, i, back), bt = dem_plane_tangential_force(w.model.dem, dem, i, back);
    b.floor[1] += fn, b.floor[0] -= ft;
    b.back[0] -= bn, b.back[1] -= bt;
    b.floor_n += std::fabs(fn), b.floor_t += std::fabs(ft), b.back_n += std::fabs(bn), b.back_t += std::fabs(bt);
    // The wall's back face is flat and vertical (x = 0.4 m) where the bed
    // touches it: a disk's force from it is normal along x, tangential along y.
    b.wall_n += std::fabs(f[0]), b.wall_t += std::fabs(f[1]);
  }
  std::vector<double> tops;
  for (std::int32_t i = 0; i < w.model.dem.n; ++i)
    tops.push_back(dem.x[1][static_cast<std::size_t>(i)] + d.dem.particles[static_cast<std::size_t>(i)].radius);
  std::partial_sort(tops.begin(), tops.begin() + 50, tops.end(), std::greater<>());
  for (int k = 0; k < 50; ++k) b.bed_top += tops[static_cast<std::size_t>(k)] / 50.0;
  b.plate_kinetic = plate_energy(w.model.plate, w.state.plate).kinetic;
  plate_support_reaction(w.model.plate, w.state.plate, b.reaction);
  const PlateModel& p = w.model.plate;
  for (int n = 0; n < p.nodes; ++n)
    for (int c = 0; c < 2; ++c) {
      const int dof = p.node_dof[static_cast<std::size_t>(2 * n + c)];
      if (dof >= 0) b.received[c] += w.state.coupling_force[static_cast<std::size_t>(dof)];
    }
  return b;
}

/// Σ over the free standard unknowns of component c of (M a): the free
/// rows' inertia, as a rigid translation sees it.
double free_inertia(const PlateModel& p, const PlateState& st, int c) {
  std::vector<double> ma(static_cast<std::size_t>(p.dofs), 0.0);
  p.mass.multiply(st.a.data(), ma.data());
  double s = 0;
  for (int n = 0; n < p.nodes; ++n) {
    const int dof = p.node_dof[static_cast<std::size_t>(2 * n + c)];
    if (dof >= 0) s += ma[static_cast<std::size_t>(dof)];
  }
  return s;
}

}  // namespace

TEST(RetainingWallLong, AtItsEndTheWallsSupportsBalanceTheBackfillUpToTheWallsInertia) {
  const std::string file = std::string(XFDEM_SOURCE_DIR) + "/scenes/demo/retaining_wall.json";
  const scene::Scene sc = scene::load_scene(file, {});
  const Coupled2dDesc d = scene::coupled2d_desc(sc);
  auto world = std::make_unique<Coupled2dWorld>();
  Coupled2dWorld& w = *world;
  const BuildResult built = w.build(d);
  ASSERT_TRUE(built.ok()) << built.message;
  const double g = -sc.gravity[1], mu = d.dem.friction;
  std::int32_t floor = -1, back = -1;
  for (std::size_t k = 0; k < sc.plane_names.size(); ++k)
    (sc.plane_names[k] == "floor" ? floor : back) = static_cast<std::int32_t>(k);
  ASSERT_GE(floor, 0);
  ASSERT_GE(back, 0);
  double energy_scale = 0;  // Σ m g r: each disk's weight over its own radius
  for (const auto& p : d.dem.particles) energy_scale += p.mass * g * p.radius;
  const auto start = std::chrono::steady_clock::now();
  double disks_p[2] = {0, 0};
  std::printf("  t (s)   KE disks (J)  KE wall (J)   wall: R + F (N)        system: vertical, horizontal (N)\n");
  for (std::int64_t step = 0; step < sc.steps; ++step) {
    if (step == sc.steps - 1)
      for (int c = 0; c < 2; ++c) disks_p[c] = dem_momentum(w.model.dem, w.state.dem, c);
    char said[256];
    const StepStatus s = w.step();
    ASSERT_EQ(s, StepStatus::ok) << "step " << step << ": " << describe(s, said, sizeof(said));
    if ((step + 1) % 1000 == 0) {
      const Books b = books(w, d, g, floor, back);
      const double held[2] = {b.disks_on_wall[0] - b.received[0], b.disks_on_wall[1] - b.received[1]};
      std::printf("  %.2f   %11.4g  %11.4g   (%9.4g, %9.4g)   %10.4g, %10.4g\n", w.state.time, b.disk_kinetic,
                  b.plate_kinetic, b.reaction[0] + b.received[0], b.reaction[1] + b.received[1],
                  b.reaction[1] - held[1] + b.floor[1] + b.back[1] - b.weight,
                  b.reaction[0] - held[0] + b.floor[0] + b.back[0]);
      std::fflush(stdout);
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Books b = books(w, d, g, floor, back);
  const PlateModel& p = w.model.plate;
  std::printf("%lld steps to t = %.3f s in %.0f s of wall time; peak passes %d, windows blended across a jump %lld, "
              "taken at their smallest residual %lld\n",
              static_cast<long long>(sc.steps), w.state.time, seconds, w.state.peak_passes,
              static_cast<long long>(w.state.blended_windows), static_cast<long long>(w.state.unsettled_windows));
  EXPECT_EQ(w.state.unsettled_windows, 0);
  EXPECT_EQ(w.state.blended_windows, 0);

  // At rest? Printed against Σ m g r (what the disks would gain falling by
  // their own radii); not asserted: the scene's end is not a settled state
  // (docs/coupled2d.md).
  std::printf("kinetic energy: disks %.4g J, wall %.4g J; Σ m g r = %.4g J (ratio %.3g)\n", b.disk_kinetic,
              b.plate_kinetic, energy_scale, (b.disk_kinetic + b.plate_kinetic) / energy_scale);

  // The wall: R + F = Σ_f (M a)_f (its free rows' inertia), since Σ (K u) over
  // all the standard rows of a component is 0 (a translation strains
  // nothing) and the free rows are Newmark's M a + K u = f at t_{n+1}. That
  // is Newton's law for the wall, and the supports' reaction is the statics'
  // R = −F up to the wall's inertia. Round-off: each row's residual a few ε
  // of its terms, at most 64 max |K_ab| max |u| (as
  // PlateStatic.SupportReactionBalancesTheLoads), plus the coupling force's
  // and the inertia's own sums, ε Σ |f|, ε Σ |M a| per row: bound ε × dofs
  // × (64 max |K| max |u| + max |f| + max |M a|).
  double kmax = 0, umax = 0, fmax = 0, mamax = 0;
  for (double x : p.element_stiffness) kmax = std::max(kmax, std::fabs(x));
  for (double x : p.other_cell_matrix) kmax = std::max(kmax, std::fabs(x));
  for (double x : w.state.plate.u) umax = std::max(umax, std::fabs(x));
  for (double x : w.state.coupling_force) fmax = std::max(fmax, std::fabs(x));
  {
    std::vector<double> ma(static_cast<std::size_t>(p.dofs), 0.0);
    p.mass.multiply(w.state.plate.a.data(), ma.data());
    for (double x : ma) mamax = std::max(mamax, std::fabs(x));
  }
  const double roundoff = DBL_EPSILON * p.dofs * (64.0 * kmax * umax + fmax + mamax);
  for (int c = 0; c < 2; ++c) {
    const double inertia = free_inertia(p, w.state.plate, c);
    const double off = b.reaction[c] + b.received[c];
    std::printf("wall %c: supports' reaction %.6g N, the disks' force it received %.6g N: R + F = %.4g N "
                "(%.3g of |F|), its free rows' inertia %.4g N; R + F − inertia %.3g N (round-off bound %.3g N)\n",
                c == 0 ? 'x' : 'y', b.reaction[c], b.received[c], off, std::fabs(off) / std::fabs(b.received[c]),
                inertia, off - inertia, roundoff);
    EXPECT_LE(std::fabs(off - inertia), roundoff);
  }
  // What of the disks' force (their own account) the wall's unknowns did not
  // receive went to held components: contacts on the base's cell only.
  const double held[2] = {b.disks_on_wall[0] - b.received[0], b.disks_on_wall[1] - b.received[1]};
  std::printf("the disks' force on the wall (x, y) = (%.6g, %.6g) N; on held components (%.4g, %.4g) N, the forces "
              "of the disks on the base's cell %.4g N\n",
              b.disks_on_wall[0], b.disks_on_wall[1], held[0], held[1], b.base_share_bound);
  EXPECT_LE(std::hypot(held[0], held[1]), b.base_share_bound * (1.0 + 1e-12) + 1e-9);

  // The whole system, vertical and horizontal: residual = the bodies'
  // momentum rate (printed: the disks' over the last step for comparison).
  const double vertical = b.reaction[1] - held[1] + b.floor[1] + b.back[1] - b.weight;
  const double horizontal = b.reaction[0] - held[0] + b.floor[0] + b.back[0];
  std::printf("system: weight %.6g N; supports' vertical reaction %.6g N, floor %.6g N, back plane %.6g N: "
              "off by %.4g N (%.3g of the weight); horizontal: supports %.6g, back plane %.6g, floor's friction %.6g: "
              "off by %.4g N; the disks' momentum rate over the last step (%.4g, %.4g) N, plus the wall's "
              "inertia (%.4g, %.4g) N\n",
              b.weight, b.reaction[1] - held[1], b.floor[1], b.back[1], vertical, std::fabs(vertical) / b.weight,
              b.reaction[0] - held[0], b.back[0], b.floor[0], horizontal,
              (dem_momentum(w.model.dem, w.state.dem, 0) - disks_p[0]) / w.model.dt,
              (dem_momentum(w.model.dem, w.state.dem, 1) - disks_p[1]) / w.model.dt,
              (dem_momentum(w.model.dem, w.state.dem, 0) - disks_p[0]) / w.model.dt + free_inertia(p, w.state.plate, 0),
              (dem_momentum(w.model.dem, w.state.dem, 1) - disks_p[1]) / w.model.dt + free_inertia(p, w.state.plate, 1));

  // Coulomb at every contact, |F_t| ≤ μ |F_n| (the law's cap), summed.
  std::printf("Coulomb: wall Σ|F_t| %.5g ≤ μ Σ|F_n| %.5g; floor %.5g ≤ %.5g; back plane %.5g ≤ %.5g\n", b.wall_t,
              mu * b.wall_n, b.floor_t, mu * b.floor_n, b.back_t, mu * b.back_n);
  EXPECT_LE(b.wall_t, mu * b.wall_n * (1.0 + 1e-12));
  EXPECT_LE(b.floor_t, mu * b.floor_n * (1.0 + 1e-12));
  EXPECT_LE(b.back_t, mu * b.back_n * (1.0 + 1e-12));

  // The thrust: the disks push the wall towards its front (−x).
  const double thrust = -b.disks_on_wall[0];
  EXPECT_GT(thrust, 0.0);
  const double height = b.bed_top, width = d.dem.planes[static_cast<std::size_t>(back)].point[0] - p.desc.max[0];
  const double unit_weight = b.weight / (width * height);
  const double phi = std::atan(mu), ka = (1 - std::sin(phi)) / (1 + std::sin(phi)), k0 = 1 - std::sin(phi);
  std::printf("thrust %.5g N/m, drag %.5g N/m; bed %.4g m high, unit weight %.4g N/m3: thrust / (γ H²/2) = %.3g "
              "(φ = atan μ = %.2f°: Rankine active %.3f, Jaky at rest %.3f, passive %.3f)\n",
              thrust, -b.disks_on_wall[1], height, unit_weight, thrust / (0.5 * unit_weight * height * height),
              phi * 180 / M_PI, ka, k0, 1 / ka);

  // The crack's probes, as the scene's.
  int probes = 0;
  for (const scene::Probe& pr : sc.probes) {
    double value = 0;
    if (pr.kind == scene::Probe::Kind::plate_crack_opening) {
      value = plate_crack_opening(p, w.state.plate, pr.other, pr.at[0], pr.at[1], pr.component);
    } else if (pr.kind == scene::Probe::Kind::plate_stress_intensity) {
      double k[2];
      plate_stress_intensity(p, w.state.plate, pr.other, pr.tip_end, pr.radius, k);
      value = k[pr.component];
    } else {
      continue;
    }
    ++probes;
    std::printf("%s = %.4g\n", pr.name.c_str(), value);
    EXPECT_TRUE(std::isfinite(value)) << pr.name;
  }
  EXPECT_EQ(probes, 4);
}

}  // namespace xfdem
