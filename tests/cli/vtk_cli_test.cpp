// `xfdem run SCENE --vtk DIR` (scenes-2d.md, "Output for viewing"): the files
// of a plate and of a 2D particle scene, read back and compared with the run's
// own CSV probes at the same times and with the stress the test computes from
// the written displacements; bad --vtk input refused with the exact message.
#include <gtest/gtest.h>

#include "scene/scene.hpp"
#include "scene/vtk.hpp"
#include "support/command.hpp"
#include "support/csv.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/xfem/level_set.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using xfdem::testing::slurp;
using Result = xfdem::testing::CommandResult;

fs::path scratch() { return xfdem::testing::scratch("vtk_cli_test"); }
Result run(const std::string& args) { return xfdem::testing::run_command(XFDEM_CLI, args); }
std::string tension() { return xfdem::testing::scene_file("plate_tension.json"); }

using xfdem::testing::Csv;
using xfdem::testing::read_csv;

/// The numbers of the DataArray that follows `marker` (e.g. `Name="velocity"`
/// or `<Points>`) in a VTK XML file.
std::vector<double> array(const std::string& text, const std::string& marker) {
  const auto at = text.find(marker);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << marker;
    return {};
  }
  // A name is inside its DataArray's tag; an element (<Points>) holds one.
  const auto tag = marker[0] == '<' ? text.find("<DataArray", at) : at;
  const auto begin = text.find('>', tag) + 1;
  const auto end = text.find("</DataArray>", begin);
  std::vector<double> out;
  std::stringstream s(text.substr(begin, end - begin));
  for (std::string word; s >> word;) out.push_back(std::strtod(word.c_str(), nullptr));
  return out;
}

/// The collection: (time, file) of every data set, in order.
std::vector<std::pair<double, std::string>> collection(const fs::path& pvd) {
  std::vector<std::pair<double, std::string>> out;
  const std::string text = slurp(pvd);
  for (auto at = text.find("<DataSet"); at != std::string::npos; at = text.find("<DataSet", at + 1)) {
    const auto t = text.find("timestep=\"", at) + 10;
    const auto f = text.find("file=\"", at) + 6;
    out.emplace_back(std::strtod(text.c_str() + t, nullptr), text.substr(f, text.find('"', f) - f));
  }
  return out;
}

}  // namespace

