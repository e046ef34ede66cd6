// libFuzzer target: arbitrary bytes as a snapshot.
//
// Three fixed small worlds are built once from the project's scenes: V1 (three
// particles in 1D), the V2 bar (FEM, tied interface) and Case II (particles
// coupled to the bar). Each input is offered to every world twice:
//   1. as it is;
//   2. with its header and payload checksums recomputed (when it is long enough
//      to hold a header), so that arbitrary payloads under a well-formed header
//      reach the accept path instead of stopping at the checksum.
// restore_snapshot must either refuse with a status, leaving the state
// untouched (the full-state hash is compared before and after), or accept; an
// accepted state is then stepped a few times, which must not crash, and the
// world is put back to its initial state for the next input.
// Seeds: a valid snapshot of each world (after a few steps), written by
// `snapshot_restore_fuzz -write_seeds=DIR` (tools/fuzz.sh does this).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "scene/scene_world.hpp"
#include "xfdem/state_io.hpp"

namespace {

using namespace xfdem;
using namespace xfdem::scene;

constexpr int kStepsAfterAccept = 5;
constexpr int kWarmUpSteps = 3;  // the seeds are of states a few steps in (history, pairs)

struct Fixed {
  std::string name;
  std::unique_ptr<SceneWorld> world;
  std::vector<std::byte> initial;  // snapshot of the state every input starts from
};

std::vector<Fixed>& worlds() {
  static std::vector<Fixed> all = [] {
    std::vector<Fixed> out;
    for (const char* name : {"v1_k1e4", "v2_fem", "case2_fem"}) {
      const Scene scene = load_scene(std::string(XFDEM_SCENES_DIR) + "/" + name + ".json", {});
      Fixed f{name, std::make_unique<SceneWorld>(scene), {}};
      for (int k = 0; k < kWarmUpSteps; ++k) (void)f.world->step();
      f.initial.resize(f.world->snapshot_size());
      if (!f.world->save(f.initial).ok()) std::abort();
      out.push_back(std::move(f));
    }
    return out;
  }();
  return all;
}

void put_u64(std::byte* at, std::uint64_t v) { std::memcpy(at, &v, 8); }
std::uint64_t get_u64(const std::byte* at) {
  std::uint64_t v;
  std::memcpy(&v, at, 8);
  return v;
}

/// Recomputes the payload checksum (over the bytes present, up to the header's
/// payload size) and then the header checksum.
void fix_checksums(std::vector<std::byte>& b) {
  const std::uint64_t declared = get_u64(b.data() + 40);
  const std::size_t present = b.size() - kSnapshotHeaderBytes;
  const std::size_t n = declared < present ? static_cast<std::size_t>(declared) : present;
  put_u64(b.data() + 48, fnv1a(b.data() + kSnapshotHeaderBytes, n));
  put_u64(b.data() + 56, fnv1a(b.data(), 56));
}

void offer(Fixed& f, std::span<const std::byte> bytes) {
  const std::uint64_t before = f.world->hash();
  const SnapshotResult r = f.world->restore(bytes);
  if (!r.ok()) {
    if (f.world->hash() != before) {
      std::fprintf(stderr, "finding: refused snapshot (%s) changed the %s state\n", snapshot_status_name(r.status),
                   f.name.c_str());
      std::abort();
    }
    return;
  }
  for (int k = 0; k < kStepsAfterAccept; ++k) (void)f.world->step();
  if (!f.world->restore(f.initial).ok()) std::abort();  // back to the start for the next input
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  // -write_seeds=DIR: write one valid snapshot per world into DIR and exit.
  for (int k = 1; k < *argc; ++k) {
    const std::string arg = (*argv)[k];
    if (arg.rfind("-write_seeds=", 0) != 0) continue;
    const std::string dir = arg.substr(13);
    for (Fixed& f : worlds()) {
      const std::string path = dir + "/" + f.name + ".snap";
      std::FILE* file = std::fopen(path.c_str(), "wb");
      if (file == nullptr || std::fwrite(f.initial.data(), 1, f.initial.size(), file) != f.initial.size()) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        std::exit(1);
      }
      std::fclose(file);
      std::printf("wrote %s (%zu bytes)\n", path.c_str(), f.initial.size());
    }
    std::exit(0);
  }
  (void)worlds();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> raw(reinterpret_cast<const std::byte*>(data), size);
  for (Fixed& f : worlds()) offer(f, raw);
  if (size >= kSnapshotHeaderBytes) {
    std::vector<std::byte> fixed(raw.begin(), raw.end());
    fix_checksums(fixed);
    for (Fixed& f : worlds()) offer(f, fixed);
  }
  return 0;
}
