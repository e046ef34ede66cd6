// Contact force kernels, one instantiation per feature set, picked once by
// build_dem() (no feature test inside the inner loops).
#pragma once
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "dem/contact_law.hpp"
#include "xfdem/dem.hpp"
#include "xfdem/parallel.hpp"

namespace xfdem::dem_detail {

/// Which contacts carried a force, as a number: each evaluation sums the tags
/// of its contacts (a sum, so the two parts' halves add up in any order) and
/// folds the sum into DemWorkspace::contact_signature after the ones before.
/// Two runs with the same signature saw, but for a hash collision, the same
/// contacts at the same evaluations (the coupled stepper's test that its
/// window was affine in its input). Unsigned: wrapping is the hash's.
inline std::uint64_t plane_contact_tag(std::int32_t n, std::size_t plane, std::int32_t i) {
  return (static_cast<std::uint64_t>(plane) * static_cast<std::uint64_t>(n) + static_cast<std::uint64_t>(i) + 1) *
         0xBF58476D1CE4E5B9ull;
}
inline std::uint64_t pair_contact_tag(std::int32_t n, std::int32_t i, std::int32_t j) {
  return (static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(n) + static_cast<std::uint64_t>(j) + 1) *
         0x9E3779B97F4A7C15ull;
}
inline void fold_contacts(std::uint64_t& signature, std::uint64_t evaluation) {
  signature = (signature ^ evaluation) * 0x100000001B3ull;
}

/// Builds the pair list (grid broad phase) at positions x. Defined in broadphase.cpp.
template <int D>
StepStatus build_pair_list(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x);

// network_omega2 (the contact network's stable-step bound): dem/network.hpp.

/// The number of particles a step loops over: N > 0 when the step was
/// instantiated for that count (the small-system step, whose loops over one
/// or two particles the compiler then unrolls), else the model's (N = 0).
template <int N, int D>
constexpr std::int32_t particle_count(const DemModel<D>& m) {
  return N > 0 ? N : m.n;
}

/// The same for the planes: P > 0 when the step was instantiated for P
/// planes (then no host totals follow them in the impulse ledger), else the
/// length of the planes' array `a` (P = 0).
template <int P, class T>
constexpr std::size_t plane_count(const std::vector<T>& a) {
  return P > 0 ? static_cast<std::size_t>(P) : a.size();
}

/// dx = x_j − x_i per axis; returns |dx|² (the one order of operations every
/// path uses, so that they round alike).
template <int D>
inline double separation(ConstColumns<D> x, std::int32_t i, std::int32_t j, double (&dx)[D]) {
  double dist2 = 0;
  for (int d = 0; d < D; ++d) {
    dx[d] = x[d][j] - x[d][i];
    dist2 += dx[d] * dx[d];
  }
  return dist2;
}

/// Where plane p is at time t (it moves when the host drives it).
template <int D>
std::array<double, D> plane_point_at(const DemModel<D>& m, const DemState<D>& s, std::size_t p, double t) {
  std::array<double, D> point = m.plane_point[p];
  const double shift = s.plane_offset[p] + s.plane_speed[p] * (t - s.plane_time);
  for (int d = 0; d < D; ++d) point[d] += shift * m.plane_normal[p][d];
  return point;
}

/// The contact indicator (contact_indicator) of particle i and plane p at
/// (x, v), the plane's point at that time given: > 0 when the contact is on.
template <int D>
double plane_indicator(const DemModel<D>& m, const DemState<D>& s, std::size_t p, const std::array<double, D>& point,
                       ConstColumns<D> x, ConstColumns<D> v, std::int32_t i) {
  const auto& normal = m.plane_normal[p];
  double gap = 0, rate = s.plane_speed[p];
  for (int d = 0; d < D; ++d) {
    gap += (x[d][i] - point[d]) * normal[d];
    rate -= v[d][i] * normal[d];
  }
  return contact_indicator(m.features.nontensile, m.radius[i] - gap, rate, m.stiffness[i], m.plane_eta[i]);
}

/// The contact indicator of listed pair c at (x, v): > 0 when the contact is on.
template <int D>
double pair_indicator(const DemModel<D>& m, const DemState<D>& s, std::int32_t c, ConstColumns<D> x,
                      ConstColumns<D> v) {
  const std::int32_t i = s.pair_i[c], j = s.pair_j[c];
  double dx[D], dist = 0;
  for (int d = 0; d < D; ++d) {
    dx[d] = x[d][j] - x[d][i];
    dist += dx[d] * dx[d];
  }
  dist = std::sqrt(dist);
  double rate = 0;
  if (dist > 0)
    for (int d = 0; d < D; ++d) rate -= (v[d][j] - v[d][i]) * dx[d] / dist;
  return contact_indicator(m.features.nontensile, m.radius[i] + m.radius[j] - dist, rate, s.pair_stiffness[c],
                           s.pair_eta[c]);
}

/// True when some contact of the planes or the pair list is on at (xa, va,
/// time ta) and off at (xb, vb, tb) or the reverse (abm4_events' test).
template <int D>
bool contact_set_changed(const DemModel<D>& m, const DemState<D>& s, double ta, ConstColumns<D> xa,
                         ConstColumns<D> va, double tb, ConstColumns<D> xb, ConstColumns<D> vb) {
  for (std::size_t p = 0; p < m.plane_point.size(); ++p) {
    const auto pa = plane_point_at(m, s, p, ta), pb = plane_point_at(m, s, p, tb);
    for (std::int32_t i = 0; i < m.n; ++i)
      if ((plane_indicator<D>(m, s, p, pa, xa, va, i) > 0) != (plane_indicator<D>(m, s, p, pb, xb, vb, i) > 0)) return true;
  }
  for (std::int32_t c = 0; c < s.pair_count; ++c)
    if ((pair_indicator<D>(m, s, c, xa, va) > 0) != (pair_indicator<D>(m, s, c, xb, vb) > 0)) return true;
  return false;
}

/// abm4_events' bisection for the first fraction of an interval at which the
/// contact set changes: `piece(length)` steps from the interval's start over
/// `length` into the trial columns (its status added to `status`),
/// `changed(length)` tests the trial against the start. 48 halvings; returns
/// the fraction just past the event (where the new set holds), or −1 when a
/// piece was not taken (stop_now).
template <typename Piece, typename Changed>
double locate_contact_event(double remaining, StepStatus& status, Piece&& piece, Changed&& changed) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 48; ++it) {
    const double mid = 0.5 * (lo + hi);
    status |= piece(mid * remaining);
    if (has(status, kStepNotTaken)) return -1.0;
    (changed(mid * remaining) ? hi : lo) = mid;
  }
  return hi;
}

