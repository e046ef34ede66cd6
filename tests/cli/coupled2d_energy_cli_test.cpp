// The energy balance check of a coupled 2D scene through the command line
// (scene key `energy_check`; docs/coupled2d.md, "The energy check"): the books
// are the `energy` probe's (scene/coupled2d_run.hpp), so each test recomputes
// from the CSV's energy column where the check must trip, and compares it with
// the step the warning names.
#include <gtest/gtest.h>

#include "scene/json_reader.hpp"
#include "support/command.hpp"
#include "support/csv.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using xfdem::testing::Csv;
using xfdem::testing::read_csv;
using Result = xfdem::testing::CommandResult;

fs::path scratch() { return xfdem::testing::scratch("coupled2d_energy_cli_test"); }
Result run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }
std::string scene(const char* name) { return xfdem::testing::scene_file(name); }

/// The step from which the CLI warns of energy_growth (0: no warning).
long long warned_from(const Result& r) {
  const auto at = r.err.find("warning: from step ");
  if (at == std::string::npos) return 0;
  return std::stoll(r.err.substr(at + 19));
}

std::vector<double> column(const Csv& c, const std::string& name) {
  std::vector<double> out;
  const std::size_t k = c.column(name);
  for (const auto& row : c.rows) out.push_back(row[k]);
  return out;
}

/// Where the check of energy_check.hpp trips on a scene whose energy is all in
/// motion and on which nothing outside does work (E_motion = E, W = 0): the
/// first checked step k (every `interval`, rows at every step) with
/// E_k − E_0 > tolerance · max over checked j ≤ k of E_j; 0 if none.
long long expected_trip(const std::vector<double>& e, int interval, double tolerance) {
  double peak = e[0];
  for (std::size_t k = 1; k < e.size(); ++k) {
    if (k % static_cast<std::size_t>(interval) != 0) continue;
    peak = std::max(peak, e[k]);
    if (e[k] - e[0] > tolerance * peak) return static_cast<long long>(k);
  }
  return 0;
}

/// Largest (E_k − E_0) / max_{j ≤ k} E_j over the rows.
double worst_rise(const std::vector<double>& e) {
  double peak = e[0], worst = 0;
  for (const double x : e) {
    peak = std::max(peak, x);
    worst = std::max(worst, (x - e[0]) / peak);
  }
  return worst;
}

}  // namespace

