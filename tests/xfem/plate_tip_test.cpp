// Crack tips in the plate: branch-function enrichment (topological and within a
// radius) and the stress intensity factors by the domain interaction integral,
// against the Williams near-tip fields imposed on the boundary (closed form)
// and Tada's edge-crack polynomial.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "xfdem/plate.hpp"
#include "xfdem/xfem/level_set.hpp"

using namespace xfdem;

namespace {

constexpr double kE = 2e11, kNu = 0.3;

double node_x(const PlateDesc& d, int i) { return i == d.cells[0] ? d.max[0] : d.min[0] + (d.max[0] - d.min[0]) * i / d.cells[0]; }
double node_y(const PlateDesc& d, int j) { return j == d.cells[1] ? d.max[1] : d.min[1] + (d.max[1] - d.min[1]) * j / d.cells[1]; }

/// The Williams field of (k1, k2) of a crack along −x from the tip (0, 0), global = tip frame.
xfem::WilliamsField williams_at(const PlateDesc& d, double k1, double k2, double x, double y) {
  const double mu = d.youngs_modulus / (2 * (1 + d.poisson_ratio));
  const double kappa = xfem::kolosov(d.poisson_ratio, d.plane == PlateDesc::Plane::strain);
  return xfem::williams_field(k1, k2, mu, kappa, std::hypot(x, y), std::atan2(y, x));
}

/// The square [−1, 1]² (n × n cells, n odd: the crack y = 0 and the tip (0, 0)
/// run through cell middles) with a crack from the left edge to its centre and
/// the Williams field of (k1, k2) prescribed on every boundary node.
PlateDesc williams_square(int n, double k1, double k2, double tip_radius) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.youngs_modulus = kE, d.poisson_ratio = kNu, d.density = 7800, d.thickness = 1.0;
  d.analysis = PlateDesc::Analysis::statics;
  d.min[0] = d.min[1] = -1.0, d.max[0] = d.max[1] = 1.0;
  d.cells[0] = d.cells[1] = n;
  d.tip_radius = tip_radius;
  PlateDiscontinuity c;
  c.name = "c";
  c.points = {{-1.5, 0.0}, {0.0, 0.0}};
  d.discontinuities.push_back(c);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      if (i != 0 && i != n && j != 0 && j != n) continue;
      const double x = node_x(d, i), y = node_y(d, j);
      const xfem::WilliamsField w = williams_at(d, k1, k2, x, y);
      d.prescribed.push_back({{x, y}, {w.u[0], w.u[1]}});
    }
  return d;
}

}  // namespace

// Pure mode I, pure mode II and mixed: the Williams field on the boundary of a
// square cracked to its centre. With branch functions on every node within
// 0.3 of the tip (geometric enrichment), the interaction integral over a ring
// of radius 0.5 gives K_I and K_II within 1 % of the imposed ones.
TEST(PlateTip, WilliamsFieldsGiveTheirStressIntensityFactors) {
  const double k0 = 1e6;
  for (auto [k1, k2] : {std::pair{k0, 0.0}, std::pair{0.0, k0}, std::pair{0.8 * k0, -0.6 * k0}}) {
    PlateDesc d = williams_square(21, k1, k2, 0.3);
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(m.tips.size(), 1u);
    EXPECT_GT(m.tip_nodes, 4);
    double k[2];
    plate_stress_intensity(m, st, 0, true, 0.5, k);
    std::printf("Williams K_I %.4g K_II %.4g: computed %.6g %.6g (errors %.3e %.3e of |K|)\n", k1, k2, k[0], k[1],
                (k[0] - k1) / k0, (k[1] - k2) / k0);
    EXPECT_NEAR(k[0], k1, 0.01 * k0);
    EXPECT_NEAR(k[1], k2, 0.01 * k0);
    // No first point tip: NaN.
    plate_stress_intensity(m, st, 0, false, 0.5, k);
    EXPECT_TRUE(std::isnan(k[0]) && std::isnan(k[1]));
  }
}
