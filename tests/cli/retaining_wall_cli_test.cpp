// The demonstration scene through the command line (scenes/demo/retaining_wall.json,
// written by tools/demo/retaining_wall.py; docs/coupled2d.md, "Demonstration"),
// shortened to its first 300 plate steps (0.03 s):
//  - the backfill, released from rest in a lattice whose disks touch nothing,
//    falls freely until its lowest disk reaches the floor: until then the
//    particles' momentum is symplectic Euler's free fall of the whole mass,
//    each probed disk's height its closed form, and the wall is untouched
//    (every wall probe exactly 0); after it, the floor has pushed the bed up;
//  - the same bytes on one and two workers (2912 disks: two workers split them).
// Under AddressSanitizer the scene's 2912 disks run some 20 times slower: the
// sanitizer build compares the two workers over the first 50 plate steps (the
// split step on a falling bed, before it lands; Coupled2dCli's own
// two-worker test covers a bed in contact under the sanitizer) and leaves
// the fall's physics to the release build.
#include <gtest/gtest.h>

#include "scene/json_reader.hpp"
#include "support/command.hpp"
#include "support/csv.hpp"
#include "support/sanitizers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using xfdem::testing::Csv;
using xfdem::testing::read_csv;
using xfdem::testing::slurp;
using Result = xfdem::testing::CommandResult;

fs::path scratch() { return xfdem::testing::scratch("retaining_wall_cli_test"); }
Result run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }

const std::string kShort = " --set time.end=0.03 --set output.every=0.0001";
#ifdef XFDEM_UNDER_ASAN
const std::string kTwoWorkersRun = " --set time.end=0.005 --set output.every=0.0001";
#else
const std::string kTwoWorkersRun = kShort;
#endif

xfdem::scene::Json wall_scene() {
  std::ifstream in(xfdem::testing::scene_file("demo/retaining_wall.json"));
  std::stringstream text;
  text << in.rdbuf();
  return xfdem::scene::parse_json(text.str(), "", true);
}

}  // namespace

