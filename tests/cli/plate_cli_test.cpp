// The plate through the command line (scenes-2d.md, "The 2D continuum: a
// plate"): static and dynamic runs, the same bytes on one and two workers, a
// tied crack and a hole, and the keys of later slices and bad plate input
// refused with the key named.
#include <gtest/gtest.h>

#include "support/command.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using xfdem::testing::slurp;
using Result = xfdem::testing::CommandResult;

fs::path scratch() { return xfdem::testing::scratch("plate_cli_test"); }
Result run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }
std::string tension() { return xfdem::testing::scene_file("plate_tension.json"); }
std::string cracked() { return xfdem::testing::scene_file("plate_crack.json"); }
std::string holed() { return xfdem::testing::scene_file("plate_hole.json"); }

std::vector<std::string> lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<double> values(const std::string& row) {
  std::vector<double> out;
  std::stringstream s(row);
  for (std::string cell; std::getline(s, cell, ',');) out.push_back(std::stod(cell));
  return out;
}

}  // namespace

// Static: one row at t = 0 with the closed form of uniaxial tension in plane
// stress (u = σ0 L / E at the loaded edge, σ_xx = σ0, σ_yy = σ_xy = 0).
TEST(PlateCli, StaticAnalysisWritesOneRowAtTimeZero) {
  const fs::path csv = scratch() / "static.csv";
  const Result r = run("run " + tension() + " --set continuum.analysis=static --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(csv);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], "t,u_tip,v_tip,a_tip,uy_top,sxx_mid,syy_mid,sxy_mid,E_total,E_kinetic,E_elastic,p_x");
  const auto v = values(rows[1]);
  ASSERT_EQ(v.size(), 12u);
  EXPECT_EQ(v[0], 0.0);
  const double sigma0 = 1e6, e = 2e11, nu = 0.3;
  EXPECT_NEAR(v[1], sigma0 * 2.0 / e, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[4], -nu * sigma0 * 1.0 / e, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[5], sigma0, 256 * 2.2e-16 * sigma0);
  EXPECT_NEAR(v[6], 0.0, 256 * 2.2e-16 * sigma0);
  EXPECT_NEAR(v[7], 0.0, 256 * 2.2e-16 * sigma0);
  EXPECT_EQ(v[2], 0.0);
  EXPECT_EQ(v[3], 0.0);
}

// A static scene needs neither a time block nor output.every.
TEST(PlateCli, StaticSceneNeedsNoTimeBlock) {
  std::string text = slurp(tension());
  const auto time = text.find("\"time\"");
  text.erase(time, text.find('\n', time) - time + 1);
  const auto every = text.find("\"every\"");
  text.erase(every, text.find('\n', every) - every + 1);
  const auto dyn = text.find("\"dynamic\"");
  text.replace(dyn, 9, "\"static\"");
  const fs::path scene = scratch() / "static_plate.json";
  std::ofstream(scene) << text;
  const fs::path csv = scratch() / "static_no_time.csv";
  const Result r = run("run " + scene.string() + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines(csv).size(), 2u);
}

TEST(PlateCli, DynamicRunIsTheSameOnOneAndTwoWorkers) {
  const fs::path a = scratch() / "one.csv", b = scratch() / "two.csv";
  ASSERT_EQ(run("run " + tension() + " --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + tension() + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  const auto rows = lines(a);
  EXPECT_EQ(rows.size(), 202u);  // header + t = 0, 1e-5, ..., 2e-3
  // The traction's impulse: p_x = σ0 · (height · thickness) · t exactly for
  // the trapezoidal rule (the held left edge pushes back only once the wave
  // reaches it: after 2 m / c_p ≈ 3.8e-4 s, so compare before).
  const auto v = values(rows[11]);  // t = 1e-4
  EXPECT_NEAR(v[11], 1e6 * 0.02 * 1e-4, 1e-9 * 2.0);
}

// The tied crack across the strip, static: the traction passes the crack
// unchanged, so σ_xx = σ0 everywhere, the crack opens by σ0 / k_n, does not
// slide, and the loaded edge moves by σ0 L / E + σ0 / k_n.
TEST(PlateCli, TiedCrackOpensBySigmaOverItsStiffness) {
  const fs::path csv = scratch() / "crack_static.csv";
  const Result r = run("run " + cracked() + " --set continuum.analysis=static --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(csv);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], "t,u_tip,opening,sliding,sxx_mid,E_total,E_elastic,p_x");
  const auto v = values(rows[1]);
  const double sigma0 = 1e6, e = 2e11, kn = 1e13, length = 2.0;
  EXPECT_NEAR(v[1], sigma0 * length / e + sigma0 / kn, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[2], sigma0 / kn, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[3], 0.0, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[4], sigma0, 256 * 2.2e-16 * sigma0);
}

// The same crack made unilateral and pushed (traction −σ0): the faces close
// and the closed form is that of the tied faces with the sign turned.
TEST(PlateCli, UnilateralCrackClosesUnderCompression) {
  const fs::path csv = scratch() / "crack_unilateral.csv";
  const Result r = run("run " + cracked() +
                       " --set continuum.analysis=static --set continuum.discontinuities.0.faces=unilateral "
                       "--set continuum.loads.0.traction=[-1e6,0] --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(csv);
  ASSERT_EQ(rows.size(), 2u);
  const auto v = values(rows[1]);
  const double sigma0 = -1e6, e = 2e11, kn = 1e13, length = 2.0;
  EXPECT_NEAR(v[1], sigma0 * length / e + sigma0 / kn, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[2], sigma0 / kn, 64 * 2.2e-16 * 1e-5);
  EXPECT_NEAR(v[3], 0.0, 64 * 2.2e-16 * 1e-5);  // frictionless: no tangential penalty, and no shear to carry
  EXPECT_NEAR(v[4], sigma0, 256 * 2.2e-16 * 1e6);
}

// The tied crack ending inside the strip (a tip at (1.03, 0.73)), static:
// the faces' springs (k_n = 1e13 Pa/m) carry the traction across the crack,
// so the loaded edge moves as the uncracked strip's σ0 L / E plus at most
// the faces' opening σ0 / k_n, and the crack opens by σ0 / k_n within 10 %
// (two cells from the tip the discrete opening swings about σ/k_n by up to
// that: tests/xfem/plate_tip_faces_test.cpp); the dynamic run is the same on
// one and two workers.
TEST(PlateCli, TiedCrackWithATipRuns) {
  const std::string tip = " --set 'continuum.discontinuities.0.points=[[1.03,-0.1],[1.03,0.73]]'";
  const fs::path csv = scratch() / "tip_static.csv";
  const Result r = run("run " + cracked() + tip + " --set continuum.analysis=static --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(csv);
  ASSERT_EQ(rows.size(), 2u);
  const auto v = values(rows[1]);
  const double sigma0 = 1e6, e = 2e11, kn = 1e13, length = 2.0;
  EXPECT_GE(v[1], sigma0 * length / e);
  EXPECT_LE(v[1], sigma0 * length / e + sigma0 / kn);
  EXPECT_NEAR(v[2], sigma0 / kn, 0.1 * sigma0 / kn);
  const fs::path a = scratch() / "tip_one.csv", b = scratch() / "tip_two.csv";
  ASSERT_EQ(run("run " + cracked() + tip + " --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + cracked() + tip + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_EQ(lines(a).size(), 202u);  // header + t = 0, 1e-5, ..., 2e-3
}

TEST(PlateCli, CrackAndHoleScenesAreTheSameOnOneAndTwoWorkers) {
  for (const std::string& scene : {cracked(), holed()}) {
    const fs::path a = scratch() / "cut_one.csv", b = scratch() / "cut_two.csv";
    ASSERT_EQ(run("run " + scene + " --csv " + a.string()).exit_code, 0);
    ASSERT_EQ(run("run " + scene + " --threads 2 --csv " + b.string()).exit_code, 0);
    EXPECT_EQ(slurp(a), slurp(b));
    EXPECT_GE(lines(a).size(), 2u);
  }
}

struct PlateBadInput {
  const char* args;
  const char* must_mention;
};

class PlateCliRejects : public ::testing::TestWithParam<PlateBadInput> {};

TEST_P(PlateCliRejects, WithTheKeyNamedAndNoOutput) {
  const fs::path csv = scratch() / "never.csv";
  fs::remove(csv);
  const Result r = run("run " + tension() + " " + GetParam().args + " --csv " + csv.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(GetParam().must_mention), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
}

INSTANTIATE_TEST_SUITE_P(
    BadValues, PlateCliRejects,
    ::testing::Values(
        PlateBadInput{"--set continuum.tip_enrichment.radius=-0.1",
                      "scene key 'continuum.tip_enrichment.radius': must be >= 0"},
        PlateBadInput{"--set 'dem={\"particles\":[]}' --set continuum.analysis=static",
                      "scene key 'continuum.analysis': particles against the plate need \"dynamic\""},
        PlateBadInput{"--set dimension=1 --set gravity=[0]", "scene key 'dimension': a plate scene must have dimension 2"},
        PlateBadInput{"--set continuum.plane=strain --set continuum.material.poisson_ratio=0.5",
                      "scene key 'continuum.material.poisson_ratio': must be < 0.5 in plane strain"},
        PlateBadInput{"--set continuum.cells=[0,3]", "scene key 'continuum.cells': each count must be in [1, 100000]"},
        PlateBadInput{"--set continuum.cells=[3000,3000]",
                      "scene key 'continuum.cells': 3000 x 3000 needs about 1.08e+11 stored entries per matrix"},
        PlateBadInput{"--set 'continuum.prescribed=[{\"at\":[0.05,0],\"displacement\":[0,0]}]'",
                      "scene key 'continuum.prescribed.0.at': (0.05, 0) is not a node of the mesh"},
        PlateBadInput{"--set 'continuum.prescribed=[{\"at\":[0,0.5],\"displacement\":[1e-3,0]}]'",
                      "scene key 'continuum.prescribed.0.displacement': the node at (0, 0.5) is held at 0 in x"},
        PlateBadInput{"--set continuum.supports=[] --set continuum.analysis=static",
                      "scene key 'continuum.supports': the plate is not held against rigid motion"},
        PlateBadInput{"--set continuum.analysis=static --set continuum.loads.0.shape=half_sine "
                      "--set continuum.loads.0.duration=1",
                      "scene key 'continuum.loads.0.shape': a static analysis has no time"},
        PlateBadInput{"--set continuum.supports.0.edge=middle",
                      "scene key 'continuum.supports.0.edge': 'middle' is not one of"},
        PlateBadInput{"--set continuum.supports.0.fix=[\\\"z\\\"]",
                      "scene key 'continuum.supports.0.fix': components are \"x\" and \"y\""},
        PlateBadInput{"--set continuum.loads.0.force=[1,0]", "scene key 'continuum.loads.0.force': an edge load takes a traction"},
        PlateBadInput{"--set continuum.newmark.beta=0.2", "scene key 'continuum.newmark.beta': must be >= (gamma + 1/2)^2 / 4"},
        PlateBadInput{"--set output.probes.0.at=[3,0]", "scene key 'output.probes.0.at': (3, 0) is outside the plate's domain"},
        PlateBadInput{"--set output.probes.4.component=zz", "scene key 'output.probes.4.component': 'zz' is not one of"},
        PlateBadInput{"--set output.probes.0.quantity=position", "scene key 'output.probes.0.quantity': 'position' is not one of"},
        PlateBadInput{"--set continuum.material.colour=1", "scene key 'continuum.material.colour': unknown key"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[3,0],[3,1]]}]'",
                      "scene key 'continuum.discontinuities.0.points': the crack 'c' does not enter the domain"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[0.43,0.52],[0.57,0.52]]}]'",
                      "scene key 'continuum.discontinuities.0.points': the node at (0.5, 0.5) belongs to the cells of "
                      "two crack tips (the start of 'c' and the end of 'c')"},
        // Branch functions within 0.3 over cells 0.3 x 0.025: nearly dependent.
        PlateBadInput{"--set continuum.domain.max=[3,0.5] --set continuum.cells=[10,20] "
                      "--set continuum.tip_enrichment.radius=0.3 --set 'continuum.discontinuities=[{\"name\":\"c0\","
                      "\"type\":\"crack\",\"points\":[[2.378,0.0589],[2.668,2.012]]},{\"name\":\"c1\",\"type\":"
                      "\"crack\",\"points\":[[2.976,0.3756],[4.178,1.726]]}]' "
                      "--set 'output.probes=[{\"name\":\"E\",\"quantity\":\"energy\",\"of\":\"total\"}]'",
                      "scene key 'continuum.tip_enrichment.radius': the mass matrix is not positive definite to working "
                      "precision: the branch functions within 0.3 of a tip, over cells of 0.3 x 0.025, are nearly "
                      "dependent"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[0.41,0.52],[0.44,0.52]]}]'",
                      "scene key 'continuum.discontinuities.0.points': the crack 'c' from (0.41, 0.52) to (0.44, 0.52) "
                      "lies inside the cell (4, 5)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\","
                      "\"points\":[[-1,0.33],[0.45,0.33],[0.48,0.36]]}]'",
                      "scene key 'continuum.discontinuities.0.points': the crack 'c' bends inside the cell holding its tip "
                      "at (0.48, 0.36)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[-1,0.33],[0.45,0.33]]},"
                      "{\"name\":\"d\",\"type\":\"crack\",\"points\":[[0.48,0.36],[3,0.36]]}]'",
                      "scene key 'continuum.discontinuities.1.points': two crack tips in the cell (4, 3)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[-1,0.3],[1,0.3]],"
                      "\"faces\":\"tied\",\"stiffness\":[1e13,0]}]'",
                      "scene key 'continuum.discontinuities.0.stiffness.1': must be > 0 (got 0)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[-1,0.33],[1,0.33]]},"
                      "{\"name\":\"d\",\"type\":\"crack\",\"points\":[[3,0.63],[1.15,0.63]]}]' "
                      "--set continuum.tip_enrichment.radius=0.3",
                      "scene key 'continuum.tip_enrichment.radius': the node at"},
        PlateBadInput{"--set continuum.analysis=static --set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\","
                      "\"points\":[[1.03,-1],[1.03,2]],\"faces\":\"unilateral\",\"stiffness\":[1e13,1e13]}]'",
                      "'continuum.supports': the plate is not held against rigid motion once its unilateral crack "
                      "faces open"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"polygon\":[[0.2,0.2],[0.6,0.6],"
                      "[0.6,0.2],[0.2,0.6]]}]'",
                      "scene key 'continuum.discontinuities.0.polygon': crosses itself"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"circle\":{\"centre\":[0.5,0.5],"
                      "\"radius\":0.2}},{\"name\":\"i\",\"type\":\"inclusion\",\"circle\":{\"centre\":[0.8,0.5],\"radius\":0.2},"
                      "\"material\":{\"youngs_modulus\":1e9,\"poisson_ratio\":0.2,\"density\":1000}}]'",
                      "scene key 'continuum.discontinuities.1': the inclusion 'i' overlaps the void 'h'"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"circle\":{\"centre\":[1,0.5],"
                      "\"radius\":0.2}}]'",
                      "scene key 'output.probes.4.at': (1, 0.5) is inside void 'h': there is no material there"},
        // A point force or a prescribed node inside a void would act on nothing.
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"circle\":{\"centre\":[0.5,0.5],"
                      "\"radius\":0.2}}]' --set 'continuum.loads=[{\"at\":[0.5,0.5],\"force\":[0,1e5],\"shape\":\"step\"}]'",
                      "scene key 'continuum.loads.0.at': (0.5, 0.5) is inside void 'h': there is no material there"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"circle\":{\"centre\":[0.5,0.5],"
                      "\"radius\":0.2}}]' --set 'continuum.prescribed=[{\"at\":[0.5,0.5],\"displacement\":[0,1e-3]}]'",
                      "scene key 'continuum.prescribed.0.at': (0.5, 0.5) is inside void 'h': there is no material there"},
        // A polygon written closed (its first vertex again at the end), or with
        // a vertex twice in a row, repeats a vertex; it does not cross itself.
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"h\",\"type\":\"void\",\"polygon\":[[0.3,0.3],[0.7,0.3],"
                      "[0.7,0.7],[0.3,0.7],[0.3,0.3]]}]'",
                      "scene key 'continuum.discontinuities.0.polygon': vertex 4 repeats vertex 0 (a polygon closes "
                      "itself; give each vertex once)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"i\",\"type\":\"inclusion\",\"polygon\":[[0.3,0.3],"
                      "[0.7,0.3],[0.7,0.3],[0.7,0.7],[0.3,0.7]],\"material\":{\"youngs_modulus\":1e10,\"poisson_ratio\":0.3,"
                      "\"density\":1000}}]'",
                      "scene key 'continuum.discontinuities.0.polygon': vertex 2 repeats vertex 1 (a polygon closes "
                      "itself; give each vertex once)"},
        // A stress_intensity probe at a crack end that is not a tip: inside a
        // void, on the boundary, outside it, within 1e-6 of a cell of it.
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[-0.1,0.625],[0.5,0.625]]},"
                      "{\"name\":\"h\",\"type\":\"void\",\"circle\":{\"centre\":[0.5,0.5],\"radius\":0.2}}]' "
                      "--set 'output.probes=[{\"name\":\"K\",\"quantity\":\"stress_intensity\",\"crack\":\"c\",\"tip\":\"end\","
                      "\"mode\":\"I\"}]'",
                      "scene key 'output.probes.0.tip': the end of crack 'c' at (0.5, 0.625) is not a crack tip: it ends "
                      "inside void 'h' (no material about it)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[0.5,0.625],[2,0.625]]}]' "
                      "--set 'output.probes=[{\"name\":\"K\",\"quantity\":\"stress_intensity\",\"crack\":\"c\",\"tip\":\"end\","
                      "\"mode\":\"I\"}]'",
                      "scene key 'output.probes.0.tip': the end of crack 'c' at (2, 0.625) is not a crack tip: it ends on "
                      "or outside the plate's boundary (within 1e-6 of a cell counts as on it)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[0.5,0.625],[2.5,0.625]]}]' "
                      "--set 'output.probes=[{\"name\":\"K\",\"quantity\":\"stress_intensity\",\"crack\":\"c\",\"tip\":\"end\","
                      "\"mode\":\"I\"}]'",
                      "scene key 'output.probes.0.tip': the end of crack 'c' at (2.5, 0.625) is not a crack tip: it ends on "
                      "or outside the plate's boundary (within 1e-6 of a cell counts as on it)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[0.5,0.625],[1.99999999999,0.625]]}]' "
                      "--set 'output.probes=[{\"name\":\"K\",\"quantity\":\"stress_intensity\",\"crack\":\"c\",\"tip\":\"end\","
                      "\"mode\":\"I\"}]'",
                      "scene key 'output.probes.0.tip': the end of crack 'c' at (1.99999999999, 0.625) is not a crack tip: it ends on "
                      "or outside the plate's boundary (within 1e-6 of a cell counts as on it)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\",\"points\":[[1,-1],[1,2]]}]'",
                      "scene key 'output.probes.4.at': (1, 0.5) is on a discontinuity"},
        PlateBadInput{"--set continuum.cells=[90000,1] --set 'continuum.discontinuities=[{\"name\":\"c\",\"type\":\"crack\","
                      "\"points\":[[-1,0.37],[3,0.37]]}]'",
                      "'continuum.max_enriched_dofs': the discontinuities need 270001 enriched unknowns, more than 200000"},
        PlateBadInput{"--set output.probes.0.quantity=stress_intensity --set output.probes.0.crack=none",
                      "scene key 'output.probes.0.crack': no crack named 'none'"},
        // A cell may hold one crack and one void or inclusion, not two cracks; a
        // crack tip's branch functions may not reach a cell a crack and an
        // inclusion cut.
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c1\",\"type\":\"crack\",\"points\":[[-1,0.55],[3,0.55]]},"
                      "{\"name\":\"c2\",\"type\":\"crack\",\"points\":[[1.05,-1],[1.05,2]]}]'",
                      "scene key 'continuum.discontinuities.1': 'c2' and 'c1' cut the same cell (10, 5); this build allows "
                      "one discontinuity per cell, or one crack and one void or inclusion (refine the mesh or move them "
                      "apart)"},
        PlateBadInput{"--set 'continuum.discontinuities=[{\"name\":\"c1\",\"type\":\"crack\",\"points\":[[-1,0.55],[1.02,0.55]]},"
                      "{\"name\":\"i\",\"type\":\"inclusion\",\"circle\":{\"centre\":[0.8,0.55],\"radius\":0.23},"
                      "\"material\":{\"youngs_modulus\":1e9,\"poisson_ratio\":0.2,\"density\":1000}}]'",
                      "scene key 'continuum.discontinuities.0': a crack tip's branch functions reach the cell (10, 5) that "
                      "the crack 'c1' and the inclusion 'i' both cut; this build needs a tip at least a cell from such a "
                      "cell (refine the mesh or move the tip from the inclusion's boundary)"}));

