// The heap of disks (scenes/granular/heap_2d*.json): run a scene with a friction and a
// rolling friction, and measure the angle of repose of the pile from the
// disks' final positions, as tools/validation/heap.py does (docs/dem.md, "The
// heap and the column collapse").
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "support/command.hpp"
#include "support/dem_scenes.hpp"
#include "xfdem/dem.hpp"

namespace xfdem::testing {

struct Heap {
  double angle_deg = 0;  ///< mean of the two flanks' fitted angles (0: a flank had fewer than 3 points)
  double height = 0;     ///< top of the highest disk, m
  double mean_diameter = 0;
};

/// The free surface is the top (y + r) of the highest disk in each bin of
/// width 2 r0 (r0 the mean radius); the pile is the run of occupied bins on
/// either side of the highest one; on each flank a line is fitted to the
/// surface between 20 % and 80 % of the pile's height.
inline Heap measure_heap(const DemModel<2>& m, const DemState<2>& s) {
  double mean_r = 0;
  for (std::int32_t i = 0; i < m.n; ++i) mean_r += m.radius[i];
  mean_r /= m.n;
  const double w = 2 * mean_r;
  std::map<long, double> top;
  for (std::int32_t i = 0; i < m.n; ++i) {
    const long b = static_cast<long>(std::floor(s.x[0][i] / w));
    const double h = s.x[1][i] + m.radius[i];
    auto [it, fresh] = top.emplace(b, h);
    if (!fresh) it->second = std::max(it->second, h);
  }
  const auto peak = std::max_element(top.begin(), top.end(), [](auto& a, auto& b) { return a.second < b.second; });
  Heap heap;
  heap.height = peak->second;
  heap.mean_diameter = w;
  double sum = 0;
  for (const long step : {-1L, 1L}) {
    std::vector<std::pair<double, double>> points;
    for (long b = peak->first; top.count(b) != 0; b += step) {
      const double h = top[b];
      if (h >= 0.2 * heap.height && h <= 0.8 * heap.height)
        points.emplace_back(static_cast<double>(std::labs(b - peak->first)) * w, h);
    }
    if (points.size() < 3) return heap;
    sum += std::atan(-least_squares_slope(points)) * 180 / 3.14159265358979323846;
  }
  heap.angle_deg = sum / 2;
  return heap;
}

/// Runs scenes/<file> to its end with friction mu and rolling friction mu_r.
inline Heap run_heap(const char* file, double mu, double mu_r) {
  char friction[64], rolling[64];
  std::snprintf(friction, sizeof(friction), "dem.contact.friction=%.17g", mu);
  std::snprintf(rolling, sizeof(rolling), "dem.contact.rolling_friction=%.17g", mu_r);
  const scene::Scene scene = scene::load_scene(scene_file(file), {friction, rolling});
  DemWorld<2> world;
  const BuildResult built = world.build(std::get<DemDesc<2>>(scene.dem));
  EXPECT_TRUE(built.ok()) << built.message;
  for (std::int64_t k = 0; k < scene.steps; ++k) {
    const StepStatus status = world.step();
    if (has(status, kStepNotTaken) || has(status, StepStatus::non_finite) || has(status, StepStatus::unstable_time_step)) {
      ADD_FAILURE() << file << " mu " << mu << " mu_r " << mu_r << ": step " << k << " status "
                    << static_cast<unsigned>(status);
      break;
    }
  }
  const Heap heap = measure_heap(world.model, world.state);
  std::printf("%s mu %.2f mu_r %.2f: angle of repose %.2f deg, pile height %.2f mean diameters\n", file, mu, mu_r,
              heap.angle_deg, heap.height / heap.mean_diameter);
  return heap;
}

}  // namespace xfdem::testing
