// Deep runs of the continuum's stress cases (label `long`): 1e6 steps (1000 s
// of the kicked rod, about a thousand bounces of the upper piece) at the
// corners the fast sweeps in tests/stress/bar_sweep_test.cpp single out: the
// paper's interface (100·E·A, mid-element), the stiffest and thinnest one
// (1e6·E·A at a cut of 1e-9) and, for the unilateral interface, the softest
// (1·E·A, whose contact mode the 1 ms step resolves); Newmark (¼, ½), the
// paper's (0.4, 0.6) and the boundary β = (γ + ½)²/4 for γ = 0.6 and 0.9; both
// methods. The
// bound, its ε (which grows linearly with the number of steps) and the energy
// identity are those of tests/stress/bar_sweeps.hpp.
#include <gtest/gtest.h>

#include <cstdio>

#include "stress/bar_sweeps.hpp"

namespace xfdem::stress {
namespace {

using Behaviour = BarInterfaceDesc::Behaviour;
using Method = BarDesc::Method;

constexpr std::int64_t kSteps = 1000000;

struct Newmark {
  double beta, gamma;
};
struct Corner {
  double multiple, fraction;
};

double boundary_beta(double gamma) { return 0.25 * (gamma + 0.5) * (gamma + 0.5); }

void deep_run(Behaviour behaviour, std::initializer_list<Corner> corners, bool absorbing = false) {
  const bool unilateral = behaviour == Behaviour::unilateral;
  for (Newmark nm : {Newmark{0.25, 0.5}, Newmark{0.4, 0.6}, Newmark{boundary_beta(0.6), 0.6},
                     Newmark{boundary_beta(0.9), 0.9}})
    for (Corner corner : corners)
      for (Method method : {Method::xfem, Method::fem}) {
        if (unilateral && nm.gamma == 0.6 && nm.beta != 0.4) continue;
        BarDesc d = kicked_rod();
        d.interface->stiffness = penalty(d, corner.multiple);
        d.interface->position = 14.0 + corner.fraction;
        d.interface->behaviour = behaviour;
        d.method = method;
        d.beta = nm.beta;
        d.gamma = nm.gamma;
        if (absorbing) make_absorbing(d);
        char label[160];
        std::snprintf(label, sizeof label, "%-10s beta %.4f gamma %.2f  k %.0e EA cut %-5.2g %-4s %s", name(behaviour),
                      nm.beta, nm.gamma, corner.multiple, corner.fraction, name(method), name(d.base));
        const KickedRod load = load_for(d);
        const BarOutcome o = run_bar_case(d, load, kSteps);
        print_outcome(label, o);
        expect_case(label, d, o);
      }
}

}  // namespace

TEST(BarLong, TiedInterfaceStaysBoundedOver1e6Steps) {
  deep_run(Behaviour::tied, {Corner{1e2, 0.5}, Corner{1e6, 1e-9}});
}

TEST(BarLong, TiedInterfaceOnAnAbsorbingBaseStaysBoundedOver1e6Steps) {
  deep_run(Behaviour::tied, {Corner{1e6, 1e-9}}, true);
}

// Over 1e6 steps, (¼, ½) with its events located, (0.4, 0.6) and (0.49, 0.9):
// E ≤ Ê0 + W throughout. γ = 0.6 on the boundary is left out here; the fast
// sweep (BarStress.UnilateralNewmarkOnTheStabilityBoundaryStaysBounded, 2e4
// steps) covers it.
TEST(BarLong, UnilateralInterfaceStaysBoundedOver1e6Steps) {
  deep_run(Behaviour::unilateral, {Corner{1.0, 0.5}, Corner{1e2, 0.5}, Corner{1e6, 1e-9}});
}

}  // namespace xfdem::stress