/// Plain-mode particle–plane contacts (K = k_i, m_eff = m_i), plane by plane
/// (so each particle receives its plane contributions in plane order). Also
/// sums each plane's force into w.plane_force for the impulse ledger. Returns
/// the sum of the tags of the contacts that carried a force (contact_tag).
template <int D, bool Damped, bool NonTensile, int P = 0>
std::uint64_t plane_forces(const DemModel<D>& m, const DemState<D>& s, const DemWorkspace<D>& w, ConstColumns<D> x,
                  ConstColumns<D> v, Columns<D> a, std::int32_t begin, std::int32_t end, double* totals) {
  const double* radius = m.radius.data();
  const double* inv_mass = m.inv_mass.data();
  const double* stiffness = m.stiffness.data();
  const double* plane_eta = m.plane_eta.data();
  const std::size_t planes = plane_count<P>(m.plane_point);
  std::uint64_t active = 0;
  for (std::size_t p = 0; p < planes; ++p) {
    const std::array<double, D> point = plane_point_at(m, s, p, w.eval_time);
    const auto& normal = m.plane_normal[p];
    const double speed = s.plane_speed[p];
    double total = 0;
    auto contact = [&](std::int32_t i) {
      double gap = 0;
      for (int d = 0; d < D; ++d) gap += (x[d][i] - point[d]) * normal[d];
      const double overlap = radius[i] - gap;
      if (!(overlap > 0)) return;
      double rate = speed;
      if constexpr (Damped)
        for (int d = 0; d < D; ++d) rate -= v[d][i] * normal[d];
      const double force = normal_force<Damped, NonTensile>(stiffness[i], plane_eta[i], overlap, rate);
      active += force != 0.0 ? plane_contact_tag(m.n, p, i) : 0;
      total += force;
      const double scaled = force * inv_mass[i];
      for (int d = 0; d < D; ++d) a[d][i] += scaled * normal[d];
    };
    int nonzero = 0, axis = 0;
    for (int d = 0; d < D; ++d)
      if (normal[d] != 0.0) ++nonzero, axis = d;
    if (nonzero == 1) {
      // Axis-aligned (the usual box): for finite positions the other terms of
      // the gap are ±0, so one coordinate decides; `contact` re-tests in full.
      const double* xa = x[axis];
      const double pa = point[axis], na = normal[axis];
      for (std::int32_t i = begin; i < end; ++i)
        if (radius[i] - (xa[i] - pa) * na > 0) [[unlikely]] contact(i);
    } else {
      for (std::int32_t i = begin; i < end; ++i) contact(i);
    }
    totals[p] = total;
  }
  return active;
}

