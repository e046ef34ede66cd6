// The command line end to end: output format, determinism, and bad input
// rejected with the key named, a non-zero exit and no output file.
#include <gtest/gtest.h>

#include "support/command.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

using xfdem::testing::slurp;

fs::path scratch() { return xfdem::testing::scratch("cli_test"); }

using Result = xfdem::testing::CommandResult;

Result run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }

std::string scene(const char* name) { return xfdem::testing::scene_file(name); }

TEST(Cli, WritesTheHeaderAndOneRowPerOutputInterval) {
  const fs::path csv = scratch() / "v1.csv";
  const Result r = run("run " + scene("v1_k1e4.json") + " --set time.end=0.01 --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,y,v,E_total,E_kinetic,E_elastic,E_potential");
  int rows = 0;
  std::string last;
  while (std::getline(in, line)) ++rows, last = line;
  EXPECT_EQ(rows, 11);  // t = 0, 0.001, ..., 0.01 inclusive
  EXPECT_EQ(last.rfind("0.01,", 0), 0u) << last;
  EXPECT_NE(r.err.find("steps"), std::string::npos);  // the summary line
}

TEST(Cli, ValuesReadBackBitExactAndRunsRepeatBitForBit) {
  const fs::path a = scratch() / "a.csv", b = scratch() / "b.csv";
  ASSERT_EQ(run("run " + scene("v1_k1e5.json") + " --set time.end=1 --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + scene("v1_k1e5.json") + " --set time.end=1 --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  // 17 significant digits round-trip: re-printing a parsed value gives the same text.
  std::ifstream in(a);
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  std::getline(in, line);
  const std::string field = line.substr(line.find(',') + 1, line.find(',', line.find(',') + 1) - line.find(',') - 1);
  char again[40];
  std::snprintf(again, sizeof(again), "%.17g", std::stod(field));
  EXPECT_EQ(field, again);
}

struct BadInput {
  const char* args;
  const char* must_mention;
};

class CliRejects : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliRejects, WithTheKeyNamedAndNoOutput) {
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  const Result r = run(std::string("run ") + scene("v1_k1e4.json") + " " + GetParam().args + " --csv " + csv.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(GetParam().must_mention), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(csv.string() + ".partial"));
}

INSTANTIATE_TEST_SUITE_P(
    BadValues, CliRejects,
    ::testing::Values(BadInput{"--set dem.particles.0.mass=-1", "dem.particles.0.mass"},
                      BadInput{"--set dem.particles.0.radius=0", "dem.particles.0.radius"},
                      BadInput{"--set dem.contact.damping_ratio=1", "dem.contact.damping_ratio"},
                      BadInput{"--set dem.contact.damping_ratio=-0.1", "dem.contact.damping_ratio"},
                      BadInput{"--set time.dt=0", "time.dt"},
                      BadInput{"--set time.dt=-1e-4", "time.dt"},
                      BadInput{"--set output.every=0.00015", "output.every"},
                      BadInput{"--set time.end=0.00015", "time.end"},
                      BadInput{"--set dem.particles.0.mass=\\\"heavy\\\"", "dem.particles.0.mass"},
                      BadInput{"--set dem.particles.0.position=[1,2]", "dem.particles.0.position"},
                      BadInput{"--set dem.particles.0.colour=1", "dem.particles.0.colour"},
                      BadInput{"--set dem.integrator=euler", "dem.integrator"},
                      BadInput{"--set dem.contact.law=hertz", "dem.contact.law"},
                      BadInput{"--set dem.particles.0.stiffness=1e999", "dem.particles.0.stiffness"},
                      BadInput{"--set dem.planes.0.normal=[0]", "dem.planes.0.normal"},
                      BadInput{"--set dimension=4", "dimension"},
                      BadInput{"--set time.dt=0.05", "dt"},  // past the stable step
                      BadInput{"--set output.probes.0.particle=p9", "output.probes.0.particle"},
                      BadInput{"--set dem.particles.7.mass=1", "dem.particles.7"},
                      BadInput{"--threads 3", "--threads"},
                      BadInput{"--set energy_check.tolerance=0", "energy_check.tolerance"},
                      BadInput{"--set energy_check.interval=-1", "energy_check.interval"},
                      BadInput{"--set energy_check.every=4", "energy_check.every"},
                      // end/dt = 6e29 steps: rejected, not cast past int64 (found by the loader fuzzer)
                      BadInput{"--set time.dt=1e-29 --set output.every=1e-29", "time.end"},
                      BadInput{"--frobnicate", "--frobnicate"}));

TEST(Cli, MissingFileAndMalformedJsonAreErrors) {
  Result r = run("run /nonexistent/scene.json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos) << r.err;
  const fs::path broken = scratch() / "broken.json";
  std::ofstream(broken) << "{ \"dimension\": 1, ";
  r = run("run " + broken.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not valid JSON"), std::string::npos) << r.err;
  r = run("launch x");
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace

namespace {

// A gain the energy check reports does not stop the run: the CSV is written
// and stderr names the first step that said energy_growth. Case I with its
// interface a billionth of an element above a node (docs/stability.md, known
// gaps), then the same with the check switched off by the scene.
TEST(Cli, EnergyGrowthIsAWarningNamingTheStep) {
  // Undamped impacts under symplectic Euler (first order) at a quarter of its
  // stable step gain energy (docs/stability.md): reported from step 1104 on.
  const std::string gaining =
      " --set dem.integrator=symplectic_euler --set dem.contact.damping_ratio=0 --set time.dt=5e-3 --set output.every=0.01";
  const fs::path csv = scratch() / "gaining.csv";
  const Result r = run("run " + scene("v1_k1e4.json") + gaining + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(csv));
  EXPECT_NE(r.err.find("warning: from step"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("energy_growth"), std::string::npos) << r.err;
  const Result off = run("run " + scene("v1_k1e4.json") + gaining + " --set energy_check.interval=0 --csv " +
                         csv.string());
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_EQ(off.err.find("energy_growth"), std::string::npos) << off.err;
  // The published scene, checked at every step at 1e-9 of its energy in motion: nothing to report.
  const Result tight = run("run " + scene("case1_xfem.json") +
                           " --set energy_check.interval=1 --set energy_check.tolerance=1e-9 --csv " + csv.string());
  ASSERT_EQ(tight.exit_code, 0) << tight.err;
  EXPECT_EQ(tight.err.find("energy_growth"), std::string::npos) << tight.err;
}

}  // namespace
