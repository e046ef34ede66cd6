// "A NaN or an infinity anywhere in the state is detected within one step and
// reported" (StepStatus::non_finite), for the three steppers.
//
// Every floating-point field of each state, as the state's own visitor lists it
// (so a field added later is covered without editing this file), gets a NaN,
// then +inf, in its first element and, for an array, in its last one; then the
// state takes one step. Exactly one of these outcomes is accepted:
//   (a) the step reports non_finite;
//   (b) the step never read the value before overwriting it: nothing
//       non-finite is left in the state, and the state has the same hash (the
//       same bits) as after the same step without the injection;
//   (c) the one documented exception (docs/dem.md, "Non-finite values"): the
//       pair list's cached K and η (pair_stiffness, pair_eta) are read only for
//       a pair that touches, and a slot past the end of the list belongs to no
//       pair. Checking every cached value would cost a pass over the list at
//       every step, and the cache is rewritten from the model at every list
//       build. So a value injected into the cache of a pair that does not touch
//       stays where it is, unreported, with the rest of the state exactly as
//       without it; as soon as the pair touches, the value is read and the step
//       reports it (PairCacheIsReadOnlyWhenThePairTouches). An undamped model
//       reads no η, so there the check reads the listed η instead: (a).
// Inputs are covered too: DemState::external_force (a state field) and
// BarInput::tip_force. The scenes have contacts between particles and with a
// plane, gravity and external forces; each prints which fields fell in (a),
// (b) and (c).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "support/coupled_scenes.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"
#include "xfem/reference.hpp"

