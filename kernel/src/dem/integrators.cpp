// Time integrators for the particles.
//
// The state is y = (x, v) and f(y) = (v, a(x, v)); a depends on the state only.
// Every integrator computes its new (x, v) and the acceleration it keeps for the
// next step in workspace arrays first, and commits them to the State by swapping
// buffers (O(1), no allocation) only when every force evaluation succeeded: a
// step that hits a capacity leaves positions, velocities and time untouched.
//
// History convention: slot `history_head` of hist_v/hist_a holds f(y_n).
#include <cmath>
#include <cstring>
#include <algorithm>
#include <type_traits>

#include "dem/energy_books.hpp"
#include "dem/forces.hpp"
#include "dem/granular.hpp"
#include "dem/network.hpp"

namespace xfdem {
namespace {

using dem_detail::contact_set_changed;
using dem_detail::plane_count;
using dem_detail::zero_probe;

template <int D>
ConstColumns<D> view(const std::array<std::vector<double>, D>& a) {
  ConstColumns<D> c;
  for (int d = 0; d < D; ++d) c[d] = a[d].data();
  return c;
}
template <int D>
Columns<D> view(std::array<std::vector<double>, D>& a) {
  Columns<D> c;
  for (int d = 0; d < D; ++d) c[d] = a[d].data();
  return c;
}

template <int D>
ConstColumns<D> constant(Columns<D> c) {
  ConstColumns<D> r;
  for (int d = 0; d < D; ++d) r[d] = c[d];
  return r;
}

constexpr bool stop_now(StepStatus s) { return has(s, kStepNotTaken); }

/// One force evaluation of the state (x, v) at time t (moving planes need it).
template <int D>
StepStatus evaluate(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, AccelerationKernel<D> kernel, double t,
                    ConstColumns<D> x, ConstColumns<D> v, Columns<D> a) {
  w.eval_time = t;
  if (w.clock_ns == nullptr) return kernel(m, s, w, x, v, a);
  const std::int64_t start = w.clock_ns();
  const std::int64_t broad_before = w.profile.broad_phase_ns;
  const StepStatus status = kernel(m, s, w, x, v, a);
  w.profile.contacts_ns += w.clock_ns() - start - (w.profile.broad_phase_ns - broad_before);
  return status;
}

/// One term of a plane ledger sum: weight · the planes' forces at an evaluation.
struct Weighted {
  double weight;
  const double* force;
};

/// out = c · Σ_k weight_k · force_k over the planes (the impulse ledger), the
/// terms added in order from 0. An array, not an initializer_list, so that the
/// compiler unrolls it. P: the run's plane count (plane_count).
template <int P, std::size_t K>
inline void weigh(std::vector<double>& out, double c, const Weighted (&terms)[K]) {
  for (std::size_t p = 0; p < plane_count<P>(out); ++p) {
    double sum = 0;
    for (const Weighted& term : terms) sum += term.weight * term.force[p];
    out[p] = c * sum;
  }
}

/// Where a step's loops and force evaluations run. The integrators below are
/// written once over it, so both runs do the same operations in the same
/// order (tests/dem/small_system_test.cpp compares their bits step by step).
///
/// GeneralRun: any model. Loops over the model's parts through the host's
/// ParallelFor, the force kernel picked at build called through its pointer
/// (and timed when the host installed a clock), the new state built in the
/// workspace and committed by swapping buffers, so that a step that hits a
/// capacity leaves the state untouched.
template <int D>
struct GeneralRun {
  const DemModel<D>& m;
  DemState<D>& s;
  DemWorkspace<D>& w;
  AccelerationKernel<D> kernel;
  static constexpr int kCount = 0;   ///< particle_count: the model's
  static constexpr int kPlanes = 0;  ///< plane_count: the arrays' own
  static constexpr bool kInputsOncePerCall = false;  ///< all_finite checks inputs_probe's values every step

  template <class F>
  void over(F&& f) const {
    for_parts(w.parallel, m.parts, [&](int part) { f(part == 0 ? 0 : m.split, part == 0 ? m.split : m.n); });
  }
  StepStatus eval(double t, ConstColumns<D> x, ConstColumns<D> v, Columns<D> a) const {
    return evaluate<D>(m, s, w, kernel, t, x, v, a);
  }
  /// Where the step puts the new x, v and their acceleration.
  Columns<D> x1() const { return view<D>(w.x1); }
  Columns<D> v1() const { return view<D>(w.v1); }
  Columns<D> a1() const { return view<D>(w.a0); }
  /// Moves them into the state and history slot `slot`.
  void adopt(std::int32_t slot) const {
    for (int d = 0; d < D; ++d) {
      s.x[d].swap(w.x1[d]);
      s.v[d].swap(w.v1[d]);
      s.hist_a[slot][d].swap(w.a0[d]);
    }
  }
  /// The history ring: the state's own arrays.
  double* hist_v(int slot, int d) const { return s.hist_v[slot][d].data(); }
  double* hist_a(int slot, int d) const { return s.hist_a[slot][d].data(); }
  double* hist_force(int slot) const { return s.hist_plane_force[slot].data(); }
  /// Keeps the planes' forces of the last evaluation in slot `slot`
  /// (w.plane_force is rewritten by every evaluation: swapped, not copied).
  void keep_force(int slot) const { s.hist_plane_force[slot].swap(w.plane_force); }
};

/// The history ring of a small-system step with its particle count N and
/// plane count P compiled in: one block on the step's stack, slot by slot the
/// velocities and the accelerations (axis by axis) and the planes' forces, at
/// offsets known at compile time. load() copies the state's slots in when the
/// step's call starts and store() copies them back when it ends, so that the
/// substeps of a window address one base instead of a std::vector per slot and
/// axis, reading and writing the same values. With N or P = 0 (counts read at
/// run time) it is the state's own arrays.
template <int D, int N, int P>
struct HistoryRing {
  static constexpr bool kPacked = N > 0 && P > 0;
  static constexpr int kSlot = 2 * D * N + P;
  DemState<D>& s;
  double block[kPacked ? 4 * kSlot : 1];  // filled by load()

