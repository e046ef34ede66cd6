// Stability stress sweeps of the continuum (label `stress`): the interface
// penalty over six decades, cut fractions down to 1e-9 (1e-12 for a unilateral one), Newmark parameters at
// and beyond the stability boundary, for a tied and a unilateral interface,
// X-FEM and the conforming mesh. Each case runs 2e4 steps (20 s of the kicked
// rod, about twenty bounces of the upper piece) and prints one line of the
// map; tests/long runs the worst corners for 1e6 steps. bar_sweeps.hpp gives
// the energy identity, the bound and its ε.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "stress/bar_sweeps.hpp"
#include "support/sanitizers.hpp"

namespace xfdem::stress {
namespace {

using Behaviour = BarInterfaceDesc::Behaviour;
using Method = BarDesc::Method;
using Base = BarDesc::Base;

constexpr std::int64_t kSteps = 20000;

struct Newmark {
  double beta, gamma;
};
constexpr Newmark kTrapezoidal{0.25, 0.5};  // energy-conserving: the identity is an equality
constexpr Newmark kPaper{0.4, 0.6};         // the paper's and the scenes' choice: dissipative

/// β on the stability boundary for this γ, (γ + ½)²/4.
double boundary_beta(double gamma) { return 0.25 * (gamma + 0.5) * (gamma + 0.5); }

/// The unilateral sweeps' schemes: the two above, on the boundary at γ = 0.6,
/// and 1.15 times it at γ = 0.539 (where the coupled sweep once gained 0.25 of
/// A before the energy rule of bar_step()).
const std::initializer_list<Newmark> kUnilateralSchemes = {
    kTrapezoidal, kPaper, {0.3025, 0.6}, {1.15 * 0.25 * 1.039 * 1.039, 0.539}};

void run_and_check(BarDesc d, const char* label) {
  const KickedRod load = load_for(d);
  const BarOutcome o = run_bar_case(d, load, kSteps);
  print_outcome(label, o);
  expect_case(label, d, o);
}

// k from 1·E·A to 1e6·E·A per metre, Newmark (¼, ½) and (0.4, 0.6), both
// methods, fixed and absorbing base, interface mid-element (14.5 m).
void penalty_sweep(Behaviour behaviour, std::initializer_list<Newmark> schemes = {kTrapezoidal, kPaper}) {
  for (double multiple : {1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6}) {
    // Under the sanitizer the decades 1, 1e3 and 1e6 only.
    if (test::kUnderAsan && multiple != 1.0 && multiple != 1e3 && multiple != 1e6) continue;
    for (Newmark nm : schemes)
      for (Method method : {Method::xfem, Method::fem})
        for (Base base : {Base::fixed, Base::absorbing}) {
          BarDesc d = kicked_rod();
          d.interface->stiffness = penalty(d, multiple);
          d.interface->behaviour = behaviour;
          d.method = method;
          d.beta = nm.beta;
          d.gamma = nm.gamma;
          if (base == Base::absorbing) make_absorbing(d);
          char label[160];
          std::snprintf(label, sizeof label, "%-10s k %.0e EA  beta %.4f gamma %.2f  %-4s %-9s", name(behaviour),
                        multiple, nm.beta, nm.gamma, name(method), name(base));
          run_and_check(d, label);
        }
  }
}

// Interface at x_e + f·h in element 14 (x_e = 14 m, h = 1 m), f = 1e-1 … 1e-9
// and 1 − 1e-9, the paper's penalty 100·E·A, fixed base.
void cut_sweep(Behaviour behaviour, std::initializer_list<Newmark> schemes = {kTrapezoidal, kPaper},
               std::initializer_list<double> fractions = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9,
                                                          1.0 - 1e-9}) {
  for (double f : fractions)
    for (Newmark nm : schemes)
      for (Method method : {Method::xfem, Method::fem}) {
        BarDesc d = kicked_rod();
        d.interface->position = 14.0 + f;
        d.interface->behaviour = behaviour;
        d.method = method;
        d.beta = nm.beta;
        d.gamma = nm.gamma;
        char label[160];
        std::snprintf(label, sizeof label, "%-10s cut %-11.9g beta %.4f gamma %.2f  %-4s", name(behaviour), f,
                      nm.beta, nm.gamma, name(method));
        run_and_check(d, label);
      }
}

// On the boundary of the accepted region: (¼, ½) and β = (γ + ½)²/4 for
// γ = 0.6 and 0.9, at the paper's interface (100·E·A, mid-element) and at the
// stiffest, thinnest corner (1e6·E·A at a cut of 1e-9).
void boundary_sweep(Behaviour behaviour, std::initializer_list<double> gammas = {0.5, 0.6, 0.9}) {
  struct Corner {
    double multiple, fraction;
  };
  for (double gamma : gammas)
    for (Corner corner : {Corner{1e2, 0.5}, Corner{1e6, 1e-9}})
      for (Method method : {Method::xfem, Method::fem}) {
        BarDesc d = kicked_rod();
        d.interface->stiffness = penalty(d, corner.multiple);
        d.interface->position = 14.0 + corner.fraction;
        d.interface->behaviour = behaviour;
        d.method = method;
        d.gamma = gamma;
        d.beta = boundary_beta(gamma);
        char label[160];
        std::snprintf(label, sizeof label, "%-10s beta %.4f gamma %.2f  k %.0e EA cut %-5.2g %-4s", name(behaviour),
                      d.beta, gamma, corner.multiple, corner.fraction, name(method));
        run_and_check(d, label);
      }
}

}  // namespace