namespace xfdem::testing {
namespace {

constexpr double kInjected[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()};
constexpr DemIntegrator kIntegrators[] = {DemIntegrator::abm4, DemIntegrator::abm4_events, DemIntegrator::verlet,
                                          DemIntegrator::symplectic_euler, DemIntegrator::rk4};

template <class T>
constexpr bool is_double = std::is_same_v<std::remove_cv_t<T>, double>;

/// One element of one floating-point field of a state.
struct Target {
  std::size_t field = 0;    ///< index in the visitor's order
  std::size_t element = 0;  ///< index in the field
  std::string part, name;   ///< as the visitor names them ("dem", "pair_stiffness")
  std::string label;        ///< field_name() of state_io ("dem.hist_a[5]"), then "[element]"
};

template <class State>
std::vector<Target> every_target(State& s) {
  std::vector<Target> out;
  std::size_t k = 0;
  for_each_field(s, [&](const char* part, const char* name, auto* data, std::size_t count) {
    if constexpr (is_double<std::remove_pointer_t<decltype(data)>>) {
      char label[96];
      field_name(s, k, label, sizeof label);
      auto add = [&](std::size_t e) {
        out.push_back({k, e, part, name, std::string(label) + "[" + std::to_string(e) + "]"});
      };
      if (count > 0) add(0);
      if (count > 1) add(count - 1);
    }
    ++k;
  });
  return out;
}

template <class State>
double& element(State& s, const Target& t) {
  double* at = nullptr;
  std::size_t k = 0;
  for_each_field(s, [&](const char*, const char*, auto* data, std::size_t) {
    if constexpr (is_double<std::remove_pointer_t<decltype(data)>>)
      if (k == t.field) at = data + t.element;
    ++k;
  });
  return *at;
}

/// Name of the first non-finite element of the state, or "".
template <class State>
std::string first_non_finite(State& s) {
  std::string found;
  std::size_t k = 0;
  for_each_field(s, [&](const char*, const char*, auto* data, std::size_t count) {
    if constexpr (is_double<std::remove_pointer_t<decltype(data)>>)
      for (std::size_t e = 0; e < count && found.empty(); ++e)
        if (!std::isfinite(data[e])) {
          char label[96];
          field_name(s, k, label, sizeof label);
          found = std::string(label) + "[" + std::to_string(e) + "]";
        }
    ++k;
  });
  return found;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Which outcome each field had, for the printed summary.
struct Tally {
  std::map<std::string, std::string> outcome;  // field label without the element -> "a", "b", "c" or a mix
  void add(const Target& t, char what) {
    std::string& o = outcome[t.label.substr(0, t.label.rfind('[')) + (t.element == 0 ? "#first" : "#last")];
    if (o.find(what) == std::string::npos) o += what;
  }
  void print(const std::string& scene) const {
    std::string b, c, failed;
    int a = 0;
    for (const auto& [field, o] : outcome) {
      if (o == "a") ++a;
      if (o.find('b') != std::string::npos) b += " " + field + (o == "b" ? "" : "(" + o + ")");
      if (o.find('c') != std::string::npos) c += " " + field + (o == "c" ? "" : "(" + o + ")");
      if (o.find('F') != std::string::npos) failed += " " + field;
    }
    std::printf("%s: (a) reported: %d; (b) overwritten unread:%s; (c) pair cache:%s%s%s\n", scene.c_str(), a,
                b.empty() ? " none" : b.c_str(), c.empty() ? " none" : c.c_str(),
                failed.empty() ? "" : "; FAILED:", failed.c_str());
  }
};

/// Injects into every target in turn and checks the outcome of one step.
/// `step(state)` steps a copy with a fresh workspace; `cache_exempt(target,
/// before, after_reference)` says whether the target is the pair cache of a
/// pair that touches neither before nor after the step (outcome c).
template <class State, class Step, class Exempt>
void check_every_field(const State& base, Step&& step, const std::string& scene, Exempt&& cache_exempt,
                       Tally& tally) {
  State reference = base;
  const StepStatus reference_status = step(reference);
  ASSERT_EQ(reference_status, StepStatus::ok) << scene << ": the scene itself must step cleanly";
  ASSERT_EQ(first_non_finite(reference), "") << scene;
  State probe = base;
  const std::vector<Target> targets = every_target(probe);
  ASSERT_FALSE(targets.empty()) << scene;
  for (const Target& t : targets)
    for (double value : kInjected) {
      State s = base;
      element(s, t) = value;
      const StepStatus status = step(s);
      const std::string what = scene + ", " + t.label + " = " + std::to_string(value);
      if (has(status, StepStatus::non_finite)) {  // (a)
        tally.add(t, 'a');
        continue;
      }
      if (cache_exempt(t, base, reference)) {  // (c): left in place, nothing else differs
        const bool kept = same_bits(element(s, t), value);
        element(s, t) = element(reference, t);
        const bool ok = kept && status == reference_status && first_non_finite(s).empty() &&
                        state_hash(s) == state_hash(reference);
        EXPECT_TRUE(ok) << what << ": pair cache of a pair apart, yet the step differs from the clean one";
        tally.add(t, ok ? 'c' : 'F');
        continue;
      }
      // (b): overwritten before being read, so the step is the clean one.
      const std::string left = first_non_finite(s);
      const bool same = state_hash(s) == state_hash(reference) && status == reference_status;
      EXPECT_TRUE(left.empty() && same) << what << ": not reported; "
                                        << (left.empty() ? "" : left + " is left non-finite; ")
                                        << (same ? "" : "the step differs from the clean one");
      tally.add(t, left.empty() && same ? 'b' : 'F');
    }
}

// ---- DEM ------------------------------------------------------------------------

template <int D>
bool pair_touches(const DemModel<D>& m, const DemState<D>& s, std::int32_t c) {
  if (c >= s.pair_count) return false;
  const std::int32_t i = s.pair_i[static_cast<std::size_t>(c)], j = s.pair_j[static_cast<std::size_t>(c)];
  double dist2 = 0;
  for (int d = 0; d < D; ++d) dist2 += (s.x[d][j] - s.x[d][i]) * (s.x[d][j] - s.x[d][i]);
  const double reach = m.radius[i] + m.radius[j];
  return dist2 < reach * reach;
}

bool is_pair_cache(const Target& t) { return t.name == "pair_stiffness" || t.name == "pair_eta"; }

/// What every DEM case shares: gravity along the last axis, ζ = 0.1,
/// `integrator` at step `dt`, and external forces on (an input to poison).
template <int D>
DemDesc<D> falling(DemIntegrator integrator, double dt) {
  DemDesc<D> d;
  d.gravity[D - 1] = -9.81;
  d.damping_ratio = 0.1;
  d.integrator = integrator;
  d.dt = dt;
  d.external_forces = true;
  return d;
}

/// A column of four rods on a floor (1D): 0 rests on the floor, 1 and 2 are
/// stacked on it (the pairs 0–1 and 1–2 touch), 3 falls from above (its pairs
/// do not touch); a ceiling nobody touches. Damped, with gravity and external
/// forces.
DemDesc<1> column_1d(DemIntegrator integrator) {
  DemDesc<1> d = falling<1>(integrator, 1e-4);
  d.particles = {{1.0, 0.1, 1e4, {0.099}, {0.05}},
                 {1.2, 0.1, 1e4, {0.297}, {-0.1}},
                 {0.8, 0.1, 2e4, {0.495}, {0.02}},
                 {1.0, 0.1, 1e4, {1.0}, {-1.0}}};
  d.planes = {{{0.0}, {1.0}}, {{2.0}, {-1.0}}};
  return d;
}

/// Five spheres (3D, all pairs): three touching on the floor, two in flight;
/// walls nobody touches, one of them oblique.
DemDesc<3> cluster_3d(DemIntegrator integrator) {
  DemDesc<3> d = falling<3>(integrator, 1e-4);
  d.particles = {{1.0, 0.1, 1e4, {0.0, 0.0, 0.099}, {0.01, 0.0, 0.0}},
                 {1.0, 0.1, 1e4, {0.198, 0.0, 0.099}, {-0.02, 0.01, 0.0}},
                 {0.5, 0.1, 1e4, {0.099, 0.0, 0.27}, {0.0, 0.0, -0.05}},
                 {1.0, 0.1, 1e4, {0.0, 0.5, 1.0}, {0.0, 0.0, -1.0}},
                 {2.0, 0.15, 1e4, {0.6, 0.6, 0.5}, {0.1, 0.0, 0.0}}};
  d.planes = {{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}},
              {{-0.5, 0.0, 0.0}, {1.0, 0.0, 0.0}},
              {{1.5, 1.5, 0.0}, {-1.0, -1.0, 0.0}}};
  return d;
}

/// A lattice of 4 x 3 x 3 spheres on a floor (grid broad phase): columns touch
/// along y and z, and are 0.3 mm apart along x (listed, within the skin, but
/// not touching). Split into two parts from 4 particles on: particle 0 is in
/// part 0, the last one in part 1.
DemDesc<3> lattice_3d(DemIntegrator integrator) {
  DemDesc<3> d = falling<3>(integrator, 2e-5);
  d.split_from = 4;
  const double r = 0.01, pitch = 0.0198, apart = 0.0203;
  std::uint64_t seed = 0x5eedull;
  auto jitter = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return (static_cast<double>(seed >> 11) * 0x1.0p-53 - 0.5) * 0.02;
  };
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        d.particles.push_back({1e-2, r, 2e3, {r + i * apart, r + j * pitch, r - 1e-4 + k * pitch},
                               {jitter(), jitter(), jitter()}});
  d.planes = {{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}, {{-0.1, 0.0, 0.0}, {1.0, 0.0, 0.0}}};
  return d;
}

template <int D>
void check_dem(const DemDesc<D>& desc, int warm_up, const std::string& scene, const ParallelFor& parallel = {}) {
  DemWorld<D> world;
  const BuildResult built = world.build(desc);
  ASSERT_TRUE(built.ok()) << built.message;
  world.workspace.parallel = parallel;
  for (std::int32_t i = 0; i < world.model.n; ++i)
    for (int d = 0; d < D; ++d) world.state.external_force[d][i] = 0.01 * (d + 1) * (i % 2 ? 1.0 : -1.0);
  dem_inputs_changed(world.state);
  for (int k = 0; k < warm_up; ++k) ASSERT_EQ(world.step(), StepStatus::ok) << scene;
  // Contacts with each other and with a plane are live.
  bool pair = false, plane = false;
  for (std::int32_t c = 0; c < world.state.pair_count; ++c) pair |= pair_touches(world.model, world.state, c);
  for (std::int32_t i = 0; i < world.model.n; ++i) plane |= dem_plane_force(world.model, world.state, i, 0) > 0;
  ASSERT_TRUE(pair && plane) << scene;

  const DemWorkspace<D> fresh = world.workspace;
  auto step = [&](DemState<D>& s) {
    DemWorkspace<D> w = fresh;
    return dem_step(world.model, s, w);
  };
  auto exempt = [&](const Target& t, const DemState<D>& before, const DemState<D>& after) {
    const auto c = static_cast<std::int32_t>(t.element);
    return is_pair_cache(t) && !pair_touches(world.model, before, c) && !pair_touches(world.model, after, c);
  };
  Tally tally;
  check_every_field(world.state, step, scene, exempt, tally);
  tally.print(scene);
}

std::string dem_scene(const char* what, DemIntegrator integrator, int warm_up) {
  return std::string(what) + " " + integrator_name(integrator) + " after " + std::to_string(warm_up) + " steps";
}

// After 1 step the multistep history is still starting (RK4 steps); after 6 it
// is full and abm4 reads every slot.
TEST(NonFinite, DemColumn1D) {
  for (DemIntegrator integrator : kIntegrators)
    for (int warm_up : {1, 6}) check_dem(column_1d(integrator), warm_up, dem_scene("column 1D", integrator, warm_up));
}

// Undamped, no force reads a pair's η: the check reads it instead.
TEST(NonFinite, DemColumn1DUndamped) {
  for (DemIntegrator integrator : kIntegrators) {
    DemDesc<1> desc = column_1d(integrator);
    desc.damping_ratio = 0;
    check_dem(desc, 6, dem_scene("column 1D undamped", integrator, 6));
  }
}

TEST(NonFinite, DemCluster3D) {
  for (DemIntegrator integrator : kIntegrators)
    for (int warm_up : {1, 6}) check_dem(cluster_3d(integrator), warm_up, dem_scene("cluster 3D", integrator, warm_up));
}

// Two parts on two workers: the first element of a per-particle array is in
// part 0, the last one in part 1.
TEST(NonFinite, DemLatticeOnTwoWorkers) {
  platform::TwoWorkerPool pool;
  for (DemIntegrator integrator : kIntegrators) {
    const DemDesc<3> desc = lattice_3d(integrator);
    DemWorld<3> probe;
    ASSERT_TRUE(probe.build(desc).ok());
    ASSERT_EQ(probe.model.parts, 2);
    ASSERT_EQ(probe.model.features.broad_phase, BroadPhase::grid);
    check_dem(desc, 6, dem_scene("lattice 3D, two workers", integrator, 6), pool.parallel_for());
  }
}

// The exception (c), precisely: a NaN or inf in the cached K or η of a listed
// pair is reported within the step in which the pair touches, and not read
// (the step is the clean one) while it does not. A pair apart is then made to
// touch (particle j moved onto i, by less than skin/2 so that the list is not
// rebuilt), and the next step reports it; the same move without the injection
// is reported as nothing.
template <int D>
void check_pair_cache(const DemDesc<D>& desc, const std::string& scene, const ParallelFor& parallel = {}) {
  DemWorld<D> world;
  ASSERT_TRUE(world.build(desc).ok());
  world.workspace.parallel = parallel;
  for (int k = 0; k < 6; ++k) ASSERT_EQ(world.step(), StepStatus::ok);
  const bool grid = world.model.features.broad_phase == BroadPhase::grid;
  auto step = [&](DemState<D>& s) {
    DemWorkspace<D> w = world.workspace;
    return dem_step(world.model, s, w);
  };
  DemState<D> clean = world.state;
  ASSERT_EQ(step(clean), StepStatus::ok);
  // Moves particle j so that it overlaps i by 0.1 % of their reach; false if
  // that is farther than a grid list allows without a rebuild.
  auto make_touch = [&](DemState<D>& s, std::int32_t c) {
    const std::int32_t i = s.pair_i[static_cast<std::size_t>(c)], j = s.pair_j[static_cast<std::size_t>(c)];
    double dist = 0;
    for (int d = 0; d < D; ++d) dist += (s.x[d][j] - s.x[d][i]) * (s.x[d][j] - s.x[d][i]);
    dist = std::sqrt(dist);
    const double target = 0.999 * (world.model.radius[i] + world.model.radius[j]);
    if (grid && dist - target > 0.4 * world.model.skin) return false;
    for (int d = 0; d < D; ++d) s.x[d][j] = s.x[d][i] + (s.x[d][j] - s.x[d][i]) * (target / dist);
    return true;
  };
  int touching = 0, apart = 0, made = 0;
  using Cache = std::vector<double> DemState<D>::*;
  for (std::int32_t c = 0; c < world.state.pair_count; ++c) {
    const bool touches = pair_touches(world.model, world.state, c);
    (touches ? touching : apart) += 1;
    bool moved = false;
    for (Cache cache : {Cache{&DemState<D>::pair_stiffness}, Cache{&DemState<D>::pair_eta}})
      for (double value : kInjected) {
        const std::string what = scene + ", pair " + std::to_string(c) + ", " +
                                 (cache == &DemState<D>::pair_stiffness ? "K" : "eta") + " = " + std::to_string(value);
        DemState<D> s = world.state;
        (s.*cache)[static_cast<std::size_t>(c)] = value;
        const StepStatus status = step(s);
        if (touches) {
          EXPECT_TRUE(has(status, StepStatus::non_finite)) << what;
          continue;
        }
        ASSERT_FALSE(pair_touches(world.model, s, c)) << what;
        EXPECT_EQ(status, StepStatus::ok) << what;
        (s.*cache)[static_cast<std::size_t>(c)] = (clean.*cache)[static_cast<std::size_t>(c)];
        EXPECT_EQ(state_hash(s), state_hash(clean)) << what << ": the step differs from the clean one";
        (s.*cache)[static_cast<std::size_t>(c)] = value;
        DemState<D> control = clean;
        if (!make_touch(s, c) || !make_touch(control, c)) continue;
        moved = true;
        EXPECT_TRUE(has(step(s), StepStatus::non_finite)) << what << ", once the pair touches";
        EXPECT_FALSE(has(step(control), StepStatus::non_finite)) << what << ", control";
      }
    made += moved;
  }
  std::printf("%s: %d touching pairs (reported), %d listed pairs apart (not read; %d made to touch: reported)\n",
              scene.c_str(), touching, apart, made);
  EXPECT_GT(touching, 0) << scene;
  EXPECT_GT(apart, 0) << scene;
  EXPECT_GT(made, 0) << scene;
}

TEST(NonFinite, PairCacheIsReadOnlyWhenThePairTouches) {
  platform::TwoWorkerPool pool;
  for (DemIntegrator integrator : kIntegrators) {
    check_pair_cache(column_1d(integrator), std::string("column 1D ") + integrator_name(integrator));
    check_pair_cache(cluster_3d(integrator), std::string("cluster 3D ") + integrator_name(integrator));
    check_pair_cache(lattice_3d(integrator), std::string("lattice 3D ") + integrator_name(integrator),
                     pool.parallel_for());
  }
}

// ---- bar -------------------------------------------------------------------------

BarDesc loaded_bar(BarDesc::Method method, BarInterfaceDesc::Behaviour behaviour, BarDesc::Base base) {
  BarDesc d = test::v2_rod();
  d.method = method;
  d.base = base;
  d.interface = BarInterfaceDesc{14.5, 1.2e9, behaviour};
  d.tip_load = BarDesc::TipLoad::step;
  d.tip_duration = 0.0;
  return d;
}

TEST(NonFinite, Bar) {
  for (auto method : {BarDesc::Method::xfem, BarDesc::Method::fem})
    for (auto behaviour : {BarInterfaceDesc::Behaviour::tied, BarInterfaceDesc::Behaviour::unilateral})
      for (auto base : {BarDesc::Base::fixed, BarDesc::Base::absorbing}) {
        const std::string scene = std::string("bar ") + (method == BarDesc::Method::xfem ? "xfem" : "fem") +
                                  (behaviour == BarInterfaceDesc::Behaviour::tied ? " tied" : " unilateral") +
                                  (base == BarDesc::Base::fixed ? " fixed" : " absorbing");
        BarModel model;
        BarState state;
        BarWorkspace workspace;
        ASSERT_TRUE(build_bar(loaded_bar(method, behaviour, base), model, state, workspace).ok());
        const BarInput input{250.0};
        // Until the load's compression wave (c = 122 m/s) has reached the
        // interface 15.5 m below the tip and the interface spring acts.
        for (int k = 0; k < 400 && !(k > 130 && state.interface_closed == 1); ++k)
          ASSERT_EQ(bar_step(model, state, workspace, input), StepStatus::ok) << scene;
        ASSERT_EQ(state.interface_closed, 1) << scene;
        ASSERT_LT(bar_interface_gap(model, state), 0.0) << scene;
        auto step = [&](BarState& s) {
          BarWorkspace w = workspace;
          return bar_step(model, s, w, input);
        };
        Tally tally;
        check_every_field(state, step, scene, [](const Target&, const BarState&, const BarState&) { return false; },
                          tally);
        tally.print(scene);
        for (double value : kInjected) {
          // The input.
          BarState s = state;
          BarWorkspace w = workspace;
          EXPECT_TRUE(has(bar_step(model, s, w, BarInput{value}), StepStatus::non_finite)) << scene << ", tip_force";
          // bar_initial_acceleration (the coupled step's first call) takes the
          // load at state.time, which bar_step itself never reads.
          s = state;
          s.time = value;
          EXPECT_TRUE(has(bar_initial_acceleration(model, s, w, input), StepStatus::non_finite)) << scene << ", time";
        }
      }
}

// ---- coupled -----------------------------------------------------------------------

TEST(NonFinite, Coupled) {
  for (const char* file : {"case2_xfem.json", "case1_fem.json"}) {
    CoupledWorld world;
    const BuildResult built = world.build(coupled_scene(file));
    ASSERT_TRUE(built.ok()) << built.message;
    // Into the first impact, when the window needs several passes.
    int k = 0;
    for (; k < 5000 && !(coupled_top_force(world.model, world.state, 0) > 0 && world.state.last_passes > 2); ++k)
      ASSERT_EQ(world.step(), StepStatus::ok) << file;
    ASSERT_LT(k, 5000) << file << ": no impact";
    const CoupledWorkspace fresh = world.workspace;
    std::int32_t passes = -1;
    auto step = [&](CoupledState& s) {
      CoupledWorkspace w = fresh;
      const StepStatus status = coupled_step(world.model, s, w);
      passes = s.last_passes;
      return status;
    };
    // Wraps `step`: a window that went non-finite is not iterated further.
    auto step_and_check_passes = [&](CoupledState& s) {
      const StepStatus status = step(s);
      if (has(status, StepStatus::non_finite)) {
        EXPECT_EQ(passes, 1) << file << ": the fixed point went on after a non-finite pass";
        EXPECT_FALSE(has(status, StepStatus::coupling_unstable)) << file;
      }
      return status;
    };
    auto exempt = [&](const Target& t, const CoupledState& before, const CoupledState& after) {
      const auto c = static_cast<std::int32_t>(t.element);
      return t.part == "dem" && is_pair_cache(t) && !pair_touches(world.model.dem, before.dem, c) &&
             !pair_touches(world.model.dem, after.dem, c);
    };
    Tally tally;
    check_every_field(world.state, step_and_check_passes, std::string("coupled ") + file, exempt, tally);
    tally.print(std::string("coupled ") + file);
  }
}

}  // namespace
}  // namespace xfdem::testing
