// Free vibration of a plate with an edge crack (a tip, branch enrichment) and
// a circular void, Newmark (¼, ½): set in motion by a short half-sine
// traction, then unloaded; its energy ½vᵀMv + ½uᵀKu must stay constant to
// round-off. Shared by the short run (tests/xfem/plate_dynamic_test.cpp) and
// the 1e5-step run (tests/long/plate_long_test.cpp, label `long`).
#pragma once
#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "support/plate_scenes.hpp"
#include "xfdem/plate.hpp"
#include "xfem/reference.hpp"

namespace xfdem::test {

struct FreeVibration {
  bool built = false;
  std::int64_t steps = 0;         ///< unloaded steps taken
  int dofs = 0, enriched = 0;     ///< unknowns, of which enrichment (Heaviside and branch)
  double energy0 = 0.0;           ///< E when the load has ended, J
  double drift = 0.0;             ///< max |E − E0| over the unloaded steps, J
  double elastic_peak = 0.0;      ///< the largest elastic part, J (the energy really moves)
  double condition = 0.0;         ///< κ of the Jacobi-scaled M + βΔt²K
  double allowance = 0.0;         ///< 16 κ u N: the stated round-off allowance, relative
  bool statuses_ok = true;        ///< no step returned a status
};

inline PlateDesc cracked_plate_with_a_void() {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.max[0] = 2.0, d.max[1] = 1.0;
  d.cells[0] = 20, d.cells[1] = 10;
  d.youngs_modulus = 2e11;
  d.poisson_ratio = 0.3;
  d.density = 7800.0;
  d.dt = 5e-6;
  d.supports.push_back({PlateEdge::right, {true, true}, false});
  PlateDiscontinuity crack;
  crack.name = "crack";
  crack.points = {{-0.1, 0.53}, {0.73, 0.53}};  // from the left edge to a tip inside
  d.discontinuities = {crack, testing::circle(PlateDiscontinuity::Kind::hole, 1.3, 0.45, 0.23)};
  PlateLoad kick;  // the initial impulse: 5 steps of a half-sine on the top edge
  kick.edge = PlateEdge::top;
  kick.value[0] = 2e6, kick.value[1] = -1e7;
  kick.shape = PlateLoadShape::half_sine, kick.duration = 5 * d.dt;
  d.loads = {kick};
  return d;
}

/// Runs the plate above for `steps` unloaded steps after the kick. The
/// allowance is that of the bar's sweeps (tests/stress/bar_sweeps.hpp,
/// roundoff_epsilon): each step the state is the exact Newmark image of the
/// previous one plus a rounding error of relative size ≤ 16·κ·u in the scaled
/// unknowns, adding at worst linearly over the steps.
inline FreeVibration run_free_vibration(std::int64_t steps, const PlateDesc& d = cracked_plate_with_a_void()) {
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  FreeVibration r;
  if (!build_plate(d, m, st, ws).ok()) return r;
  r.built = true;
  r.dofs = m.dofs;
  r.enriched = m.enriched_dofs + 8 * m.tip_nodes;
  {
    Eigen::MatrixXd a = dense(m.mass) + m.scheme.fac0() * dense(m.stiffness);
    const Eigen::VectorXd s = a.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(s.asDiagonal() * a * s.asDiagonal(),
                                                                               Eigen::EigenvaluesOnly)
                                   .eigenvalues();
    r.condition = ev.maxCoeff() / ev.minCoeff();
  }
  r.allowance = 16.0 * r.condition * (DBL_EPSILON / 2) * static_cast<double>(steps);
  auto total = [&] {
    const PlateEnergy e = plate_energy(m, st);
    return e.kinetic + e.elastic;
  };
  while (st.time <= d.loads[0].duration)  // past its end: both ends of every later step unloaded
    r.statuses_ok = r.statuses_ok && plate_step(m, st, ws) == StepStatus::ok;
  r.energy0 = total();
  for (std::int64_t n = 0; n < steps; ++n) {
    r.statuses_ok = r.statuses_ok && plate_step(m, st, ws) == StepStatus::ok;
    const PlateEnergy e = plate_energy(m, st);
    r.drift = std::max(r.drift, std::fabs(e.kinetic + e.elastic - r.energy0));
    r.elastic_peak = std::max(r.elastic_peak, e.elastic);
    ++r.steps;
  }
  return r;
}

/// What both runs print and assert: the statuses, a real elastic swing, the
/// drift within the round-off allowance 16 κ u N and, as the uncut plate's run
/// (TrapezoidalRuleConserves…), within 1e-12 of E0.
inline void expect_energy_kept(const FreeVibration& r) {
  std::printf("cracked plate with a void, %d unknowns (%d enriched), %lld unloaded steps of (1/4, 1/2): energy "
              "drift %.3g of E0 = %.6g J (%.3g relative; allowance 16 kappa u N = %.3g, kappa = %.3g); elastic peak "
              "%.3g J\n",
              r.dofs, r.enriched, static_cast<long long>(r.steps), r.drift, r.energy0, r.drift / r.energy0,
              r.allowance, r.condition, r.elastic_peak);
  EXPECT_TRUE(r.statuses_ok);
  EXPECT_GT(r.enriched, 0);
  EXPECT_GT(r.elastic_peak, 0.1 * r.energy0);
  EXPECT_LE(r.drift, r.allowance * r.energy0);
  EXPECT_LE(r.drift, 1e-12 * r.energy0);
}

}  // namespace xfdem::test
