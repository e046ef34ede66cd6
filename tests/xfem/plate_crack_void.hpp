// A crack from a circular hole in a large plate under remote tension
// (Bowie's problem), shared by the short run (tests/xfem/plate_crack_void_test.cpp)
// and the fine meshes (tests/long/plate_crack_void_long_test.cpp, label `long`).
#pragma once
#include <cmath>
#include <numbers>

#include "support/plate_scenes.hpp"
#include "xfdem/plate.hpp"

namespace xfdem::test {

constexpr double kBowieE = 2e11, kBowieSigma = 1e6;

// Bowie's factors for cracks of length a from a circular hole of radius R in
// an infinite plate under remote tension across them, K_I = σ √(πa) F (Tada,
// Paris & Irwin, The Stress Analysis of Cracks Handbook). Two symmetric
// cracks: Tada's fit F = ½ (3 − s) [1 + 1.243 (1 − s)³], s = a / (R + a),
// within 1 % of Bowie's table (its limits: 3 × 1.12 as a → 0, 1 as a → ∞).
// One crack: the table as Broek reproduces it, F = 1.37 at a = R.
inline double bowie_two(double a_over_r) {
  const double s = a_over_r / (1.0 + a_over_r);
  return 0.5 * (3.0 - s) * (1.0 + 1.243 * (1.0 - s) * (1.0 - s) * (1.0 - s));
}
constexpr double kBowieOneAtR = 1.37;

/// The factor of the infinite plate from those of plates w and 2w wide (same
/// cells): the finite width adds a term ∝ 1/w² (√sec(π c / w) ≈ 1 + (π c / w)² / 4
/// for a flaw of half-length c), so F∞ = (4 F(2w) − F(w)) / 3.
inline double infinite_plate(double f_w, double f_2w) { return (4.0 * f_2w - f_w) / 3.0; }

/// The square [−L, L]² (n × n cells, n odd: y = 0 runs along the middle of a
/// row), plane stress, static, pulled by σ on its top edge, a roller on its
/// bottom edge and its lower-left corner held; a void of radius 1 about the
/// origin and a crack from the origin (inside the void) to (1 + a, 0), or
/// (`two`) through the void from (−1 − a, 0) to (1 + a, 0): two cracks.
inline PlateDesc bowie_plate(double half, int n, double a, bool two = false) {
  PlateDesc d = testing::plate(kBowieE, 2 * half, 2 * half, n, n);
  d.min[0] = d.min[1] = -half, d.max[0] = d.max[1] = half;
  d.plane = PlateDesc::Plane::stress;
  d.analysis = PlateDesc::Analysis::statics;
  d.discontinuities.push_back(testing::circle(PlateDiscontinuity::Kind::hole, 0.0, 0.0, 1.0));
  PlateDiscontinuity c;
  c.name = "c1";
  c.points = {{two ? -1.0 - a : 0.0, 0.0}, {1.0 + a, 0.0}};
  d.discontinuities.push_back(c);
  d.supports.push_back({PlateEdge::bottom, {false, true}, false});
  d.prescribed.push_back({{-half, -half}, {0.0, 0.0}});
  PlateLoad top;
  top.edge = PlateEdge::top;
  top.value[1] = kBowieSigma;
  d.loads = {top};
  return d;
}

/// F = K_I / (σ √(πa)) by the interaction integral within `radius` of the tip.
inline double bowie_factor(const PlateModel& m, const PlateState& s, double a, double radius) {
  double k[2] = {0.0, 0.0};
  plate_stress_intensity(m, s, 1, true, radius, k, false);
  return k[0] / (kBowieSigma * std::sqrt(std::numbers::pi * a));
}


}  // namespace xfdem::test
