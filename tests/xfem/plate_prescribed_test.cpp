// Prescribed nodes with a time shape (docs/xfem2d.md, "Prescribed nodes with
// a time shape"): a column on rollers driven at its top by a half sine or a
// ramp is a 1D consistent-mass bar driven so, stepped by a Newmark written
// here; the energy books balance with moving held nodes; a slow ramp ends at
// the static solution within a bound derived below; a step never allocates
// and a snapshot replays bit for bit; bad shapes are refused naming the field.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/state_io.hpp"

using namespace xfdem;

namespace {

// The column: the V2 rod's numbers (tests/xfem/reference.hpp) as a plate one
// cell (1 m) wide, thickness = the rod's area.
constexpr double kLength = 30.0, kE = 3e7, kArea = 0.4, kRho = 2000.0;
constexpr int kCells = 30;
constexpr double kLift = 1e-3;  // the top's prescribed displacement, m

PlateDesc column(PlatePrescribedShape shape, double duration, double dt, double beta, double gamma) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::stress;
  d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 1.0, d.max[1] = kLength;
  d.cells[0] = 1, d.cells[1] = kCells;
  d.thickness = kArea;
  d.youngs_modulus = kE;
  d.poisson_ratio = 0.0;
  d.density = kRho;
  d.dt = dt, d.beta = beta, d.gamma = gamma;
  d.supports.push_back({PlateEdge::left, {true, false}, false});
  d.supports.push_back({PlateEdge::right, {true, false}, false});
  d.supports.push_back({PlateEdge::bottom, {false, true}, false});
  for (double x : {0.0, 1.0}) {
    PlatePrescribed p;
    p.at[0] = x, p.at[1] = kLength;
    p.displacement[1] = kLift;
    p.shape = shape, p.duration = duration;
    d.prescribed.push_back(p);
  }
  return d;
}

double shape_at(PlatePrescribedShape shape, double duration, double t) {
  if (shape == PlatePrescribedShape::half_sine)
    return t >= 0.0 && t <= duration ? std::sin(std::numbers::pi * t / duration) : 0.0;
  return t <= 0.0 ? 0.0 : t < duration ? t / duration : 1.0;
}

/// The 1D bar with nodes 0 … n (node 0 fixed, node n at g(t)), consistent
/// mass ρAh/6 [2 1; 1 2] and stiffness EA/h [1 −1; −1 1], stepped by Newmark
/// on the whole vector: every node obeys u = ũ + βΔt² a, v = ṽ + γΔt a; the
/// driven node's a follows from its given u, and the free rows of
/// M a + K u = 0 give the free a, solved densely. (The acceleration form: the
/// displacement form's a = (u − ũ)/(βΔt²) cancels digits that the driven
/// node's rates, which ring at the Nyquist frequency after a kink of g,
/// carry from step to step; docs/xfem2d.md.)
struct Bar1d {
  int n;
  double dt, beta, gamma;
  Eigen::MatrixXd mass, stiffness;
  Eigen::VectorXd u, v, a;
  Eigen::LDLT<Eigen::MatrixXd> factor;

  Bar1d(int cells, double step, double b, double g) : n(cells), dt(step), beta(b), gamma(g) {
    const double h = kLength / n;
    mass = Eigen::MatrixXd::Zero(n + 1, n + 1);
    stiffness = Eigen::MatrixXd::Zero(n + 1, n + 1);
    for (int e = 0; e < n; ++e) {
      mass.block(e, e, 2, 2) += kRho * kArea * h / 6.0 * (Eigen::Matrix2d() << 2, 1, 1, 2).finished();
      stiffness.block(e, e, 2, 2) += kE * kArea / h * (Eigen::Matrix2d() << 1, -1, -1, 1).finished();
    }
    u = v = a = Eigen::VectorXd::Zero(n + 1);
    const Eigen::MatrixXd s = mass + beta * dt * dt * stiffness;
    factor.compute(s.block(1, 1, n - 1, n - 1));
  }
  void step(double g_next) {
    const double f0 = beta * dt * dt;
    const Eigen::VectorXd up = u + dt * v + (0.5 - beta) * dt * dt * a;
    const Eigen::VectorXd vp = v + (1.0 - gamma) * dt * a;
    Eigen::VectorXd next = Eigen::VectorXd::Zero(n + 1);
    next(n) = (g_next - up(n)) / f0;
    // Free rows: (M + βΔt² K)_ff a_f = −K_f· ũ − (M + βΔt² K)_fn a_n (u_0 = 0).
    Eigen::VectorXd rhs = -(stiffness * up).segment(1, n - 1);
    rhs -= (mass.block(1, n, n - 1, 1) + f0 * stiffness.block(1, n, n - 1, 1)) * next(n);
    next.segment(1, n - 1) = factor.solve(rhs);
    a = next;
    u = up + f0 * a;
    u(n) = g_next;
    v = vp + gamma * dt * a;
  }
};

}  // namespace

