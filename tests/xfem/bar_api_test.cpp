// Contracts of the bar API: a step never allocates, bad descriptions are
// rejected naming the field, non-finite states are reported, the state is plain
// data (a copy replays bit for bit).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfem/reference.hpp"

using namespace xfdem;

TEST(BarApi, StepNeverAllocates) {
  // The paths of a unilateral step: located events under (¼, ½), the energy
  // rule's velocity correction under another scheme (on the stability
  // boundary (0.3025, 0.6) openings gain most), and a cut 1e-9 of an element
  // from a node (whole steps). Openings held to the step's end do not occur
  // in this scene (printed).
  struct Scheme {
    double beta, gamma;
  };
  int removals = 0, held = 0;
  for (auto method : {BarDesc::Method::xfem, BarDesc::Method::fem})
    for (auto behaviour : {BarInterfaceDesc::Behaviour::tied, BarInterfaceDesc::Behaviour::unilateral})
      for (auto base : {BarDesc::Base::fixed, BarDesc::Base::absorbing})
        for (const Scheme scheme : {Scheme{0.25, 0.5}, Scheme{0.3025, 0.6}})
          for (const double cut : {14.5, 15.0 + 1e-9}) {
            BarDesc d = test::v2_rod(30);
            d.method = method;
            d.base = base;
            d.beta = scheme.beta;
            d.gamma = scheme.gamma;
            d.interface = BarInterfaceDesc{cut, 1.2e9, behaviour};
            BarModel m;
            BarState st;
            BarWorkspace ws;
            ASSERT_TRUE(build_bar(d, m, st, ws).ok());
            platform::AllocationCounter counter;
            double sink = 0.0;
            int events = 0;  // a unilateral interface's located events refactor; the factor's storage is reused
            for (int i = 0; i < 2000; ++i) {
              const BarInput in{i % 7 == 0 ? 500.0 : 0.0};
              bar_step(m, st, ws, in);
              events += ws.last_events;
              removals += ws.last_energy_removed > 0.0 ? 1 : 0;
              held += ws.last_held_open;
              sink += bar_displacement(m, st, 14.5) + bar_velocity(m, st, 3.0) + bar_interface_gap(m, st) +
                      bar_energy(m, st).kinetic + bar_tip_displacement(m, st);
            }
            bar_initial_acceleration(m, st, ws);
            EXPECT_EQ(counter.allocations(), 0u);
            EXPECT_TRUE(std::isfinite(sink));
            if (behaviour == BarInterfaceDesc::Behaviour::unilateral && scheme.beta == 0.25 && cut == 14.5) {
              EXPECT_GT(events, 0);
            }
          }
  std::printf("unilateral steps whose velocity the energy rule corrected: %d; openings held: %d\n", removals, held);
  EXPECT_GT(removals, 0);
}

namespace {
void expect_rejected(const BarDesc& d, const char* field) {
  BarModel m;
  BarState st;
  BarWorkspace ws;
  const BuildResult r = build_bar(d, m, st, ws);
  EXPECT_FALSE(r.ok()) << field;
  EXPECT_EQ(std::string(r.message).rfind(std::string(field) + ":", 0), 0u) << "message: " << r.message;
  EXPECT_EQ(bar_step(m, st, ws), StepStatus::not_built);
}
}  // namespace

TEST(BarApi, BadDescriptionsNameTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const BarDesc good = [] {
    BarDesc d = test::v2_rod(30);
    d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::tied};
    return d;
  }();
  {
    BarModel m;
    BarState st;
    BarWorkspace ws;
    ASSERT_TRUE(build_bar(good, m, st, ws).ok());
  }
  auto with = [&](auto edit) {
    BarDesc d = good;
    edit(d);
    return d;
  };
  expect_rejected(with([](BarDesc& d) { d.length = 0; }), "length");
  expect_rejected(with([&](BarDesc& d) { d.length = nan; }), "length");
  expect_rejected(with([](BarDesc& d) { d.youngs_modulus = -1; }), "youngs_modulus");
  expect_rejected(with([](BarDesc& d) { d.area = 0; }), "area");
  expect_rejected(with([](BarDesc& d) { d.density = std::numeric_limits<double>::infinity(); }), "density");
  expect_rejected(with([](BarDesc& d) { d.elements = 0; }), "elements");
  expect_rejected(with([](BarDesc& d) { d.method = static_cast<BarDesc::Method>(7); }), "method");
  expect_rejected(with([](BarDesc& d) { d.base = static_cast<BarDesc::Base>(7); }), "base");
  expect_rejected(with([](BarDesc& d) { d.base_stiffness = 1e6; }), "base_stiffness");  // fixed base
  expect_rejected(with([](BarDesc& d) { d.base = BarDesc::Base::absorbing; d.base_stiffness = -1; }), "base_stiffness");
  expect_rejected(with([](BarDesc& d) { d.interface->position = 30.0; }), "interface.position");
  expect_rejected(with([](BarDesc& d) { d.interface->position = 0.0; }), "interface.position");
  expect_rejected(with([](BarDesc& d) { d.interface->position = 31.0; }), "interface.position");
  expect_rejected(with([](BarDesc& d) { d.interface->stiffness = 0.0; }), "interface.stiffness");
  expect_rejected(with([](BarDesc& d) { d.interface->behaviour = static_cast<BarInterfaceDesc::Behaviour>(9); }),
                  "interface.behaviour");
  expect_rejected(with([](BarDesc& d) { d.dt = 0; }), "dt");
  expect_rejected(with([](BarDesc& d) { d.gamma = 0.4; }), "gamma");
  expect_rejected(with([](BarDesc& d) { d.beta = 0.0; }), "beta");   // central differences: conditional
  expect_rejected(with([](BarDesc& d) { d.beta = 0.25; d.gamma = 0.6; }), "beta");  // needs β ≥ 0.3025
  expect_rejected(with([](BarDesc& d) { d.tip_duration = 0; }), "tip_duration");
  expect_rejected(with([](BarDesc& d) { d.tip_load = BarDesc::TipLoad::step; }), "tip_duration");  // 0.25 given
  expect_rejected(with([](BarDesc& d) { d.tip_load = static_cast<BarDesc::TipLoad>(5); }), "tip_load");
  expect_rejected(with([&](BarDesc& d) { d.tip_amplitude = nan; }), "tip_amplitude");
  expect_rejected(with([](BarDesc& d) { d.tip_load = BarDesc::TipLoad::none; d.tip_duration = 0; }), "tip_amplitude");
  expect_rejected(with([](BarDesc& d) { d.max_active_set_iterations = 0; }), "max_active_set_iterations");
  expect_rejected(with([](BarDesc& d) { d.max_dofs = 10; }), "max_dofs");
}

