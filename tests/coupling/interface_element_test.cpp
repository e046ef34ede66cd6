// Type c contact geometry (eq 13–17) on 2D segments and its 1D degenerate
// form, which the coupled stepper realises as a driven plane.
#include <gtest/gtest.h>

#include "support/coupled_scenes.hpp"
#include "xfdem/coupling/interface_element.hpp"

namespace xfdem::coupling {
namespace {

TEST(InterfaceElement, EdgeContactProjectsOntoTheSegment) {
  // Segment from (0,0) to (4,0); a disk of radius 0.5 centred at (1, 0.3).
  const auto c = interface_contact<2>({1.0, 0.3}, 0.5, {0.0, 0.0}, {4.0, 0.0}, 0.01);
  EXPECT_FALSE(c.vertex);
  EXPECT_DOUBLE_EQ(c.t, 0.25);
  EXPECT_DOUBLE_EQ(c.point[0], 1.0);
  EXPECT_DOUBLE_EQ(c.point[1], 0.0);
  EXPECT_DOUBLE_EQ(c.normal[1], 1.0);
  EXPECT_DOUBLE_EQ(c.gap, 0.3);
  EXPECT_DOUBLE_EQ(c.overlap, 0.2);
  EXPECT_DOUBLE_EQ(c.weight[0], 0.75);
  EXPECT_DOUBLE_EQ(c.weight[1], 0.25);
}

TEST(InterfaceElement, SlantedSegmentGapIsTheDistanceToTheLine) {
  // Segment along (1,1)/√2; centre at distance 0.2 from it, above its middle.
  const double s = std::sqrt(0.5);
  const auto c = interface_contact<2>({1.0 - 0.2 * s, 1.0 + 0.2 * s}, 0.3, {0.0, 0.0}, {2.0, 2.0});
  EXPECT_FALSE(c.vertex);
  EXPECT_NEAR(c.t, 0.5, 1e-15);
  EXPECT_NEAR(c.gap, 0.2, 1e-15);
  EXPECT_NEAR(c.normal[0], -s, 1e-15);
  EXPECT_NEAR(c.normal[1], s, 1e-15);
}

TEST(InterfaceElement, VertexContactBeyondTheEndsAndWithinTheMargin) {
  // Beyond node 1: the contact point is the node, the gap the distance to it.
  auto c = interface_contact<2>({4.3, 0.4}, 0.6, {0.0, 0.0}, {4.0, 0.0});
  EXPECT_TRUE(c.vertex);
  EXPECT_DOUBLE_EQ(c.point[0], 4.0);
  EXPECT_NEAR(c.gap, 0.5, 1e-15);
  EXPECT_NEAR(c.overlap, 0.1, 1e-15);
  EXPECT_DOUBLE_EQ(c.weight[1], 1.0);
  EXPECT_DOUBLE_EQ(c.weight[0], 0.0);
  // Inside the segment but within δ of node 0: a vertex contact with node 0.
  c = interface_contact<2>({0.02, 0.3}, 0.5, {0.0, 0.0}, {4.0, 0.0}, 0.01);
  EXPECT_TRUE(c.vertex);
  EXPECT_DOUBLE_EQ(c.weight[0], 1.0);
  // Zero-length element: a vertex, no division by zero.
  c = interface_contact<2>({0.0, 0.2}, 0.5, {0.0, 0.0}, {0.0, 0.0});
  EXPECT_TRUE(c.vertex);
  EXPECT_DOUBLE_EQ(c.gap, 0.2);
}

TEST(InterfaceElement, NoContactWhenTheGapReachesTheRadius) {
  const auto c = interface_contact<2>({1.0, 0.5}, 0.5, {0.0, 0.0}, {4.0, 0.0});
  EXPECT_LE(c.overlap, 0.0);  // eq 18: the force acts while r − g_n > 0
}

TEST(InterfaceElement, EnrichedSharesFollowTheShiftedHeaviside) {
  // An element cut by the interface: node 0 below (φ < 0), node 1 above (φ > 0).
  const double weight[2] = {0.3, 0.7};
  const double phi[2] = {-0.2, 0.5};
  // Contact point above the interface: node 0's enrichment carries N_0, node 1's vanishes.
  EnrichedShares s = enriched_shares(weight, 0.1, phi);
  EXPECT_DOUBLE_EQ(s.standard[0], 0.3);
  EXPECT_DOUBLE_EQ(s.enriched[0], 0.3);
  EXPECT_DOUBLE_EQ(s.enriched[1], 0.0);
  // Below it: node 1's enrichment carries −N_1.
  s = enriched_shares(weight, -0.1, phi);
  EXPECT_DOUBLE_EQ(s.enriched[0], 0.0);
  EXPECT_DOUBLE_EQ(s.enriched[1], -0.7);
  // At a node the shifted enrichment vanishes: a force on a node is carried by
  // its standard unknown alone (the 1D rod's top, enriched or not).
  const double at_node[2] = {0.0, 1.0};
  s = enriched_shares(at_node, 0.5, phi);
  EXPECT_DOUBLE_EQ(s.enriched[0], 0.0);
  EXPECT_DOUBLE_EQ(s.enriched[1], 0.0);
}

TEST(InterfaceElement, OneDimensionalPointIsTheDrivenPlane) {
  // The 1D element's overlap equals the DEM plane's that stands for the rod's top.
  xfdem::DemDesc<1> d;
  d.dt = 1e-4;
  d.particles.push_back({100.0, 0.5, 1e7, {30.3}, {0.0}});
  d.planes.push_back({{30.0}, {1.0}});
  xfdem::DemWorld<1> w;
  ASSERT_TRUE(w.build(d).ok());
  xfdem::dem_drive_plane(w.model, w.state, 0, -0.01, 0.0);
  const auto c = interface_contact_point(30.3, 0.5, 30.0 - 0.01, 1.0);
  EXPECT_DOUBLE_EQ(c.overlap, 0.5 - (30.3 - 29.99));
  EXPECT_DOUBLE_EQ(xfdem::dem_plane_force(w.model, w.state, 0, 0), 1e7 * c.overlap);
  // A centre that has passed the point still has a positive overlap (pushed out).
  EXPECT_GT(interface_contact_point(29.9, 0.5, 30.0, 1.0).overlap, 0.5);
}

}  // namespace
}  // namespace xfdem::coupling

namespace xfdem::testing {
namespace {

// The interface in the rod's top element makes the top node enriched; the
// force the particles put on the top must still go to it correctly: FE-DEM and
// X-FE-DEM stay the same system.
TEST(Coupled, EnrichedTopNodeCarriesTheContactForce) {
  double worst = 0;
  CoupledWorld fem, xfem;
  ASSERT_TRUE(fem.build(coupled_scene("case1_fem.json", {"continuum.interface.position=29.7"})).ok());
  ASSERT_TRUE(xfem.build(coupled_scene("case1_xfem.json", {"continuum.interface.position=29.7"})).ok());
  for (int k = 0; k < 1300; ++k) {  // through the first impact (t ≈ 0.78 s) and flight after it
    ASSERT_EQ(fem.step(), StepStatus::ok);
    ASSERT_EQ(xfem.step(), StepStatus::ok);
    worst = std::max(worst, std::fabs(fem.state.dem.x[0][0] - xfem.state.dem.x[0][0]) +
                                std::fabs(bar_tip_displacement(fem.model.bar, fem.state.bar) -
                                          bar_tip_displacement(xfem.model.bar, xfem.state.bar)));
  }
  EXPECT_GT(std::fabs(bar_tip_displacement(fem.model.bar, fem.state.bar)), 1e-3);  // the rod was hit
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace xfdem::testing