/// True if a particle of [begin, end) moved more than skin/2 since the pair
/// list was built (NaN counts as moved: the rebuild then reports it).
template <int D>
bool moved_past_half_skin(const DemModel<D>& m, const DemState<D>& s, ConstColumns<D> x, std::int32_t begin,
                          std::int32_t end) {
  const double limit = 0.25 * m.skin * m.skin;
  bool moved = false;
  for (std::int32_t i = begin; i < end; ++i) {
    double d2 = 0;
    for (int d = 0; d < D; ++d) {
      const double dx = x[d][i] - s.x_ref[d][i];
      d2 += dx * dx;
    }
    moved |= !(d2 <= limit);
  }
  return moved;
}

/// Plain-mode particle–particle contacts from the pair list, in list order.
/// In a dense packing about half of the listed pairs do not touch, in no
/// pattern a branch predictor can learn; so the list is screened in chunks
/// without branches (indices of touching pairs compacted into a stack buffer),
/// then only the touching pairs are evaluated.
///
/// Pairs [begin, end) of the list. A contribution to a particle j >= split
/// goes to cross[·][j − split] instead of a (part 0 of a split step, so that
/// part 1 may write its own particles meanwhile); split = n: no cross buffer.
template <int D, bool Damped, bool NonTensile>
StepStatus pair_forces(const DemModel<D>& m, const DemState<D>& s, ConstColumns<D> x, ConstColumns<D> v,
                       Columns<D> a, std::int32_t begin, std::int32_t end, std::int32_t split, Columns<D> cross,
                       std::uint64_t& active) {
  constexpr std::int32_t kChunk = 512;
  std::int32_t touching[kChunk];
  double kept_dx[D][kChunk], kept_dist2[kChunk], kept_reach[kChunk];
  const double* radius = m.radius.data();
  const double* inv_mass = m.inv_mass.data();
  const std::int32_t* pi = s.pair_i.data();
  const std::int32_t* pj = s.pair_j.data();
  const double* pair_k = s.pair_stiffness.data();
  const double* pair_eta = s.pair_eta.data();
  // Where a contribution to particle j goes (see above).
  auto to_j = [&](int d, std::int32_t j) -> double& { return j < split ? a[d][j] : cross[d][j - split]; };
  // One touching pair, scalar.
  auto one = [&](std::int32_t c) {
    const std::int32_t i = pi[c], j = pj[c];
    double dx[D];
    const double dist2 = separation<D>(x, i, j, dx);
    const double reach = radius[i] + radius[j];
    const double dist = std::sqrt(dist2);
    double normal[D];
    StepStatus flag = StepStatus::ok;
    if (dist > 0) [[likely]] {
      for (int d = 0; d < D; ++d) normal[d] = dx[d] / dist;
    } else {
      // Coincident centres: no direction is better than another; take the
      // first axis and report it.
      for (int d = 0; d < D; ++d) normal[d] = d == 0 ? 1.0 : 0.0;
      flag = StepStatus::coincident_centres;
    }
    double rate = 0;
    if constexpr (Damped)
      for (int d = 0; d < D; ++d) rate -= (v[d][j] - v[d][i]) * normal[d];
    const double force = normal_force<Damped, NonTensile>(pair_k[c], pair_eta[c], reach - dist, rate);
    active += force != 0.0 ? pair_contact_tag(m.n, i, j) : 0;
    const double fi = force * inv_mass[i], fj = force * inv_mass[j];
    for (int d = 0; d < D; ++d) {
      a[d][i] -= fi * normal[d];
      to_j(d, j) += fj * normal[d];
    }
    return flag;
  };
  StepStatus status = StepStatus::ok;
  // A short list (a few particles, all_pairs): the screening pass's chunk
  // bookkeeping costs more than it saves. The same test, then the same force.
  constexpr std::int32_t kShortList = 8;
  if (end - begin <= kShortList) {
    for (std::int32_t c = begin; c < end; ++c) {
      const std::int32_t i = pi[c], j = pj[c];
      double dx[D];
      const double reach = radius[i] + radius[j];
      if (separation<D>(x, i, j, dx) < reach * reach) status |= one(c);  // false for NaN, as below
    }
    return status;
  }
  for (std::int32_t c0 = begin; c0 < end; c0 += kChunk) {
    const std::int32_t c1 = std::min(end, c0 + kChunk);
    std::int32_t hits = 0;
    for (std::int32_t c = c0; c < c1; ++c) {
      const std::int32_t i = pi[c], j = pj[c];
      double dist2 = 0;
      for (int d = 0; d < D; ++d) {
        const double dx = x[d][j] - x[d][i];
        dist2 += dx * dx;
        kept_dx[d][hits] = dx;  // kept for the force pass (no second gather)
      }
      const double reach = radius[i] + radius[j];
      touching[hits] = c;
      kept_dist2[hits] = dist2;
      kept_reach[hits] = reach;
      hits += dist2 < reach * reach ? 1 : 0;  // false for NaN, as before
    }
    std::int32_t h = 0;
#if defined(__SSE2__)
    // Two pairs per pass in the two lanes of SSE2 (x86-64 baseline): the
    // square root and the divisions, which dominate, issue once for both.
    // Lanes do exactly the scalar operations, so the bits are the same, and
    // the contributions are added in list order below.
    for (; h + 1 < hits; h += 2) {
      const std::int32_t ca = touching[h], cb = touching[h + 1];
      const std::int32_t ia = pi[ca], ja = pj[ca], ib = pi[cb], jb = pj[cb];
      const __m128d zero = _mm_setzero_pd();
      __m128d dx[D];
      for (int d = 0; d < D; ++d) dx[d] = _mm_loadu_pd(&kept_dx[d][h]);
      const __m128d dist = _mm_sqrt_pd(_mm_loadu_pd(&kept_dist2[h]));
      if (_mm_movemask_pd(_mm_cmpgt_pd(dist, zero)) != 3) {
        status |= one(ca);  // coincident centres: the scalar path handles them
        status |= one(cb);
        continue;
      }
      const __m128d reach = _mm_loadu_pd(&kept_reach[h]);
      __m128d normal[D];
      for (int d = 0; d < D; ++d) normal[d] = _mm_div_pd(dx[d], dist);
      __m128d force = _mm_mul_pd(_mm_set_pd(pair_k[cb], pair_k[ca]), _mm_sub_pd(reach, dist));
      if constexpr (Damped) {
        __m128d rate = zero;
        for (int d = 0; d < D; ++d)
          rate = _mm_sub_pd(rate, _mm_mul_pd(_mm_sub_pd(_mm_set_pd(v[d][jb], v[d][ja]), _mm_set_pd(v[d][ib], v[d][ia])),
                                             normal[d]));
        force = _mm_add_pd(force, _mm_mul_pd(_mm_set_pd(pair_eta[cb], pair_eta[ca]), rate));
      }
      if constexpr (NonTensile) force = _mm_max_pd(zero, force);  // = std::max(force, 0.0), NaN and -0 alike
      const int carried = _mm_movemask_pd(_mm_cmpneq_pd(force, zero));
      active += ((carried & 1) ? pair_contact_tag(m.n, ia, ja) : 0) + ((carried & 2) ? pair_contact_tag(m.n, ib, jb) : 0);
      const __m128d fi = _mm_mul_pd(force, _mm_set_pd(inv_mass[ib], inv_mass[ia]));
      const __m128d fj = _mm_mul_pd(force, _mm_set_pd(inv_mass[jb], inv_mass[ja]));
      alignas(16) double on_i[D][2], on_j[D][2];
      for (int d = 0; d < D; ++d) {
        _mm_store_pd(on_i[d], _mm_mul_pd(fi, normal[d]));
        _mm_store_pd(on_j[d], _mm_mul_pd(fj, normal[d]));
      }
      for (int d = 0; d < D; ++d) {
        a[d][ia] -= on_i[d][0];
        to_j(d, ja) += on_j[d][0];
      }
      for (int d = 0; d < D; ++d) {
        a[d][ib] -= on_i[d][1];
        to_j(d, jb) += on_j[d][1];
      }
    }
#endif
    for (; h < hits; ++h) status |= one(touching[h]);
  }
  return status;
}

