// Plane waves in the plate against 1D closed forms: a P or S pulse leaving
// through an absorbing (Lysmer) edge that a crack or an inclusion reaches
// reflects as little as through an uncut edge (the enrichment unknowns are
// damped too), and a P pulse at a free crack across the plate reflects as
// from a free end (d'Alembert).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "xfdem/plate.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfem/plate_fields.hpp"

using namespace xfdem;

namespace {

constexpr double kEps = DBL_EPSILON;
constexpr double kPi = std::numbers::pi;

// ---- a pulse leaving through an absorbing edge ------------------------------

enum class Cut { none, crack, tied_crack, inclusion, stiffer_right_part };

struct WaveCase {
  int component = 0;  // 0: P wave (u_x), 1: S wave (u_y), both travelling in +x
  Cut cut = Cut::none;
  double nu = 0.0;
  int cells_per_metre = 10;
  bool absorb_enrichment = true;
};

struct WaveResult {
  double fraction = 0.0;       // energy left in the plate after the pulse has left, of the initial
  std::vector<double> sample;  // the displacement on a grid of points at the end
  double amplitude = 0.0;      // the pulse's amplitude (m)
  double balance = 0.0;        // largest |Ê − Ê0 − W| over the run, J
  double scale = 0.0;          // its scale: Ê0, J
  int absorb_blocks = 0;       // blocks of the dashpots on enrichment unknowns
  std::size_t allocations = 0;  // made by the steps
};

constexpr double kLength = 8.0, kHeight = 1.0;
constexpr double kCrackY = 0.537;                    // off the node lines of both meshes
constexpr double kBandLow = 0.337, kBandHigh = 0.737;  // the inclusion: a band across the plate
constexpr double kInterfaceX = 5.03;  // the stiffer right part's interface, off the node lines

/// A rectangular inclusion (x0, y0)–(x1, y1) of the plate's ν and ρ and the given E.
void add_rectangle_inclusion(PlateDesc& d, const char* name, double x0, double y0, double x1, double y1,
                             double youngs_modulus) {
  PlateDiscontinuity q;
  q.name = name;
  q.kind = PlateDiscontinuity::Kind::inclusion;
  q.shape = PlateDiscontinuity::Shape::polygon;
  q.points = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  q.material = {youngs_modulus, d.poisson_ratio, d.density};
  d.discontinuities.push_back(q);
}

// A strip 8 × 1 m, E = 1 GPa, ρ = 1000 kg/m³, plane strain, absorbing on the
// left and right edges; rollers on the top and bottom (y held for a P wave, x
// for an S wave) make a plane wave exact: u_c = f(x − ct) with c = c_p =
// √(D₁₁/ρ) or c_s = √(μ/ρ). The pulse starts at x0 = 2 m as f(s) = A cos²(πs/2w)
// (|s| < w = 0.5 m) moving right: u = f, v = −c f'. The Lysmer dashpot absorbs
// a normally incident plane wave exactly (1D: reflection coefficient
// (ρc − η)/(ρc + η) = 0 for η = ρc), so what is left in the plate once the
// pulse has left, before the left-going reflection reaches the left edge, is
// the discretisation's reflection.
WaveResult run_wave(const WaveCase& w) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.max[0] = kLength, d.max[1] = kHeight;
  d.cells[0] = static_cast<int>(kLength) * w.cells_per_metre;
  d.cells[1] = static_cast<int>(kHeight) * w.cells_per_metre;
  d.youngs_modulus = 1e9;
  d.poisson_ratio = w.nu;
  d.density = 1000.0;
  d.absorb_enrichment = w.absorb_enrichment;
  const int held = w.component == 0 ? 1 : 0;
  PlateSupport roller;
  roller.fix[held] = true;
  roller.edge = PlateEdge::bottom;
  d.supports.push_back(roller);
  roller.edge = PlateEdge::top;
  d.supports.push_back(roller);
  d.supports.push_back({PlateEdge::left, {false, false}, true});
  d.supports.push_back({PlateEdge::right, {false, false}, true});
  if (w.cut == Cut::crack || w.cut == Cut::tied_crack) {
    PlateDiscontinuity q;
    q.name = "crack";
    q.points = {{-1.0, kCrackY}, {kLength + 1.0, kCrackY}};
    if (w.cut == Cut::tied_crack) {  // stiff faces: a jump of 1e-6 of a cell's strain × h under the wave's stress
      q.faces = PlateDiscontinuity::Faces::tied;
      q.stiffness[0] = q.stiffness[1] = 1e6 * d.youngs_modulus * w.cells_per_metre;
    }
    d.discontinuities.push_back(q);
  } else if (w.cut == Cut::stiffer_right_part) {
    // four times as stiff: twice the impedance, twice the speed
    add_rectangle_inclusion(d, "right", kInterfaceX, -1.0, kLength + 1.0, kHeight + 1.0, 4.0 * d.youngs_modulus);
  } else if (w.cut == Cut::inclusion) {
    // the same material: invisible to the wave
    add_rectangle_inclusion(d, "band", -1.0, kBandLow, kLength + 1.0, kBandHigh, d.youngs_modulus);
  }
  // E, ν, ρ give c_p, c_s; the step is half a cell's crossing time at c_p.
  const double lambda = d.youngs_modulus * w.nu / ((1.0 + w.nu) * (1.0 - 2.0 * w.nu));
  const double mu = 0.5 * d.youngs_modulus / (1.0 + w.nu);
  const double cp = std::sqrt((lambda + 2.0 * mu) / d.density), cs = std::sqrt(mu / d.density);
  const double c = w.component == 0 ? cp : cs;
  d.dt = 0.5 / (w.cells_per_metre * cp);
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  WaveResult r;
  if (!build_plate(d, m, st, ws).ok()) {
    ADD_FAILURE() << build_plate(d, m, st, ws).message;
    return r;
  }
  r.absorb_blocks = m.absorb_start.empty() ? 0 : static_cast<int>(m.absorb_start.size()) - 1;
  const double amplitude = 1e-4, x0 = 2.0, half = 0.5;
  auto f = [&](double s) { return std::fabs(s) < half ? amplitude * std::pow(std::cos(0.5 * kPi * s / half), 2) : 0.0; };
  auto fp = [&](double s) { return std::fabs(s) < half ? -amplitude * 0.5 * kPi / half * std::sin(kPi * s / half) : 0.0; };
  test::set_field(m, st.u, [&](double x, double, int comp) { return comp == w.component ? f(x - x0) : 0.0; });
  test::set_field(m, st.v, [&](double x, double, int comp) { return comp == w.component ? -c * fp(x - x0) : 0.0; });
  EXPECT_EQ(plate_initial_acceleration(m, st, ws), StepStatus::ok);
  auto total = [&] {
    const PlateEnergy e = plate_energy(m, st);
    return e.kinetic + e.elastic;
  };
  const double e0 = total();
  // The tail leaves the right edge at (L − x0 + w)/c = 6.5 m / c; the
  // reflection of the front reaches the left edge at (2L − x0 − w)/c = 13.5 m / c.
  // With the stiffer right part (c₂ = 2c): the transmitted tail leaves at
  // (x_i − x0 + w)/c + (L − x_i)/(2c) = 5.0 m / c, the interface's reflection
  // reaches the left edge at (2x_i − x0 − w)/c = 7.56 m / c.
  const double t_end = (w.cut == Cut::stiffer_right_part ? 6.0 : 10.0) / c;
  const int steps = static_cast<int>(std::ceil(t_end / d.dt));
  r.scale = plate_algorithmic_energy(m, st);
  platform::AllocationCounter counter;
  for (int step = 1; step <= steps; ++step) {
    EXPECT_EQ(plate_step(m, st, ws), StepStatus::ok);
    r.balance = std::max(r.balance, std::fabs(plate_algorithmic_energy(m, st) - st.energy.reference - st.energy.work));
  }
  r.allocations = counter.allocations();
  r.fraction = total() / e0;
  r.amplitude = amplitude;
  for (int i = 0; i <= 40; ++i)
    for (const double y : {0.05, 0.25, 0.45, 0.65, 0.85})
      for (int comp = 0; comp < 2; ++comp) r.sample.push_back(plate_displacement(m, st, 0.2 * i, y, comp));
  return r;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::fabs(a[k] - b[k]));
  return worst;
}

}  // namespace

