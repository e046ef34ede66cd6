// The step's K x, cell by cell (plate_subtract_stiffness_product), against the
// product over K's assembled profile (SymmetricBand::subtract_product) on
// plates uncut, with a tied crack, a unilateral crack, a void and an
// inclusion: the same numbers to round-off of the sums' order.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "support/command.hpp"
#include "support/plate_scenes.hpp"
#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"

using namespace xfdem;

namespace {

PlateDesc scene_plate(const char* file) {
  const scene::Scene s = scene::load_scene(xfdem::testing::scene_file(file), {});
  return *s.plate;
}

/// Compares the two products at x_k = sin(k + 1) (every unknown nonzero, both signs).
void expect_same_product(const PlateDesc& d, const std::string& what) {
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  const BuildResult r = build_plate(d, m, st, ws);
  ASSERT_TRUE(r.ok()) << what << ": " << r.message;
  const int n = m.dofs;
  ASSERT_EQ(m.stiffness.size(), n) << what;
  std::vector<double> x(static_cast<std::size_t>(n)), band(x.size(), 0.0), cells(x.size(), 0.0);
  for (int k = 0; k < n; ++k) x[static_cast<std::size_t>(k)] = std::sin(k + 1.0);
  m.stiffness.subtract_product(x.data(), band.data());
  platform::AllocationCounter counter;
  plate_subtract_stiffness_product(m, x.data(), cells.data());
  EXPECT_EQ(counter.allocations(), 0u) << what;
  // Round-off bound of row i: n ε Σ_j |K_ij x_j| (the sums' order differs).
  std::vector<double> bound(x.size(), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = m.stiffness.first_column(i); j <= i; ++j) {
      const double k = std::fabs(m.stiffness.get(i, j));
      bound[static_cast<std::size_t>(i)] += k * std::fabs(x[static_cast<std::size_t>(j)]);
      if (j != i) bound[static_cast<std::size_t>(j)] += k * std::fabs(x[static_cast<std::size_t>(i)]);
    }
  int checked = 0;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_NEAR(cells[k], band[k], 64 * DBL_EPSILON * bound[k]) << what << " row " << i;
    checked += bound[k] > 0.0;
  }
  EXPECT_EQ(checked, n) << what;
}

}  // namespace

TEST(PlateProduct, CellByCellEqualsTheProfileProduct) {
  expect_same_product(scene_plate("plate_tension.json"), "plate_tension");
  expect_same_product(scene_plate("plate_crack.json"), "plate_crack (tied)");
  expect_same_product(scene_plate("plate_hole.json"), "plate_hole (void)");
  PlateDesc inclusion = scene_plate("plate_tension.json");
  PlateDiscontinuity q = xfdem::testing::circle(PlateDiscontinuity::Kind::inclusion, 1.02, 0.47, 0.31);
  q.material = {7e10, 0.33, 2700};
  inclusion.discontinuities.push_back(q);
  expect_same_product(inclusion, "inclusion");
  PlateDesc unilateral = scene_plate("plate_crack.json");
  unilateral.discontinuities[0].faces = PlateDiscontinuity::Faces::unilateral;
  expect_same_product(unilateral, "unilateral crack");
}