// The plate: one file per output sample, listed in the .pvd at the CSV's
// times; at every sample the displacement and velocity written at the probes'
// nodes are the CSV's (bit for bit: the probes sit on nodes, where the shape
// functions are exactly 1 and 0), the points are the nodes moved by the
// displacement, and each cell's stress and von Mises are those of the written
// corner displacements (computed here from the Q4 shape functions at the
// centre and plane-stress Hooke's law).
TEST(VtkCli, PlateFilesHoldThePlateStateAtEverySample) {
  const fs::path dir = scratch() / "plate", csv_path = scratch() / "plate.csv";
  fs::remove_all(dir);
  const Result r = run("run " + tension() + " --set output.every=5e-4 --csv " + csv_path.string() + " --vtk " +
                       dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv csv = read_csv(csv_path);
  const auto sets = collection(dir / "plate_tension.pvd");
  ASSERT_EQ(sets.size(), csv.rows.size());
  ASSERT_EQ(sets.size(), 5u);  // t = 0, 5e-4, ..., 2e-3
  const double e = 2e11, nu = 0.3, hx = 0.1, hy = 0.1;
  const double d11 = e / (1 - nu * nu), d12 = nu * d11, d33 = 0.5 * (1 - nu) * d11;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const auto& row = csv.rows[k];
    EXPECT_EQ(sets[k].first, row[0]);
    char expected[64];
    std::snprintf(expected, sizeof(expected), "plate_tension_plate_%06zu.vtu", k);
    EXPECT_EQ(sets[k].second, expected);
    const std::string text = slurp(dir / sets[k].second);
    EXPECT_NE(text.find("NumberOfPoints=\"800\" NumberOfCells=\"200\""), std::string::npos);
    const auto points = array(text, "<Points>");
    const auto u = array(text, "Name=\"displacement\"");
    const auto v = array(text, "Name=\"velocity\"");
    const auto sxx = array(text, "Name=\"stress_xx\""), syy = array(text, "Name=\"stress_yy\"");
    const auto sxy = array(text, "Name=\"stress_xy\""), vm = array(text, "Name=\"von_mises\"");
    ASSERT_EQ(points.size(), 2400u);
    ASSERT_EQ(u.size(), 2400u);
    ASSERT_EQ(v.size(), 2400u);
    ASSERT_EQ(sxx.size(), 200u);
    ASSERT_EQ(vm.size(), 200u);
    int tip = 0, top = 0;
    double peak = 0.0;
    for (double s : sxx) peak = std::max(peak, std::fabs(s));
    for (std::size_t p = 0; p < 800; ++p) {
      const double x = points[3 * p] - u[3 * p], y = points[3 * p + 1] - u[3 * p + 1];
      EXPECT_EQ(points[3 * p + 2], 0.0);
      if (std::fabs(x - 2.0) < 1e-12 && std::fabs(y - 0.5) < 1e-12) {
        ++tip;
        EXPECT_EQ(u[3 * p], row[csv.column("u_tip")]);
        EXPECT_EQ(v[3 * p], row[csv.column("v_tip")]);
      }
      if (std::fabs(x - 2.0) < 1e-12 && std::fabs(y - 1.0) < 1e-12) {
        ++top;
        EXPECT_EQ(u[3 * p + 1], row[csv.column("uy_top")]);
      }
    }
    EXPECT_EQ(tip, 2);  // the node is a corner of two cells
    EXPECT_EQ(top, 1);
    for (std::size_t c = 0; c < 200; ++c) {
      const double* q = &u[12 * c];  // corners 0..3 counter-clockwise from the lower left, (x, y, 0) each
      const double exx = (q[3] - q[0] + q[6] - q[9]) / (2 * hx);
      const double eyy = (q[10] - q[1] + q[7] - q[4]) / (2 * hy);
      const double gxy = (q[9] - q[0] + q[6] - q[3]) / (2 * hy) + (q[4] - q[1] + q[7] - q[10]) / (2 * hx);
      const double s[3] = {d11 * exx + d12 * eyy, d12 * exx + d11 * eyy, d33 * gxy};
      const double tol = 1e-12 * peak;  // round-off of the order of the sums
      EXPECT_NEAR(sxx[c], s[0], tol) << "cell " << c;
      EXPECT_NEAR(syy[c], s[1], tol) << "cell " << c;
      EXPECT_NEAR(sxy[c], s[2], tol) << "cell " << c;
      EXPECT_NEAR(vm[c], std::sqrt(s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3 * s[2] * s[2]), tol) << "cell " << c;
    }
  }
  // At t = 0 (from rest) the plate is undeformed; later it is not.
  EXPECT_EQ(collection(dir / "plate_tension.pvd").size(), 5u);
  EXPECT_GT(csv.rows.back()[csv.column("u_tip")], 0.0);
}

// A static scene writes its one sample at t = 0. Uniaxial tension in plane
// stress: σ_xx = σ0, σ_yy = σ_xy = 0 and von Mises σ0 in every cell (the
// closed form), and the points are x + u with u = (σ0 x / E, −ν σ0 y / E).
TEST(VtkCli, StaticTensionHasTheClosedFormStressInEveryCell) {
  const fs::path dir = scratch() / "static";
  fs::remove_all(dir);
  const Result r = run("run " + tension() + " --set continuum.analysis=static --vtk " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto sets = collection(dir / "plate_tension.pvd");
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].first, 0.0);
  const std::string text = slurp(dir / sets[0].second);
  const double sigma0 = 1e6, e = 2e11, nu = 0.3, eps = 2.220446049250313e-16;
  const auto sxx = array(text, "Name=\"stress_xx\""), syy = array(text, "Name=\"stress_yy\"");
  const auto sxy = array(text, "Name=\"stress_xy\""), vm = array(text, "Name=\"von_mises\"");
  ASSERT_EQ(vm.size(), 200u);
  for (std::size_t c = 0; c < 200; ++c) {
    EXPECT_NEAR(sxx[c], sigma0, 256 * eps * sigma0);
    EXPECT_NEAR(syy[c], 0.0, 256 * eps * sigma0);
    EXPECT_NEAR(sxy[c], 0.0, 256 * eps * sigma0);
    EXPECT_NEAR(vm[c], sigma0, 256 * eps * sigma0);
  }
  const auto points = array(text, "<Points>"), u = array(text, "Name=\"displacement\"");
  ASSERT_EQ(points.size(), 2400u);
  for (std::size_t p = 0; p < 800; ++p) {
    const double x = points[3 * p] - u[3 * p], y = points[3 * p + 1] - u[3 * p + 1];
    EXPECT_NEAR(u[3 * p], sigma0 * x / e, 64 * eps * 1e-5);
    EXPECT_NEAR(u[3 * p + 1], -nu * sigma0 * y / e, 64 * eps * 1e-5);
  }
}