// The uncut strip: the reflected fraction is the discretisation's, and it
// falls towards the closed form's 0 as the mesh is refined (it is not a floor
// of the dashpot).
TEST(PlateWave, AbsorbingEdgeReflectsTowardsLysmersZeroUnderRefinement) {
  for (const int component : {0, 1}) {
    const double coarse = run_wave({component, Cut::none, 0.25, 10}).fraction;
    const double fine = run_wave({component, Cut::none, 0.25, 20}).fraction;
    std::printf("%s wave, uncut absorbing edge: reflected energy fraction %.3g (10 cells/m), %.3g (20 cells/m); "
                "1D Lysmer closed form 0\n",
                component == 0 ? "P" : "S", coarse, fine);
    EXPECT_GT(coarse, 0.0);
    EXPECT_LT(coarse, 1e-2);
    EXPECT_LT(fine, 0.25 * coarse);
  }
}

// An absorbing edge reached by a free crack (P wave, ν = 0) or by an
// inclusion of the plate's own material (P and S waves, ν = 0.25): neither is
// seen by the plane wave (no stress acts across the crack with ν = 0; the
// inclusion is the same material), so the enriched plate must give the uncut
// plate's answer. It does to round-off when the dashpots act on the
// enrichment unknowns too (the Galerkin equations of the enrichment
// functions factor into the uncut ones); with dashpots on the standard
// unknowns only, the enrichment rows are left with the edge's traction
// unbalanced and the edge reflects far more.
TEST(PlateWave, AbsorbingEdgeCutByACrackOrAnInclusionReflectsAsTheUncutEdge) {
  struct Case {
    int component;
    Cut cut;
    double nu;
    const char* what;
  };
  for (const Case k : {Case{0, Cut::crack, 0.0, "P wave, free crack, nu = 0"},
                       Case{0, Cut::inclusion, 0.25, "P wave, inclusion band, nu = 0.25"},
                       Case{1, Cut::inclusion, 0.25, "S wave, inclusion band, nu = 0.25"}}) {
    const WaveResult uncut = run_wave({k.component, Cut::none, k.nu, 10});
    const WaveResult cut = run_wave({k.component, k.cut, k.nu, 10});
    const WaveResult standard_only = run_wave({k.component, k.cut, k.nu, 10, false});
    const double diff = largest_difference(cut.sample, uncut.sample);
    std::printf("%s: reflected fraction uncut %.6g, cut %.6g (relative difference %.3g), dashpots on the standard "
                "unknowns only %.3g (%.3g x); displacement cut vs uncut %.3g m of %.3g (%.1f eps); %d enriched "
                "dashpot blocks; energy books |E - E0 - W| %.3g of %.3g J\n",
                k.what, uncut.fraction, cut.fraction, std::fabs(cut.fraction - uncut.fraction) / uncut.fraction,
                standard_only.fraction, standard_only.fraction / uncut.fraction, diff, cut.amplitude,
                diff / (cut.amplitude * kEps), cut.absorb_blocks, cut.balance, cut.scale);
    EXPECT_GT(cut.absorb_blocks, 0);
    EXPECT_EQ(cut.allocations, 0u);  // the blocks' product and work use the workspace sized at build
    EXPECT_LE(diff, 1024 * kEps * cut.amplitude);
    EXPECT_LE(std::fabs(cut.fraction - uncut.fraction), 1e-6 * uncut.fraction);
    EXPECT_GT(standard_only.fraction, 1.02 * uncut.fraction);  // 6.9x, 4.4x, 1.05x (printed)
    EXPECT_LE(cut.balance, 1e-12 * cut.scale);  // (1/4, 1/2): the dashpots' work is booked exactly
  }
}

