// The dense settled 3D packing shared by the packing benchmarks (bm_dem.cpp)
// and xfdem_packing_export (the same packing written out for other codes, e.g.
// tools/bench_liggghts.py): one generator, so every program times the same
// spheres.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <vector>

#include "xfdem/dem.hpp"

namespace xfdem_bench {

using namespace xfdem;

inline void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "dem packing: %s\n", what);
    std::abort();
  }
}

// Glass-bead-like spheres: r = 1 mm, 2500 kg/m³, k = 2000 N/m (a pair spring of
// 1000 N/m: the weight of a 9 cm column compresses a contact by ~0.5 % of r).
constexpr double kRadius = 1e-3;
constexpr double kDensity = 2500.0;
constexpr double kStiffness = 2000.0;
constexpr double kGravity = -9.81;
inline const double kMass = 4.0 / 3.0 * 3.14159265358979323846 * kRadius * kRadius * kRadius * kDensity;

/// Deterministic uniform [0, 1) (splitmix64): the packing is the same on every machine.
struct Random {
  std::uint64_t s;
  double uniform() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

struct Packing {
  std::vector<std::array<double, 3>> position;  ///< in grid-cell order (see below)
  double side = 0;                              ///< box side in x and y (m)
  double top = 0;                               ///< height of the lid (m)
};

/// Builds `desc` once to learn the integrator's single-contact stable step,
/// then again with dt = fraction of it; desc.dt is that step on return.
inline void build_at_stable_fraction(DemDesc<3>& desc, double fraction, DemModel<3>& model, DemState<3>& state,
                                     DemWorkspace<3>& work) {
  desc.dt = 1.0;
  desc.reject_unstable_dt = false;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");
  desc.dt = fraction * model.stable_dt;
  desc.reject_unstable_dt = true;
  require(build_dem(desc, model, state, work).ok(), "packing: build failed");
}

inline DemDesc<3> packing_desc(const std::vector<std::array<double, 3>>& position, double side, double top) {
  DemDesc<3> desc;
  desc.particles.reserve(position.size());
  for (const auto& p : position)
    desc.particles.push_back({.mass = kMass, .radius = kRadius, .stiffness = kStiffness, .position = p, .velocity = {}});
  desc.planes = {{.point = {0, 0, 0}, .normal = {1, 0, 0}},    {.point = {side, 0, 0}, .normal = {-1, 0, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 1, 0}},    {.point = {0, side, 0}, .normal = {0, -1, 0}},
                 {.point = {0, 0, 0}, .normal = {0, 0, 1}},    {.point = {0, 0, top}, .normal = {0, 0, -1}}};
  desc.gravity = {0, 0, kGravity};
  return desc;
}

/// Settles N spheres from a loose jittered lattice under gravity with the
/// kernel itself (Verlet, heavy contact damping, kinetic energy bled off every
/// few steps), then sorts them in grid-cell order so that neighbours in space
/// are neighbours in memory (the kernel keeps the caller's particle order).
/// Built once per N and process.
inline const Packing& packing(std::int32_t n) {
  static std::map<std::int32_t, Packing> cache;
  if (auto it = cache.find(n); it != cache.end()) return it->second;

  const double spacing = 2.2 * kRadius;
  const auto per_side = static_cast<std::int32_t>(std::ceil(std::cbrt(static_cast<double>(n)) * 0.9));
  const std::int32_t layers = (n + per_side * per_side - 1) / (per_side * per_side);
  Packing pk;
  pk.side = per_side * spacing;
  pk.top = (layers + 1) * spacing;
  std::vector<std::array<double, 3>> start;
  Random random{0x5eedull + static_cast<std::uint64_t>(n)};
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t ix = k % per_side, iy = (k / per_side) % per_side, iz = k / (per_side * per_side);
    std::array<double, 3> p{(ix + 0.5) * spacing, (iy + 0.5) * spacing, (iz + 0.5) * spacing};
    for (auto& c : p) c += 0.08 * kRadius * (2.0 * random.uniform() - 1.0);
    start.push_back(p);
  }
  DemDesc<3> desc = packing_desc(start, pk.side, pk.top);
  desc.damping_ratio = 0.5;
  desc.integrator = DemIntegrator::verlet;
  DemModel<3> model;
  DemState<3> state;
  DemWorkspace<3> work;
  build_at_stable_fraction(desc, 0.5, model, state, work);

  // Fall under gravity with contact damping only, then bleed off what is left
  // of the kinetic energy (velocities halved every 25 steps).
  const double fall = std::sqrt(2.0 * 0.5 * pk.top / -kGravity);  // generous: half the height
  const auto fall_steps = static_cast<std::int64_t>(1.5 * fall / desc.dt);
  const auto quench_steps = static_cast<std::int64_t>(0.1 / desc.dt);
  for (std::int64_t k = 0; k < fall_steps + quench_steps; ++k) {
    require(!has(dem_step(model, state, work), kStepNotTaken | StepStatus::non_finite), "packing: settle step");
    if (k >= fall_steps && k % 25 == 24)
      for (auto& column : state.v)
        for (double& v : column) v *= 0.5;
  }
  // Cell order: z layers of one diameter, then y rows, then x.
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const double cell = 2.0 * kRadius;
  auto key = [&](std::int32_t i) {
    const auto cx = static_cast<std::int64_t>(state.x[0][i] / cell);
    const auto cy = static_cast<std::int64_t>(state.x[1][i] / cell);
    const auto cz = static_cast<std::int64_t>(state.x[2][i] / cell);
    return (cz * 4096 + cy) * 4096 + cx;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) { return key(a) < key(b); });
  for (std::int32_t i : order) pk.position.push_back({state.x[0][i], state.x[1][i], state.x[2][i]});
  return cache.emplace(n, std::move(pk)).first->second;
}

