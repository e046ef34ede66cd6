// The command line end to end: output format, determinism, and bad input
// rejected with the key named, a non-zero exit and no output file.
#include <gtest/gtest.h>

#include "support/command.hpp"
#include "xfdem/platform/memory.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "support/sanitizers.hpp"

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

// Each case names the key and the reason it expects, as the message gives
// them ("scene key 'KEY': REASON").
INSTANTIATE_TEST_SUITE_P(
    BadValues, CliRejects,
    ::testing::Values(
        BadInput{"--set dem.particles.0.mass=-1", "scene key 'dem.particles.0.mass': must be > 0 (got -1)"},
        BadInput{"--set dem.particles.0.radius=0", "scene key 'dem.particles.0.radius': must be > 0 (got 0)"},
        BadInput{"--set dem.contact.damping_ratio=1",
                 "scene key 'dem.contact.damping_ratio': must be >= 0 and < 1 (got 1)"},
        BadInput{"--set dem.contact.damping_ratio=-0.1", "scene key 'dem.contact.damping_ratio': must be >= 0 and < 1"},
        BadInput{"--set time.dt=0", "scene key 'time.dt': must be > 0 (got 0)"},
        BadInput{"--set time.dt=-1e-4", "scene key 'time.dt': must be > 0 (got -0.0001)"},
        BadInput{"--set output.every=0.00015", "scene key 'output.every': must be a whole multiple of time.dt"},
        BadInput{"--set time.end=0.00015", "scene key 'time.end': must be a whole multiple of time.dt"},
        BadInput{"--set dem.particles.0.mass=\\\"heavy\\\"",
                 "scene key 'dem.particles.0.mass': expected a number, got a string"},
        BadInput{"--set dem.particles.0.position=[1,2]",
                 "scene key 'dem.particles.0.position': expected 1 numbers (one per dimension), got 2"},
        BadInput{"--set dem.particles.0.colour=1", "scene key 'dem.particles.0.colour': unknown key"},
        BadInput{"--set dem.integrator=euler", "scene key 'dem.integrator': 'euler' is not one of"},
        // hertz takes restitution and the particles' E and ν, not the linear laws' keys.
        BadInput{"--set dem.contact.law=hertz", "scene key 'dem.contact.damping_ratio': used by the linear laws only"},
        BadInput{"--set dem.contact.law=nonlinear", "scene key 'dem.contact.law': 'nonlinear' is not one of"},
        BadInput{"--set dem.contact.friction=-0.5", "scene key 'dem.contact.friction': must be >= 0 (got -0.5)"},
        BadInput{"--set dem.contact.rolling_friction=-1", "scene key 'dem.contact.rolling_friction': must be >= 0"},
        BadInput{"--set dem.contact.tangential_stiffness_ratio=0",
                 "scene key 'dem.contact.tangential_stiffness_ratio': must be > 0 (got 0)"},
        BadInput{"--set dem.contact.friction=0.3", "scene key 'dem.contact.friction': rods on a line do not rotate"},
        BadInput{"--set dem.particles.0.inertia=-1", "scene key 'dem.particles.0.inertia': must be > 0 (got -1)"},
        BadInput{"--set dem.particles.0.angular_velocity=1",
                 "scene key 'dem.particles.0.angular_velocity': rods on a line do not rotate"},
        BadInput{"--set dem.particles.0.stiffness=1e999",
                 "scene key 'dem.particles.0.stiffness': value '1e999' is not a finite number"},
        BadInput{"--set dem.planes.0.normal=[0]", "scene key 'dem.planes.0.normal': must not be the zero vector"},
        BadInput{"--set dimension=4", "scene key 'dimension': must be an integer in [1, 3] (got 4)"},
        // past the stable step (the output interval set along, so that it is the step that is refused)
        BadInput{"--set time.dt=0.05 --set output.every=0.05", "scene key 'time.dt': 0.05 s exceeds the stable step"},
        BadInput{"--set output.probes.0.particle=p9",
                 "scene key 'output.probes.0.particle': 'p9' is not a particle of this scene"},
        BadInput{"--set dem.particles.7.mass=1", "--set 'dem.particles.7.mass': 'dem.particles.7' is past the end"},
        BadInput{"--threads 3", "--threads: must be 1 or 2 (got '3')"},
        BadInput{"--set energy_check.tolerance=0", "scene key 'energy_check.tolerance': must be > 0 (got 0)"},
        BadInput{"--set energy_check.interval=-1", "scene key 'energy_check.interval': must be an integer in"},
        BadInput{"--set energy_check.every=4", "scene key 'energy_check.every': unknown key"},
        // end/dt = 6e29 steps: rejected, not cast past int64 (found by the loader fuzzer)
        BadInput{"--set time.dt=1e-29 --set output.every=1e-29", "scene key 'time.end': needs more than 4e9 steps"},
        BadInput{"--frobnicate", "unknown option '--frobnicate'"},
        // capacities: the index type bounds them (memory is the build's to say), and one the model would not use is refused
        BadInput{"--set dem.capacities.max_pairs=2000000001",
                 "scene key 'dem.capacities.max_pairs': must be an integer in [0, 2000000000] (got 2000000001)"},
        BadInput{"--set dem.capacities.max_grid_cells=1000",
                 "scene key 'dem.capacities.max_grid_cells': not used: 1 particle has no pairs to list"},
        // a start deeper in the ground than the radius (moderate overlaps are legal)
        BadInput{"--set dem.particles.0.position=[-0.5]",
                 "scene key 'dem.particles.0.position': particle 'p1' overlaps plane 'plane0' by 0.6 m at the start, "
                 "more than its radius 0.1 m (its centre is on the plane's solid side): its contact would throw it out "
                 "at up to 60 m/s"},
        // a key given twice in an override's object (nlohmann keeps the last silently)
        BadInput{"--set 'dem.contact={\"law\": \"linear\", \"law\": \"linear_nontensile\"}'",
                 "scene key 'dem.contact.law': given twice"},
        BadInput{"--set 'dem.particles=[{\"mass\": 1, \"radius\": 0.1, \"stiffness\": 1e4, \"position\": [3], "
                 "\"position\": [4]}]'",
                 "scene key 'dem.particles.0.position': given twice"},
        BadInput{"--set dem.capacities.max_events_per_step=3",
                 "scene key 'dem.capacities.max_events_per_step': not used: only dem.integrator abm4_events locates "
                 "contact events (this scene's is abm4)"},
        // the same key set twice on the command line (the last used to win silently)
        BadInput{"--set time.dt=1e-4 --set time.dt=2e-4", "--set time.dt: given twice"}));