  explicit HistoryRing(DemState<D>& state) : s(state) {}

  double* v(int slot, int d) {
    if constexpr (kPacked) return block + slot * kSlot + d * N;
    return s.hist_v[slot][d].data();
  }
  double* a(int slot, int d) {
    if constexpr (kPacked) return block + slot * kSlot + (D + d) * N;
    return s.hist_a[slot][d].data();
  }
  double* force(int slot) {
    if constexpr (kPacked) return block + slot * kSlot + 2 * D * N;
    return s.hist_plane_force[slot].data();
  }
  void load() {
    if constexpr (kPacked)
      for (int slot = 0; slot < 4; ++slot) {
        for (int d = 0; d < D; ++d)
          for (int i = 0; i < N; ++i) {
            v(slot, d)[i] = s.hist_v[slot][d][i];
            a(slot, d)[i] = s.hist_a[slot][d][i];
          }
        for (int p = 0; p < P; ++p) force(slot)[p] = s.hist_plane_force[slot][p];
      }
  }
  void store() {
    if constexpr (kPacked)
      for (int slot = 0; slot < 4; ++slot) {
        for (int d = 0; d < D; ++d)
          for (int i = 0; i < N; ++i) {
            s.hist_v[slot][d][i] = v(slot, d)[i];
            s.hist_a[slot][d][i] = a(slot, d)[i];
          }
        for (int p = 0; p < P; ++p) s.hist_plane_force[slot][p] = force(slot)[p];
      }
  }
};

/// SmallRun: few particles in one part with a fixed pair list (broad phase
/// none or all_pairs) and no event location: DemModel::small_step, picked at
/// build. One plain loop, the same force code inlined for the scene's
/// features, and the new x, v and acceleration written straight into the
/// state and the next history slot (every update is element by element, so
/// in place reads what it would read from a copy). Nothing there can hit a
/// capacity, so the step is never refused. N > 0: the model has N particles,
/// and every loop over them has that trip count at compile time (unrolled);
/// N = 0: the model's count (dem_detail::particle_count). P the same for the
/// planes and every loop over the impulse ledger (dem_detail::plane_count).
template <int D, bool Gravity, bool Damped, bool NonTensile, int N, int P>
struct SmallRun {
  const DemModel<D>& m;
  DemState<D>& s;
  DemWorkspace<D>& w;
  HistoryRing<D, N, P>& ring;  ///< the history slots the step reads and writes
  static constexpr int kCount = N;
  static constexpr int kPlanes = P;
  /// inputs_probe's values, which no step writes, are checked once per call
  /// of small_step: the same statuses together.
  static constexpr bool kInputsOncePerCall = true;

  template <class F>
  void over(F&& f) const {
    f(std::int32_t{0}, dem_detail::particle_count<N>(m));
  }
  // One function with the force code inlined (flatten), called from each stage.
  [[gnu::flatten, gnu::noinline]] StepStatus eval(double t, ConstColumns<D> x, ConstColumns<D> v, Columns<D> a) const {
    w.eval_time = t;
    return dem_detail::one_part_accelerations<D, Gravity, Damped, NonTensile, N, P>(m, s, w, x, v, a);
  }
  Columns<D> x1() const { return view<D>(s.x); }
  Columns<D> v1() const { return view<D>(s.v); }
  Columns<D> a1() const {
    Columns<D> a;
    for (int d = 0; d < D; ++d) a[d] = ring.a((s.history_head + 1) & 3, d);
    return a;
  }
  void adopt(std::int32_t) const {}
  double* hist_v(int slot, int d) const { return ring.v(slot, d); }
  double* hist_a(int slot, int d) const { return ring.a(slot, d); }
  double* hist_force(int slot) const { return ring.force(slot); }
  void keep_force(int slot) const {
    if constexpr (HistoryRing<D, N, P>::kPacked) {
      for (int p = 0; p < P; ++p) ring.force(slot)[p] = w.plane_force[static_cast<std::size_t>(p)];
    } else {
      s.hist_plane_force[slot].swap(w.plane_force);
    }
  }
};

/// The accelerations kept in history slot `slot` of the run's ring.
template <int D, class Run>
Columns<D> hist_a_of(const Run& run, int slot) {
  Columns<D> a;
  for (int d = 0; d < D; ++d) a[d] = run.hist_a(slot, d);
  return a;
}

/// One classical RK4 step of size h from (x0, v0) whose acceleration a0 is
/// known, into (x1, v1). Stage work in w.xs/vs/as and w.sum_x/sum_v.
/// S3 is evaluated at y_n + S2 h/2 (paper-notes, slip in eq 31).
/// t0 is the time of (x0, v0) and f0 the planes' forces there; the planes'
/// weighted impulse h/6 (F1 + 2F2 + 2F3 + F4) is left in w.plane_weighted.
/// x1, v1 may be x0, v0 (in place).
template <int D, class Run>
StepStatus rk4_step(const Run& run, double t0, ConstColumns<D> x0, ConstColumns<D> v0, ConstColumns<D> a0,
                    const double* f0, double h, Columns<D> x1, Columns<D> v1) {
  DemWorkspace<D>& w = run.w;
  const double half = 0.5 * h;
  auto xs = view<D>(w.xs), vs = view<D>(w.vs), as = view<D>(w.as);
  auto sx = view<D>(w.sum_x), sv = view<D>(w.sum_v);
  auto cxs = view<D>(static_cast<const std::array<std::vector<double>, D>&>(w.xs));
  auto cvs = view<D>(static_cast<const std::array<std::vector<double>, D>&>(w.vs));
  // S1 = (v0, a0); stage 2 at y0 + S1 h/2.
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        sx[d][i] = v0[d][i];
        sv[d][i] = a0[d][i];
        xs[d][i] = x0[d][i] + half * v0[d][i];
        vs[d][i] = v0[d][i] + half * a0[d][i];
      }
  });
  std::vector<double>& ledger = w.plane_weighted;
  const std::size_t planes = plane_count<Run::kPlanes>(ledger);
  for (std::size_t p = 0; p < planes; ++p) ledger[p] = f0[p];
  StepStatus status = run.eval(t0 + half, cxs, cvs, as);
  if (stop_now(status)) return status;
  for (std::size_t p = 0; p < planes; ++p) ledger[p] += 2.0 * w.plane_force[p];
  // S2 = (vs, as); stage 3 at y0 + S2 h/2.
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        const double s2x = vs[d][i], s2v = as[d][i];
        sx[d][i] += 2.0 * s2x;
        sv[d][i] += 2.0 * s2v;
        xs[d][i] = x0[d][i] + half * s2x;
        vs[d][i] = v0[d][i] + half * s2v;
      }
  });
  status |= run.eval(t0 + half, cxs, cvs, as);
  if (stop_now(status)) return status;
  for (std::size_t p = 0; p < planes; ++p) ledger[p] += 2.0 * w.plane_force[p];
  // S3; stage 4 at y0 + S3 h.
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        const double s3x = vs[d][i], s3v = as[d][i];
        sx[d][i] += 2.0 * s3x;
        sv[d][i] += 2.0 * s3v;
        xs[d][i] = x0[d][i] + h * s3x;
        vs[d][i] = v0[d][i] + h * s3v;
      }
  });
  status |= run.eval(t0 + h, cxs, cvs, as);
  if (stop_now(status)) return status;
  const double sixth = h / 6.0;
  for (std::size_t p = 0; p < planes; ++p) ledger[p] = sixth * (ledger[p] + w.plane_force[p]);
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        x1[d][i] = x0[d][i] + sixth * (sx[d][i] + vs[d][i]);
        v1[d][i] = v0[d][i] + sixth * (sv[d][i] + as[d][i]);
      }
  });
  return status;
}

