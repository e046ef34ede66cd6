// One world built from a loaded scene, whatever it holds (particles in 1, 2 or
// 3 D, a bar or a plate, or particles coupled to either), with the state-io calls of xfdem/state_io.hpp
// behind one interface. Used by `xfdem replay` and the determinism tests.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "scene/scene.hpp"
#include "xfdem/state_io.hpp"

namespace xfdem::scene {

class SceneWorld {
 public:
  /// Builds the scene's models and states; throws SceneError naming the key on
  /// a build failure (as run_scene does).
  explicit SceneWorld(const Scene& scene);
  ~SceneWorld();
  SceneWorld(const SceneWorld&) = delete;
  SceneWorld& operator=(const SceneWorld&) = delete;

  /// One step of the scene's dt (a coupled step with its particle substeps).
  StepStatus step();

  std::uint64_t hash() const;
  std::uint64_t layout() const;
  std::size_t field_count() const;
  std::size_t field_hashes(std::span<std::uint64_t> out) const;
  const char* field_name(std::size_t k, char* buffer, int buffer_size) const;
  /// model_fingerprint() of the world's model: the tag its snapshots carry.
  std::uint64_t model_tag() const;

  std::size_t snapshot_size() const;
  SnapshotResult save(std::span<std::byte> buffer) const;
  SnapshotResult restore(std::span<const std::byte> buffer);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace xfdem::scene