// ---- a P pulse at a free crack across the strip ------------------------------

namespace {

constexpr double kStripLength = 4.0, kStripHeight = 0.4;
constexpr double kSigma = 1e6, kPulse = 5e-4;  // Pa, s: the half-sine traction's amplitude and duration

struct StripRun {
  double front_error = 0.0;    // max |u − u_exact| in front of the crack, of the largest |u_exact|
  double behind = 0.0;         // max |u| behind the crack (x and y), m
  double front_peak = 0.0;     // max |u| in front, m
  double face_velocity = 0.0;  // the largest velocity of the front face, m/s
  std::vector<double> front;   // u_x at the probes in front, every step
  int steps = 0;
};

// A strip [0, 4] × [0, 0.4] m, E = 1 GPa, ρ = 1000 kg/m³, ν = 0, plane strain,
// y held on the top and bottom: a 1D rod with c = √(E/ρ). The left edge takes
// the traction σ0 sin(πt/T) (t ≤ T, pushing in +x); a free crack from the
// bottom to the top at x = xc (none for a plate of length xc: the conforming
// cut, the crack as its right edge). d'Alembert: the incident wave
// v = σ0/(ρc) s(t − x/c) reflects from the free face with the same velocity,
// so in front u = σ0/(ρc)[S(t − x/c) + S(t − (2xc − x)/c)], S(τ) = ∫₀^τ s =
// (T/π)(1 − cos(πτ/T)) for 0 ≤ τ ≤ T, 2T/π after; the face moves at twice
// the incident velocity; behind the crack nothing moves. Valid until the
// reflection, re-reflected at the left edge, comes back: t < (2xc + x)/c; the
// run stops at t = 2xc/c.
StripRun run_strip(double xc, bool crack, int cells_per_metre) {
  PlateDesc d;
  d.plane = PlateDesc::Plane::strain;
  d.max[0] = crack ? kStripLength : xc, d.max[1] = kStripHeight;
  d.cells[0] = static_cast<int>(std::lround(d.max[0] * cells_per_metre));
  d.cells[1] = static_cast<int>(std::lround(kStripHeight * cells_per_metre));
  d.youngs_modulus = 1e9;
  d.poisson_ratio = 0.0;
  d.density = 1000.0;
  const double c = std::sqrt(d.youngs_modulus / d.density);
  d.dt = 0.25 / (cells_per_metre * c);
  for (const PlateEdge e : {PlateEdge::bottom, PlateEdge::top}) d.supports.push_back({e, {false, true}, false});
  PlateLoad push;
  push.edge = PlateEdge::left;
  push.value[0] = kSigma;
  push.shape = PlateLoadShape::half_sine, push.duration = kPulse;
  d.loads.push_back(push);
  if (crack) {
    PlateDiscontinuity q;
    q.name = "crack";
    q.points = {{xc, -1.0}, {xc, kStripHeight + 1.0}};
    d.discontinuities.push_back(q);
  }
  PlateModel m;
  PlateState st;
  PlateWorkspace ws;
  StripRun r;
  if (const BuildResult b = build_plate(d, m, st, ws); !b.ok()) {
    ADD_FAILURE() << b.message;
    return r;
  }
  const double z = kSigma / (d.density * c);  // σ0/(ρc): the incident velocity's amplitude
  auto big_s = [&](double tau) {
    if (tau <= 0.0) return 0.0;
    return tau >= kPulse ? 2.0 * kPulse / kPi : kPulse / kPi * (1.0 - std::cos(kPi * tau / kPulse));
  };
  auto exact = [&](double x, double t) { return z * (big_s(t - x / c) + big_s(t - (2.0 * xc - x) / c)); };
  const double face = xc - 1e-9;  // the front face (a probe exactly on the crack is refused)
  const double front_x[] = {0.0, 0.5, 1.0, 1.5, 1.8, face};
  const double behind_x[] = {xc + 1e-9, 2.5, 3.0, kStripLength};
  const int steps = static_cast<int>(std::lround(2.0 * xc / c / d.dt));
  r.steps = steps;
  double worst = 0.0;
  for (int step = 1; step <= steps; ++step) {
    EXPECT_EQ(plate_step(m, st, ws), StepStatus::ok);
    for (const double x : front_x)
      for (const double y : {0.0, 0.13, kStripHeight}) {
        const double u = plate_displacement(m, st, x, y, 0);
        r.front.push_back(u);
        worst = std::max(worst, std::fabs(u - exact(x, st.time)));
        r.front_peak = std::max(r.front_peak, std::fabs(exact(x, st.time)));
      }
    r.face_velocity = std::max(r.face_velocity, plate_velocity(m, st, face, 0.2, 0));
    if (crack)
      for (const double x : behind_x)
        for (const double y : {0.0, 0.13, kStripHeight})
          for (int comp = 0; comp < 2; ++comp) r.behind = std::max(r.behind, std::fabs(plate_displacement(m, st, x, y, comp)));
  }
  r.front_error = worst / r.front_peak;
  r.face_velocity /= z;
  return r;
}

}  // namespace