/// Makes the run's (x1, v1) the new state and a1 its acceleration, kept in a
/// new history slot with a copy of the velocity. The planes' forces at the
/// last evaluation (of the new state) go into the same history slot, and the
/// step's plane impulse `impulse` into the ledger.
template <int D, class Run>
void commit(const Run& run, const std::vector<double>& impulse) {
  DemState<D>& s = run.s;
  const std::int32_t slot = (s.history_head + 1) & 3;  // head is in [0, 4): & 3 is % 4 without the sign fix-up
  run.adopt(slot);
  // A plain loop, not std::copy: for the few particles of a coupled scene the
  // memmove call costs more than the copy.
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d) {
      const double* v = s.v[d].data();
      double* kept = run.hist_v(slot, d);
      for (std::int32_t i = begin; i < end; ++i) kept[i] = v[i];
    }
  });
  run.keep_force(slot);
  for (std::size_t p = 0; p < plane_count<Run::kPlanes>(impulse); ++p) s.plane_impulse[p] += impulse[p];
  s.history_head = slot;
}

/// Evaluates f(y_n) into the head slot when the history was invalidated.
template <int D, class Run>
StepStatus ensure_current_acceleration(const Run& run) {
  DemState<D>& s = run.s;
  if (s.history_count > 0) return StepStatus::ok;
  const auto& cs = s;
  const StepStatus status = run.eval(s.time, view<D>(cs.x), view<D>(cs.v), hist_a_of<D>(run, s.history_head));
  if (stop_now(status)) return status;
  // Element by element (the sizes match): an assignment of a few values costs
  // more in its checks and memmove call than the copy.
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d) {
      const double* v = s.v[d].data();
      double* kept = run.hist_v(s.history_head, d);
      for (std::int32_t i = begin; i < end; ++i) kept[i] = v[i];
    }
  });
  const std::vector<double>& force = run.w.plane_force;
  double* kept_force = run.hist_force(s.history_head);
  for (std::size_t p = 0; p < plane_count<Run::kPlanes>(force); ++p) kept_force[p] = force[p];
  s.history_count = 1;
  return status;
}

template <int D, class Run>
StepStatus step_rk4(const Run& run) {
  const DemModel<D>& m = run.m;
  DemState<D>& s = run.s;
  const auto& cs = s;
  const Columns<D> x1 = run.x1(), v1 = run.v1();
  StepStatus status = rk4_step<D>(run, s.time, view<D>(cs.x), view<D>(cs.v),
                                  constant<D>(hist_a_of<D>(run, s.history_head)), run.hist_force(s.history_head),
                                  m.dt, x1, v1);
  if (stop_now(status)) return status;
  // f(y_{n+1}) is S1 of the next step (and the multistep history).
  status |= run.eval(s.time + m.dt, constant<D>(x1), constant<D>(v1), run.a1());
  if (stop_now(status)) return status;
  commit<D>(run, run.w.plane_weighted);
  s.history_count = std::min(s.history_count + 1, 4);
  return status;
}

