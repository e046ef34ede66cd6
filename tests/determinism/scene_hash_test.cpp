// Run after run: every scene in scenes/ gives the same per-step state hashes 10
// times over (1e4 steps, or to the scene's end if shorter; particles against a
// plate included), and so does a dense 3D packing of ~1e4 spheres; a few
// scenes' final hashes are golden.
#include <gtest/gtest.h>

#include <optional>

#include "xfdem/platform/worker_pool.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "scene/scene_world.hpp"
#include "xfdem/state_io.hpp"

#include "support/sanitizers.hpp"

namespace xfdem {
namespace {

#ifdef XFDEM_UNDER_ASAN
constexpr int kRuns = 3;  // the sanitizer build checks the same thing on fewer runs
#else
constexpr int kRuns = 10;
#endif
constexpr std::int64_t kSteps = 10000;

std::string scene_path(const std::string& file) { return std::string(XFDEM_SOURCE_DIR) + "/scenes/" + file; }

struct SceneRun {
  std::uint64_t final_hash = 0;
  std::uint64_t trajectory = kFnvOffset;  ///< FNV-1a over every step's full-state hash
  std::int64_t steps = 0;
};

SceneRun run_scene(const std::string& file) {
  const scene::Scene sc = scene::load_scene(scene_path(file), {});
  scene::SceneWorld world(sc);
  SceneRun run;
  run.steps = std::min(kSteps, sc.steps);
  auto mix = [&] {
    const std::uint64_t h = world.hash();
    run.trajectory = fnv1a(reinterpret_cast<const std::byte*>(&h), sizeof(h), run.trajectory);
  };
  mix();
  for (std::int64_t s = 0; s < run.steps; ++s) {
    EXPECT_FALSE(has(world.step(), kStepNotTaken)) << file << " step " << s;
    mix();
  }
  run.final_hash = world.hash();
  return run;
}

std::vector<std::string> every_scene() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(XFDEM_SOURCE_DIR) + "/scenes"))
    if (entry.path().extension() == ".json") files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(RunAfterRun, EverySceneHashesTheSameTenTimes) {
  const auto files = every_scene();
  ASSERT_GE(files.size(), 9u);
  for (const auto& file : files) {
    const SceneRun first = run_scene(file);
    for (int r = 1; r < kRuns; ++r) {
      const SceneRun again = run_scene(file);
      EXPECT_EQ(again.trajectory, first.trajectory) << file << ", run " << r;
      EXPECT_EQ(again.final_hash, first.final_hash) << file << ", run " << r;
    }
  }
}

// Golden hashes: the full-state hash after the given steps, in this build's
// configuration (x86-64 baseline, -ffp-contract=off, no fast-math; see
// docs/determinism.md). They change only on a deliberate change of results (a
// force law, an integrator, the order of a sum, a new state field); such a
// change updates them in the same commit and says why.
struct Golden {
  const char* scene;
  std::uint64_t hash;
};
constexpr Golden kGolden[] = {
    {"v1_k1e4.json", 0x4832cc3024c6dd60ull},
    {"v2_xfem.json", 0x100ccb8dbbc44b14ull},
    {"case2_xfem.json", 0xa335aa7076db0072ull},
};

TEST(GoldenHashes, AfterTenThousandStepsOrTheSceneEnd) {
  for (const Golden& g : kGolden) {
    const SceneRun run = run_scene(g.scene);
    EXPECT_EQ(run.final_hash, g.hash) << g.scene << " after " << run.steps << " steps: 0x" << std::hex
                                      << run.final_hash;
  }
}

// ---- a dense 3D packing -------------------------------------------------------------

/// 22 × 22 × 21 = 10 164 spheres on a slightly jittered cubic lattice whose
/// spacing (1.98 r) makes every neighbour overlap, in a box of six planes,
/// under gravity: every sphere has up to six contacts from the first step.
DemDesc<3> packing(DemIntegrator integrator) {
  constexpr double r = 1e-3, spacing = 1.98e-3;
  constexpr int nx = 22, ny = 22, nz = 21;
  DemDesc<3> d;
  d.gravity = {0, 0, -9.81};
  d.damping_ratio = 0.2;
  d.integrator = integrator;
  std::uint64_t s = 0x5eedull;
  auto jitter = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return (static_cast<double>(s >> 11) * 0x1.0p-53 - 0.5) * 0.02 * r;
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        d.particles.push_back({.mass = 1e-5,
                               .radius = r,
                               .stiffness = 2000.0,
                               .position = {r + i * spacing + jitter(), r + j * spacing + jitter(),
                                            r + k * spacing + jitter()},
                               .velocity = {}});
  const double sx = 2 * r + (nx - 1) * spacing, sy = 2 * r + (ny - 1) * spacing, sz = 2 * r + nz * spacing;
  d.planes = {{.point = {0, 0, 0}, .normal = {1, 0, 0}},  {.point = {sx, 0, 0}, .normal = {-1, 0, 0}},
              {.point = {0, 0, 0}, .normal = {0, 1, 0}},  {.point = {0, sy, 0}, .normal = {0, -1, 0}},
              {.point = {0, 0, 0}, .normal = {0, 0, 1}},  {.point = {0, 0, sz}, .normal = {0, 0, -1}}};
  DemModel<3> m;
  DemState<3> st;
  DemWorkspace<3> w;
  d.dt = 1.0;
  d.reject_unstable_dt = false;
  EXPECT_TRUE(build_dem(d, m, st, w).ok());
  // 0.35 of the single contact's stable step: the packing settles into ~8
  // contacts per sphere, whose network bound (DemState::network_omega2) is 4×
  // the single contact's ω², i.e. the network's limit sits at 0.5.
  d.dt = 0.35 * m.stable_dt;
  d.reject_unstable_dt = true;
  return d;
}

TEST(RunAfterRun, ADensePackingOfTenThousandSpheres) {
#ifdef XFDEM_UNDER_ASAN
  constexpr int runs = 2, steps = 40;
#else
  constexpr int runs = kRuns, steps = 300;
#endif
  for (DemIntegrator integrator : {DemIntegrator::verlet, DemIntegrator::abm4}) {
    const DemDesc<3> desc = packing(integrator);
    ASSERT_GT(desc.particles.size(), 10000u);
    std::uint64_t first = 0;
    for (int r = 0; r < runs; ++r) {
      DemWorld<3> world;
      ASSERT_TRUE(world.build(desc).ok());
      ASSERT_EQ(world.model.parts, 2) << "the packing is split into two parts";
      // Odd runs on two workers: the hash must not depend on it.
      std::optional<platform::TwoWorkerPool> pool;
      if (r % 2 == 1) {
        pool.emplace();
        world.workspace.parallel = pool->parallel_for();
      }
      for (int s = 0; s < steps; ++s) ASSERT_EQ(world.step(), StepStatus::ok) << integrator_name(integrator) << " step " << s;
      ASSERT_GT(world.state.pair_count, 20000) << "the packing is dense";
      const std::uint64_t h = state_hash(world.state);
      if (r == 0)
        first = h;
      else
        EXPECT_EQ(h, first) << integrator_name(integrator) << ", run " << r << (r % 2 ? " (two workers)" : " (one worker)");
    }
  }
}

}  // namespace
}  // namespace xfdem