// A tied interface is a linear spring: E ≤ E0 + W to round-off for every
// accepted (β, γ), with equality at (¼, ½). The identity's residual is ~4e-13
// of A with X-FEM at every penalty and cut; with the conforming mesh a sliver
// element of length f·h is itself a spring of stiffness E·A/(f·h), κ grows
// like 1/f (3e7 at f = 1e-9) and so does the residual (2e-5 of A), inside ε.
TEST(BarStress, TiedInterfacePenaltyOverSixDecades) { penalty_sweep(Behaviour::tied); }
TEST(BarStress, TiedCutFractionsDownTo1e9) { cut_sweep(Behaviour::tied); }
TEST(BarStress, TiedNewmarkOnTheStabilityBoundaryStaysBounded) { boundary_sweep(Behaviour::tied); }

// A unilateral interface (load: the upper piece dropped from 0.1 m under the
// press, bouncing about once a second). Integrated across a switch, the
// Newmark average of its kinked force gains R = k(1 − γ)|g_n|g_{n+1} −
// k(γ − ½)g_n² at an opening (bar_sweeps.hpp), which nothing in the scheme
// bounds. What the map shows:
//   - (¼, ½): every step in which the set changes is split where the gap is
//     zero, each substep of a linear system, so E = E0 + W holds to round-off;
//     a switch the location cannot place (a sliver's mode moving the gap too
//     fast, 1e6·E·A at a 1e-9 cut) is left to the energy rule;
//   - the other schemes, one step each: the energy rule of bar_step() takes
//     out R − D where it is positive (the `removed` column), so E ≤ Ê0 + W at
//     every step, on the boundary at γ = 0.6 too (which gained 0.65–47·A before).
// Cuts down to 1e-12 of an element from a node (and 1 − 1e-12), both meshes.
TEST(BarStress, UnilateralInterfacePenaltyOverSixDecades) {
  penalty_sweep(Behaviour::unilateral, kUnilateralSchemes);
}
TEST(BarStress, UnilateralCutFractionsDownTo1e12) {
  cut_sweep(Behaviour::unilateral, kUnilateralSchemes,
            {1e-1, 1e-3, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1.0 - 1e-9, 1.0 - 1e-12});
}
TEST(BarStress, UnilateralNewmarkOnTheStabilityBoundaryStaysBounded) {
  boundary_sweep(Behaviour::unilateral, {0.5, 0.6, 0.9});
}