/// Overlapping particle pairs ×2 plus wall contacts, per particle.
inline double contacts_per_particle(const DemModel<3>& model, const DemState<3>& state) {
  std::int64_t ends = 0;
  for (std::int32_t c = 0; c < state.pair_count; ++c) {
    const std::int32_t i = state.pair_i[c], j = state.pair_j[c];
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += (state.x[d][j] - state.x[d][i]) * (state.x[d][j] - state.x[d][i]);
    const double reach = model.radius[i] + model.radius[j];
    if (d2 < reach * reach) ends += 2;
  }
  for (std::size_t p = 0; p < model.plane_point.size(); ++p)
    for (std::int32_t i = 0; i < model.n; ++i) {
      double gap = 0;
      for (int d = 0; d < 3; ++d) gap += (state.x[d][i] - model.plane_point[p][d]) * model.plane_normal[p][d];
      if (gap < model.radius[i]) ++ends;
    }
  return static_cast<double>(ends) / model.n;
}

/// Whether this kernel has Coulomb friction (DemDesc::friction and the
/// tangential spring's stiffness ratio): the frictional packing rows exist
/// only then.
template <class Desc>
constexpr bool kHasFriction = requires(Desc d) {
  d.friction = 0.0;
  d.tangential_stiffness_ratio = 0.0;
};

/// The frictional packing: μ = 0.5, k_t / k_n = 2/7 (a sphere's tangential
/// contact oscillation then has the normal one's frequency).
constexpr double kPackingFriction = 0.5;
constexpr double kPackingTangentialRatio = 2.0 / 7.0;

/// Gives a packing run the frictional law; false (nothing set) when the
/// kernel has no friction.
template <class Desc>
bool set_packing_friction(Desc& desc) {
  if constexpr (kHasFriction<Desc>) {
    desc.friction = kPackingFriction;
    desc.tangential_stiffness_ratio = kPackingTangentialRatio;
    return true;
  } else {
    return false;
  }
}

/// The Hertz–Mindlin packing (LIGGGHTS's `model hertz tangential history`):
/// E = 5e7 Pa (soft, so that a contact's stiffness at the packing's overlaps,
/// about a micrometre, is near the linear law's 1000 N/m and dt stays
/// comparable), ν = 0.25 for the spheres and the walls, restitution 0.7,
/// μ = 0.5.
constexpr double kPackingYoungsModulus = 5e7;
constexpr double kPackingPoissonRatio = 0.25;
constexpr double kPackingRestitution = 0.7;

/// Whether this kernel has the hertz law with friction.
template <class Desc>
constexpr bool kHasHertz = kHasFriction<Desc> && requires(Desc d) { d.restitution = 0.0; };

/// Gives a packing run the hertz law with friction (no stiffness, damping
/// ratio or tangential ratio: the law derives them); false (nothing set) when
/// the kernel has no such law.
template <class Desc>
bool set_packing_hertz(Desc& desc) {
  if constexpr (kHasHertz<Desc>) {
    desc.law = ContactLaw::hertz;
    desc.restitution = kPackingRestitution;
    desc.friction = kPackingFriction;
    desc.damping_ratio = 0;
    desc.tangential_stiffness_ratio = 0;
    for (auto& p : desc.particles) {
      p.stiffness = 0;
      p.youngs_modulus = kPackingYoungsModulus;
      p.poisson_ratio = kPackingPoissonRatio;
    }
    for (auto& plane : desc.planes) {
      plane.youngs_modulus = kPackingYoungsModulus;
      plane.poisson_ratio = kPackingPoissonRatio;
    }
    return true;
  } else {
    return false;
  }
}

/// The packing as the benchmarks run it: ζ = 0.1, the given integrator and
/// skin (in radii; 0: the kernel's default, half a radius). The caller may
/// change more before build_packing_run().
inline DemDesc<3> packing_run_desc(const Packing& pk, DemIntegrator integrator, double skin_radii) {
  DemDesc<3> desc = packing_desc(pk.position, pk.side, pk.top);
  desc.damping_ratio = 0.1;
  desc.integrator = integrator;
  desc.skin = skin_radii * kRadius;
  return desc;
}

/// Builds `desc` with dt a fifth of the integrator's single-contact stable
/// step (a packed sphere has several contacts and higher frequencies than one
/// contact); desc.dt is that step on return.
inline void build_packing_run(DemDesc<3>& desc, DemModel<3>& model, DemState<3>& state, DemWorkspace<3>& work) {
  build_at_stable_fraction(desc, 0.2, model, state, work);
}

}  // namespace xfdem_bench