// The free cracked plate hit by four disks, no gravity, no damping, no
// friction, checked at every step (a row at every step): the total energy
// rises during the contacts (symplectic Euler's energy error while a spring is
// loaded) by less than the default tolerance, so the check is silent; with the
// tolerance set just below the largest rise the CSV shows, it trips at the
// first step the test finds past it, and just above it stays silent.
TEST(Coupled2dEnergyCheck, UndampedFrictionlessFreePlatePassesAndTripsWhereItsBooksSay) {
  const std::string base = "run " + scene("coupled2d_free_plate.json") +
                           " --set dem.contact.damping_ratio=0 --set energy_check.interval=1";
  const fs::path csv = scratch() / "free_plate.csv";
  const Result r = run(base + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(warned_from(r), 0) << r.err;
  const std::vector<double> e = column(read_csv(csv), "E_total");
  ASSERT_EQ(e.size(), 601u);
  const double rise = worst_rise(e);
  std::printf("free plate, undamped: largest rise %.3g of the energy (E0 = %.6g J)\n", rise, e[0]);
  EXPECT_GT(rise, 0.0);
  EXPECT_LT(rise, 0.05);  // the default tolerance

  char below[64], above[64];
  std::snprintf(below, sizeof(below), " --set energy_check.tolerance=%.17g", 0.9 * rise);
  std::snprintf(above, sizeof(above), " --set energy_check.tolerance=%.17g", 1.1 * rise);
  const Result tight = run(base + below + " --csv " + csv.string());
  ASSERT_EQ(tight.exit_code, 0) << tight.err;
  const long long expected = expected_trip(e, 1, 0.9 * rise);
  ASSERT_GT(expected, 0);
  EXPECT_EQ(warned_from(tight), expected) << tight.err;
  EXPECT_NE(tight.err.find("energy_check"), std::string::npos) << tight.err;
  const Result loose = run(base + above + " --csv " + csv.string());
  ASSERT_EQ(loose.exit_code, 0) << loose.err;
  EXPECT_EQ(warned_from(loose), 0) << loose.err;
}

// The same disks 400 times stiffer with one substep: ω h is past symplectic
// Euler's stable step (allowed by dem.allow_unstable_dt), and the contacts
// throw the disks out with more energy than they came in with. The default
// check (every 16 steps, 0.05) trips at the checked step the test finds in
// the CSV; with the check off nothing is said.
TEST(Coupled2dEnergyCheck, ContactsPastTheStableStepGainEnergyAndTripIt) {
  std::string stiff = " --set time.dem_substeps=1 --set dem.allow_unstable_dt=true --set dem.contact.damping_ratio=0";
  for (int i = 0; i < 4; ++i) stiff += " --set dem.particles." + std::to_string(i) + ".stiffness=4e8";
  const fs::path csv = scratch() / "stiff.csv";
  const Result r = run("run " + scene("coupled2d_free_plate.json") + stiff + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> e = column(read_csv(csv), "E_total");
  ASSERT_EQ(e.size(), 601u);
  const long long expected = expected_trip(e, 16, 0.05);
  std::printf("stiff contacts: energy %.6g J at the start, %.6g J at the end; tripped at step %lld\n", e[0], e.back(),
              warned_from(r));
  ASSERT_GT(expected, 0);
  EXPECT_EQ(warned_from(r), expected) << r.err;
  const Result off =
      run("run " + scene("coupled2d_free_plate.json") + stiff + " --set energy_check.interval=0 --csv " + csv.string());
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_EQ(warned_from(off), 0) << off.err;
}

// The work of the plate's loads is in the books: the plate in tension (a step
// traction on its right edge) with a disk falling far above it, checked at
// every step at 1e-9 of the energy in motion, is silent although its energy
// (the probe's total: the disk's and the plate's) rises by far more than that
// as the traction loads the plate.
TEST(Coupled2dEnergyCheck, ThePlatesLoadWorkIsBooked) {
  std::ifstream in(scene("plate_tension.json"));
  std::stringstream text;
  text << in.rdbuf();
  xfdem::scene::Json doc = xfdem::scene::parse_json(text.str(), "", true);
  doc["time"]["dem_substeps"] = 4;
  doc["dem"] = xfdem::scene::Json::parse(R"({"integrator": "symplectic_euler", "particles": [
      {"name": "d1", "mass": 2.0, "radius": 0.05, "stiffness": 1e5, "position": [1.0, 3.0]}]})");
  auto& probes = doc["output"]["probes"];
  xfdem::scene::Json kept = xfdem::scene::Json::array();
  for (auto& p : probes)
    if (p["quantity"] == "energy") kept.push_back(p);
  probes = kept;
  const fs::path path = scratch() / "tension_with_disk.json", csv = scratch() / "tension.csv";
  std::ofstream(path) << doc.dump(2);
  const Result r =
      run("run " + path.string() + " --set energy_check.interval=1 --set energy_check.tolerance=1e-9 --csv " +
          csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(warned_from(r), 0) << r.err;
  const Csv c = read_csv(csv);
  const std::vector<double> e = column(c, "E_total"), elastic = column(c, "E_elastic");
  const double peak = *std::max_element(elastic.begin(), elastic.end());
  const double rise = *std::max_element(e.begin(), e.end()) - e[0];
  std::printf("plate in tension: energy rose by %.6g J, the plate's elastic peak %.6g J\n", rise, peak);
  EXPECT_GT(rise, 1e3 * 1e-9 * (peak + e[0]));
}

// The published columns (Cases I and II in 2D: gravity, damped disks, a tied
// crack) checked at every step at 1e-9 of their energy in motion: gravity's
// potential and the exchange are in the books, and the dashpots only take
// energy out, so there is nothing to report.
TEST(Coupled2dEnergyCheck, PublishedColumnsAreSilentAtEveryStep) {
  for (const char* name : {"coupled2d_case1_xfem.json", "coupled2d_case2_xfem.json"}) {
    const Result r = run("run " + scene(name) + " --set energy_check.interval=1 --set energy_check.tolerance=1e-9 --csv " +
                         (scratch() / "column.csv").string());
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_EQ(warned_from(r), 0) << name << ": " << r.err;
  }
}

// The hertz branch of the disk–plate contact's energy (coupled2d_boundary_energy),
// against Hertz's closed form: a 1 kg disk (E = 1e8 Pa, ν = 0.3, r = 0.05 m,
// restitution 0.1) set down on a nearly rigid supported plate (E = 2e15 Pa)
// under gravity settles where 4/3 E* √r δ^{3/2} = m g, with 1/E* the sum of
// the two bodies' (1 − ν²)/E; the energy probe's elastic part there is the
// contact's 8/15 E* √r δ^{5/2} = 2/5 m g δ (the plate's own, (m g)² over its
// stiffness, is ~1e-10 of it), and the check at every step is silent.
TEST(Coupled2dEnergyCheck, AHertzDiskRestingOnThePlateHoldsHertzsEnergy) {
  const double m = 1.0, g = 9.81, r = 0.05, e_disk = 1e8, e_plate = 2e15, nu = 0.3, top = 0.2;
  char text[2000];
  std::snprintf(text, sizeof(text), R"({"name": "hertz_rest", "dimension": 2, "gravity": [0, %.17g],
  "time": {"end": 0.5, "dt": 1e-4, "dem_substeps": 10},
  "dem": {"integrator": "symplectic_euler", "contact": {"law": "hertz", "restitution": 0.1},
    "particles": [{"name": "d1", "mass": %.17g, "radius": %.17g, "youngs_modulus": %.17g, "poisson_ratio": %.17g,
                   "position": [1.0, %.17g]}]},
  "continuum": {"type": "plate", "domain": {"min": [0, 0], "max": [2, %.17g]}, "cells": [10, 1],
    "material": {"youngs_modulus": %.17g, "poisson_ratio": %.17g, "density": 7800},
    "supports": [{"edge": "bottom", "fix": ["x", "y"]}]},
  "energy_check": {"interval": 1},
  "output": {"every": 0.5, "probes": [
    {"name": "y", "particle": "d1", "quantity": "position", "component": 1},
    {"name": "E_kinetic", "quantity": "energy", "of": "kinetic"},
    {"name": "E_elastic", "quantity": "energy", "of": "elastic"}]}})",
                -g, m, r, e_disk, nu, top + r, top, e_plate, nu);
  const fs::path path = scratch() / "hertz_rest.json", csv = scratch() / "hertz_rest.csv";
  std::ofstream(path) << text;
  const Result res = run("run " + path.string() + " --csv " + csv.string());
  ASSERT_EQ(res.exit_code, 0) << res.err;
  EXPECT_EQ(warned_from(res), 0) << res.err;
  const Csv c = read_csv(csv);
  ASSERT_EQ(c.rows.size(), 2u);
  const double e_star = 1.0 / ((1 - nu * nu) / e_disk + (1 - nu * nu) / e_plate);
  const double delta = std::pow(3.0 * m * g / (4.0 * e_star * std::sqrt(r)), 2.0 / 3.0);
  const double energy = 8.0 / 15.0 * e_star * std::sqrt(r) * std::pow(delta, 2.5);
  const double y = c.rows[1][c.column("y")], elastic = c.rows[1][c.column("E_elastic")];
  std::printf("hertz at rest: overlap %.9g m, %.2g from the closed form; elastic %.9g J, %.2g from 2/5 m g delta\n",
              top + r - y, std::fabs(top + r - y - delta) / delta, elastic, std::fabs(elastic - energy) / energy);
  EXPECT_NEAR(top + r - y, delta, 1e-8 * delta);  // the plate's compliance: ~1e-10
  EXPECT_NEAR(elastic, energy, 1e-8 * energy);
  EXPECT_LT(c.rows[1][c.column("E_kinetic")], 1e-9 * energy);
}

