// Runs a loaded scene and writes its probes as CSV (scenes.md: "Overrides and
// output"). Used by `xfdem run` and by the tests.
#pragma once
#include <cstdint>
#include <ostream>
#include <string>

#include "scene/scene.hpp"

namespace xfdem::scene {

class VtkSeries;  // scene/vtk.hpp

struct RunSummary {
  std::int64_t steps = 0;
  double wall_seconds = 0;
  double mean_step_seconds = 0;
  double worst_step_seconds = 0;
  /// Per-stage time shares (of every 64th step, which alone is timed stage by
  /// stage) and peak use of every capacity, one line.
  std::string stages;
  /// Steps past the stated stable limit (unstable_time_step), carried on past
  /// because the scene set dem.allow_unstable_dt.
  std::int64_t unstable_steps = 0;
  /// The first step that said energy_growth (0: none). The run carries on past
  /// it (the flag stays up from there on) and the CLI warns.
  std::int64_t first_energy_growth_step = 0;
};

/// The CSV stream failed (a stream reports that by its state, not by an
/// exception: an in-memory one that cannot grow, a full disk): the run stops.
class OutputError : public SceneError {
 public:
  OutputError(std::int64_t step, double time, std::int64_t rows);
  std::int64_t step, rows;  ///< the step whose row failed, rows written before it
  double time;              ///< of that step, s
};

/// Builds the scene's models, steps to time.end, writes the header and one row
/// per output.every to `csv`. Throws SceneError on a build failure (message
/// names the field; "out of memory while building the scene's model" when the
/// system refuses an allocation outside the kernel's own arrays, which the
/// kernel reports by key), on a step status other than ok (message names the
/// flag and the step), but for energy_growth, which it books in the summary,
/// and OutputError when `csv` fails.
///
/// With `vtk`, every output sample is also written there (a plate and
/// particles; a scene with a bar is refused: SceneError naming --vtk).
RunSummary run_scene(const Scene& scene, std::ostream& csv, int threads = 1, VtkSeries* vtk = nullptr);

}  // namespace xfdem::scene