template <int D, class Run>
StepStatus step_verlet(const Run& run) {
  const DemModel<D>& m = run.m;
  DemState<D>& s = run.s;
  DemWorkspace<D>& w = run.w;
  const double h = m.dt, half = 0.5 * m.dt;
  const Columns<D> a = hist_a_of<D>(run, s.history_head);
  const Columns<D> x1 = run.x1(), v1 = run.v1(), a1 = run.a1();
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        const double v_half = s.v[d][i] + half * a[d][i];
        w.vs[d][i] = v_half;
        x1[d][i] = s.x[d][i] + h * v_half;
      }
  });
  // The dashpot sees the half-step velocity (explicit; LIGGGHTS does the same).
  const StepStatus status =
      run.eval(s.time + h, constant<D>(x1), view<D>(static_cast<const decltype(w.vs)&>(w.vs)), a1);
  if (stop_now(status)) return status;
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) v1[d][i] = w.vs[d][i] + half * a1[d][i];
  });
  weigh<Run::kPlanes>(w.plane_weighted, half, {{1.0, run.hist_force(s.history_head)}, {1.0, w.plane_force.data()}});
  commit<D>(run, w.plane_weighted);
  s.history_count = std::min(s.history_count + 1, 4);
  return status;
}

template <int D, class Run>
StepStatus step_symplectic_euler(const Run& run) {
  const DemModel<D>& m = run.m;
  DemState<D>& s = run.s;
  DemWorkspace<D>& w = run.w;
  const double h = m.dt;
  const Columns<D> a = hist_a_of<D>(run, s.history_head);
  const Columns<D> x1 = run.x1(), v1 = run.v1();
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d)
      for (std::int32_t i = begin; i < end; ++i) {
        const double v_new = s.v[d][i] + h * a[d][i];
        v1[d][i] = v_new;
        x1[d][i] = s.x[d][i] + h * v_new;
      }
  });
  const StepStatus status = run.eval(s.time + h, constant<D>(x1), constant<D>(v1), run.a1());
  if (stop_now(status)) return status;
  weigh<Run::kPlanes>(w.plane_weighted, h, {{1.0, run.hist_force(s.history_head)}});
  commit<D>(run, w.plane_weighted);
  s.history_count = std::min(s.history_count + 1, 4);
  return status;
}

/// One ABM4 PECE step (history complete) from the state into the run's
/// (x1, v1). The run's kernel evaluates at the prediction (frozen for
/// abm4_events). Reports non_finite if a predicted position is not finite:
/// the prediction reaches the new state only through the forces, and a
/// contact test with NaN is false, so the oldest velocity slot (which nothing
/// else reads) would otherwise silently drop the particle's contacts.
template <int D, class Run>
StepStatus abm4_pece(const Run& run) {
  const DemModel<D>& m = run.m;
  DemState<D>& s = run.s;
  DemWorkspace<D>& w = run.w;
  const double c = m.dt / 24.0;
  const int f0 = s.history_head, f1 = (f0 + 3) & 3, f2 = (f0 + 2) & 3, f3 = (f0 + 1) & 3;  // head in [0, 4)
  double probe[2] = {0, 0};
  run.over([&](std::int32_t begin, std::int32_t end) {
    double sum = 0;
    for (int d = 0; d < D; ++d) {
      const double *v0 = run.hist_v(f0, d), *v1 = run.hist_v(f1, d), *v2 = run.hist_v(f2, d), *v3 = run.hist_v(f3, d);
      const double *a0 = run.hist_a(f0, d), *a1 = run.hist_a(f1, d), *a2 = run.hist_a(f2, d), *a3 = run.hist_a(f3, d);
      const double *x = s.x[d].data(), *v = s.v[d].data();
      double *xs = w.xs[d].data(), *vs = w.vs[d].data();
      for (std::int32_t i = begin; i < end; ++i) {
        xs[i] = x[i] + c * (55.0 * v0[i] - 59.0 * v1[i] + 37.0 * v2[i] - 9.0 * v3[i]);
        vs[i] = v[i] + c * (55.0 * a0[i] - 59.0 * a1[i] + 37.0 * a2[i] - 9.0 * a3[i]);
        sum += 0.0 * xs[i];
      }
    }
    probe[begin == 0 ? 0 : 1] = sum;  // part 1 starts at split >= 1
  });
  StepStatus status = run.eval(s.time + m.dt, view<D>(static_cast<const decltype(w.xs)&>(w.xs)),
                               view<D>(static_cast<const decltype(w.vs)&>(w.vs)), view<D>(w.as));
  if (stop_now(status)) return status;
  if (!(probe[0] + probe[1] == 0.0)) status |= StepStatus::non_finite;
  // The planes' share of the corrector's velocity update.
  weigh<Run::kPlanes>(w.plane_weighted, c,
        {{9.0, w.plane_force.data()}, {19.0, run.hist_force(f0)}, {-5.0, run.hist_force(f1)}, {1.0, run.hist_force(f2)}});
  const Columns<D> x1 = run.x1(), v1 = run.v1();
  run.over([&](std::int32_t begin, std::int32_t end) {
    for (int d = 0; d < D; ++d) {
      const double *v0 = run.hist_v(f0, d), *v1h = run.hist_v(f1, d), *v2 = run.hist_v(f2, d);
      const double *a0 = run.hist_a(f0, d), *a1 = run.hist_a(f1, d), *a2 = run.hist_a(f2, d);
      const double *x = s.x[d].data(), *v = s.v[d].data();
      const double *vs = w.vs[d].data(), *as = w.as[d].data();
      double *xn = x1[d], *vn = v1[d];
      for (std::int32_t i = begin; i < end; ++i) {
        xn[i] = x[i] + c * (9.0 * vs[i] + 19.0 * v0[i] - 5.0 * v1h[i] + v2[i]);
        vn[i] = v[i] + c * (9.0 * as[i] + 19.0 * a0[i] - 5.0 * a1[i] + a2[i]);
      }
    }
  });
  return status;
}

