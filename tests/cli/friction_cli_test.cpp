// Rotation and friction through the command line (scenes-2d.md, "Particles:
// rotation and friction"): a disk sliding down an incline, read by the
// probes angular_velocity, rotation and contact_force (normal, tangential).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/command.hpp"

namespace {
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

xfdem::testing::CommandResult run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }

/// A disk (m = 1, r = 0.05, k = 1e6) on a slope of 40° with μ = 0.2: above
/// tan θ = 3μ it slides. The plane is named "slope".
std::string incline_scene(const std::string& integrator) {
  const double theta = 40 * kPi / 180, g = 9.81;
  const double height = 0.05 - g * std::cos(theta) / 1e6;
  std::ostringstream o;
  o.precision(17);
  o << R"({ "dimension": 2, "gravity": [0, -9.81], "time": { "end": 0.3, "dt": 1e-5 },
  "dem": { "integrator": ")" << integrator << R"(",
    "contact": { "damping_ratio": 0.5, "friction": 0.2, "tangential_stiffness_ratio": 0.25 },
    "particles": [ { "name": "d1", "mass": 1, "radius": 0.05, "stiffness": 1e6,
                     "position": [)" << -std::sin(theta) * height << ", " << std::cos(theta) * height << R"(],
                     "angular_velocity": 0 } ],
    "planes": [ { "name": "slope", "point": [0, 0], "normal": [)" << -std::sin(theta) << ", " << std::cos(theta) << R"(] } ] },
  "output": { "every": 0.1, "probes": [
    { "name": "w", "quantity": "angular_velocity", "particle": "d1" },
    { "name": "angle", "quantity": "rotation", "particle": "d1" },
    { "name": "fn", "quantity": "contact_force", "between": ["d1", "slope"] },
    { "name": "ft", "quantity": "contact_force", "between": ["d1", "slope"], "part": "tangential" } ] } })";
  return o.str();
}