struct BadCheck {
  const char* set;
  const char* message;  ///< the whole first line of stderr after "xfdem: "
};

class Coupled2dEnergyCheckRejects : public ::testing::TestWithParam<BadCheck> {};

TEST_P(Coupled2dEnergyCheckRejects, NamingTheKey) {
  const fs::path csv = scratch() / "rejected.csv";
  fs::remove(csv);
  const Result r = run("run " + scene("coupled2d_free_plate.json") + " " + GetParam().set + " --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.substr(0, r.err.find('\n')), std::string("xfdem: ") + GetParam().message);
  EXPECT_FALSE(fs::exists(csv));
}

INSTANTIATE_TEST_SUITE_P(
    Keys, Coupled2dEnergyCheckRejects,
    ::testing::Values(
        BadCheck{"--set energy_check.tolerance=0", "scene key 'energy_check.tolerance': must be > 0 (got 0)"},
        BadCheck{"--set energy_check.tolerance=-0.5", "scene key 'energy_check.tolerance': must be > 0 (got -0.5)"},
        BadCheck{"--set energy_check.interval=-1",
                 "scene key 'energy_check.interval': must be an integer in [0, 1000000000] (got -1)"},
        BadCheck{"--set energy_check.interval=2.5",
                 "scene key 'energy_check.interval': expected an integer, got a fractional number"},
        BadCheck{"--set energy_check.every=4", "scene key 'energy_check.every': unknown key"},
        BadCheck{"--set energy_check=16", "scene key 'energy_check': expected an object, got a number"}));