template <int D, class Run>
StepStatus step_abm4(const Run& run) {
  if (run.s.history_count < 4) return step_rk4<D>(run);  // the three RK4 start steps
  StepStatus status = abm4_pece<D>(run);
  if (stop_now(status)) return status;
  status |= run.eval(run.s.time + run.m.dt, constant<D>(run.x1()), constant<D>(run.v1()), run.a1());
  if (stop_now(status)) return status;
  commit<D>(run, run.w.plane_weighted);
  return status;
}

// ---- contact events (abm4_events) ------------------------------------------

/// Whether every x[d][i] and v[d][i] is finite.
template <int D>
bool columns_finite(const DemModel<D>& m, ConstColumns<D> x, ConstColumns<D> v) {
  double sum = 0;
  for (int d = 0; d < D; ++d) sum += zero_probe<2>({x[d], v[d]}, 0, m.n);
  return sum == 0.0;
}

/// abm4 whose steps never straddle a contact event. The trial step (RK4 start
/// or PECE) runs with the contact set frozen at the step start; if the set at
/// the end differs, the step is redone in pieces: bisection finds the first
/// instant the set changes (to 2^-48 of the remaining interval), RK4 with the
/// frozen set integrates up to just past it, and the rest of the step starts
/// from there with the new set. The multistep history then restarts, since it
/// spans a kink of the right-hand side.
template <int D>
StepStatus step_abm4_events(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  const auto& cs = s;
  const GeneralRun<D> plain{m, s, w, m.accelerations}, frozen{m, s, w, m.accelerations_frozen};
  const double t_n = s.time, t_end = s.time + m.dt;
  auto x_n = view<D>(cs.x), v_n = view<D>(cs.v);
  w.mode_x = x_n;
  w.mode_v = v_n;
  w.mode_time = t_n;
  StepStatus status;
  if (s.history_count < 4) {
    status = rk4_step<D>(frozen, t_n, x_n, v_n, view<D>(cs.hist_a[s.history_head]),
                         s.hist_plane_force[s.history_head].data(), m.dt, view<D>(w.x1), view<D>(w.v1));
  } else {
    status = abm4_pece<D>(frozen);
  }
  if (stop_now(status)) return status;
  auto x1c = view<D>(static_cast<const decltype(w.x1)&>(w.x1));
  auto v1c = view<D>(static_cast<const decltype(w.v1)&>(w.v1));
  // A non-finite trial is committed as it is: a NaN reads as "no contact", so
  // locating events in it would redo the step from the finite start and lose
  // the NaN the trial read from the history.
  if (has(status, StepStatus::non_finite) || !columns_finite<D>(m, x1c, v1c) ||
      !contact_set_changed<D>(m, s, t_n, x_n, v_n, t_end, x1c, v1c)) {
    status |= evaluate<D>(m, s, w, m.accelerations, t_end, x1c, v1c, view<D>(w.a0));
    if (stop_now(status)) return status;
    commit<D>(plain, w.plane_weighted);
    s.history_count = std::min(s.history_count + 1, 4);
    return status;
  }

  // Event(s) inside the step. Work from (x0, v0, a0, plane_force0) = the start
  // of the remaining interval; the planes' impulse of the accepted pieces adds
  // up in plane_step_impulse.
  for (int d = 0; d < D; ++d) {
    w.x0[d] = s.x[d];
    w.v0[d] = s.v[d];
    w.a0[d] = s.hist_a[s.history_head][d];
  }
  w.plane_force0 = s.hist_plane_force[s.history_head];
  for (double& J : w.plane_step_impulse) J = 0.0;
  auto x0 = view<D>(static_cast<const decltype(w.x0)&>(w.x0));
  auto v0 = view<D>(static_cast<const decltype(w.v0)&>(w.v0));
  auto a0 = view<D>(static_cast<const decltype(w.a0)&>(w.a0));
  double t0 = t_n, remaining = m.dt;
  std::int32_t events = 0;
  auto piece = [&](double length) {
    return rk4_step<D>(frozen, t0, x0, v0, a0, w.plane_force0.data(), length, view<D>(w.x1),
                       view<D>(w.v1));
  };
  for (;;) {
    w.mode_x = x0;
    w.mode_v = v0;
    w.mode_time = t0;
    status |= piece(remaining);
    if (stop_now(status)) return status;
    if (!contact_set_changed<D>(m, s, t0, x0, v0, t0 + remaining, x1c, v1c)) break;
    if (events == m.capacities.max_events_per_step) {
      status |= StepStatus::event_capacity;
      break;
    }
    const double hi = dem_detail::locate_contact_event(remaining, status, piece, [&](double length) {
      return contact_set_changed<D>(m, s, t0, x0, v0, t0 + length, x1c, v1c);
    });
    if (stop_now(status)) return status;
    // Land just past the event, where the new contact set holds.
    const double length = hi * remaining;
    status |= piece(length);
    if (stop_now(status)) return status;
    for (std::size_t p = 0; p < w.plane_step_impulse.size(); ++p) w.plane_step_impulse[p] += w.plane_weighted[p];
    for (int d = 0; d < D; ++d) {
      w.x0[d].swap(w.x1[d]);
      w.v0[d].swap(w.v1[d]);
    }
    x0 = view<D>(static_cast<const decltype(w.x0)&>(w.x0));
    v0 = view<D>(static_cast<const decltype(w.v0)&>(w.v0));
    x1c = view<D>(static_cast<const decltype(w.x1)&>(w.x1));
    v1c = view<D>(static_cast<const decltype(w.v1)&>(w.v1));
    t0 += length;
    remaining -= length;
    status |= evaluate<D>(m, s, w, m.accelerations, t0, x0, v0, view<D>(w.a0));
    if (stop_now(status)) return status;
    w.plane_force0 = w.plane_force;
    ++events;
  }
  for (std::size_t p = 0; p < w.plane_step_impulse.size(); ++p) w.plane_step_impulse[p] += w.plane_weighted[p];
  w.mode_x = {};
  w.mode_v = {};
  // Into w.a0 (the last piece's start acceleration, read no more), which commit takes.
  status |= evaluate<D>(m, s, w, m.accelerations, t_end, x1c, v1c, view<D>(w.a0));
  if (stop_now(status)) return status;
  commit<D>(plain, w.plane_step_impulse);
  s.history_count = 1;  // restart: the next three steps are RK4
  s.events_located += events;
  s.peak_events = std::max(s.peak_events, events);
  return status;
}

