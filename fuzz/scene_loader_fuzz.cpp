// libFuzzer target: arbitrary bytes as a scene file.
//
// The bytes are parsed as JSON (comments allowed, as load_scene does); a parse
// error, or a key given twice in an object, is an ordinary refusal. A document is then validated by parse_scene,
// whose refusals are SceneError. A scene that loads and is small enough to step
// quickly (see the bounds below) is built into its world and stepped a few
// times; a build refusal is a SceneError too, and a step may report any status.
// Anything else (another exception, a crash, a hang, a sanitizer report) is a
// finding. Seeds: the scenes under scenes/ (tools/fuzz.sh copies them).
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>

#include "scene/scene.hpp"
#include "scene/scene_world.hpp"

namespace {

using namespace xfdem::scene;

// Bounds on what is built and stepped, so one input stays fast. Inputs above
// them are parsed and validated only.
constexpr std::size_t kMaxParticles = 64;
constexpr int kMaxElements = 200;
constexpr int kMaxSubsteps = 64;
constexpr std::int64_t kMaxCapacity = 1 << 16;
constexpr std::int64_t kMaxSteps = 50;

template <int D>
bool small_dem(const xfdem::DemDesc<D>& d) {
  const auto& c = d.capacities;
  return d.particles.size() <= kMaxParticles && d.planes.size() <= kMaxParticles && c.max_pairs <= kMaxCapacity &&
         c.max_grid_cells <= kMaxCapacity && c.max_neighbors_per_particle <= kMaxCapacity &&
         c.max_events_per_step <= kMaxCapacity;
}

bool small_enough(const Scene& s) {
  if (s.bar && s.bar->elements > kMaxElements) return false;
  if (s.dem_substeps > kMaxSubsteps) return false;
  return std::visit(
      [](const auto& d) {
        if constexpr (std::is_same_v<std::decay_t<decltype(d)>, std::monostate>) {
          return true;
        } else {
          return small_dem(d);
        }
      },
      s.dem);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Json document;
  try {
    document = parse_json(std::string(reinterpret_cast<const char*>(data), size), "", /*ignore_comments=*/true);
  } catch (const Json::exception&) {
    return 0;  // not JSON: refused before the loader sees it
  } catch (const SceneError&) {
    return 0;  // a key given twice, named
  }
  Scene scene;
  try {
    scene = parse_scene(document);
  } catch (const SceneError&) {
    return 0;  // refused, naming the key
  }
  if (!small_enough(scene)) return 0;
  try {
    SceneWorld world(scene);
    const std::int64_t steps = scene.steps < kMaxSteps ? scene.steps : kMaxSteps;
    for (std::int64_t k = 0; k < steps; ++k) (void)world.step();
  } catch (const SceneError&) {
    return 0;  // the kernel refused to build it; the message names the key
  }
  return 0;
}
