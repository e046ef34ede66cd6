#include "scene/scene_world.hpp"

#include <string>
#include <variant>

#include "xfdem/coupled.hpp"
#include "xfdem/coupled2d.hpp"

namespace xfdem::scene {
namespace {

struct BarWorld {
  BarModel model;
  BarState state;
  BarWorkspace workspace;
  StepStatus step() { return bar_step(model, state, workspace); }
};

struct PlateWorld {
  PlateModel model;
  PlateState state;
  PlateWorkspace workspace;
  StepStatus step() { return plate_step(model, state, workspace); }
};

}  // namespace

struct SceneWorld::Impl {
  std::variant<DemWorld<1>, DemWorld<2>, DemWorld<3>, BarWorld, CoupledWorld, PlateWorld, Coupled2dWorld> world;

  template <class F>
  auto with_state(F&& f) {
    return std::visit([&](auto& w) { return f(w.state, w.model); }, world);
  }
};

SceneWorld::SceneWorld(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  auto& world = impl_->world;
  if (scene.plate && !std::holds_alternative<std::monostate>(scene.dem)) {
    auto& w = world.emplace<Coupled2dWorld>();
    const BuildResult built = w.build(coupled2d_desc(scene));
    if (!built.ok()) throw build_refusal(scene, Built::coupled, built);
  } else if (scene.bar && !std::holds_alternative<std::monostate>(scene.dem)) {
    auto& w = world.emplace<CoupledWorld>();
    const BuildResult built = w.build(coupled_desc(scene));
    if (!built.ok()) throw build_refusal(scene, Built::coupled, built);
  } else if (const auto* d1 = std::get_if<DemDesc<1>>(&scene.dem)) {
    auto& w = world.emplace<DemWorld<1>>();
    if (const BuildResult built = w.build(*d1); !built.ok()) throw build_refusal(scene, Built::dem, built);
  } else if (const auto* d2 = std::get_if<DemDesc<2>>(&scene.dem)) {
    auto& w = world.emplace<DemWorld<2>>();
    if (const BuildResult built = w.build(*d2); !built.ok()) throw build_refusal(scene, Built::dem, built);
  } else if (const auto* d3 = std::get_if<DemDesc<3>>(&scene.dem)) {
    auto& w = world.emplace<DemWorld<3>>();
    if (const BuildResult built = w.build(*d3); !built.ok()) throw build_refusal(scene, Built::dem, built);
  } else if (scene.bar) {
    auto& w = world.emplace<BarWorld>();
    if (const BuildResult built = build_bar(*scene.bar, w.model, w.state, w.workspace); !built.ok())
      throw build_refusal(scene, Built::continuum, built);
  } else if (scene.plate) {
    auto& w = world.emplace<PlateWorld>();
    if (const BuildResult built = build_plate(*scene.plate, w.model, w.state, w.workspace); !built.ok())
      throw build_refusal(scene, Built::continuum, built);
  } else {
    throw SceneError("scene: nothing to run");
  }
}

SceneWorld::~SceneWorld() = default;

StepStatus SceneWorld::step() {
  return std::visit([](auto& w) { return w.step(); }, impl_->world);
}

std::uint64_t SceneWorld::hash() const {
  return impl_->with_state([](const auto& s, const auto&) { return state_hash(s); });
}
std::uint64_t SceneWorld::layout() const {
  return impl_->with_state([](const auto& s, const auto&) { return layout_hash(s); });
}
std::size_t SceneWorld::field_count() const {
  return impl_->with_state([](const auto& s, const auto&) { return xfdem::field_count(s); });
}
std::size_t SceneWorld::field_hashes(std::span<std::uint64_t> out) const {
  return impl_->with_state([&](const auto& s, const auto&) { return xfdem::field_hashes(s, out); });
}
const char* SceneWorld::field_name(std::size_t k, char* buffer, int buffer_size) const {
  return impl_->with_state([&](const auto& s, const auto&) { return xfdem::field_name(s, k, buffer, buffer_size); });
}
std::uint64_t SceneWorld::model_tag() const {
  return impl_->with_state([](const auto&, const auto& m) { return model_fingerprint(m); });
}
std::size_t SceneWorld::snapshot_size() const {
  return impl_->with_state([](const auto& s, const auto&) { return xfdem::snapshot_size(s); });
}
SnapshotResult SceneWorld::save(std::span<std::byte> buffer) const {
  return impl_->with_state([&](const auto& s, const auto& m) { return save_snapshot(s, buffer, model_fingerprint(m)); });
}
SnapshotResult SceneWorld::restore(std::span<const std::byte> buffer) {
  return impl_->with_state([&](auto& s, const auto& m) { return restore_snapshot(s, buffer, model_fingerprint(m)); });
}

}  // namespace xfdem::scene