namespace {

const char* kDisks = R"({
  "name": "disks_2d",
  "dimension": 2,
  "gravity": [0, -9.81],
  "time": { "end": 0.3, "dt": 1e-4 },
  "dem": {
    "integrator": "abm4",
    "contact": { "law": "linear", "damping_ratio": 0.1 },
    "particles": [
      { "name": "a", "mass": 1.0, "radius": 0.1, "stiffness": 1e4, "position": [0, 0.25], "velocity": [0.5, 0] },
      { "name": "b", "mass": 2.0, "radius": 0.15, "stiffness": 1e4, "position": [0.32, 0.2], "velocity": [-0.5, 0] }
    ],
    "planes": [ { "point": [0, 0], "normal": [0, 1] } ]
  },
  "output": {
    "every": 0.05,
    "probes": [
      { "name": "ax", "particle": "a", "quantity": "position", "component": 0 },
      { "name": "ay", "particle": "a", "quantity": "position", "component": 1 },
      { "name": "avx", "particle": "a", "quantity": "velocity", "component": 0 },
      { "name": "avy", "particle": "a", "quantity": "velocity", "component": 1 },
      { "name": "bx", "particle": "b", "quantity": "position", "component": 0 },
      { "name": "by", "particle": "b", "quantity": "position", "component": 1 },
      { "name": "bvx", "particle": "b", "quantity": "velocity", "component": 0 },
      { "name": "bvy", "particle": "b", "quantity": "velocity", "component": 1 }
    ]
  }
})";

}  // namespace

// Two disks that meet and land on a floor: a file per sample with each
// particle's position, velocity and radius as the CSV and the scene give them.
TEST(VtkCli, ParticleFilesHoldThePositionsVelocitiesAndRadii) {
  const fs::path scene = scratch() / "disks.json", dir = scratch() / "disks", csv_path = scratch() / "disks.csv";
  std::ofstream(scene) << kDisks;
  fs::remove_all(dir);
  const Result r = run("run " + scene.string() + " --vtk " + dir.string() + " --csv " + csv_path.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv csv = read_csv(csv_path);
  const auto sets = collection(dir / "disks_2d.pvd");
  ASSERT_EQ(sets.size(), 7u);  // t = 0, 0.05, ..., 0.3
  ASSERT_EQ(csv.rows.size(), 7u);
  const char* names[2] = {"a", "b"};
  const double radius[2] = {0.1, 0.15};
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const auto& row = csv.rows[k];
    EXPECT_EQ(sets[k].first, row[0]);
    const std::string text = slurp(dir / sets[k].second);
    const auto x = array(text, "<Points>"), v = array(text, "Name=\"velocity\"");
    const auto rad = array(text, "Name=\"radius\""), w = array(text, "Name=\"angular_velocity\"");
    ASSERT_EQ(x.size(), 6u);
    ASSERT_EQ(v.size(), 6u);
    ASSERT_EQ(rad.size(), 2u);
    ASSERT_EQ(w.size(), 6u);
    for (int p = 0; p < 2; ++p) {
      const std::string n = names[p];
      EXPECT_EQ(x[3 * p], row[csv.column(n + "x")]);
      EXPECT_EQ(x[3 * p + 1], row[csv.column(n + "y")]);
      EXPECT_EQ(x[3 * p + 2], 0.0);
      EXPECT_EQ(v[3 * p], row[csv.column(n + "vx")]);
      EXPECT_EQ(v[3 * p + 1], row[csv.column(n + "vy")]);
      EXPECT_EQ(rad[p], radius[p]);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(w[3 * p + c], 0.0);  // frictionless contacts: no spin
    }
  }
  // The disks met and the floor stopped them: the run is not a free flight.
  EXPECT_LT(csv.rows[3][csv.column("avx")], 0.0);
}

