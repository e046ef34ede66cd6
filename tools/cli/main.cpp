// xfdem: the command line.
//
//   xfdem run SCENE.json [--set KEY=VALUE ...] [--csv OUT.csv] [--threads N] [--vtk DIR]
//   xfdem replay record|check ...   (tools/cli/replay.cpp)
//
// Validates the whole scene (and every override) before stepping; writes the
// CSV to a temporary file renamed into place only when the run succeeded, so a
// failed run leaves no partial output (nor VTK files: those written are
// removed). Exit codes: 0 success, 2 bad input (usage, scene, override, --vtk
// directory) or out of memory (naming what was being done), 3 the stepper
// reported a status.
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli/stage.hpp"
#include "scene/runner.hpp"
#include "scene/scene.hpp"
#include "scene/vtk.hpp"
#include "xfdem/version.hpp"

int replay_command(int argc, char** argv);  // tools/cli/replay.cpp

namespace {

constexpr const char* kUsage =
    "usage: xfdem run SCENE.json [--set KEY=VALUE ...] [--csv OUT.csv] [--threads N] [--vtk DIR]\n"
    "       xfdem replay record SCENE.json [--set KEY=VALUE ...] [--steps N] --out RUN.hashes\n"
    "       xfdem replay check SCENE.json [--set KEY=VALUE ...] [--steps N] --against RUN.hashes\n"
    "       xfdem --version\n";

int usage_error(const std::string& what) {
  std::cerr << "xfdem: " << what << "\n" << kUsage;
  return 2;
}

/// Writes `text` to `stream`, then flushes and closes it (unless stdout),
/// returning the first error's errno (0: none).
int write_all(std::FILE* stream, const std::string& text, bool close) {
  int error = 0;
  if (std::fwrite(text.data(), 1, text.size(), stream) != text.size()) error = errno;
  if (std::fflush(stream) != 0 && error == 0) error = errno;
  if (close && std::fclose(stream) != 0 && error == 0) error = errno;
  return error != 0 ? error : EIO * (!close && std::ferror(stream) != 0);
}

/// The CSV: to standard output when `path` is empty. A regular file (or a new
/// one) is written to PATH.partial and renamed into place only when every
/// byte reached it, closing included (a full disk reports at close), so a
/// failed write leaves no partial file. Anything else the path names (a
/// device or a pipe: /dev/stdout, /dev/full) is written directly. Errors are
/// reported naming the path; returns false then.
bool write_output(const std::string& path, const std::string& text) {
  if (path.empty()) {
    if (const int error = write_all(stdout, text, false); error != 0) {
      std::cerr << "xfdem: cannot write the CSV to standard output: " << std::strerror(error) << "\n";
      return false;
    }
    return true;
  }
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  const bool regular = !std::filesystem::exists(status) || std::filesystem::is_regular_file(status);
  if (std::filesystem::is_directory(status)) {
    std::cerr << "xfdem: --csv '" << path << "': is a directory\n";
    return false;
  }
  const std::string target = regular ? path + ".partial" : path;
  std::FILE* out = std::fopen(target.c_str(), regular ? "wb" : "ab");
  if (out == nullptr) {
    std::cerr << "xfdem: cannot write '" << target << "': " << std::strerror(errno) << "\n";
    return false;
  }
  if (const int error = write_all(out, text, true); error != 0) {
    std::cerr << "xfdem: cannot write '" << target << "': " << std::strerror(error) << "\n";
    if (regular) std::remove(target.c_str());
    return false;
  }
  if (!regular) return true;
  std::filesystem::rename(target, path, ec);
  if (ec) {
    std::cerr << "xfdem: cannot move output into '" << path << "': " << ec.message() << "\n";
    std::remove(target.c_str());
    return false;
  }
  return true;
}

int run(int argc, char** argv) {
  std::string scene_path, csv_path, vtk_path;
  bool vtk = false;
  std::vector<std::string> overrides;
  int threads = 1;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* flag) -> std::string {
      if (i + 1 >= argc) throw xfdem::scene::SceneError(std::string(flag) + ": missing value");
      return argv[++i];
    };
    if (arg == "--set") {
      overrides.push_back(value("--set"));
    } else if (arg == "--csv") {
      csv_path = value("--csv");
      if (csv_path.empty()) throw xfdem::scene::SceneError("--csv: must name a file (got an empty path)");
    } else if (arg == "--vtk") {
      if (i + 1 >= argc || (argv[i + 1][0] == '-' && argv[i + 1][1] == '-'))
        throw xfdem::scene::SceneError("--vtk: missing value (the directory to write the VTK files in)");
      vtk_path = argv[++i];
      vtk = true;
    } else if (arg == "--threads") {
      const std::string t = value("--threads");
      if (t != "1" && t != "2") throw xfdem::scene::SceneError("--threads: must be 1 or 2 (got '" + t + "')");
      threads = std::stoi(t);
    } else if (!arg.empty() && arg[0] == '-') {
      throw xfdem::scene::SceneError("unknown option '" + arg + "'");
    } else if (scene_path.empty()) {
      scene_path = arg;
    } else {
      throw xfdem::scene::SceneError("more than one scene file given ('" + scene_path + "', '" + arg + "')");
    }
  }
  if (scene_path.empty()) throw xfdem::scene::SceneError("no scene file given");
  xfdem::cli::stage = "loading the scene file";
  const xfdem::scene::Scene scene = xfdem::scene::load_scene(scene_path, overrides);
  for (const std::string& warning : scene.warnings) std::fprintf(stderr, "xfdem: warning: %s\n", warning.c_str());
  // The VTK files of a run that fails are removed (no partial output).
  std::optional<xfdem::scene::VtkSeries> series;
  struct Abandon {
    std::optional<xfdem::scene::VtkSeries>& series;
    bool keep = false;
    ~Abandon() {
      if (!keep && series) series->abandon();
    }
  } abandon{series};
  if (vtk) {
    xfdem::cli::stage = "preparing the VTK directory";
    series.emplace(vtk_path, scene);
  }

  std::ostringstream buffer;
  xfdem::scene::RunSummary summary;
  xfdem::cli::stage = "building and running the scene";
  try {
    summary = xfdem::scene::run_scene(scene, buffer, threads, series ? &*series : nullptr);
  } catch (const xfdem::scene::OutputError& e) {
    // The CSV is held in memory until the run ends (no partial output): it could not grow.
    std::fprintf(stderr,
                 "xfdem: out of memory at step %lld (t = %.17g s): the CSV, held in memory until the run ends, could "
                 "not grow past %lld rows; raise output.every or shorten time.end\n",
                 static_cast<long long>(e.step), e.time, static_cast<long long>(e.rows));
    return 2;
  } catch (const xfdem::scene::SceneError& e) {
    const std::string what = e.what();
    std::cerr << "xfdem: " << what << "\n";
    return what.rfind("step ", 0) == 0 ? 3 : 2;
  }
  if (series) {
    xfdem::cli::stage = "writing the VTK collection";
    try {
      series->finish();
    } catch (const xfdem::scene::SceneError& e) {
      std::cerr << "xfdem: " << e.what() << "\n";
      return 2;
    }
  }
  xfdem::cli::stage = "writing the CSV";
  if (!write_output(csv_path, std::move(buffer).str())) return 2;
  abandon.keep = true;
  std::fprintf(stderr, "xfdem: %s: %lld steps, wall %.3f s, mean %.3f us/step, worst %.3f us/step\n",
               scene.name.c_str(), static_cast<long long>(summary.steps), summary.wall_seconds,
               summary.mean_step_seconds * 1e6, summary.worst_step_seconds * 1e6);
  std::fprintf(stderr, "xfdem: stages (every 64th step timed): %s\n", summary.stages.c_str());
  if (summary.unstable_steps > 0)
    std::fprintf(stderr,
                 "xfdem: warning: %lld steps past the stable time step (unstable_time_step, allowed by "
                 "dem.allow_unstable_dt): no energy bound holds (docs/stability.md)\n",
                 static_cast<long long>(summary.unstable_steps));
  if (summary.first_energy_growth_step > 0)
    std::fprintf(stderr,
                 "xfdem: warning: from step %lld on the energy exceeded its start plus the work done by more than "
                 "the energy check's tolerance (energy_growth; scene key energy_check): the method gained energy "
                 "(docs/stability.md)\n",
                 static_cast<long long>(summary.first_energy_growth_step));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage_error("no command given");
  const std::string command = argv[1];
  if (command == "--version") {
    std::printf("xfdem %s\n", xfdem::version_string());
    return 0;
  }
  if (command == "--help" || command == "-h") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command != "run" && command != "replay") return usage_error("unknown command '" + command + "'");
  try {
    xfdem::cli::stage = "reading the command line";
    return command == "replay" ? replay_command(argc, argv) : run(argc, argv);
  } catch (const std::bad_alloc&) {
    // Not through a stream: there may be no memory to format one.
    std::fprintf(stderr, "xfdem: out of memory while %s\n", xfdem::cli::stage);
    return 2;
  } catch (const xfdem::scene::SceneError& e) {
    std::cerr << "xfdem: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "xfdem: " << e.what() << "\n";
    return 2;
  }
}