TEST(BarApi, NonFiniteStateIsReported) {
  BarDesc d = test::v2_rod(30);
  BarModel m;
  BarState st;
  BarWorkspace ws;
  ASSERT_TRUE(build_bar(d, m, st, ws).ok());
  EXPECT_EQ(bar_step(m, st, ws), StepStatus::ok);
  const StepStatus s = bar_step(m, st, ws, BarInput{std::numeric_limits<double>::quiet_NaN()});
  EXPECT_TRUE(has(s, StepStatus::non_finite));
  EXPECT_EQ(st.step, 2);  // the step was taken
}

// A copied state replays bit for bit; for_each_field lists every array with its
// size and the scalars, so snapshots and hashes can be generic.
TEST(BarApi, StateIsPlainDataThatReplays) {
  BarDesc d = test::v2_rod(30);
  d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::unilateral};
  d.tip_amplitude = 1e4;
  BarModel m;
  BarState st;
  BarWorkspace ws;
  ASSERT_TRUE(build_bar(d, m, st, ws).ok());
  for (int i = 0; i < 300; ++i) bar_step(m, st, ws);
  BarState copy = st;
  BarWorkspace ws2 = ws;
  for (int i = 0; i < 700; ++i) {
    bar_step(m, st, ws);
    bar_step(m, copy, ws2);
  }
  std::size_t fields = 0, values = 0;
  auto hash = [](const BarState& s) {
    std::uint64_t h = 1469598103934665603ull;
    s.for_each_field([&](const char*, const auto* p, std::size_t n) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(p);
      for (std::size_t i = 0; i < n * sizeof(*p); ++i) h = (h ^ bytes[i]) * 1099511628211ull;
    });
    return h;
  };
  st.for_each_field([&](const char* name, const auto*, std::size_t n) {
    ++fields;
    values += n;
    EXPECT_NE(std::strlen(name), 0u);
  });
  // u, v, a; time, step, the active set; the tip input and the energy books.
  EXPECT_EQ(fields, 12u);
  EXPECT_EQ(values, 3u * static_cast<std::size_t>(m.dofs) + 9u);
  EXPECT_EQ(hash(st), hash(copy));
  EXPECT_EQ(st.step, 1000);
  EXPECT_EQ(st.time, 1000 * d.dt);
}

// The coupling's view of the tip: its unknown, its lumped mass share, and the
// extra force channel, which must act exactly like the built-in tip load.
TEST(BarApi, TipInputActsLikeTheTipLoad) {
  BarDesc d = test::v2_rod(30);
  d.interface = BarInterfaceDesc{14.5, 1.2e9, BarInterfaceDesc::Behaviour::tied};
  BarModel m1, m2;
  BarState s1, s2;
  BarWorkspace w1, w2;
  ASSERT_TRUE(build_bar(d, m1, s1, w1).ok());
  BarDesc none = d;
  none.tip_load = BarDesc::TipLoad::none;
  none.tip_amplitude = 0;
  none.tip_duration = 0;
  ASSERT_TRUE(build_bar(none, m2, s2, w2).ok());
  // ρAh/2 for the last element of an uncut mesh: 2000·0.4·1/2.
  EXPECT_DOUBLE_EQ(m1.tip_mass, 400.0);
  EXPECT_DOUBLE_EQ(bar_tip_displacement(m1, s1), bar_displacement(m1, s1, d.length));
  // Interchangeable bit for bit: every unknown's u, v and a, after every step.
  auto same_bits = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  };
  int differing_steps = 0;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(bar_step(m1, s1, w1), StepStatus::ok);
    ASSERT_EQ(bar_step(m2, s2, w2, BarInput{bar_tip_load(m1, (i + 1) * d.dt)}), StepStatus::ok);
    differing_steps += !(same_bits(s1.u, s2.u) && same_bits(s1.v, s2.v) && same_bits(s1.a, s2.a));
  }
  EXPECT_EQ(differing_steps, 0);
  EXPECT_NE(bar_tip_displacement(m1, s1), 0.0);  // the load did move the bar
  EXPECT_EQ(bar_tip_displacement(m1, s1), bar_tip_displacement(m2, s2));
  EXPECT_EQ(bar_tip_velocity(m1, s1), bar_velocity(m1, s1, d.length));
}
