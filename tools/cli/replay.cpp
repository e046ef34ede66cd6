// xfdem replay: record the per-step state hashes of a run, and check a re-run
// against them, naming the first step and the first field that differ.
//
//   xfdem replay record SCENE.json [--set KEY=VALUE ...] [--steps N] --out RUN.hashes
//   xfdem replay check  SCENE.json [--set KEY=VALUE ...] [--steps N] --against RUN.hashes
//
// A .hashes file (little-endian, docs/determinism.md):
//   "XFDEMHSH", u32 format version (1), u32 field count F, u64 layout hash,
//   u64 model tag, u64 steps N, the scene name and the F field names (each
//   NUL-terminated), then N + 1 records (step 0 = the built state, then after
//   every step): u64 full-state hash, F × u32 field hashes (the low 32 bits of
//   each field's FNV-1a). Exit codes: 0 identical / recorded, 1 a difference,
//   2 bad input, 3 a step status (record only).
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/stage.hpp"
#include "scene/scene.hpp"
#include "scene/scene_world.hpp"

namespace {

using xfdem::scene::SceneError;

constexpr char kMagic[8] = {'X', 'F', 'D', 'E', 'M', 'H', 'S', 'H'};
constexpr std::uint32_t kFormat = 1;

struct Options {
  std::string mode, scene_path, file;
  std::vector<std::string> overrides;
  std::int64_t steps = -1;
};

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 3) throw SceneError("replay: give 'record' or 'check'");
  o.mode = argv[2];
  if (o.mode != "record" && o.mode != "check")
    throw SceneError("replay: unknown mode '" + o.mode + "' (use 'record' or 'check')");
  const std::string file_flag = o.mode == "record" ? "--out" : "--against";
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const std::string& flag) -> std::string {
      if (i + 1 >= argc) throw SceneError(flag + ": missing value");
      return argv[++i];
    };
    if (arg == "--set") {
      o.overrides.push_back(value("--set"));
    } else if (arg == file_flag) {
      o.file = value(file_flag);
    } else if (arg == "--steps") {
      const std::string text = value("--steps");
      std::size_t used = 0;
      long long n = -1;
      try {
        n = std::stoll(text, &used);
      } catch (const std::exception&) {
      }
      if (used != text.size() || n < 0) throw SceneError("--steps: must be a whole number >= 0 (got '" + text + "')");
      o.steps = n;
    } else if (!arg.empty() && arg[0] == '-') {
      throw SceneError("replay " + o.mode + ": unknown option '" + arg + "'");
    } else if (o.scene_path.empty()) {
      o.scene_path = arg;
    } else {
      throw SceneError("more than one scene file given ('" + o.scene_path + "', '" + arg + "')");
    }
  }
  if (o.scene_path.empty()) throw SceneError("no scene file given");
  if (o.file.empty()) throw SceneError("replay " + o.mode + ": " + file_flag + " FILE is required");
  return o;
}

// ---- little-endian encoding ----------------------------------------------------

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xffu));
}
void put_u64(std::string& out, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xffu));
}

struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  std::string path;
  void need(std::size_t n) const {
    if (bytes.size() - at < n) throw SceneError("'" + path + "': truncated hashes file");
  }
  std::uint64_t uint(int width) {
    need(static_cast<std::size_t>(width));
    std::uint64_t v = 0;
    for (int k = 0; k < width; ++k) v |= std::uint64_t{static_cast<unsigned char>(bytes[at + k])} << (8 * k);
    at += static_cast<std::size_t>(width);
    return v;
  }
  std::string text() {
    const std::size_t end = bytes.find('\0', at);
    if (end == std::string::npos) throw SceneError("'" + path + "': truncated hashes file");
    std::string s = bytes.substr(at, end - at);
    at = end + 1;
    return s;
  }
};

struct Recording {
  std::uint64_t layout = 0, model_tag = 0;
  std::int64_t steps = 0;
  std::string scene;
  std::vector<std::string> names;
  std::vector<std::uint64_t> full;        ///< steps + 1
  std::vector<std::uint32_t> per_field;   ///< (steps + 1) × F
};

Recording read_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError("cannot read '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  Reader r{bytes, 0, path};
  r.need(8);
  if (bytes.compare(0, 8, std::string(kMagic, 8)) != 0)
    throw SceneError("'" + path + "' is not an xfdem hashes file (written by 'xfdem replay record')");
  r.at = 8;
  const auto format = static_cast<std::uint32_t>(r.uint(4));
  if (format != kFormat)
    throw SceneError("'" + path + "': hashes format " + std::to_string(format) + ", this build reads " +
                     std::to_string(kFormat));
  Recording rec;
  const auto fields = static_cast<std::size_t>(r.uint(4));
  rec.layout = r.uint(8);
  rec.model_tag = r.uint(8);
  rec.steps = static_cast<std::int64_t>(r.uint(8));
  rec.scene = r.text();
  for (std::size_t k = 0; k < fields; ++k) rec.names.push_back(r.text());
  const auto records = static_cast<std::size_t>(rec.steps) + 1;
  r.need(records * (8 + 4 * fields));
  rec.full.resize(records);
  rec.per_field.resize(records * fields);
  for (std::size_t s = 0; s < records; ++s) {
    rec.full[s] = r.uint(8);
    for (std::size_t k = 0; k < fields; ++k) rec.per_field[s * fields + k] = static_cast<std::uint32_t>(r.uint(4));
  }
  if (r.at != bytes.size()) throw SceneError("'" + path + "': " + std::to_string(bytes.size() - r.at) +
                                             " unexpected bytes after the last record");
  return rec;
}