// A coupled scene's particles step at time.dt / time.dem_substeps: past their
// stable step, the message names time.dt, the substep and what to change.
TEST(Cli, CoupledSubstepPastTheStableStepNamesTimeDt) {
  const Result r = run(std::string("run ") + scene("case2_xfem.json") +
                       " --set time.dt=0.004 --set time.dem_substeps=1 --set output.every=0.02");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'time.dt': the particle substep time.dt / time.dem_substeps = 0.004 s exceeds the "
                       "stable step"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("reduce time.dt or raise time.dem_substeps"), std::string::npos) << r.err;
}

// A particle starting inside the bar, or deeper in another particle than the
// smaller radius, is refused naming it by key and by name; resting on the tip
// at half its radius is legal.
TEST(Cli, AParticleStartingInsideTheBarOrAnotherIsRefusedNamingIt) {
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  Result r = run("run " + scene("case1_xfem.json") + " --set dem.particles.0.position=[28.5] --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'dem.particles.0.position': particle 'p1' overlaps the bar's tip by 2 m at the "
                       "start, more than its radius 0.5 m (its centre is inside the bar): its contact would throw it "
                       "out at up to 707 m/s"),
            std::string::npos)
      << r.err;
  r = run("run " + scene("case2_xfem.json") + " --set dem.particles.1.position=[33.6] --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'dem.particles.1.position': particle 'p2' overlaps particle 'p1' by 0.7 m at the "
                       "start, more than the smaller radius 0.3 m: their contact would throw them apart at up to 271 m/s"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(csv));
  r = run("run " + scene("case1_xfem.json") + " --set dem.particles.0.position=[30.25] --set time.end=0.1 --csv " +
          (scratch() / "resting.csv").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

/// Bytes as the kernel's messages print them ("25.3 GB").
std::string bytes_text(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int unit = 0;
  while (unit < 5 && bytes >= 999.5) bytes /= 1000.0, ++unit;
  char text[32];
  std::snprintf(text, sizeof(text), unit == 0 ? "%.0f %s" : "%.3g %s", bytes, units[unit]);
  return text;
}

// A capacity whose arrays would take more than the machine's memory is refused
// before anything is allocated, naming the key and what it would take. In Case
// II it is refused as unused unless the particles are put on a grid.
TEST(Cli, CapacityPastTheMachinesMemoryIsRefusedNamingTheKey) {
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  Result r = run("run " + scene("case2_xfem.json") + " --set dem.capacities.max_pairs=400000000 --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'dem.capacities.max_pairs': not used: 2 particles, at most dem.all_pairs_up_to = 8, "
                       "are paired all with all in a fixed list; it bounds the grid that more particles use"),
            std::string::npos)
      << r.err;
  // 2e9 pairs in the particle state, the coupled window's three copies of it and its sensitivity: 240 GB.
  const std::uint64_t memory = xfdem::platform::physical_memory_bytes();
  if (memory == 0 || memory >= 240'000'000'000ull) GTEST_SKIP() << "this machine has " << bytes_text(double(memory));
  r = run("run " + scene("case2_xfem.json") +
          " --set dem.all_pairs_up_to=0 --set dem.capacities.max_pairs=2000000000 --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'dem.capacities.max_pairs': 2000000000 pairs take 240 GB of the 240 GB the "
                       "particles' arrays need (24 bytes a pair, in the state, the coupled window's 3 copies of it "
                       "and its sensitivity to the force, counted as a fifth), more than the memory budget of " +
                       bytes_text(static_cast<double>(memory)) + " (this machine's physical memory)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(csv));
}

// Where the system refuses memory the budget allowed (here an address-space
// limit), the run stops with a message and exit code 2, never a crash: in the
// kernel's build, naming the key, and while the CSV (held in memory until the
// run ends) grows, naming the step.
TEST(Cli, OutOfMemoryIsReportedNotACrash) {
#ifdef XFDEM_UNDER_ASAN
  GTEST_SKIP() << "the sanitizer's shadow memory needs more address space than the limit leaves";
#endif
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  const auto limited = [](const char* kilobytes, const std::string& args) {
    return xfdem::testing::run_command(std::string("ulimit -v ") + kilobytes + " && " + XFDEM_CLI, args);
  };
  Result r = limited("400000", "run " + scene("case2_xfem.json") +
                                   " --set dem.all_pairs_up_to=0 --set dem.capacities.max_pairs=100000000 --csv " +
                                   csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scene key 'dem.capacities.max_pairs': 100000000 pairs take 12 GB of the 12 GB the "
                       "particles' arrays need (24 bytes a pair, in the state, the coupled window's 3 copies of it "
                       "and its sensitivity to the force, counted as a fifth): the allocator could not provide them"),
            std::string::npos)
      << r.err;
  r = limited("200000", "run " + scene("v1_k1e4.json") +
                            " --set time.dt=1e-3 --set time.end=4000 --set output.every=1e-3 --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("xfdem: out of memory at step ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("): the CSV, held in memory until the run ends, could not grow past "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" rows; raise output.every or shorten time.end"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(csv.string() + ".partial"));
}

// Output errors: an empty --csv, a directory, and a write that fails (a full
// device reports at the write or at close) are errors naming the path; no
// partial file is left.
TEST(Cli, OutputErrorsAreReportedAndLeaveNoPartialFile) {
  Result r = run(std::string("run ") + scene("v1_k1e4.json") + " --csv \"\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--csv: must name a file (got an empty path)"), std::string::npos) << r.err;
  r = run(std::string("run ") + scene("v1_k1e4.json") + " --csv " + scratch().string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--csv '" + scratch().string() + "': is a directory"), std::string::npos) << r.err;
  if (fs::exists("/dev/full")) {
    r = run(std::string("run ") + scene("v1_k1e4.json") + " --csv /dev/full");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("cannot write '/dev/full': No space left on device"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));  // written to, not replaced by a file
    EXPECT_FALSE(fs::exists("/dev/full.partial"));
  }
}

// A key given twice in one object of the scene file, at any depth, is an
// error naming it (a JSON parser keeps the last one silently); the same key in
// different objects is not.
TEST(Cli, AKeyGivenTwiceIsAnErrorNamingIt) {
  const std::string original = slurp(scene("v1_k1e4.json"));
  const auto with = [&](const std::string& find, const std::string& insert) {
    const std::size_t at = original.find(find);
    EXPECT_NE(at, std::string::npos) << find;
    const fs::path file = scratch() / "twice.json";
    std::ofstream(file) << original.substr(0, at + find.size()) << insert << original.substr(at + find.size());
    return file;
  };
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  struct Case {
    const char* after;
    const char* insert;
    const char* message;
  };
  for (const Case& c : {Case{"\"name\": \"v1_k1e4\",", " \"name\": \"again\",", "scene key 'name': given twice"},
                        Case{"\"mass\": 1.0,", " \"mass\": 2.0,", "scene key 'dem.particles.0.mass': given twice"},
                        Case{"\"time\": {", " \"end\": 1, ", "scene key 'time.end': given twice"},
                        Case{"\"name\": \"v\",", " \"quantity\": \"position\",",
                             "scene key 'output.probes.1.quantity': given twice"}}) {
    const Result r = run("run " + with(c.after, c.insert).string() + " --csv " + csv.string());
    EXPECT_EQ(r.exit_code, 2) << c.message;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(csv));
  }
}

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