/// Σ 0·c_k[i] over the columns c_k and i in [begin, end): 0 when every value
/// is finite, NaN otherwise (0·x is NaN exactly when x is NaN or infinite), so
/// it decides without a branch per value and whatever the order of the sum.
/// Even and odd i are summed apart, which lets the compiler use packed SSE2.
template <std::size_t K>
[[gnu::always_inline]] inline double zero_probe(const std::array<const double*, K>& c, std::int32_t begin,
                                                std::int32_t end) {
  double even = 0, odd = 0;
  std::int32_t i = begin;
  for (; i + 1 < end; i += 2) {
    double te = 0.0 * c[0][i], to = 0.0 * c[0][i + 1];
    for (std::size_t k = 1; k < K; ++k) {
      te += 0.0 * c[k][i];
      to += 0.0 * c[k][i + 1];
    }
    even += te;
    odd += to;
  }
  if (i < end)
    for (std::size_t k = 0; k < K; ++k) even += 0.0 * c[k][i];
  return even + odd;
}

/// a = g + F_ext / m on particles [begin, end): where every evaluation starts.
template <int D, bool Gravity>
inline void input_accelerations(const DemModel<D>& m, const DemState<D>& s, Columns<D> a, std::int32_t begin,
                                std::int32_t end) {
  for (int d = 0; d < D; ++d) {
    const double g = Gravity ? m.gravity[d] : 0.0;
    double* ad = a[d];
    for (std::int32_t i = begin; i < end; ++i) ad[i] = g;
    if (m.features.external_forces) {
      const double* f = s.external_force[d].data();
      for (std::int32_t i = begin; i < end; ++i) ad[i] += f[i] * m.inv_mass[i];
    }
  }
}