// With friction the disks spin: the files hold each one's angular velocity,
// in 2D about z, as the scene's angular_velocity probe reads it.
TEST(VtkCli, ParticleFilesHoldTheSpinOfRotatingDisks) {
  const fs::path scene = scratch() / "spin.json", dir = scratch() / "spin", csv_path = scratch() / "spin.csv";
  std::string text = kDisks;
  const std::string law = "\"damping_ratio\": 0.1 }";
  text.replace(text.find(law), law.size(), "\"damping_ratio\": 0.1, \"friction\": 0.4 }");
  const std::string probe = "{ \"name\": \"ax\"";
  text.replace(text.find(probe), probe.size(),
               "{ \"name\": \"aw\", \"particle\": \"a\", \"quantity\": \"angular_velocity\" },\n      " +
                   probe);
  const std::string integrator = "\"abm4\"";
  text.replace(text.find(integrator), integrator.size(), "\"verlet\"");
  std::ofstream(scene) << text;
  fs::remove_all(dir);
  const Result r = run("run " + scene.string() + " --vtk " + dir.string() + " --csv " + csv_path.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv csv = read_csv(csv_path);
  const auto sets = collection(dir / "disks_2d.pvd");
  ASSERT_EQ(sets.size(), csv.rows.size());
  bool spun = false;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const auto w = array(slurp(dir / sets[k].second), "Name=\"angular_velocity\"");
    ASSERT_EQ(w.size(), 6u);
    EXPECT_EQ(w[0], 0.0);
    EXPECT_EQ(w[1], 0.0);
    EXPECT_EQ(w[2], csv.rows[k][csv.column("aw")]);
    spun = spun || w[2] != 0.0;
  }
  EXPECT_TRUE(spun);  // the floor's friction turned disk a
}

struct VtkBadInput {
  const char* args;      ///< after the scene
  const char* message;   ///< the whole line on stderr, %s: the scratch directory
  bool bar = false;      ///< run a bar scene instead of the plate
};

class VtkCliRejects : public ::testing::TestWithParam<VtkBadInput> {};

TEST_P(VtkCliRejects, WithTheExactMessageExitTwoAndNoOutput) {
  const fs::path dir = scratch() / "bad";
  fs::create_directories(dir);
  std::ofstream(dir / "a_file") << "x";
  const fs::path csv = dir / "never.csv";
  fs::remove(csv);
  char args[512], message[512];
  std::snprintf(args, sizeof(args), GetParam().args, dir.c_str());
  std::snprintf(message, sizeof(message), GetParam().message, dir.c_str());
  const std::string scene = GetParam().bar ? xfdem::testing::scene_file("v2_fem.json") : tension();
  const Result r = run("run " + scene + " --csv " + csv.string() + " " + args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, std::string("xfdem: ") + message + "\n");
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(dir / "out"));
}

INSTANTIATE_TEST_SUITE_P(
    BadDirectories, VtkCliRejects,
    ::testing::Values(
        VtkBadInput{"--vtk", "--vtk: missing value (the directory to write the VTK files in)"},
        VtkBadInput{"--vtk --threads 2", "--vtk: missing value (the directory to write the VTK files in)"},
        VtkBadInput{"--vtk ''", "--vtk: must name a directory (got an empty path)"},
        VtkBadInput{"--vtk %s/a_file", "--vtk '%s/a_file': exists and is not a directory"},
        VtkBadInput{"--vtk %s/a_file/out", "--vtk '%s/a_file/out': cannot create the directory: Not a directory"},
        // A directory that exists and takes no new file (as root too: /proc).
        VtkBadInput{"--vtk /proc/self", "--vtk '/proc/self': cannot write in the directory: No such file or directory"},
        VtkBadInput{"--vtk %s/out", "--vtk: writes plates and particles; this scene has a bar, which has no VTK output",
                    true}));

// A run that fails after writing some samples leaves none of them.
TEST(VtkCli, AFailedRunLeavesNoFiles) {
  const fs::path dir = scratch() / "failed";
  fs::remove_all(dir);
  // The CSV cannot be written (a directory of that name): after the run, so
  // every sample was written before the failure.
  const fs::path blocker = scratch() / "blocker.csv";
  fs::create_directories(blocker);
  const Result r = run("run " + tension() + " --set output.every=5e-4 --vtk " + dir.string() + " --csv " +
                       blocker.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::is_directory(dir));
  EXPECT_TRUE(fs::is_empty(dir));
}

// ---- a plate with discontinuities ----------------------------------------------