std::string hex(std::uint64_t v, int digits = 16) {
  char text[24];
  std::snprintf(text, sizeof(text), "%0*" PRIx64, digits, v);
  return text;
}

// ---- the two modes -----------------------------------------------------------------

int record(const Options& o, const xfdem::scene::Scene& scene, xfdem::scene::SceneWorld& world,
           std::int64_t steps) {
  const std::size_t fields = world.field_count();
  std::vector<std::uint64_t> field_hash(fields);
  std::string out(kMagic, 8);
  put_u32(out, kFormat);
  put_u32(out, static_cast<std::uint32_t>(fields));
  put_u64(out, world.layout());
  put_u64(out, world.model_tag());
  put_u64(out, static_cast<std::uint64_t>(steps));
  out += scene.name;
  out.push_back('\0');
  char name[128];
  for (std::size_t k = 0; k < fields; ++k) {
    out += world.field_name(k, name, sizeof(name));
    out.push_back('\0');
  }
  out.reserve(out.size() + static_cast<std::size_t>(steps + 1) * (8 + 4 * fields));
  auto append = [&] {
    put_u64(out, world.hash());
    world.field_hashes(field_hash);
    for (std::uint64_t h : field_hash) put_u32(out, static_cast<std::uint32_t>(h));
  };
  append();
  const xfdem::StepStatus acknowledged = xfdem::scene::acknowledged_flags(scene);
  for (std::int64_t s = 1; s <= steps; ++s) {
    const xfdem::StepStatus status = xfdem::without(world.step(), acknowledged);
    if (status != xfdem::StepStatus::ok) {
      char text[200];
      std::cerr << "xfdem: step " << s << " returned " << xfdem::describe(status, text, sizeof(text))
                << "; nothing recorded\n";
      return 3;
    }
    append();
  }
  const std::string temporary = o.file + ".partial";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file << out;
    if (!file) {
      std::cerr << "xfdem: cannot write '" << temporary << "'\n";
      std::remove(temporary.c_str());
      return 2;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, o.file, ec);
  if (ec) {
    std::cerr << "xfdem: cannot move output into '" << o.file << "': " << ec.message() << "\n";
    std::remove(temporary.c_str());
    return 2;
  }
  std::printf("recorded %" PRId64 " steps of %s: %zu fields, final hash %s\n", steps, scene.name.c_str(), fields,
              hex(world.hash()).c_str());
  return 0;
}

int check(const Options& o, double dt, xfdem::scene::SceneWorld& world, std::int64_t steps_wanted) {
  const Recording rec = read_recording(o.file);
  const std::size_t fields = world.field_count();
  char name[128];
  bool same_fields = fields == rec.names.size();
  for (std::size_t k = 0; same_fields && k < fields; ++k) same_fields = rec.names[k] == world.field_name(k, name, sizeof(name));
  if (!same_fields || rec.layout != world.layout()) {
    std::printf("different layout: the recording has %zu fields (layout %s), this run %zu (layout %s); "
                "another scene or model size\n",
                rec.names.size(), hex(rec.layout).c_str(), fields, hex(world.layout()).c_str());
    return 1;
  }
  if (rec.model_tag != world.model_tag())
    std::printf("note: the model differs from the recorded one (model tag %s, recorded %s)\n",
                hex(world.model_tag()).c_str(), hex(rec.model_tag).c_str());
  const std::int64_t steps = steps_wanted >= 0 ? std::min(steps_wanted, rec.steps) : rec.steps;
  std::vector<std::uint64_t> field_hash(fields);
  auto compare = [&](std::int64_t s) -> bool {
    const auto at = static_cast<std::size_t>(s);
    if (world.hash() == rec.full[at]) return true;
    world.field_hashes(field_hash);
    std::size_t first = fields, differing = 0;
    for (std::size_t k = 0; k < fields; ++k)
      if (static_cast<std::uint32_t>(field_hash[k]) != rec.per_field[at * fields + k]) {
        if (first == fields) first = k;
        ++differing;
      }
    std::printf("first difference at step %" PRId64 " (t = %.17g s): ", s, static_cast<double>(s) * dt);
    if (first < fields)
      std::printf("field %s (hash %s, recorded %s); %zu of %zu fields differ\n", rec.names[first].c_str(),
                  hex(field_hash[first] & 0xffffffffu, 8).c_str(), hex(rec.per_field[at * fields + first], 8).c_str(),
                  differing, fields);
    else
      std::printf("full-state hash %s, recorded %s (no 32-bit field hash differs)\n", hex(world.hash()).c_str(),
                  hex(rec.full[at]).c_str());
    return false;
  };
  if (!compare(0)) return 1;
  for (std::int64_t s = 1; s <= steps; ++s) {
    world.step();  // a status is part of what a replay reproduces; the hashes judge it
    if (!compare(s)) return 1;
  }
  std::printf("identical, %" PRId64 " steps (final hash %s)\n", steps, hex(world.hash()).c_str());
  return 0;
}

}  // namespace

/// `xfdem replay …` (dispatched from main.cpp). Throws SceneError on bad input.
int replay_command(int argc, char** argv) {
  const Options o = parse(argc, argv);
  xfdem::cli::stage = "loading the scene file";
  const xfdem::scene::Scene scene = xfdem::scene::load_scene(o.scene_path, o.overrides);
  xfdem::cli::stage = "building the scene's model";
  xfdem::scene::SceneWorld world(scene);
  xfdem::cli::stage = o.mode == "record" ? "recording the run's hashes" : "checking the run against its hashes";
  if (o.mode == "record") return record(o, scene, world, o.steps >= 0 ? std::min(o.steps, scene.steps) : scene.steps);
  return check(o, scene.dt, world, o.steps);
}