/// The host's contacts (DemDesc::external_contacts), on the whole state, its
/// totals after the planes' in w.plane_force: the last thing the general
/// kernel's evaluation does, when m.features.external_contacts. (The
/// small-system step, whose kernel is inlined, is not taken for such models,
/// so that it does no work for them.)
template <int D>
[[gnu::noinline, gnu::cold]] std::uint64_t external_contacts(const DemModel<D>& m, DemWorkspace<D>& w,
                                                             ConstColumns<D> x, ConstColumns<D> v, Columns<D> a) {
  if (w.external_contacts == nullptr) return 0;
  return w.external_contacts(w.external_context, w.eval_time, x, v, a, w.plane_force.data() + m.plane_point.size());
}

/// Plain-mode evaluation of a model in one part: inputs, planes (totals into
/// w.plane_force), pairs (the grid's list rebuilt first if it is stale), in
/// this order (the general kernel then adds the host's contacts). The
/// general kernel below runs it through its pointer; the small-system step
/// (integrators.cpp) inlines it, with its particle count N (particle_count)
/// and plane count P (plane_count) known at compile time.
template <int D, bool Gravity, bool Damped, bool NonTensile, int N = 0, int P = 0>
[[gnu::always_inline]] inline StepStatus one_part_accelerations(const DemModel<D>& m, DemState<D>& s,
                                                                DemWorkspace<D>& w, ConstColumns<D> x,
                                                                ConstColumns<D> v, Columns<D> a) {
  const std::int32_t n = particle_count<N>(m);
  input_accelerations<D, Gravity>(m, s, a, 0, n);
  std::uint64_t active = plane_forces<D, Damped, NonTensile, P>(m, s, w, x, v, a, 0, n, w.plane_force.data());
  StepStatus status = StepStatus::ok;
  if (m.features.broad_phase != BroadPhase::none) {
    if (m.features.broad_phase == BroadPhase::grid && (!s.pairs_valid || moved_past_half_skin<D>(m, s, x, 0, n))) {
      const StepStatus built = build_pair_list<D>(m, s, w, x);
      if (built != StepStatus::ok) return built;
    }
    status = pair_forces<D, Damped, NonTensile>(m, s, x, v, a, 0, s.pair_count, n, a, active);
  }
  fold_contacts(w.contact_signature, active);
  return status;
}