// 1. The column driven at its top is the bar driven at its tip: with ν = 0
// and the nodes of a level moving together, the Q4 matrices summed over a
// level are the bar's; the moving nodes' rates are Newmark's own in both.
TEST(PlatePrescribed, DrivenColumnIsTheDrivenBar) {
  struct Case {
    PlatePrescribedShape shape;
    double duration, beta, gamma;
  };
  for (const Case& c : {Case{PlatePrescribedShape::half_sine, 0.1, 0.25, 0.5},
                        Case{PlatePrescribedShape::ramp, 0.1, 0.25, 0.5},
                        Case{PlatePrescribedShape::half_sine, 0.1, 0.3025, 0.6},
                        Case{PlatePrescribedShape::ramp, 0.1, 0.3025, 0.6}}) {
    const double dt = 1e-3;
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    ASSERT_TRUE(build_plate(column(c.shape, c.duration, dt, c.beta, c.gamma), m, st, ws).ok());
    ASSERT_EQ(m.dofs, 2 * (kCells - 1));
    ASSERT_EQ(m.moving_component.size(), 2u);
    Bar1d bar(kCells, dt, c.beta, c.gamma);
    double worst[3] = {0, 0, 0}, scale[3] = {0, 0, 0};
    for (int step = 1; step <= 300; ++step) {
      ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok) << step;
      bar.step(kLift * shape_at(c.shape, c.duration, step * dt));
      for (int j = 0; j <= kCells; ++j) {
        const double y = j == kCells ? kLength : kLength * j / kCells;
        const double ref[3] = {bar.u(j), bar.v(j), bar.a(j)};
        for (double x : {0.0, 1.0}) {
          const double got[3] = {plate_displacement(m, st, x, y, 1), plate_velocity(m, st, x, y, 1),
                                 plate_acceleration(m, st, x, y, 1)};
          for (int k = 0; k < 3; ++k) {
            scale[k] = std::max(scale[k], std::fabs(ref[k]));
            worst[k] = std::max(worst[k], std::fabs(got[k] - ref[k]));
          }
        }
      }
    }
    std::printf("driven column vs bar (%s, beta %.4g, gamma %.2g), 300 steps: u %.3g of %.3g, v %.3g of %.3g, "
                "a %.3g of %.3g (relative %.2g, %.2g, %.2g)\n",
                c.shape == PlatePrescribedShape::ramp ? "ramp" : "half_sine", c.beta, c.gamma, worst[0], scale[0],
                worst[1], scale[1], worst[2], scale[2], worst[0] / scale[0], worst[1] / scale[1], worst[2] / scale[2]);
    for (int k = 0; k < 3; ++k) EXPECT_LE(worst[k], 1e-12 * scale[k]) << k;
    // The top is where the shape puts it, to the last bit.
    EXPECT_EQ(plate_displacement(m, st, 0.0, kLength, 1), kLift * shape_at(c.shape, c.duration, st.time));
  }
}