// Sliding: the tangential force is the Coulomb cap μ F_n exactly, and the
// force the disk puts on the slope points down it, i.e. against the tangent
// t = (−n_y, n_x) of n from the disk to the slope; the friction torque spins
// the disk up counter-clockwise (ω > 0) at μ m g cos θ r / I = 2 μ g cos θ / r,
// which after 0.3 s (past the spring's start-up, a few ms) is within the
// start-up's share of it; the angle turned is positive. Verlet, and
// abm4_events (which carries friction as the other integrators do).
void sliding_disk_reads_the_cap_and_the_spin_up(const std::string& integrator) {
  SCOPED_TRACE(integrator);
  const fs::path dir = xfdem::testing::scratch("friction_cli_test");
  const fs::path scene = dir / ("incline_" + integrator + ".json"), csv = dir / ("incline_" + integrator + ".csv");
  std::ofstream(scene) << incline_scene(integrator);
  const auto r = run("run " + scene.string() + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> row = xfdem::testing::last_csv_row(csv);
  ASSERT_EQ(row.size(), 5u);
  const double t = row[0], w = row[1], angle = row[2], fn = row[3], ft = row[4];
  const double theta = 40 * kPi / 180, g = 9.81, mu = 0.2;
  EXPECT_NEAR(t, 0.3, 1e-12);
  EXPECT_NEAR(fn, g * std::cos(theta), 1e-6 * g);  // the static overlap's force, settled
  EXPECT_NEAR(ft, -mu * fn, 1e-12 * fn);
  const double alpha = 2 * mu * g * std::cos(theta) / 0.05;
  EXPECT_GT(w, 0.0);
  EXPECT_NEAR(w, alpha * t, 0.01 * alpha * t);  // the stick before the first slip lasts < 1 % of 0.3 s
  EXPECT_GT(angle, 0.0);
}
TEST(FrictionCli, SlidingDiskProbesReadTheCoulombCapAndTheSpinUp) {
  sliding_disk_reads_the_cap_and_the_spin_up("verlet");
  sliding_disk_reads_the_cap_and_the_spin_up("abm4_events");
}

// The same bits on two threads, and a replay of the per-step state hashes
// (angular velocities, angles and tangential springs included) agrees.
TEST(FrictionCli, TwoThreadsAndReplayGiveTheSameBits) {
  const fs::path dir = xfdem::testing::scratch("friction_cli_test");
  const fs::path scene = dir / "incline2.json", a = dir / "one.csv", b = dir / "two.csv", hashes = dir / "run.hashes";
  std::ofstream(scene) << incline_scene("symplectic_euler");
  ASSERT_EQ(run("run " + scene.string() + " --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + scene.string() + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(xfdem::testing::slurp(a), xfdem::testing::slurp(b));
  ASSERT_EQ(run("replay record " + scene.string() + " --steps 3000 --out " + hashes.string()).exit_code, 0);
  const auto check = run("replay check " + scene.string() + " --steps 3000 --against " + hashes.string());
  EXPECT_EQ(check.exit_code, 0) << check.err << check.out;
  // A different friction changes the hashes: the check sees the rotation state.
  const auto other = run("replay check " + scene.string() + " --set dem.contact.friction=0.21 --steps 3000 --against " +
                         hashes.string());
  EXPECT_NE(other.exit_code, 0);
}

// abm4_events with friction takes a fixed all-pairs list (docs/dem.md): a
// scene file without dem.all_pairs_up_to pairs its 20 disks all with all
// instead of being refused. The disks rest apart on a floor at the static
// overlap m g / k and stay there (every force balanced: the height and zero
// spin, to the overlap's round-off); with the kernel's own bound given
// (all_pairs_up_to 8) the scene is refused naming the integrator.
TEST(FrictionCli, Abm4EventsWithFrictionPairsAllWithAll) {
  const fs::path dir = xfdem::testing::scratch("friction_cli_test");
  const fs::path scene = dir / "row.json", csv = dir / "row.csv";
  const double m = 0.2, r = 0.01, k = 1e5, g = 9.81, rest = r - m * g / k;
  std::ostringstream o;
  o.precision(17);
  o << R"({ "dimension": 2, "gravity": [0, -9.81], "time": { "end": 0.05, "dt": 1e-5 },
  "dem": { "integrator": "abm4_events",
    "contact": { "damping_ratio": 0.3, "friction": 0.5, "tangential_stiffness_ratio": 0.25 }, "particles": [)";
  for (int i = 0; i < 20; ++i)
    o << (i ? ", " : "") << R"({ "name": "d)" << i << R"(", "mass": )" << m << R"(, "radius": )" << r
      << R"(, "stiffness": )" << k << R"(, "position": [)" << 0.03 * i << ", " << rest << "] }";
  o << R"(],
    "planes": [ { "name": "floor", "point": [0, 0], "normal": [0, 1] } ] },
  "output": { "every": 0.05, "probes": [
    { "name": "y0", "quantity": "position", "particle": "d0", "component": 1 },
    { "name": "y19", "quantity": "position", "particle": "d19", "component": 1 },
    { "name": "w7", "quantity": "angular_velocity", "particle": "d7" } ] } })";
  std::ofstream(scene) << o.str();
  const auto r1 = run("run " + scene.string() + " --csv " + csv.string());
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  const std::vector<double> row = xfdem::testing::last_csv_row(csv);
  ASSERT_EQ(row.size(), 4u);
  EXPECT_NEAR(row[1], rest, 1e-15);
  EXPECT_NEAR(row[2], rest, 1e-15);
  EXPECT_EQ(row[3], 0.0);
  const auto r2 = run("run " + scene.string() + " --set dem.all_pairs_up_to=8 --csv " + csv.string());
  EXPECT_NE(r2.exit_code, 0);
  EXPECT_NE(r2.err.find("scene key 'dem.integrator': abm4_events with friction, rolling friction, the hertz law or a "
                        "spinning particle takes the pairs of broad phase none or all_pairs (20 particles need the grid"),
            std::string::npos)
      << r2.err;
}

// The report's disk: a spin given in a frictionless linear scene is kept (it
// was dropped: ω and the kinetic energy read 0 from t = 0), ½ I ω² =
// 0.030625 J counted, the angle ω t turned.
TEST(FrictionCli, SpinWithoutFrictionIsKept) {
  const fs::path dir = xfdem::testing::scratch("friction_cli_test");
  const fs::path scene = dir / "spin.json", csv = dir / "spin.csv";
  std::ofstream(scene) << R"({ "dimension": 2, "gravity": [0, 0], "time": { "end": 0.1, "dt": 1e-4 },
  "dem": { "integrator": "verlet", "contact": { "law": "linear", "damping_ratio": 0.1 },
    "particles": [ { "name": "d1", "mass": 1, "radius": 0.05, "stiffness": 1e6, "position": [0, 1],
                     "angular_velocity": 7.0 } ] },
  "output": { "every": 0.05, "probes": [ { "name": "w", "particle": "d1", "quantity": "angular_velocity" },
    { "name": "angle", "particle": "d1", "quantity": "rotation" },
    { "name": "Ek", "quantity": "energy", "of": "kinetic" } ] } })";
  const auto r = run("run " + scene.string() + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const std::vector<double> row = xfdem::testing::last_csv_row(csv);
  ASSERT_EQ(row.size(), 4u);
  EXPECT_EQ(row[1], 7.0);
  EXPECT_NEAR(row[2], 0.7, 1e-13);
  EXPECT_NEAR(row[3], 0.030625, 1e-17);
}