/// all_finite's part over the values no step writes (the host sets them
/// between steps): x_ref of particles [begin, end) unless a grid is built,
/// and with the part that starts at 0 the listed pairs' η in an undamped
/// model and the planes' offsets, speeds and drive time. Σ 0·value: 0 when
/// they are finite, NaN otherwise.
template <int D, class Run>
double inputs_probe(const Run& run, std::int32_t begin, std::int32_t end) {
  const DemModel<D>& m = run.m;
  const DemState<D>& s = run.s;
  double sum = 0;
  if (m.features.broad_phase != BroadPhase::grid)
    for (int d = 0; d < D; ++d) sum += zero_probe<1>({s.x_ref[d].data()}, begin, end);
  if (begin == 0) {
    sum += 0.0 * s.plane_time;
    if (!m.features.damped) sum += zero_probe<1>({s.pair_eta.data()}, 0, s.pair_count);
    for (std::size_t p = 0; p < plane_count<Run::kPlanes>(s.plane_offset); ++p)
      sum += 0.0 * s.plane_offset[p] + 0.0 * s.plane_speed[p];
  }
  return sum;
}

/// The check after a step: whether every value of the state a NaN or an
/// infinity can be in is finite. It covers:
///  - x, v and the acceleration just stored: a NaN the step read from the
///    particles, the inputs or the history slots it used ends up in them;
///  - when the step did not read the whole history (one-step integrators, and
///    abm4 while its history starts), the slots it left unread, which nothing
///    else would look at before they are overwritten;
///  - x_ref unless a grid is built (then it is read, and a rebuild reports it);
///  - the listed pairs' η in an undamped model, where no force reads it (a
///    damped one reads the cached K and η of every touching pair);
///  - the planes' values and the time the step started from, O(planes): a NaN
///    there makes a contact test false instead of propagating.
/// `inputs`: with the values no step writes (inputs_probe); the small-system
/// step checks those once per call instead (small_step).
template <int D, class Run>
bool all_finite(const Run& run, double start_time, bool read_whole_history, bool inputs) {
  const DemState<D>& s = run.s;
  // The other slots, oldest first: h3 is the one the step started from (its
  // acceleration was read, its velocity copy was not).
  const int head = s.history_head, h1 = (head + 1) & 3, h2 = (head + 2) & 3, h3 = (head + 3) & 3;
  double probe[2] = {0, 0};
  run.over([&](std::int32_t begin, std::int32_t end) {
    double sum = 0;
    for (int d = 0; d < D; ++d) {
      const double *x = s.x[d].data(), *v = s.v[d].data(), *a = run.hist_a(head, d);
      if (read_whole_history) {
        sum += zero_probe<3>({x, v, a}, begin, end);
      } else {
        sum += zero_probe<8>({x, v, a, run.hist_v(h1, d), run.hist_v(h2, d), run.hist_v(h3, d), run.hist_a(h1, d),
                              run.hist_a(h2, d)},
                             begin, end);
      }
    }
    if (inputs) sum += inputs_probe<D>(run, begin, end);
    probe[begin == 0 ? 0 : 1] = sum;  // part 1 starts at split >= 1
  });
  double planes = 0.0 * start_time + 0.0 * s.network_omega2 + 0.0 * s.energy.reference + 0.0 * s.energy.work +
                  0.0 * s.energy.peak;
  for (std::size_t p = 0; p < plane_count<Run::kPlanes>(s.plane_offset); ++p) {
    planes += 0.0 * s.plane_impulse[p];
    for (int slot = 0; slot < 4; ++slot) planes += 0.0 * run.hist_force(slot)[p];
  }
  return probe[0] + probe[1] + planes == 0.0;
}