// The strip crossed by a free crack parallel to the loaded edge, off the node
// lines (X-FEM: the crack's cells cut, their nodes Heaviside-enriched) and on
// a node line, against d'Alembert's solution the test computes, and the node
// line against the conforming cut (a strip ending at the crack): the same
// function space on the front part, so the same answer to round-off.
TEST(PlateWave, PulseReflectsFromAFreeCrackAsFromAFreeEnd) {
  StripRun coarse;
  for (const int cells : {20, 40}) {
    const double h = 1.0 / cells;
    const double off = 2.0 + 0.37 * h;  // in a cell, 37 % of the way across
    const StripRun xfem = run_strip(off, true, cells);
    const StripRun node = run_strip(2.0, true, cells);
    const StripRun conforming = run_strip(2.0, false, cells);
    const double node_vs_conforming = largest_difference(node.front, conforming.front);
    std::printf("free crack, %d cells/m, %d steps: front displacement error of its peak %.3g m: off the nodes %.3g, "
                "on a node line %.3g, conforming %.3g; face velocity / (sigma0 / rho c) %.4f, %.4f, %.4f (closed "
                "form 2); largest displacement behind the crack %.3g m, %.3g m (%.1f, %.1f eps of the peak); node "
                "line vs conforming %.3g m (%.1f eps)\n",
                cells, xfem.steps, xfem.front_peak, xfem.front_error, node.front_error, conforming.front_error,
                xfem.face_velocity, node.face_velocity, conforming.face_velocity, xfem.behind, node.behind,
                xfem.behind / (kEps * xfem.front_peak), node.behind / (kEps * node.front_peak), node_vs_conforming,
                node_vs_conforming / (kEps * node.front_peak));
    // Nothing crosses a free crack: zero in exact arithmetic; round-off of ε
    // of the peak per step at most.
    EXPECT_LE(xfem.behind, xfem.steps * kEps * xfem.front_peak);
    EXPECT_LE(node.behind, node.steps * kEps * node.front_peak);
    // On a node line the front part is the conforming strip's function space.
    EXPECT_LE(node_vs_conforming, node.steps * kEps * node.front_peak);
    if (cells == 20) {
      coarse = xfem;
      continue;
    }
    // The discretisation's error (dispersion at the half-sine's kinks) falls
    // with the cell: 4.5 % → 2.0 % of the peak, the face velocity 2.14 → 1.994.
    EXPECT_LE(xfem.front_error, 2.5e-2);
    EXPECT_GE(coarse.front_error / xfem.front_error, 1.8);
    EXPECT_LE(std::fabs(xfem.face_velocity - 2.0), 1e-2);
    EXPECT_LT(std::fabs(xfem.face_velocity - 2.0), std::fabs(coarse.face_velocity - 2.0));
  }
}

