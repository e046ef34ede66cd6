// The momentum probe of scenes-2d.md in scenes of particles alone: Σ m v of
// the particles along a component. Contacts between particles push equally
// and oppositely, so with gravity the only external force the momentum is
// p(0) + (Σ m) g t, which the test computes itself.
#include <gtest/gtest.h>

#include <cfloat>
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

struct Body {
  double mass, x, y, vx, vy;
};
// Three disks/spheres that meet head on and obliquely within 0.05 s.
const Body kBodies[] = {{1.5, 0.0, 0.0, 2.0, 0.3}, {0.7, 0.13, 0.02, -1.0, 0.0}, {2.2, 0.06, 0.14, 0.0, -1.5}};
const double kGravity[] = {1.2, -9.81, 0.4};

std::string scene(int dim, const std::string& of, int component) {
  std::ostringstream o;
  o.precision(17);
  auto vec = [&](double a, double b, double c) {
    std::ostringstream v;
    v.precision(17);
    v << "[" << a << ", " << b << (dim == 3 ? ", " + std::to_string(c) : std::string()) << "]";
    return v.str();
  };
  o << R"({ "dimension": )" << dim << R"(, "gravity": )" << vec(kGravity[0], kGravity[1], kGravity[2])
    << R"(, "time": { "end": 0.1, "dt": 1e-5 },
  "dem": { "integrator": "verlet",
    "contact": { "law": "linear", "damping_ratio": 0.2, "friction": 0.4, "tangential_stiffness_ratio": 0.5 },
    "particles": [)";
  for (int i = 0; i < 3; ++i)
    o << (i ? ", " : "") << R"({ "mass": )" << kBodies[i].mass << R"(, "radius": 0.05, "stiffness": 1e5, "position": )"
      << vec(kBodies[i].x, kBodies[i].y, 0.0) << R"(, "velocity": )" << vec(kBodies[i].vx, kBodies[i].vy, 0.0) << " }";
  o << R"( ] },
  "output": { "every": 0.1, "probes": [ { "name": "p", "quantity": "momentum", "of": ")" << of
    << R"(", "component": )" << component << R"( } ] } })";
  return o.str();
}

TEST(MomentumCli, ParticlesMomentumIsTheInitialOnePlusTheWeightsImpulse) {
  const fs::path dir = xfdem::testing::scratch("momentum_cli_test");
  for (int dim : {2, 3})
    for (int c = 0; c < dim; ++c)
      for (const char* of : {"total", "particles"}) {
        const fs::path file = dir / "m.json", csv = dir / "m.csv";
        std::ofstream(file) << scene(dim, of, c);
        const auto r = run("run " + file.string() + " --csv " + csv.string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::vector<double> row = xfdem::testing::last_csv_row(csv);
        ASSERT_EQ(row.size(), 2u);
        double p0 = 0, m = 0, scale = 0;
        for (const Body& b : kBodies) {
          const double v = c == 0 ? b.vx : c == 1 ? b.vy : 0.0;
          p0 += b.mass * v;
          m += b.mass;
          scale += b.mass * (std::fabs(b.vx) + std::fabs(b.vy));
        }
        const double expected = p0 + m * kGravity[c] * row[0];
        // 1e4 steps of equal and opposite contact forces: round-off only
        EXPECT_NEAR(row[1], expected, 1e4 * DBL_EPSILON * (scale + m * 9.81 * row[0]))
            << "dimension " << dim << ", component " << c << ", of " << of;
      }
}

TEST(MomentumCli, ContinuumMomentumWithoutAContinuumIsRefusedNamingTheKey) {
  const fs::path dir = xfdem::testing::scratch("momentum_cli_test");
  const fs::path file = dir / "c.json", csv = dir / "c.csv";
  std::ofstream(file) << scene(2, "continuum", 0);
  const auto r = run("run " + file.string() + " --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("output.probes.0.of"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
  std::ofstream(file) << scene(2, "total", 2);
  const auto r2 = run("run " + file.string() + " --csv " + csv.string());
  EXPECT_EQ(r2.exit_code, 2);
  EXPECT_NE(r2.err.find("output.probes.0.component"), std::string::npos) << r2.err;
}

}  // namespace