namespace {

/// A 2 m × 1 m steel plate (20 × 10 cells, plane stress) cut right through by
/// a straight, inclined crack with free faces, pulled by a step traction on
/// its right edge (left edge held in x, bottom in y): the crack opens.
xfdem::PlateDesc free_crack_in_tension() {
  xfdem::PlateDesc d;
  d.max[0] = 2.0, d.max[1] = 1.0;
  d.cells[0] = 20, d.cells[1] = 10;
  d.plane = xfdem::PlateDesc::Plane::stress;
  d.thickness = 0.02;
  d.youngs_modulus = 2e11, d.poisson_ratio = 0.3, d.density = 7800;
  d.dt = 1e-5;
  d.supports.push_back({xfdem::PlateEdge::left, {true, false}, false});
  d.supports.push_back({xfdem::PlateEdge::bottom, {false, true}, false});
  xfdem::PlateLoad load;
  load.edge = xfdem::PlateEdge::right;
  load.value[0] = 1e6;
  d.loads.push_back(load);
  xfdem::PlateDiscontinuity crack;
  crack.name = "crack";
  crack.points = {{1.13, -0.1}, {0.87, 1.1}};
  d.discontinuities.push_back(crack);
  return d;
}

/// Twice the signed area of a polygon (shoelace).
double twice_area(const double (*xy)[2], int n) {
  double s = 0.0;
  for (int a = 0; a < n; ++a) {
    const int b = (a + 1) % n;
    s += xy[a][0] * xy[b][1] - xy[b][0] * xy[a][1];
  }
  return s;
}

}  // namespace

TEST(VtkCut, TheCrackFacesOfTheWrittenPiecesDifferByTheCrackOpening) {
  const xfdem::PlateDesc d = free_crack_in_tension();
  xfdem::PlateModel model;
  xfdem::PlateState state;
  xfdem::PlateWorkspace ws;
  ASSERT_TRUE(xfdem::build_plate(d, model, state, ws).ok());
  for (int n = 0; n < 100; ++n) ASSERT_EQ(xfdem::plate_step(model, state, ws), xfdem::StepStatus::ok);
  struct Corner {
    double x, y, u[2];
    int side;
  };
  std::vector<Corner> on_crack;
  double largest_u = 0.0;
  const auto& line = d.discontinuities[0].points;
  xfdem::scene::for_each_plate_piece(model, state, [&](const xfdem::scene::PlatePiece& p) {
    double cx = 0.0, cy = 0.0;
    for (int a = 0; a < p.corners; ++a) cx += p.reference[a][0] / p.corners, cy += p.reference[a][1] / p.corners;
    // The piece's side from its centroid; a sliver along the crack (the
    // crack through a node leaves pieces of rounding size) has no side to
    // tell and is left out.
    const double phi_c = xfdem::xfem::polyline_level_set(line, {cx, cy});
    if (std::fabs(phi_c) < 1e-9 * 0.1) return;
    const int side = xfdem::xfem::side_of(phi_c);
    for (int a = 0; a < p.corners; ++a) {
      largest_u = std::max({largest_u, std::fabs(p.u[a][0]), std::fabs(p.u[a][1])});
      if (std::fabs(xfdem::xfem::polyline_level_set(line, {p.reference[a][0], p.reference[a][1]})) < 1e-12)
        on_crack.push_back({p.reference[a][0], p.reference[a][1], {p.u[a][0], p.u[a][1]}, side});
    }
  });
  // The crack's direction and its normal (left of it: towards the positive side).
  const double lx = line[1][0] - line[0][0], ly = line[1][1] - line[0][1], len = std::hypot(lx, ly);
  const double t[2] = {lx / len, ly / len}, nrm[2] = {-t[1], t[0]};
  int pairs = 0;
  double smallest_opening = 1.0;
  for (const Corner& plus : on_crack) {
    if (plus.side < 0) continue;
    for (const Corner& minus : on_crack) {
      if (minus.side > 0 || std::hypot(plus.x - minus.x, plus.y - minus.y) > 1e-12) continue;
      const double jump[2] = {plus.u[0] - minus.u[0], plus.u[1] - minus.u[1]};
      const double normal = nrm[0] * jump[0] + nrm[1] * jump[1], tangential = t[0] * jump[0] + t[1] * jump[1];
      EXPECT_NEAR(normal, xfdem::plate_crack_opening(model, state, 0, plus.x, plus.y, 0), 1e-12 * largest_u);
      EXPECT_NEAR(tangential, xfdem::plate_crack_opening(model, state, 0, plus.x, plus.y, 1), 1e-12 * largest_u);
      smallest_opening = std::min(smallest_opening, normal);
      ++pairs;
    }
  }
  // The crack crosses 10 rows of cells: its 11 crossings of the horizontal
  // cell edges at least (and those of the cells' inner edges) have both faces.
  EXPECT_GE(pairs, 11);
  // Pulled apart, the faces open all along (positive: opening).
  EXPECT_GT(smallest_opening, 0.0);
}