// 2. Moving held nodes on a 2D plate with a crack near them (their enrichment
// unknowns couple to them), loads, self weight and an absorbing edge: the
// books (work of the loads, the dashpots and the moving nodes) balance
// Ê − Ê0 − W to round-off for the trapezoidal rule and stay ≤ round-off with
// γ = 0.6, and the kernel's energy check stays silent.
TEST(PlatePrescribed, EnergyBooksBalanceWithMovingHeldNodes) {
  for (const double gamma : {0.5, 0.6}) {
    PlateDesc d;
    d.plane = PlateDesc::Plane::strain;
    d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 1.5, d.max[1] = 1.0;
    d.cells[0] = 6, d.cells[1] = 4;
    d.youngs_modulus = 2e11, d.poisson_ratio = 0.3, d.density = 7800.0;
    d.gamma = gamma, d.beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    d.dt = 2e-5;
    d.self_weight = true;
    d.gravity[1] = -9.81;
    d.supports.push_back({PlateEdge::left, {true, true}, false});
    d.supports.push_back({PlateEdge::bottom, {false, false}, true});
    PlatePrescribed a, b, c;
    a.at[0] = 1.5, a.at[1] = 0.5, a.displacement[0] = 2e-5, a.displacement[1] = -1e-5;
    a.shape = PlatePrescribedShape::half_sine, a.duration = 3e-4;
    b.at[0] = 1.5, b.at[1] = 1.0, b.displacement[0] = 1e-5, b.displacement[1] = 3e-5;
    b.shape = PlatePrescribedShape::ramp, b.duration = 5e-4;
    c.at[0] = 0.75, c.at[1] = 1.0, c.displacement[1] = -1e-5;  // constant (step)
    d.prescribed = {a, b, c};
    PlateLoad traction;
    traction.edge = PlateEdge::top;
    traction.value[1] = -1e6;
    traction.shape = PlateLoadShape::half_sine, traction.duration = 2e-4;
    d.loads = {traction};
    PlateDiscontinuity crack;
    crack.name = "c";
    crack.kind = PlateDiscontinuity::Kind::crack;
    crack.points = {{0.9, 0.6}, {1.6, 0.6}};  // from the right edge, between the moving nodes
    d.discontinuities = {crack};
    // Checked every step, a gain of 1e-9 of the energy in motion flagged.
    d.energy_check.interval = 1, d.energy_check.tolerance = 1e-9;
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(m.moving_component.size(), 4u);
    ASSERT_GT(m.enriched_dofs, 0);
    double worst = 0.0, lowest = 0.0, scale = 0.0;
    for (int step = 1; step <= 3000; ++step) {
      ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok) << step;
      const double e = plate_algorithmic_energy(m, st);
      const double balance = e - st.energy.reference - st.energy.work;
      scale = std::max(scale, std::fabs(st.energy.work) + e);
      worst = std::max(worst, balance);
      lowest = std::min(lowest, balance);
    }
    EXPECT_EQ(st.energy.exceeded, 0);
    std::printf("energy books with moving held nodes, gamma = %.2f: max (E - E0 - W) = %.3g, min %.3g, of a scale "
                "%.3g J\n",
                gamma, worst, lowest, scale);
    if (gamma == 0.5) {
      EXPECT_LE(std::fabs(worst), 1e-11 * scale);
      EXPECT_LE(std::fabs(lowest), 1e-11 * scale);
    } else {
      EXPECT_LE(worst, 1e-11 * scale);
      EXPECT_LT(lowest, -1e-4 * scale);  // the dissipation is real
    }
  }
}

