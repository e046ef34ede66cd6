// The hertz law through the command line (scenes-2d.md, "Particles: rotation
// and friction"): `law: hertz`, `restitution`, the particles' and planes'
// `youngs_modulus` and `poisson_ratio`; a disk resting on an elastic floor,
// the same bits on two threads, and bad keys refused by name.
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

xfdem::testing::CommandResult run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }

constexpr double kMass = 0.1, kRadius = 0.05, kE = 1e7, kNu = 0.3, kG = 9.81;

/// A disk on the floor y = 0 (both E = 1e7, ν = 0.3), started at the static
/// Hertz overlap m g = 4/3 E* √r δ^{3/2}, E* = E / (2 (1 − ν²)).
std::string resting_disk(const std::string& extra_contact, const std::string& extra_particle) {
  const double e_star = kE / (2 * (1 - kNu * kNu));
  const double overlap = std::pow(kMass * kG / (4.0 / 3.0 * e_star * std::sqrt(kRadius)), 2.0 / 3.0);
  std::ostringstream o;
  o.precision(17);
  o << R"({ "dimension": 2, "gravity": [0, -9.81], "time": { "end": 0.5, "dt": 1e-4 },
  "dem": { "integrator": "verlet",
    "contact": { "law": "hertz", "restitution": 0.5, "friction": 0.3)" << extra_contact << R"( },
    "particles": [ { "name": "d1", "mass": 0.1, "radius": 0.05, "youngs_modulus": 1e7, )" << extra_particle
    << R"("position": [0, )" << kRadius - overlap << R"(] } ],
    "planes": [ { "name": "floor", "point": [0, 0], "normal": [0, 1], "youngs_modulus": 1e7, "poisson_ratio": 0.3 } ] },
  "output": { "every": 0.25, "probes": [
    { "name": "fn", "quantity": "contact_force", "between": ["d1", "floor"] },
    { "name": "ft", "quantity": "contact_force", "between": ["d1", "floor"], "part": "tangential" },
    { "name": "y", "quantity": "position", "particle": "d1", "component": 1 } ] } })";
  return o.str();
}

// At rest on the floor: the Hertz force at the static overlap carries m g
// (round-off of the overlap's 2/3 power and of the steps), no tangential load.
TEST(HertzCli, RestingDiskCarriesItsWeight) {
  const fs::path dir = xfdem::testing::scratch("hertz_cli_test");
  const fs::path scene = dir / "rest.json", csv = dir / "rest.csv";
  std::ofstream(scene) << resting_disk("", R"("poisson_ratio": 0.3, )");
  const auto r = run("run " + scene.string() + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<double> row = xfdem::testing::last_csv_row(csv);
  ASSERT_EQ(row.size(), 4u);
  EXPECT_NEAR(row[0], 0.5, 1e-12);
  EXPECT_NEAR(row[1], kMass * kG, 1e-9 * kMass * kG);
  EXPECT_NEAR(row[2], 0.0, 1e-9 * kMass * kG);
}

TEST(HertzCli, TwoThreadsGiveTheSameBits) {
  const fs::path dir = xfdem::testing::scratch("hertz_cli_test");
  const fs::path scene = dir / "rest2.json", a = dir / "one.csv", b = dir / "two.csv";
  std::ofstream(scene) << resting_disk("", R"("poisson_ratio": 0.3, "velocity": [0.1, 0.2], )");
  ASSERT_EQ(run("run " + scene.string() + " --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + scene.string() + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(xfdem::testing::slurp(a), xfdem::testing::slurp(b));
}

TEST(HertzCli, BadKeysAreRefusedByName) {
  const fs::path dir = xfdem::testing::scratch("hertz_cli_test");
  auto refused = [&](const std::string& contact, const std::string& particle, const std::string& expect) {
    const fs::path scene = dir / "bad.json", csv = dir / "bad.csv";
    std::ofstream(scene) << resting_disk(contact, particle);
    const auto r = run("run " + scene.string() + " --csv " + csv.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
  };
  refused("", "", "poisson_ratio");          // a hertz particle without ν
  refused("", "", "missing");
  refused(R"(, "damping_ratio": 0.1)", R"("poisson_ratio": 0.3, )", "dem.contact.damping_ratio");
  refused("", R"("poisson_ratio": 0.5, )", "poisson_ratio");
  refused("", R"("poisson_ratio": 0.3, "stiffness": 1e5, )", "stiffness");
}

}  // namespace