/// One step through `run` (GeneralRun or SmallRun): the integrator, then the
/// time, the network bound, the finiteness check and the energy books.
template <int D, class Run>
StepStatus step_with(const Run& run) {
  const DemModel<D>& m = run.m;
  DemState<D>& s = run.s;
  DemWorkspace<D>& w = run.w;
  StepStatus status = ensure_current_acceleration<D>(run);
  if (stop_now(status)) return status;
  const double start_time = s.time;  // overwritten below, read by the step (moving planes)
  // The work of the external forces and moving planes is booked by differences
  // over the step; the forces' moment is O(n), so not with the check off.
  const bool moment_booked = m.energy_check.interval > 0;
  const double moment_start = moment_booked ? dem_detail::external_force_moment(m, s) : 0.0;
  const double planes_start = dem_detail::plane_work_sum<Run::kPlanes>(s);
  // A full ABM4 step reads every history slot; the others read only the head.
  const bool read_whole_history =
      (m.integrator == DemIntegrator::abm4 || m.integrator == DemIntegrator::abm4_events) && s.history_count == 4;
  switch (m.integrator) {
    case DemIntegrator::abm4: status |= step_abm4<D>(run); break;
    case DemIntegrator::abm4_events:
      if constexpr (std::is_same_v<Run, GeneralRun<D>>) status |= step_abm4_events(m, s, w);
      break;
    case DemIntegrator::verlet: status |= step_verlet<D>(run); break;
    case DemIntegrator::symplectic_euler: status |= step_symplectic_euler<D>(run); break;
    case DemIntegrator::rk4: status |= step_rk4<D>(run); break;
  }
  if (stop_now(status)) {
    // Positions, velocities and time are untouched; intermediate evaluations
    // may have overwritten nothing but scratch, except that the history can no
    // longer be trusted to continue smoothly: restart it.
    s.history_count = 0;
    return status;
  }
  ++s.step;
  s.time = static_cast<double>(s.step) * m.dt;
  // Past the single contact's stable step (only with DemDesc::reject_unstable_dt
  // off), or past the contact network's (several contacts on one particle):
  // say it on every such step. The bound is re-read from the touching contacts
  // here unless the grid keeps it with its pair list. 1e-12: rounding of dt²ω²
  // at a step set exactly to the limit.
  if (m.features.broad_phase != BroadPhase::grid) {
    ConstColumns<D> x;
    for (int d = 0; d < D; ++d) x[d] = s.x[d].data();
    s.network_omega2 = dem_detail::network_omega2<D, false, Run::kCount, Run::kPlanes>(m, s, w, x);
  }
  if (m.dt > m.stable_dt || m.dt * m.dt * s.network_omega2 > m.stable_factor * m.stable_factor * (1 + 1e-12))
    status |= StepStatus::unstable_time_step;
  if (!all_finite<D>(run, start_time, read_whole_history, !Run::kInputsOncePerCall))
    status |= StepStatus::non_finite;
  const double moment_end = moment_booked ? dem_detail::external_force_moment(m, s) : 0.0;
  s.energy.work += (moment_end - moment_start) + (dem_detail::plane_work_sum<Run::kPlanes>(s) - planes_start);
  if (energy_check_due(m.energy_check, s.step))
    energy_check(s.energy, m.energy_check, dem_detail::energy_totals(m, s, w.parallel));
  if (s.energy.exceeded != 0) status |= StepStatus::energy_growth;
  return status;
}

/// The small-system step for a feature set, particle and plane count
/// (DemModel::small_step): `steps` steps in one call, so that a window of
/// substeps pays the calls and the function's entry once.
template <int D, bool Gravity, bool Damped, bool NonTensile, int N, int P>
StepStatus small_step(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, std::int32_t steps) {
  HistoryRing<D, N, P> ring(s);
  ring.load();
  const SmallRun<D, Gravity, Damped, NonTensile, N, P> run{m, s, w, ring};
  StepStatus status = StepStatus::ok;
  bool checked = false;  // whether a step reached its finiteness check (a step not taken returns before it)
  for (std::int32_t k = 0; k < steps && !stop_now(status); ++k) {
    const StepStatus step = step_with<D>(run);
    status |= step;
    checked |= !stop_now(step);
  }
  // The values no step writes: as each step's check would have found them.
  if (checked && !(inputs_probe<D>(run, 0, dem_detail::particle_count<N>(m)) == 0.0))
    status |= StepStatus::non_finite;
  ring.store();
  return status;
}

template <int D, int N, int P>
StepFunction<D> small_step_for(const DemFeatures& f) {
  switch ((f.gravity ? 4 : 0) | (f.damped ? 2 : 0) | (f.nontensile ? 1 : 0)) {
    case 0: return &small_step<D, false, false, false, N, P>;
    case 1: return &small_step<D, false, false, true, N, P>;
    case 2: return &small_step<D, false, true, false, N, P>;
    case 3: return &small_step<D, false, true, true, N, P>;
    case 4: return &small_step<D, true, false, false, N, P>;
    case 5: return &small_step<D, true, false, true, N, P>;
    case 6: return &small_step<D, true, true, false, N, P>;
    default: return &small_step<D, true, true, true, N, P>;
  }
}

}  // namespace

namespace dem_detail {

template <int D>
StepFunction<D> select_small_step(const DemModel<D>& m) {
  // External contacts are called by the general kernel only (forces.hpp):
  // the small-system step stays exactly what it is without them.
  if (m.n > kSmallSystem || m.parts != 1 || m.features.broad_phase == BroadPhase::grid ||
      m.integrator == DemIntegrator::abm4_events || m.features.external_contacts)
    return nullptr;
  // One and two particles (V1, Cases I and II) get their count compiled in,
  // and with one plane (the floor, or the bar's top) the plane count too;
  // 3..kSmallSystem share the instantiation that reads both. (No host totals
  // follow the planes in the ledger: external contacts are excluded above.)
  const bool one_plane = m.plane_point.size() == 1;
  if (m.n == 1) return one_plane ? small_step_for<D, 1, 1>(m.features) : small_step_for<D, 1, 0>(m.features);
  if (m.n == 2) return one_plane ? small_step_for<D, 2, 1>(m.features) : small_step_for<D, 2, 0>(m.features);
  return small_step_for<D, 0, 0>(m.features);
}
template StepFunction<1> select_small_step<1>(const DemModel<1>&);
template StepFunction<2> select_small_step<2>(const DemModel<2>&);
template StepFunction<3> select_small_step<3>(const DemModel<3>&);

}  // namespace dem_detail