// An S wave along a crack is not blind to it (σ_xy acts on the faces), so a
// free crack scatters it; with faces tied by a stiff penalty (k = 1e6 E/h)
// the crack transmits the wave up to jumps of 1e-6 of a cell's relative
// displacement, and the edge it reaches must again absorb as the uncut one.
TEST(PlateWave, AbsorbingEdgeCutByAStiffTiedCrackAbsorbsAnSWave) {
  const WaveResult uncut = run_wave({1, Cut::none, 0.25, 10});
  const WaveResult cut = run_wave({1, Cut::tied_crack, 0.25, 10});
  const WaveResult standard_only = run_wave({1, Cut::tied_crack, 0.25, 10, false});
  const double diff = largest_difference(cut.sample, uncut.sample);
  std::printf("S wave, tied crack k = 1e6 E/h: reflected fraction uncut %.6g, cut %.6g (relative difference %.3g), "
              "dashpots on the standard unknowns only %.3g (%.3g x); displacement cut vs uncut %.3g m of %.3g; %d "
              "enriched dashpot blocks; energy books |E - E0 - W| %.3g of %.3g J\n",
              uncut.fraction, cut.fraction, std::fabs(cut.fraction - uncut.fraction) / uncut.fraction,
              standard_only.fraction, standard_only.fraction / uncut.fraction, diff, cut.amplitude, cut.absorb_blocks,
              cut.balance, cut.scale);
  EXPECT_GT(cut.absorb_blocks, 0);
  EXPECT_LE(diff, 1e-6 * cut.amplitude);                                   // the penalty's jump scale
  EXPECT_LE(std::fabs(cut.fraction - uncut.fraction), 1e-3 * uncut.fraction);
  EXPECT_GT(standard_only.fraction - uncut.fraction, 10.0 * std::fabs(cut.fraction - uncut.fraction));
  EXPECT_LE(cut.balance, 1e-12 * cut.scale);
  EXPECT_EQ(cut.allocations, 0u);
}