// Keys without effect are accepted (a sweep of μ down to 0 keeps its other
// keys) but said on stderr, naming the key and why: the tangential stiffness
// ratio with friction 0, a particle's inertia on a line or in a model whose
// particles do not rotate. The run is the same as without them.
TEST(FrictionCli, KeysWithoutEffectAreWarnings) {
  const fs::path dir = xfdem::testing::scratch("friction_cli_test");
  auto scene_with = [&](const std::string& name, int dimension, const std::string& contact, const std::string& extra) {
    const fs::path scene = dir / (name + ".json");
    const std::string zeros = dimension == 1 ? "0" : "0, 0";
    std::ofstream(scene) << R"({ "dimension": )" << dimension << R"(, "gravity": [)" << (dimension == 1 ? "-9.81" : "0, -9.81")
                         << R"(], "time": { "end": 0.01, "dt": 1e-4 },
  "dem": { "integrator": "verlet", "contact": { "damping_ratio": 0.1)" << contact << R"( },
    "particles": [ { "name": "p", "mass": 1, "radius": 0.05, "stiffness": 1e6, "position": [)"
                         << (dimension == 1 ? "0.2" : "0, 0.2") << "]" << extra << R"( } ],
    "planes": [ { "point": [)" << zeros << R"(], "normal": [)" << (dimension == 1 ? "1" : "0, 1") << R"(] } ] },
  "output": { "every": 0.005, "probes": [ { "name": "y", "particle": "p", "quantity": "position", "component": )"
                         << dimension - 1 << R"( } ] } })";
    return scene;
  };
  const std::string ratio_warning =
      "xfdem: warning: dem.contact.tangential_stiffness_ratio: has no effect: friction is 0, so the contacts carry no "
      "tangential spring\n";
  {
    const auto r = run("run " + scene_with("line", 1, R"(, "tangential_stiffness_ratio": 0.5)", R"(, "inertia": 0.3)")
                                    .string() +
                       " --csv " + (dir / "line.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(ratio_warning), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("xfdem: warning: dem.particles.0.inertia: has no effect: rods on a line do not rotate\n"),
              std::string::npos)
        << r.err;
    const auto plain = run("run " + scene_with("line_plain", 1, "", "").string() + " --csv " +
                           (dir / "line_plain.csv").string());
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_EQ(plain.err.find("warning"), std::string::npos) << plain.err;
    EXPECT_EQ(xfdem::testing::slurp(dir / "line.csv"), xfdem::testing::slurp(dir / "line_plain.csv"));
  }
  {
    const auto r = run("run " + scene_with("plane2d", 2, R"(, "friction": 0, "tangential_stiffness_ratio": 0.5)",
                                           R"(, "inertia": 0.003)")
                                    .string() +
                       " --csv " + (dir / "plane2d.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(ratio_warning), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("xfdem: warning: dem.particles.0.inertia: has no effect: the particles do not rotate (no "
                         "friction, rolling_friction, hertz law or angular_velocity)\n"),
              std::string::npos)
        << r.err;
  }
  {  // with friction, or a spin, neither is said
    const auto r = run("run " + scene_with("rough", 2, R"(, "friction": 0.3, "tangential_stiffness_ratio": 0.5)",
                                           R"(, "inertia": 0.003)")
                                    .string() +
                       " --csv " + (dir / "rough.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const auto spin = run("run " + scene_with("spin", 2, "", R"(, "inertia": 0.003, "angular_velocity": 2)").string() +
                          " --csv " + (dir / "spin.csv").string());
    ASSERT_EQ(spin.exit_code, 0) << spin.err;
    EXPECT_EQ(spin.err.find("warning"), std::string::npos) << spin.err;
  }
}

}  // namespace
