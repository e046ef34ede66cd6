// Pair list for the particle–particle contacts.
//
// all_pairs: the list of every pair, written once at build (few particles).
// grid: a Verlet list. Pairs whose surfaces are closer than the skin are listed;
// the list stays valid while no particle has moved more than skin/2 since it was
// built, so it is rebuilt only when one has (checked at every force evaluation,
// so an evaluation inside a step can trigger it too). A rebuild bins the
// particles into a uniform grid over their bounding box (cell >= 2 r_max + skin)
// with a counting sort, which keeps particles of a cell in index order: the list
// comes out in the same order whatever happened before, so the stepper is
// deterministic without any sort of equal keys.
#include <cmath>

#include "dem/contact_parameters.hpp"
#include "dem/forces.hpp"
#include "dem/network.hpp"

namespace xfdem::dem_detail {

template <int D>
StepStatus build_pair_list_untimed(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x);

template <int D>
StepStatus build_pair_list(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x) {
  if (w.clock_ns == nullptr) return build_pair_list_untimed<D>(m, s, w, x);
  const std::int64_t start = w.clock_ns();
  const StepStatus status = build_pair_list_untimed<D>(m, s, w, x);
  w.profile.broad_phase_ns += w.clock_ns() - start;
  return status;
}

template <int D>
StepStatus build_pair_list_untimed(const DemModel<D>& m, DemState<D>& s, DemWorkspace<D>& w, ConstColumns<D> x) {
  const std::int32_t n = m.n;
  s.pairs_valid = 0;
  s.pair_count = 0;
  // Bounding box; non-finite positions cannot be binned. A non-finite x_ref
  // (the rebuild is how it is read) is reported the same way, and kept.
  double lo[D], hi[D];
  for (int d = 0; d < D; ++d) {
    lo[d] = x[d][0];
    hi[d] = x[d][0];
    for (std::int32_t i = 0; i < n; ++i) {
      const double xi = x[d][i];
      if (!std::isfinite(xi) || !std::isfinite(s.x_ref[d][i])) return StepStatus::non_finite;
      lo[d] = std::min(lo[d], xi);
      hi[d] = std::max(hi[d], xi);
    }
  }
  std::int32_t dims[D];
  std::int64_t strides[D];
  double cells = 1;
  for (int d = 0; d < D; ++d) {
    const double span = std::floor((hi[d] - lo[d]) / m.cell_size) + 1;
    cells *= span;
    if (!(cells <= static_cast<double>(m.capacities.max_grid_cells))) return StepStatus::grid_capacity;
    dims[d] = static_cast<std::int32_t>(span);
  }
  const auto cell_count = static_cast<std::int32_t>(cells);
  strides[0] = 1;
  for (int d = 1; d < D; ++d) strides[d] = strides[d - 1] * dims[d - 1];
  s.peak_grid_cells = std::max(s.peak_grid_cells, cell_count);
  w.grid_cells_used = cell_count;

  // Counting sort of particles by cell (stable: index order inside a cell).
  std::int32_t* start = w.cell_start.data();
  std::int32_t* sorted = w.cell_particles.data();
  std::int32_t* cell_of = w.particle_cell.data();
  for (std::int32_t c = 0; c <= cell_count; ++c) start[c] = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    std::int64_t c = 0;
    for (int d = 0; d < D; ++d) {
      auto k = static_cast<std::int32_t>((x[d][i] - lo[d]) / m.cell_size);
      k = std::min(k, dims[d] - 1);
      c += k * strides[d];
    }
    cell_of[i] = static_cast<std::int32_t>(c);
    ++start[c + 1];
  }
  for (std::int32_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
  // Fill using cell_start as running cursors, then shift back.
  for (std::int32_t i = 0; i < n; ++i) sorted[start[cell_of[i]]++] = i;
  for (std::int32_t c = cell_count; c > 0; --c) start[c] = start[c - 1];
  start[0] = 0;

  // For each particle, scan the 3^D surrounding cells for partners j > i.
  const double skin = m.skin;
  const std::int32_t max_pairs = m.capacities.max_pairs;
  const std::int32_t max_nb = m.capacities.max_neighbors_per_particle;
  std::int32_t count = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    std::int32_t home[D];
    {
      std::int64_t rest = cell_of[i];
      for (int d = D - 1; d >= 0; --d) {
        home[d] = static_cast<std::int32_t>(rest / strides[d]);
        rest -= home[d] * strides[d];
      }
    }
    std::int32_t neighbours = 0;
    constexpr int kOffsets = D == 1 ? 3 : (D == 2 ? 9 : 27);
    for (int o = 0; o < kOffsets; ++o) {
      std::int64_t c = 0;
      bool inside = true;
      int code = o;
      for (int d = 0; d < D; ++d) {
        const std::int32_t k = home[d] + (code % 3) - 1;
        code /= 3;
        if (k < 0 || k >= dims[d]) {
          inside = false;
          break;
        }
        c += k * strides[d];
      }
      if (!inside) continue;
      for (std::int32_t q = start[c]; q < start[c + 1]; ++q) {
        const std::int32_t j = sorted[q];
        if (j <= i) continue;
        double dist2 = 0;
        for (int d = 0; d < D; ++d) {
          const double dx = x[d][j] - x[d][i];
          dist2 += dx * dx;
        }
        const double reach = m.radius[i] + m.radius[j] + skin;
        if (!(dist2 < reach * reach)) continue;
        if (neighbours == max_nb) return StepStatus::neighbor_capacity;
        if (count == max_pairs) return StepStatus::pair_capacity;
        ++neighbours;
        s.pair_i[count] = i;
        s.pair_j[count] = j;
        ++count;
      }
    }
    s.peak_neighbors = std::max(s.peak_neighbors, neighbours);
  }
  // Pairs of one particle came out cell by cell; put them in j order so that
  // the list does not depend on where the grid's origin happened to fall.
  // (Insertion sort per particle: runs are short and nearly sorted.)
  for (std::int32_t c = 1; c < count; ++c) {
    const std::int32_t i = s.pair_i[c], j = s.pair_j[c];
    std::int32_t k = c;
    while (k > 0 && s.pair_i[k - 1] == i && s.pair_j[k - 1] > j) {
      s.pair_j[k] = s.pair_j[k - 1];
      --k;
    }
    s.pair_j[k] = j;
  }
  for (std::int32_t c = 0; c < count; ++c) {
    const PairParameters pp = pair_parameters(m, s.pair_i[c], s.pair_j[c]);
    s.pair_stiffness[c] = pp.stiffness;
    s.pair_eta[c] = pp.eta;
  }
  s.pair_count = count;
  s.peak_pairs = std::max(s.peak_pairs, count);
  for (int d = 0; d < D; ++d)
    for (std::int32_t i = 0; i < n; ++i) s.x_ref[d][i] = x[d][i];
  s.pairs_valid = 1;
  ++s.list_builds;
  // The contacts touching now (listed pairs within the skin would count
  // near-misses that the dense packings of docs/benchmarks.md are full of).
  s.network_omega2 = m.law == ContactLaw::hertz ? network_omega2<D, true>(m, s, w, x) : network_omega2<D>(m, s, w, x);
  return StepStatus::ok;
}

#define XFDEM_INSTANTIATE(D)                                                                                 \
  template StepStatus build_pair_list<D>(const DemModel<D>&, DemState<D>&, DemWorkspace<D>&, ConstColumns<D>);
XFDEM_INSTANTIATE(1)
XFDEM_INSTANTIATE(2)
XFDEM_INSTANTIATE(3)
#undef XFDEM_INSTANTIATE

}  // namespace xfdem::dem_detail