// 3. A slow ramp ends at the static solution. With u_s the static field of
// the final displacement and e = u − u_s on the unknowns after the ramp
// (held nodes still), the semi-discrete e is the free vibration the ramp's
// two kinks start: in the modes φ_i (M-normalised) of the held plate,
// q̈_i + ω_i² q_i = −p_i s̈, s̈ = (δ(t) − δ(t − T))/T, p_i = φ_iᵀ(M u_s)_f, so
// after T |q_i| ≤ 2|p_i|/(ω_i T) and ½eᵀKe = ½Σω_i²q_i² ≤ (2/T²) Σ p_i² =
// (2/T²) (Mu_s)_fᵀ M_ff⁻¹ (Mu_s)_f ≤ (2/T²) u_sᵀMu_s (the Schur complement
// of M is positive). The trapezoidal rule keeps each mode's energy, so the
// bound holds at every step after T; it is asserted, and with T long against
// the wave transit times it is a few 1e-5 of the static elastic energy.
TEST(PlatePrescribed, SlowRampEndsAtTheStaticSolution) {
  auto plate = [](PlateDesc::Analysis analysis) {
    PlateDesc d;
    d.plane = PlateDesc::Plane::strain;
    d.min[0] = 0.0, d.min[1] = 0.0, d.max[0] = 2.0, d.max[1] = 1.0;
    d.cells[0] = 8, d.cells[1] = 4;
    d.youngs_modulus = 2e11, d.poisson_ratio = 0.3, d.density = 7800.0;
    d.analysis = analysis;
    d.supports.push_back({PlateEdge::left, {true, true}, false});
    for (int j = 0; j <= 4; ++j) {
      PlatePrescribed p;
      p.at[0] = 2.0, p.at[1] = j == 4 ? 1.0 : 0.25 * j;
      p.displacement[0] = 1e-4, p.displacement[1] = -2e-4;
      d.prescribed.push_back(p);
    }
    return d;
  };
  PlateModel sm;
  PlateState ss;
  PlateWorkspace sw;
  ASSERT_TRUE(build_plate(plate(PlateDesc::Analysis::statics), sm, ss, sw).ok());

  // T = 0.1 s (5000 steps) is long against the plate's wave transit times
  // (2 m / c_s ≈ 0.64 ms): the bound below comes out at 6e-5 of the static
  // elastic energy.
  const double ramp = 0.1, dt = 2e-5;
  PlateDesc d = plate(PlateDesc::Analysis::dynamic);
  for (PlatePrescribed& p : d.prescribed) p.shape = PlatePrescribedShape::ramp, p.duration = ramp;
  d.dt = dt;
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  ASSERT_EQ(m.dofs, sm.dofs);  // the same unknowns in the same order

  // u_sᵀMu_s: twice the kinetic energy of a state whose velocity is u_s
  // (the moving nodes' velocity their final displacement).
  PlateState probe = st;
  probe.v = ss.u;
  for (std::size_t h = 0; h < m.moving_component.size(); ++h) probe.held_v[h] = m.moving_amplitude[h];
  const double usmus = 2.0 * plate_energy(m, probe).kinetic;
  const double bound = 2.0 * usmus / (ramp * ramp);
  const double static_elastic = plate_energy(sm, ss).elastic;

  const int ramp_steps = static_cast<int>(std::lround(ramp / dt));
  double worst = 0.0, worst_u = 0.0, u_scale = 0.0;
  PlateState error = st;  // e on the unknowns, held nodes at 0 (the ramp's value at t = 0)
  error.time = 0.0;
  for (int step = 1; step <= ramp_steps + 2000; ++step) {
    ASSERT_EQ(plate_step(m, st, ws), StepStatus::ok) << step;
    if (step < ramp_steps) continue;
    for (int i = 0; i < m.dofs; ++i) {
      const auto k = static_cast<std::size_t>(i);
      error.u[k] = st.u[k] - ss.u[k];
      worst_u = std::max(worst_u, std::fabs(error.u[k]));
      u_scale = std::max(u_scale, std::fabs(ss.u[k]));
    }
    worst = std::max(worst, plate_energy(m, error).elastic);
  }
  std::printf("slow ramp (T = %.3g s, %d steps) vs static: error energy %.3g J <= bound %.3g J (static elastic "
              "%.3g J); largest displacement error %.3g of %.3g m\n",
              ramp, ramp_steps, worst, bound, static_elastic, worst_u, u_scale);
  EXPECT_LE(worst, bound);
  EXPECT_LE(bound, 1e-3 * static_elastic);  // the bound says something
}