// Beyond the boundary (β < (γ + ½)²/4, or γ < ½) the scheme is at best
// conditionally stable, with a step limit set by the highest frequency, which a
// stiff penalty or a sliver cut drives to infinity: the build must refuse,
// naming the parameter. γ is checked first, so γ < ½ names `gamma` whatever β
// is; otherwise `beta`, and its message states the bound, which must be the
// closed form (γ + ½)²/4, and the value refused, in full. The boundary itself is accepted, computed or written
// in decimal (the kernel allows a relative slack of 1e-12 for that); 1e-10
// below it is refused.
TEST(BarStress, NewmarkBeyondTheStabilityBoundaryIsRefused) {
  struct Case {
    double beta, gamma;
    const char* field;  // nullptr: must be accepted
  };
  const double nan = std::nan("");
  const Case cases[] = {
      {0.0, 0.5, "beta"},                             // central difference
      {1.0 / 12.0, 0.5, "beta"},                      // Fox–Goodwin
      {1.0 / 6.0, 0.5, "beta"},                       // linear acceleration
      {0.25 * (1 - 1e-10), 0.5, "beta"},              // a hair below the trapezoidal rule
      {-0.1, 0.5, "beta"},
      {0.3, 0.6, "beta"},                             // below 0.3025
      {boundary_beta(0.6) * (1 - 1e-10), 0.6, "beta"},
      {0.45, 0.9, "beta"},                            // below 0.49
      {nan, 0.5, "beta"},
      {0.25, 0.49, "gamma"},                          // γ below ½ (negative numerical damping)
      {0.3, 0.4, "gamma"},
      {0.0, 0.0, "gamma"},
      {1.0, 0.5 * (1 - 1e-15), "gamma"},              // γ a hair below ½: no slack on γ
      {0.25, nan, "gamma"},
      {0.25, 0.5, nullptr},
      {0.3025, 0.6, nullptr},                         // the boundary written in decimal
      {boundary_beta(0.6), 0.6, nullptr},
      {0.49, 0.9, nullptr},
      {boundary_beta(0.9), 0.9, nullptr},
      {0.25 * (1 - 1e-13), 0.5, nullptr},             // within the stated slack
  };
  for (const Case& c : cases) {
    for (Behaviour behaviour : {Behaviour::tied, Behaviour::unilateral}) {
      BarDesc d = kicked_rod();
      d.interface->behaviour = behaviour;
      d.beta = c.beta;
      d.gamma = c.gamma;
      BarModel m;
      BarState st;
      BarWorkspace ws;
      const BuildResult r = build_bar(d, m, st, ws);
      const std::string message = r.message;
      std::printf("  beta %-22.17g gamma %-20.17g %-10s: %s%s\n", c.beta, c.gamma, name(behaviour),
                  r.ok() ? "accepted" : "refused: ", message.c_str());
      EXPECT_EQ(std::string(validate_bar(d).message), message);
      if (c.field == nullptr) {
        EXPECT_TRUE(r.ok()) << message;
        EXPECT_EQ(bar_step(m, st, ws), StepStatus::ok);
        continue;
      }
      ASSERT_FALSE(r.ok()) << "beta " << c.beta << " gamma " << c.gamma;
      EXPECT_EQ(message.rfind(std::string(c.field) + ":", 0), 0u) << message;
      // Past the boundary is a stability refusal; a non-finite value is bad input.
      const bool finite = std::isfinite(c.beta) && std::isfinite(c.gamma);
      EXPECT_EQ(r.code, finite ? BuildResult::Code::unstable_time_step : BuildResult::Code::invalid_argument)
          << message;
      if (finite) {
        // The offending value is printed in full: a hair past the bound does not read as the bound.
        const double value = std::string(c.field) == "beta" ? c.beta : c.gamma;
        const std::size_t got = message.rfind("got ");
        ASSERT_NE(got, std::string::npos) << message;
        EXPECT_EQ(std::strtod(message.c_str() + got + 4, nullptr), value) << message;
      }
      EXPECT_EQ(bar_step(m, st, ws), StepStatus::not_built);
      if (std::string(c.field) == "beta" && finite) {
        // "... >= (gamma + 1/2)^2 / 4 = <bound> for gamma ..."
        const std::string key = "/ 4 = ";
        const std::size_t at = message.find(key);
        ASSERT_NE(at, std::string::npos) << message;
        const double stated = std::strtod(message.c_str() + at + key.size(), nullptr);
        EXPECT_NEAR(stated, boundary_beta(c.gamma), 1e-15) << message;
      }
    }
  }
}

}  // namespace xfdem::stress