TEST(VtkCut, TheWrittenPiecesCoverThePlateLessTheVoid) {
  const xfdem::scene::Scene scene = xfdem::scene::load_scene(xfdem::testing::scene_file("plate_hole.json"), {});
  ASSERT_TRUE(scene.plate.has_value());
  const xfdem::PlateDesc& d = *scene.plate;
  xfdem::PlateModel model;
  xfdem::PlateState state;
  xfdem::PlateWorkspace ws;
  ASSERT_TRUE(xfdem::build_plate(d, model, state, ws).ok());
  double written = 0.0;
  bool counter_clockwise = true;
  xfdem::scene::for_each_plate_piece(model, state, [&](const xfdem::scene::PlatePiece& p) {
    const double a2 = twice_area(p.reference, p.corners);
    counter_clockwise = counter_clockwise && a2 > 0.0;
    written += 0.5 * a2;
  });
  EXPECT_TRUE(counter_clockwise);
  // The void as the cut geometry approximates it: each cell's four triangles
  // (two nodes and the centre, φ there the nodes' mean), in each the part
  // where φ interpolated linearly is negative.
  const auto& hole = d.discontinuities[0];
  const int nx = d.cells[0], ny = d.cells[1];
  const double hx = (d.max[0] - d.min[0]) / nx, hy = (d.max[1] - d.min[1]) / ny;
  auto phi = [&](double x, double y) {
    return xfdem::xfem::circle_level_set({hole.centre[0], hole.centre[1]}, hole.radius, {x, y});
  };
  // The part of a triangle of area `area` where the linear function with vertex values a, b, c is < 0.
  auto negative_part = [](double area, double a, double b, double c) {
    const int neg = (a < 0) + (b < 0) + (c < 0);
    if (neg == 0) return 0.0;
    if (neg == 3) return area;
    if (neg == 2) {  // a: the non-negative vertex, its corner is the positive part
      while (a < 0) std::swap(a, b), std::swap(b, c);
      return area * (1.0 - (a / (a - b)) * (a / (a - c)));
    }
    while (a >= 0) std::swap(a, b), std::swap(b, c);
    return area * (a / (a - b)) * (a / (a - c));
  };
  double void_area = 0.0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x0 = d.min[0] + i * hx, y0 = d.min[1] + j * hy;
      const double f[4] = {phi(x0, y0), phi(x0 + hx, y0), phi(x0 + hx, y0 + hy), phi(x0, y0 + hy)};
      const double centre = 0.25 * (f[0] + f[1] + f[2] + f[3]);
      for (int t = 0; t < 4; ++t) void_area += negative_part(0.25 * hx * hy, f[t], f[(t + 1) % 4], centre);
    }
  const double plate = (d.max[0] - d.min[0]) * (d.max[1] - d.min[1]);
  EXPECT_NEAR(written, plate - void_area, 1e-12 * plate);
  // And that polygon is the quarter circle to O(h²).
  EXPECT_NEAR(void_area, 0.25 * std::acos(-1.0) * hole.radius * hole.radius, hx * hy);
}

TEST(VtkCut, TheCutScenesWriteNoNaN) {
  for (const std::string name : {"plate_hole", "plate_crack"}) {
    const fs::path dir = scratch() / name;
    fs::remove_all(dir);
    const Result r = run("run " + xfdem::testing::scene_file((name + ".json").c_str()) +
                         " --set output.every=5e-4 --vtk " + dir.string());
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() != ".vtu") continue;
      ++files;
      const std::string text = slurp(entry.path());
      for (const char* marker : {"<Points>", "Name=\"displacement\"", "Name=\"velocity\"", "Name=\"stress_xx\"",
                                 "Name=\"stress_yy\"", "Name=\"stress_xy\"", "Name=\"von_mises\""}) {
        const auto values = array(text, marker);
        EXPECT_FALSE(values.empty()) << entry.path() << " " << marker;
        for (double x : values) ASSERT_TRUE(std::isfinite(x)) << entry.path() << " " << marker;
      }
      EXPECT_EQ(text.find("nan"), std::string::npos) << entry.path();
      EXPECT_EQ(text.find("inf"), std::string::npos) << entry.path();
    }
    EXPECT_GE(files, 1) << name;
  }
}