// A step with moving nodes never allocates, and a snapshot (whose fields now
// carry the moving nodes' rates) restores and replays bit for bit.
TEST(PlatePrescribed, StepNeverAllocatesAndSnapshotReplays) {
  PlateDesc d = column(PlatePrescribedShape::half_sine, 0.1, 1e-3, 0.25, 0.5);
  d.cells[1] = 10;
  d.energy_check.interval = 1;
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  EXPECT_EQ(field_count(st), 11u);
  {
    platform::AllocationCounter counter;
    double sink = 0.0;
    for (int i = 0; i < 200; ++i) {
      EXPECT_EQ(plate_step(m, st, ws), StepStatus::ok);
      sink += plate_displacement(m, st, 0.0, kLength, 1) + plate_velocity(m, st, 0.5, kLength, 1) +
              plate_acceleration(m, st, 1.0, kLength, 1) + plate_energy(m, st).kinetic + plate_momentum(m, st, 1) +
              plate_algorithmic_energy(m, st);
    }
    plate_initial_acceleration(m, st, ws);
    EXPECT_EQ(counter.allocations(), 0u);
    EXPECT_TRUE(std::isfinite(sink));
  }
  std::vector<std::byte> buffer(snapshot_size(st));
  ASSERT_TRUE(save_snapshot(st, buffer, model_fingerprint(m)).ok());
  const std::uint64_t at_save = state_hash(st);
  for (int i = 0; i < 150; ++i) plate_step(m, st, ws);
  const std::uint64_t later = state_hash(st);
  ASSERT_TRUE(restore_snapshot(st, buffer, model_fingerprint(m)).ok());
  EXPECT_EQ(state_hash(st), at_save);
  for (int i = 0; i < 150; ++i) plate_step(m, st, ws);
  EXPECT_EQ(state_hash(st), later);
  // Another shape is another model.
  PlateDesc other = d;
  for (PlatePrescribed& p : other.prescribed) p.shape = PlatePrescribedShape::ramp;
  PlateModel m2;
  PlateState st2;
  PlateWorkspace ws2;
  ASSERT_TRUE(build_plate(other, m2, st2, ws2).ok());
  EXPECT_NE(model_fingerprint(m2), model_fingerprint(m));
}

// A step shape is today's constant: no moving component, the same unknowns.
TEST(PlatePrescribed, StepShapeIsTheConstantValue) {
  PlateDesc d = column(PlatePrescribedShape::step, 0.0, 1e-3, 0.25, 0.5);
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  ASSERT_TRUE(build_plate(d, m, st, ws).ok());
  EXPECT_TRUE(m.moving_component.empty());
  EXPECT_TRUE(st.held_v.empty());
  EXPECT_EQ(field_count(st), 9u);
  EXPECT_EQ(plate_displacement(m, st, 0.0, kLength, 1), kLift);
}

TEST(PlatePrescribed, BadShapesAreRefusedNamingTheField) {
  struct Bad {
    PlatePrescribedShape shape;
    double duration;
    PlateDesc::Analysis analysis;
    std::string message;
  };
  const auto dynamic = PlateDesc::Analysis::dynamic, statics = PlateDesc::Analysis::statics;
  for (const Bad& b : {
           Bad{PlatePrescribedShape::half_sine, 0.0, dynamic,
               "prescribed.0.duration: must be positive and finite (s), got 0"},
           Bad{PlatePrescribedShape::ramp, -1.0, dynamic, "prescribed.0.duration: must be positive and finite (s), got -1"},
           Bad{PlatePrescribedShape::ramp, std::numeric_limits<double>::infinity(), dynamic,
               "prescribed.0.duration: must be positive and finite (s), got inf"},
           Bad{PlatePrescribedShape::step, 0.5, dynamic,
               "prescribed.0.duration: only a half_sine or ramp shape has a duration; must be 0, got 0.5"},
           Bad{PlatePrescribedShape::ramp, 0.5, statics,
               "prescribed.0.shape: a static analysis has no time; ramp needs analysis dynamic (use step)"},
           Bad{static_cast<PlatePrescribedShape>(7), 0.5, dynamic,
               "prescribed.0.shape: must be step, half_sine or ramp"},
       }) {
    PlateDesc d = column(b.shape, b.duration, 1e-3, 0.25, 0.5);
    d.analysis = b.analysis;
    PlateModel m;
    PlateState st;
    PlateWorkspace ws;
    const BuildResult r = build_plate(d, m, st, ws);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(std::string(r.message), b.message);
  }
  // The same node prescribed twice with different shapes.
  PlateDesc d = column(PlatePrescribedShape::ramp, 0.2, 1e-3, 0.25, 0.5);
  d.prescribed.push_back(d.prescribed[0]);
  d.prescribed.back().shape = PlatePrescribedShape::half_sine;
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  const BuildResult r = build_plate(d, m, st, ws);
  EXPECT_EQ(std::string(r.message),
            "prescribed.2.shape: the node at (0, 30) is already prescribed by prescribed.0 with another shape or "
            "duration");
}