template <int D>
StepStatus dem_step_untimed(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  if (m.accelerations == nullptr) return StepStatus::not_built;
  // The small-system step has no stage clocks: a profiled step takes the general one (same bits).
  if (m.small_step != nullptr && w.clock_ns == nullptr) return m.small_step(m, s, w, 1);
  if constexpr (D > 1)
    if (m.features.rotation) return dem_detail::granular_step<D>(m, s, w);
  return step_with<D>(GeneralRun<D>{m, s, w, m.accelerations});
}

template <int D>
StepStatus dem_step(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w) {
  if (w.clock_ns == nullptr) return dem_step_untimed<D>(m, s, w);
  const std::int64_t start = w.clock_ns();
  const StepStatus status = dem_step_untimed<D>(m, s, w);
  w.profile.step_ns += w.clock_ns() - start;
  ++w.profile.steps;
  return status;
}

template <int D>
StepStatus dem_steps(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, std::int32_t steps) {
  if (m.accelerations != nullptr && m.small_step != nullptr && w.clock_ns == nullptr)
    return m.small_step(m, s, w, steps);
  StepStatus status = StepStatus::ok;
  for (std::int32_t k = 0; k < steps && !stop_now(status); ++k) status |= dem_step<D>(m, s, w);
  return status;
}

template <int D>
void dem_drive_plane(const DemModel<D>& m, DemState<D>& s, std::int32_t p, double offset, double speed) {
  const auto q = static_cast<std::size_t>(p);
  const bool touching = s.history_count > 0 && s.hist_plane_force[s.history_head][q] != 0.0;
  const bool moved = s.plane_offset[q] + s.plane_speed[q] * (s.time - s.plane_time) != offset;
  const bool changed = moved || s.plane_speed[q] != speed;
  // A plane put somewhere else squeezes or frees its contacts: the host's work.
  const bool book = moved && m.energy_check.interval > 0;
  const double elastic_before = book ? dem_detail::plane_elastic_energy(m, s, q) : 0.0;
  s.plane_offset[q] = offset;
  s.plane_speed[q] = speed;
  s.plane_time = s.time;
  if (book) s.energy.work += dem_detail::plane_elastic_energy(m, s, q) - elastic_before;
  if (touching && changed) s.history_count = 0;
}

template <int D>
void dem_inputs_changed(DemState<D>& s) {
  s.history_count = 0;
}
template void dem_inputs_changed<1>(DemState<1>&);
template void dem_inputs_changed<2>(DemState<2>&);
template void dem_inputs_changed<3>(DemState<3>&);

template <int D>
void dem_copy_state(DemState<D>& to, const DemState<D>& from) {
  bool same = true;
  to.for_each_array(
      [&](const char*, auto* data, auto count, auto source) {
        if (source.count != static_cast<std::size_t>(count)) {
          same = false;
          return;
        }
        for (std::size_t i = 0; i < source.count; ++i) data[i] = source.data[i];
      },
      from);
  if (!same) to = from;
}
template void dem_copy_state<1>(DemState<1>&, const DemState<1>&);
template void dem_copy_state<2>(DemState<2>&, const DemState<2>&);
template void dem_copy_state<3>(DemState<3>&, const DemState<3>&);

template <int D>
bool dem_blend_state(DemState<D>& into, const DemState<D>& other, double theta) {
  bool same = true;
  into.for_each_array(
      [&](const char*, auto* data, auto count, auto o) {
        using T = std::remove_cv_t<std::remove_pointer_t<decltype(data)>>;
        if (o.count != static_cast<std::size_t>(count)) same = false;
        if constexpr (!std::is_same_v<T, double>)
          for (std::size_t i = 0; same && i < o.count; ++i) same = data[i] == o.data[i];
      },
      other);
  if (!same) return false;
  into.for_each_array(
      [&](const char* name, auto* data, auto count, auto o) {
        using T = std::remove_cv_t<std::remove_pointer_t<decltype(data)>>;
        if constexpr (std::is_same_v<T, double>) {
          const bool bound = std::strcmp(name, "network_omega2") == 0 || std::strcmp(name, "energy_peak") == 0;
          for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
            if (data[i] == o.data[i]) continue;
            data[i] = bound ? std::max(data[i], o.data[i]) : (1.0 - theta) * data[i] + theta * o.data[i];
          }
        }
      },
      other);
  return true;
}
template bool dem_blend_state<1>(DemState<1>&, const DemState<1>&, double);
template bool dem_blend_state<2>(DemState<2>&, const DemState<2>&, double);
template bool dem_blend_state<3>(DemState<3>&, const DemState<3>&, double);

template void dem_drive_plane<1>(const DemModel<1>&, DemState<1>&, std::int32_t, double, double);
template void dem_drive_plane<2>(const DemModel<2>&, DemState<2>&, std::int32_t, double, double);
template void dem_drive_plane<3>(const DemModel<3>&, DemState<3>&, std::int32_t, double, double);

template StepStatus dem_step<1>(const DemModel<1>&, DemState<1>&, DemWorkspace<1>&);
template StepStatus dem_step<2>(const DemModel<2>&, DemState<2>&, DemWorkspace<2>&);
template StepStatus dem_step<3>(const DemModel<3>&, DemState<3>&, DemWorkspace<3>&);
template StepStatus dem_steps<1>(const DemModel<1>&, DemState<1>&, DemWorkspace<1>&, std::int32_t);
template StepStatus dem_steps<2>(const DemModel<2>&, DemState<2>&, DemWorkspace<2>&, std::int32_t);
template StepStatus dem_steps<3>(const DemModel<3>&, DemState<3>&, DemWorkspace<3>&, std::int32_t);

}  // namespace xfdem
