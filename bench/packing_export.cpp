// xfdem_packing_export N STEPS DIR [friction | hertz] [one_worker]
//
// Writes the dense settled packing of the packing benchmarks (dem_packing.hpp,
// N spheres) to DIR/packing.txt, so that another code can run the same
// spheres (tools/bench_liggghts.py), then steps it STEPS times from rest, as
// the benchmarks run it (verlet, ζ = 0.1, dt a fifth of the stable step), on
// one worker and on two, and writes the state after those steps to
// DIR/xfdem_after.txt. Prints whether the two runs end with the same bits.
// With `friction`, the frictional law of dem_packing.hpp (refused by a kernel
// without friction); with `hertz`, its Hertz–Mindlin law; with `one_worker`, no two-worker run (for instruction
// counts: callgrind runs the workers' threads one at a time).
// Timings are not taken here (Google Benchmark: BM_DemPacking/vs_liggghts).
//
// packing.txt: "# key value" lines (n, radius, density, mass, stiffness,
// damping_ratio, dt, side, top, and the contact parameters the kernel derived:
// pair_stiffness, pair_eta, plane_stiffness, plane_eta; with friction also
// friction and tangential_ratio; with hertz: law_hertz 1, youngs_modulus,
// poisson_ratio, restitution, friction), then one line
// "x y z" per sphere in the kernel's particle order. xfdem_after.txt: one line
// "x y z vx vy vz" per sphere, same order. Numbers in %.17g (round trip).
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dem_packing.hpp"
#include "xfdem/platform/worker_pool.hpp"
#include "xfdem/state_io.hpp"

namespace {

using namespace xfdem;
using namespace xfdem_bench;

long parse_count(const char* text, const char* what, long low) {
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || value < low) {
    std::fprintf(stderr, "xfdem_packing_export: %s must be an integer >= %ld, got '%s'\n", what, low, text);
    std::exit(2);
  }
  return value;
}

std::FILE* open_or_die(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    std::fprintf(stderr, "xfdem_packing_export: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  return f;
}

/// Steps the packing `steps` times from rest; returns the state.
DemState<3> run(const Packing& pk, long steps, bool two_workers, bool friction, bool hertz, DemModel<3>& model,
                DemDesc<3>& desc) {
  desc = packing_run_desc(pk, DemIntegrator::verlet, 0.0);
  if (friction && !set_packing_friction(desc)) {
    std::fprintf(stderr, "xfdem_packing_export: this kernel has no friction (DemDesc::friction)\n");
    std::exit(2);
  }
  if (hertz && !set_packing_hertz(desc)) {
    std::fprintf(stderr, "xfdem_packing_export: this kernel has no hertz law with friction\n");
    std::exit(2);
  }
  DemState<3> state;
  DemWorkspace<3> work;
  build_packing_run(desc, model, state, work);
  static platform::TwoWorkerPool pool;
  if (two_workers) work.parallel = pool.parallel_for();
  for (long k = 0; k < steps; ++k)
    require(!has(dem_step(model, state, work), kStepNotTaken | StepStatus::non_finite), "export: step");
  return state;
}

}  // namespace

int main(int argc, char** argv) {
  bool friction = false, hertz = false, one_worker = false;
  for (int k = 4; k < argc; ++k) {
    const std::string option = argv[k];
    if (option == "friction") {
      friction = true;
    } else if (option == "hertz") {
      hertz = true;
    } else if (option == "one_worker") {
      one_worker = true;
    } else {
      std::fprintf(stderr, "xfdem_packing_export: unknown option '%s' (friction, hertz, one_worker)\n", argv[k]);
      return 2;
    }
  }
  if (argc < 4) {
    std::fprintf(stderr, "usage: xfdem_packing_export N STEPS DIR [friction | hertz] [one_worker]\n");
    return 2;
  }
  const auto n = static_cast<std::int32_t>(parse_count(argv[1], "N", 2));
  const long steps = parse_count(argv[2], "STEPS", 0);
  const std::string dir = argv[3];
  const Packing& pk = packing(n);

  DemModel<3> model;
  DemDesc<3> desc;
  const DemState<3> one = run(pk, steps, false, friction, hertz, model, desc);
  DemModel<3> model2;
  DemDesc<3> desc2;
  const DemState<3> two = one_worker ? one : run(pk, steps, true, friction, hertz, model2, desc2);

  std::FILE* f = open_or_die(dir + "/packing.txt");
  // Equal spheres: springs in series K = k/2, m_eff = m/2, η = 2ζ√(K m_eff)
  // (dem.hpp); a plane contact has K = k, m_eff = m (the kernel's plane_eta).
  const double pair_stiffness = 0.5 * kStiffness;
  const double pair_eta = 2.0 * desc.damping_ratio * std::sqrt(pair_stiffness * 0.5 * kMass);
  std::fprintf(f, "# n %d\n# radius %.17g\n# density %.17g\n# mass %.17g\n# stiffness %.17g\n", n, kRadius, kDensity,
               kMass, kStiffness);
  std::fprintf(f, "# damping_ratio %.17g\n# dt %.17g\n# gravity %.17g\n# side %.17g\n# top %.17g\n", desc.damping_ratio,
               desc.dt, kGravity, pk.side, pk.top);
  std::fprintf(f, "# pair_stiffness %.17g\n# pair_eta %.17g\n# plane_stiffness %.17g\n# plane_eta %.17g\n", pair_stiffness, pair_eta, model.stiffness[0], model.plane_eta[0]);
  if (friction) std::fprintf(f, "# friction %.17g\n# tangential_ratio %.17g\n", kPackingFriction, kPackingTangentialRatio);
  if (hertz)
    std::fprintf(f, "# law_hertz 1\n# youngs_modulus %.17g\n# poisson_ratio %.17g\n# restitution %.17g\n# friction %.17g\n",
                 kPackingYoungsModulus, kPackingPoissonRatio, kPackingRestitution, kPackingFriction);
  for (const auto& p : pk.position) std::fprintf(f, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  std::fclose(f);

  f = open_or_die(dir + "/xfdem_after.txt");
  for (std::int32_t i = 0; i < n; ++i)
    std::fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g\n", one.x[0][i], one.x[1][i], one.x[2][i], one.v[0][i],
                 one.v[1][i], one.v[2][i]);
  std::fclose(f);

  if (one_worker) {
    std::printf("steps %ld\nsplit %d\n", steps, model.parts);
    return 0;
  }
  const bool same = state_hash(one) == state_hash(two);
  std::printf("steps %ld\nsplit %d\nsame_bits_1_vs_2_workers %s\nstate_hash_1 %016llx\nstate_hash_2 %016llx\n", steps,
              model.parts, same ? "yes" : "no", static_cast<unsigned long long>(state_hash(one)),
              static_cast<unsigned long long>(state_hash(two)));
  return same ? 0 : 1;
}