// A crack through an inclusion (cells cut by both; refused before the two
// could share a cell): the plate alone runs, the same bytes on one and two
// workers; so does a coupled scene with such a cell (its contact boundary
// traces the crack's faces there, not the inclusion's boundary).
TEST(PlateCli, CrackThroughAnInclusionRunsAloneAndCoupled) {
  const std::string disc =
      " --set 'continuum.discontinuities=[{\"name\":\"c1\",\"type\":\"crack\",\"points\":[[-1,0.55],[3,0.55]]},"
      "{\"name\":\"i\",\"type\":\"inclusion\",\"circle\":{\"centre\":[0.8,0.55],\"radius\":0.23},"
      "\"material\":{\"youngs_modulus\":1e9,\"poisson_ratio\":0.2,\"density\":1000}}]'";
  const std::string probes =
      " --set 'output.probes=[{\"name\":\"u\",\"quantity\":\"displacement\",\"at\":[2,0.5],\"component\":0},"
      "{\"name\":\"open\",\"quantity\":\"crack_opening\",\"crack\":\"c1\",\"at\":[0.8,0.55],\"component\":\"normal\"},"
      "{\"name\":\"s\",\"quantity\":\"stress\",\"at\":[0.8,0.45],\"component\":\"xx\"}]'";
  const fs::path a = scratch() / "crack_inclusion_one.csv", b = scratch() / "crack_inclusion_two.csv";
  const Result one = run("run " + tension() + disc + probes + " --csv " + a.string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(run("run " + tension() + disc + probes + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  const auto rows = lines(a);
  ASSERT_GE(rows.size(), 2u);
  for (std::size_t k = 1; k < rows.size(); ++k)
    for (double v : values(rows[k])) EXPECT_TRUE(std::isfinite(v)) << rows[k];
  const fs::path c = scratch() / "crack_inclusion_coupled.csv", e = scratch() / "crack_inclusion_coupled_two.csv";
  const std::string coupled_scene = "run " + xfdem::testing::scene_file("coupled2d_free_plate.json") +
                                    " --set continuum.cells=[20,10] --set 'output.probes=[]'" + disc;
  const Result coupled = run(coupled_scene + " --csv " + c.string());
  ASSERT_EQ(coupled.exit_code, 0) << coupled.err;
  ASSERT_EQ(run(coupled_scene + " --threads 2 --csv " + e.string()).exit_code, 0);
  EXPECT_EQ(slurp(c), slurp(e));
  const auto coupled_rows = lines(c);
  ASSERT_GE(coupled_rows.size(), 2u);
  for (std::size_t k = 1; k < coupled_rows.size(); ++k)
    for (double v : values(coupled_rows[k])) EXPECT_TRUE(std::isfinite(v)) << coupled_rows[k];
}

// A crack from a void (one cell cut by both): the plate alone runs, the same
// bytes on one and two workers; so does a coupled scene with such a cell
// (its contact boundary traces the void on each side of the crack and the
// faces outside it).
TEST(PlateCli, CrackFromAVoidRunsAloneAndCoupled) {
  const std::string disc =
      " --set 'continuum.discontinuities=[{\"name\":\"hole\",\"type\":\"void\",\"circle\":{\"centre\":[0.8,0.55],"
      "\"radius\":0.23}},{\"name\":\"c1\",\"type\":\"crack\",\"points\":[[0.9,0.55],[1.45,0.55]]}]'";
  const std::string probes =
      " --set 'output.probes=[{\"name\":\"u\",\"quantity\":\"displacement\",\"at\":[2,0.5],\"component\":0},"
      "{\"name\":\"open\",\"quantity\":\"crack_opening\",\"crack\":\"c1\",\"at\":[1.2,0.55],\"component\":\"normal\"}]'";
  const fs::path a = scratch() / "crack_void_one.csv", b = scratch() / "crack_void_two.csv";
  const Result one = run("run " + tension() + disc + probes + " --csv " + a.string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(run("run " + tension() + disc + probes + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_GE(lines(a).size(), 2u);
  const fs::path c = scratch() / "crack_void_coupled.csv", e = scratch() / "crack_void_coupled_two.csv";
  const std::string coupled_scene = "run " + xfdem::testing::scene_file("coupled2d_free_plate.json") +
                                    " --set continuum.cells=[20,10] --set 'output.probes=[]'" + disc;
  const Result coupled = run(coupled_scene + " --csv " + c.string());
  ASSERT_EQ(coupled.exit_code, 0) << coupled.err;
  ASSERT_EQ(run(coupled_scene + " --threads 2 --csv " + e.string()).exit_code, 0);
  EXPECT_EQ(slurp(c), slurp(e));
  EXPECT_GE(lines(c).size(), 2u);
}

std::string driven() { return xfdem::testing::scene_file("plate_driven.json"); }

// A column driven at its top by a prescribed half sine (scenes/plate_driven.json,
// an extension of the scene spec: docs/xfem2d.md, "Prescribed nodes with a
// time shape"): the top follows d sin(πt/T) for t ≤ T and then stays at 0, the
// run is byte-identical on one and two workers, and the energy check (every
// step, tolerance 1e-9 of the energy in motion) stays silent.
TEST(PlateCli, DrivenColumnFollowsItsHalfSine) {
  const fs::path a = scratch() / "driven_one.csv", b = scratch() / "driven_two.csv";
  const Result one = run("run " + driven() + " --csv " + a.string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.err.find("energy_growth"), std::string::npos) << one.err;
  const Result two = run("run " + driven() + " --threads 2 --csv " + b.string());
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(slurp(a), slurp(b));
  const auto rows = lines(a);
  ASSERT_EQ(rows.size(), 32u);  // header + t = 0, 0.01, ..., 0.3
  EXPECT_EQ(rows[0], "t,u_top,u_mid,v_mid,syy_mid,E_total,p_y");
  const double d = 1e-3, duration = 0.1;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto v = values(rows[k]);
    const double t = v[0];
    const double expected = t <= duration ? d * std::sin(3.141592653589793 * t / duration) : 0.0;
    EXPECT_NEAR(v[1], expected, 4 * 2.2e-16 * d) << "t = " << t;
  }
}

// The prescribed shape's keys refused with the whole message (stderr is that line alone).
TEST(PlateCli, PrescribedShapeKeysAreRefusedExactly) {
  struct Case {
    const char* set;
    const char* message;
  };
  const std::string node = "{\"at\":[2,1],\"displacement\":[1e-6,0]";
  for (const Case& c : {
           Case{",\"shape\":\"ramp\"}", "scene key 'continuum.prescribed.0.duration': missing (required)"},
           Case{",\"shape\":\"ramp\",\"duration\":0}", "scene key 'continuum.prescribed.0.duration': must be > 0 (got 0)"},
           Case{",\"shape\":\"half_sine\",\"duration\":-1}",
                "scene key 'continuum.prescribed.0.duration': must be > 0 (got -1)"},
           Case{",\"shape\":\"half_sine\",\"duration\":\"x\"}",
                "scene key 'continuum.prescribed.0.duration': expected a number, got a string"},
           Case{",\"shape\":\"step\",\"duration\":1}",
                "scene key 'continuum.prescribed.0.duration': not used by shape 'step'"},
           Case{",\"duration\":1}", "scene key 'continuum.prescribed.0.duration': not used by shape 'step'"},
           Case{",\"shape\":\"smooth\",\"duration\":1}",
                "scene key 'continuum.prescribed.0.shape': 'smooth' is not one of step | half_sine | ramp"},
       }) {
    const fs::path csv = scratch() / "never.csv";
    fs::remove(csv);
    const Result r = run("run " + tension() + " --set 'continuum.prescribed=[" + node + c.set + "]' --csv " + csv.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(r.err, std::string("xfdem: ") + c.message + "\n");
    EXPECT_FALSE(fs::exists(csv));
  }
  // A shape with a static analysis: no time to shape.
  const Result r = run("run " + tension() + " --set continuum.analysis=static --set 'continuum.prescribed=[" + node +
                       ",\"shape\":\"ramp\",\"duration\":1}]'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.err,
            "xfdem: scene key 'continuum.prescribed.0.shape': a static analysis has no time; ramp needs \"analysis\": "
            "\"dynamic\" (use step)\n");
}

std::string edge_crack() { return xfdem::testing::scene_file("plate_edge_crack.json"); }

// The edge crack in a strip (scenes/plate_edge_crack.json, a/W = 0.4, the
// strip 6W high): K_I through the probe against Tada's F(a/W) within 1 %
// (as the kernel's test), K_II about nothing, and the opening positive.
TEST(PlateCli, EdgeCrackStressIntensityFollowsTada) {
  const fs::path csv = scratch() / "edge_crack.csv";
  const Result r = run("run " + edge_crack() + " --csv " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(csv);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], "t,K_I,K_II,opening,E_elastic");
  const auto v = values(rows[1]);
  const double alpha = 0.4, sigma = 1e6;
  const double f = 1.12 - 0.231 * alpha + 10.55 * alpha * alpha - 21.72 * std::pow(alpha, 3) + 30.39 * std::pow(alpha, 4);
  const double exact = sigma * std::sqrt(std::acos(-1.0) * alpha) * f;
  EXPECT_NEAR(v[1], exact, 0.01 * exact);
  EXPECT_LT(std::fabs(v[2]), 0.01 * exact);
  EXPECT_GT(v[3], 0.0);
}

// A tip nearer the boundary than the interaction integral's 4 cells: the
// domain shrinks to fit (down to 1.5 cells) instead of refusing the probe.
// An edge crack a/W = 0.2 is 2, 4 and 8 cells from the far edge of strips of
// 10, 20 and 40 cells: the smaller domains cost accuracy, which refinement
// wins back.
TEST(PlateCli, EdgeCrackNearTheBoundaryShrinksTheDomainAndConverges) {
  const double alpha = 0.2, sigma = 1e6;
  const double f = 1.12 - 0.231 * alpha + 10.55 * alpha * alpha - 21.72 * std::pow(alpha, 3) + 30.39 * std::pow(alpha, 4);
  const double exact = sigma * std::sqrt(std::acos(-1.0) * alpha) * f;
  double previous = 1;
  for (const int nx : {10, 20, 40}) {
    const fs::path csv = scratch() / ("edge_near_" + std::to_string(nx) + ".csv");
    const std::string cells = "[" + std::to_string(nx) + "," + std::to_string(6 * nx) + "]";
    const Result r = run("run " + edge_crack() + " --set continuum.cells=" + cells +
                         " --set continuum.discontinuities.0.points=[[-0.5,3.05],[0.2,3.05]]"
                         " --set output.probes.2.at=[0.1,3.05] --csv " + csv.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto v = values(lines(csv).at(1));
    const double error = std::fabs(v[1] / exact - 1);
    EXPECT_LT(error, 0.05) << nx << " cells";  // 2.3e-2, 8.8e-3, 3.3e-3
    EXPECT_LT(error, previous) << nx << " cells";
    previous = error;
  }
}

TEST(PlateCli, CrackTipDynamicRunIsTheSameOnOneAndTwoWorkers) {
  const std::string args = " --set continuum.analysis=dynamic --set continuum.cells=[20,120]";
  const fs::path a = scratch() / "tip_one.csv", b = scratch() / "tip_two.csv";
  ASSERT_EQ(run("run " + edge_crack() + args + " --csv " + a.string()).exit_code, 0);
  ASSERT_EQ(run("run " + edge_crack() + args + " --threads 2 --csv " + b.string()).exit_code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_EQ(lines(a).size(), 22u);
}

// The same refusals on the edge-crack scene.
class PlateTipCliRejects : public ::testing::TestWithParam<PlateBadInput> {};

TEST_P(PlateTipCliRejects, WithTheKeyNamedAndNoOutput) {
  const fs::path csv = scratch() / "never_tip.csv";
  fs::remove(csv);
  const Result r = run("run " + edge_crack() + " " + GetParam().args + " --csv " + csv.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(GetParam().must_mention), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
}

INSTANTIATE_TEST_SUITE_P(
    BadValues, PlateTipCliRejects,
    ::testing::Values(
        PlateBadInput{"--set output.probes.0.tip=start",
                    "scene key 'output.probes.0.tip': the start of crack 'edge' at (-0.5, "},
        PlateBadInput{"--set output.probes.0.tip=middle", "scene key 'output.probes.0.tip': 'middle' is not one of"},
        PlateBadInput{"--set output.probes.0.mode=III", "scene key 'output.probes.0.mode': 'III' is not one of"},
        PlateBadInput{"--set continuum.cells=[2,12]",
                    "scene key 'output.probes.0.tip': the end tip of crack 'edge' is 0.4"},
        PlateBadInput{"--set continuum.cells=[2,12]",
                    "interaction integral's domain (at least 1.5 cells, 0.75 m) must stay inside the plate"},
        PlateBadInput{"--set continuum.tip_enrichment.radius=x", "scene key 'continuum.tip_enrichment.radius'"},
        PlateBadInput{"--set continuum.cells=[100,600] --set continuum.tip_enrichment.radius=10",
                    "scene key 'continuum.max_enriched_dofs': the discontinuities need"},
        PlateBadInput{"--set continuum.tip_enrichment.size=1", "scene key 'continuum.tip_enrichment.size': unknown key"}));