/// a = g + Σ contact forces / m at the state (x, v).
/// Frozen: a contact is on iff it was on at the interval start (w.mode_x,
/// w.mode_v), and then follows the unclamped linear law even past δ = 0; the
/// right-hand side is then smooth over the interval, which the event-located
/// integrator needs for its order.
template <int D, bool Gravity, bool Damped, bool NonTensile, bool Frozen>
StepStatus accelerations(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x,
                         ConstColumns<D> v, Columns<D> a) {
  const std::int32_t n = m.n;
  auto gravity = [&](std::int32_t begin, std::int32_t end) { input_accelerations<D, Gravity>(m, s, a, begin, end); };
  if constexpr (!Frozen) {
    const bool grid = m.features.broad_phase == BroadPhase::grid;
    const std::size_t planes = m.plane_point.size();
    if (m.parts == 1) {
      const StepStatus status = one_part_accelerations<D, Gravity, Damped, NonTensile>(m, s, w, x, v, a);
      if (m.features.external_contacts) fold_contacts(w.contact_signature, external_contacts<D>(m, w, x, v, a));
      return status;
    }
    // Two parts: particles [0, split) and [split, n). Phase 1: each part's
    // gravity, plane contacts (totals per part) and displacement check.
    bool moved[2] = {false, false};
    std::uint64_t active[2] = {0, 0};  // per part; sums of integers, so the total is the same either way
    for_parts(w.parallel, 2, [&](int part) {
      const std::int32_t begin = part == 0 ? 0 : m.split, end = part == 0 ? m.split : n;
      gravity(begin, end);
      active[part] =
          plane_forces<D, Damped, NonTensile>(m, s, w, x, v, a, begin, end, w.plane_force_part.data() + part * planes);
      if (grid && s.pairs_valid) moved[part] = moved_past_half_skin<D>(m, s, x, begin, end);
    });
    for (std::size_t p = 0; p < planes; ++p) w.plane_force[p] = w.plane_force_part[p] + w.plane_force_part[planes + p];
    std::uint64_t carried = active[0] + active[1];
    if (m.features.broad_phase == BroadPhase::none) {
      if (m.features.external_contacts) carried += external_contacts<D>(m, w, x, v, a);
      fold_contacts(w.contact_signature, carried);
      return StepStatus::ok;
    }
    if (grid && (!s.pairs_valid || moved[0] || moved[1])) {
      const StepStatus built = build_pair_list<D>(m, s, w, x);  // rare: on one thread
      if (built != StepStatus::ok) return built;
    }
    // Phase 2: the list is sorted by i, so part 0 owns the pairs with i < split
    // (their j may lie in part 1: those contributions go to the cross buffer)
    // and part 1 the rest (both particles in part 1).
    const std::int32_t* first = s.pair_i.data();
    const std::int32_t boundary =
        static_cast<std::int32_t>(std::lower_bound(first, first + s.pair_count, m.split) - first);
    Columns<D> cross;
    for (int d = 0; d < D; ++d) cross[d] = w.cross[d].data();
    StepStatus part_status[2] = {StepStatus::ok, StepStatus::ok};
    for_parts(w.parallel, 2, [&](int part) {
      if (part == 0) {
        for (int d = 0; d < D; ++d) std::fill(w.cross[d].begin(), w.cross[d].end(), 0.0);
        active[0] = 0;
        part_status[0] = pair_forces<D, Damped, NonTensile>(m, s, x, v, a, 0, boundary, m.split, cross, active[0]);
      } else {
        active[1] = 0;
        part_status[1] =
            pair_forces<D, Damped, NonTensile>(m, s, x, v, a, boundary, s.pair_count, n, cross, active[1]);
      }
    });
    // Phase 3: part 0's contributions to part 1's particles, in a fixed order.
    for (int d = 0; d < D; ++d)
      for (std::int32_t j = m.split; j < n; ++j) a[d][j] += cross[d][j - m.split];
    if (m.features.external_contacts) carried += external_contacts<D>(m, w, x, v, a);
    fold_contacts(w.contact_signature, carried + active[0] + active[1]);
    return part_status[0] | part_status[1];
  }
  gravity(0, n);
  // Frozen mode (abm4_events, meant for few particles): plain loops.
  const double* radius = m.radius.data();
  const double* inv_mass = m.inv_mass.data();
  const double* stiffness = m.stiffness.data();
  const double* plane_eta = m.plane_eta.data();

  // Particle–plane contacts (K = k_i, m_eff = m_i).
  const std::size_t planes = m.plane_point.size();
  std::uint64_t carried = 0;
  for (std::size_t p = 0; p < planes; ++p) {
    // The frozen set is decided at the interval start, with the plane where it
    // was then (w.mode_time); the force uses the plane where it is now.
    const std::array<double, D> point = plane_point_at(m, s, p, w.eval_time);
    const std::array<double, D> point0 = plane_point_at(m, s, p, w.mode_time);
    const auto& normal = m.plane_normal[p];
    const double speed = s.plane_speed[p];
    double total = 0;
    for (std::int32_t i = 0; i < n; ++i) {
      double gap = 0;
      for (int d = 0; d < D; ++d) gap += (x[d][i] - point[d]) * normal[d];
      const double overlap = radius[i] - gap;
      double gap0 = 0, rate0 = speed;
      for (int d = 0; d < D; ++d) {
        gap0 += (w.mode_x[d][i] - point0[d]) * normal[d];
        rate0 -= w.mode_v[d][i] * normal[d];
      }
      if (!(contact_indicator(NonTensile, radius[i] - gap0, rate0, stiffness[i], plane_eta[i]) > 0)) continue;
      double rate = speed;
      if constexpr (Damped)
        for (int d = 0; d < D; ++d) rate -= v[d][i] * normal[d];
      const double force = normal_force<Damped, false>(stiffness[i], plane_eta[i], overlap, rate);
      carried += force != 0.0 ? plane_contact_tag(m.n, p, i) : 0;
      total += force;
      const double scaled = force * inv_mass[i];
      for (int d = 0; d < D; ++d) a[d][i] += scaled * normal[d];
    }
    w.plane_force[p] = total;
  }

  // Particle–particle contacts from the pair list.
  if (m.features.broad_phase == BroadPhase::none) {
    fold_contacts(w.contact_signature, carried);
    return StepStatus::ok;
  }
  StepStatus status = StepStatus::ok;
  if (m.features.broad_phase == BroadPhase::grid && (!s.pairs_valid || moved_past_half_skin<D>(m, s, x, 0, n))) {
    status = build_pair_list<D>(m, s, w, x);
    if (status != StepStatus::ok) return status;
  }
  const std::int32_t* pi = s.pair_i.data();
  const std::int32_t* pj = s.pair_j.data();
  const double* pair_k = s.pair_stiffness.data();
  const double* pair_eta = s.pair_eta.data();
  const std::int32_t count = s.pair_count;
  for (std::int32_t c = 0; c < count; ++c) {
    const std::int32_t i = pi[c], j = pj[c];
    double dx[D];
    const double dist2 = separation<D>(x, i, j, dx);
    const double reach = radius[i] + radius[j];
    double dx0[D];
    const double dist0 = std::sqrt(separation<D>(w.mode_x, i, j, dx0));
    double rate0 = 0;
    if (dist0 > 0)
      for (int d = 0; d < D; ++d) rate0 -= (w.mode_v[d][j] - w.mode_v[d][i]) * dx0[d] / dist0;
    if (!(contact_indicator(NonTensile, reach - dist0, rate0, pair_k[c], pair_eta[c]) > 0)) continue;
    const double dist = std::sqrt(dist2);
    double normal[D];
    if (dist > 0) {
      for (int d = 0; d < D; ++d) normal[d] = dx[d] / dist;
    } else {
      for (int d = 0; d < D; ++d) normal[d] = d == 0 ? 1.0 : 0.0;
      status |= StepStatus::coincident_centres;
    }
    double rate = 0;
    if constexpr (Damped)
      for (int d = 0; d < D; ++d) rate -= (v[d][j] - v[d][i]) * normal[d];
    const double force = normal_force<Damped, false>(pair_k[c], pair_eta[c], reach - dist, rate);
    carried += force != 0.0 ? pair_contact_tag(m.n, i, j) : 0;
    const double fi = force * inv_mass[i], fj = force * inv_mass[j];
    for (int d = 0; d < D; ++d) {
      a[d][i] -= fi * normal[d];
      a[d][j] += fj * normal[d];
    }
  }
  fold_contacts(w.contact_signature, carried);
  return status;
}

/// The kernel for a feature set (plain or frozen).
template <int D>
AccelerationKernel<D> select_kernel(const DemFeatures& f, bool frozen);

/// Most particles the small-system step takes (DemDesc::small_system_path).
constexpr std::int32_t kSmallSystem = 8;

/// The small-system step for a built model, or nullptr where it does not
/// apply (more than kSmallSystem particles, two parts, the grid, abm4_events).
/// Defined in integrators.cpp.
template <int D>
StepFunction<D> select_small_step(const DemModel<D>& m);

}  // namespace xfdem::dem_detail