TEST(RetainingWallCli, TheBackfillFallsFreelyUntilItLandsAndTheWallIsUntouched) {
#ifdef XFDEM_UNDER_ASAN
  GTEST_SKIP() << "300 plate steps of 2912 disks: the release build checks the fall; "
                  "SameBytesOnOneAndTwoWorkers runs the scene under the sanitizer";
#endif
  const xfdem::scene::Json s = wall_scene();
  const double g = -s["gravity"][1].get<double>();
  const double dt = s["time"]["dt"].get<double>();
  const int n = s["time"]["dem_substeps"].get<int>();
  const double h = dt / n;
  const double wall_x = s["continuum"]["domain"]["max"][0].get<double>();
  double back_x = 0, floor_y = 0;
  for (const auto& plane : s["dem"]["planes"])
    (plane["name"] == "back" ? back_x : floor_y) = plane["point"][plane["name"] == "back" ? 0 : 1].get<double>();
  // The lattice: no disk touches another, the wall or the back plane, so all
  // fall alike until the lowest reaches the floor, `gap` below it.
  std::vector<double> px, py, pr;
  double mass = 0;
  std::map<std::string, double> y0;
  for (const auto& p : s["dem"]["particles"]) {
    px.push_back(p["position"][0].get<double>());
    py.push_back(p["position"][1].get<double>());
    pr.push_back(p["radius"].get<double>());
    mass += p["mass"].get<double>();
    y0[p["name"].get<std::string>()] = py.back();
  }
  double gap = std::numeric_limits<double>::infinity(), closest = gap;
  for (std::size_t i = 0; i < px.size(); ++i) {
    gap = std::min(gap, py[i] - pr[i] - floor_y);
    ASSERT_GT(px[i] - pr[i], wall_x) << i;
    ASSERT_LT(px[i] + pr[i], back_x) << i;
    for (std::size_t j = i + 1; j < px.size(); ++j)
      closest = std::min(closest, std::hypot(px[i] - px[j], py[i] - py[j]) - pr[i] - pr[j]);
  }
  ASSERT_GT(closest, 0.0);
  ASSERT_GT(gap, 0.0);
  // After k substeps of symplectic Euler from rest, y_k = y0 − g h² k(k+1)/2:
  // the first substep whose start finds the lowest disk on the floor.
  long landing = 0;
  while (gap - g * h * h * static_cast<double>(landing) * static_cast<double>(landing + 1) / 2 > 0) ++landing;

  const fs::path csv = scratch() / "wall.csv";
  const Result r = run("run " + xfdem::testing::scene_file("demo/retaining_wall.json") + kShort + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv c = read_csv(csv);
  ASSERT_EQ(c.rows.size(), 301u);
  const std::size_t kt = c.column("t"), kpy = c.column("py_particles"), kpx = c.column("px_particles");
  long free_rows = 0;
  double worst_p = 0, worst_y = 0;
  for (std::size_t row = 0; row < c.rows.size(); ++row) {
    const auto& v = c.rows[row];
    const long k = static_cast<long>(row) * n;  // substeps taken
    for (std::size_t col = 0; col < c.header.size(); ++col) ASSERT_TRUE(std::isfinite(v[col])) << c.header[col];
    // The wall: nothing touches it in these 0.03 s (the lattice's first column
    // reaches the back face later), so every plate probe and wall force is 0.
    for (std::size_t col = 0; col < c.header.size(); ++col) {
      const std::string& name = c.header[col];
      if (name == "t" || name.rfind("py_", 0) == 0 || name.rfind("px_particles", 0) == 0 ||
          name.rfind("y_", 0) == 0 || name == "E_kinetic")
        continue;
      EXPECT_EQ(v[col], 0.0) << name << " at t = " << v[kt];
    }
    if (k > landing) continue;
    ++free_rows;
    const double p = -mass * g * h * static_cast<double>(k);
    worst_p = std::max(worst_p, std::fabs(v[kpy] - p));
    EXPECT_NEAR(v[kpy], p, 1e-12 * mass * g * dt * 300) << "t = " << v[kt];
    EXPECT_EQ(v[kpx], 0.0);
    for (std::size_t col = 0; col < c.header.size(); ++col) {
      if (c.header[col].rfind("y_", 0) != 0) continue;
      const double y = y0.at(c.header[col].substr(2)) - g * h * h * static_cast<double>(k) * static_cast<double>(k + 1) / 2;
      worst_y = std::max(worst_y, std::fabs(v[col] - y));
      EXPECT_NEAR(v[col], y, 1e-12) << c.header[col] << " at t = " << v[kt];
    }
  }
  // The floor's impulse on the bed after landing: upwards, and less than the
  // bed's weight over the run would be if it were all at rest at once.
  const auto& last = c.rows.back();
  const double lifted = last[kpy] + mass * g * last[kt];
  std::printf("mass %.6g kg, lowest gap %.4g m: lands at substep %ld (t = %.5g s); %ld free rows, momentum within "
              "%.3g of %.6g kg m/s, heights within %.3g m; floor impulse by t = %.3g s: %.6g N s (weight x t %.6g)\n",
              mass, gap, landing, static_cast<double>(landing) * h, free_rows, worst_p, mass * g * dt * 300, worst_y,
              last[kt], lifted, mass * g * last[kt]);
  EXPECT_GT(free_rows, 100);
  EXPECT_LT(free_rows, 300);
  EXPECT_GT(lifted, 0.0);
}

// 2912 disks, more than split_from (1000): two workers run the DEM in two parts.
TEST(RetainingWallCli, SameBytesOnOneAndTwoWorkers) {
  const fs::path a = scratch() / "one.csv", b = scratch() / "two.csv";
  const std::string scene = xfdem::testing::scene_file("demo/retaining_wall.json");
  const Result r1 = run("run " + scene + kTwoWorkersRun + " --csv " + a.string());
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  const Result r2 = run("run " + scene + kTwoWorkersRun + " --threads 2 --csv " + b.string());
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  EXPECT_EQ(slurp(a), slurp(b));
}