// The absorbing edge takes the impedance of the material at it: the strip's
// right part (x > 5.03 m, an inclusion reaching the edge) has 4 E and the same
// ρ, so Z₂ = 2Z₁. The P pulse meets the interface at normal incidence: the 1D
// closed form reflects ((Z₂ − Z₁)/(Z₂ + Z₁))² = 1/9 of its energy; the rest
// leaves through the right edge, whose dashpot √(ρ·4D₁₁) absorbs it (one with
// the strip's own Z₁ would send a further 8/9 · 1/9 back). Measured when the
// transmitted pulse has left and the reflected one has not reached the left edge.
TEST(PlateWave, AbsorbingEdgeInAStifferPartTakesItsImpedance) {
  const double z1 = 1.0, z2 = 2.0;
  const double closed = std::pow((z2 - z1) / (z2 + z1), 2);
  double previous = 0.0;
  for (const int cells : {10, 20}) {
    const WaveResult r = run_wave({0, Cut::stiffer_right_part, 0.25, cells});
    const double error = std::fabs(r.fraction / closed - 1.0);
    std::printf("P wave into a part of twice the impedance, absorbed at its edge, %d cells/m: energy left %.6g, 1D "
                "closed form %.6g (relative difference %.3g); with the strip's own impedance at the edge it would "
                "be %.6g\n",
                cells, r.fraction, closed, error, closed + (1.0 - closed) * closed);
    EXPECT_LE(r.balance, 1e-12 * r.scale);
    EXPECT_EQ(r.allocations, 0u);
    if (cells == 10) {
      previous = error;
      continue;
    }
    EXPECT_LE(error, 1e-2);           // 3.45 % → 0.74 %: second order
    EXPECT_LT(error, 0.3 * previous);
  }
}
