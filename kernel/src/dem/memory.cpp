// dem_memory(): the bytes build_dem() allocates, counted before it does, and
// the refusal that names what takes them.
#include "dem/memory.hpp"

#include <algorithm>
#include <cstdio>

namespace xfdem {

BroadPhase dem_broad_phase(std::int64_t particles, std::int32_t all_pairs_up_to) noexcept {
  if (particles < 2) return BroadPhase::none;
  if (particles <= std::max<std::int32_t>(all_pairs_up_to, 0)) return BroadPhase::all_pairs;
  return BroadPhase::grid;
}

namespace dem_detail {

template <int D>
ResolvedSizes resolve_sizes(const DemDesc<D>& desc) {
  ResolvedSizes r;
  const auto n = static_cast<std::int64_t>(desc.particles.size());
  r.broad_phase = dem_broad_phase(n, desc.all_pairs_up_to);
  // The split is a property of the model, never of the number of workers.
  if (desc.split_from > 0 && n >= desc.split_from && n >= 2) {
    r.parts = 2;
    r.split = static_cast<std::int32_t>(n / 2);
  } else {
    r.parts = 1;
    r.split = static_cast<std::int32_t>(n);
  }
  const auto pick = [](std::int32_t given, std::int64_t fallback) {
    return given > 0 ? static_cast<std::int64_t>(given) : fallback;
  };
  if (r.broad_phase == BroadPhase::all_pairs) r.max_pairs = n * (n - 1) / 2;
  if (r.broad_phase == BroadPhase::grid) {
    r.max_pairs = pick(desc.capacities.max_pairs, 8 * n + 64);
    r.max_cells = pick(desc.capacities.max_grid_cells, 8 * n + 4096);
  }
  r.max_neighbors = pick(desc.capacities.max_neighbors_per_particle, 48);
  r.max_events = pick(desc.capacities.max_events_per_step, 16);
  return r;
}

void format_bytes(double bytes, char* out, std::size_t size) {
  static constexpr const char* kUnits[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  double value = bytes;
  int unit = 0;
  // Move up while the value would print as 1000 or more at three digits.
  while (unit + 1 < 6 && value >= 999.5) {
    value /= 1000.0;
    ++unit;
  }
  std::snprintf(out, size, unit == 0 ? "%.0f %s" : "%.3g %s", value, kUnits[unit]);
}

void format_speed(double speed, char* out, std::size_t size) {
  if (speed >= 999.5)
    std::snprintf(out, size, "%.3g km/s", speed / 1000.0);
  else
    std::snprintf(out, size, "%.3g m/s", speed);
}

template <int D>
BuildResult memory_refusal(const DemDesc<D>& desc, const DemMemory& memory, int states, const char* state_note,
                           std::uint64_t budget, bool allocator_failed) {
  const std::uint64_t total = memory.total(states);
  const std::uint64_t pair_bytes = static_cast<std::uint64_t>(memory.pairs) * memory.bytes_per_pair *
                                   static_cast<std::uint64_t>(states);
  const std::uint64_t cell_bytes =
      memory.grid_cells > 0 ? static_cast<std::uint64_t>(memory.grid_cells + 1) * DemMemory::kBytesPerGridCell : 0;
  // A capacity the description gave (and the model uses) is named when its
  // arrays take the most; the particles answer for the rest, defaults included.
  const bool grid = memory.grid_cells > 0;
  const bool pairs_given = grid && desc.capacities.max_pairs > 0;
  const bool cells_given = grid && desc.capacities.max_grid_cells > 0;
  const std::uint64_t particle_bytes = total - (pairs_given ? pair_bytes : 0) - (cells_given ? cell_bytes : 0);
  char part[32], whole[32], limit[32], each[48];
  format_bytes(static_cast<double>(total), whole, sizeof(whole));
  format_bytes(static_cast<double>(budget), limit, sizeof(limit));
  const char* field = "particles";
  const char* things = "particles";
  long long count = static_cast<long long>(desc.particles.size());
  std::uint64_t bytes = particle_bytes;
  if (pairs_given && pair_bytes >= bytes && pair_bytes >= (cells_given ? cell_bytes : 0)) {
    field = "capacities.max_pairs";
    things = "pairs";
    count = memory.pairs;
    bytes = pair_bytes;
    std::snprintf(each, sizeof(each), "%llu bytes a pair", static_cast<unsigned long long>(memory.bytes_per_pair));
  } else if (cells_given && cell_bytes >= bytes) {
    field = "capacities.max_grid_cells";
    things = "grid cells";
    count = memory.grid_cells;
    bytes = cell_bytes;
    std::snprintf(each, sizeof(each), "%llu bytes a cell", static_cast<unsigned long long>(DemMemory::kBytesPerGridCell));
  } else {
    char one[32];
    format_bytes(count > 0 ? static_cast<double>(bytes) / static_cast<double>(count) : 0.0, one, sizeof(one));
    std::snprintf(each, sizeof(each), "%s a particle", one);
  }
  format_bytes(static_cast<double>(bytes), part, sizeof(part));
  if (allocator_failed)
    return BuildResult::failure(BuildResult::Code::memory,
                                "%s: %lld %s take %s of the %s the particles' arrays need (%s%s): the allocator could "
                                "not provide them",
                                field, count, things, part, whole, each, state_note);
  return BuildResult::failure(BuildResult::Code::memory,
                              "%s: %lld %s take %s of the %s the particles' arrays need (%s%s), more than the memory "
                              "budget of %s (max_memory_bytes)",
                              field, count, things, part, whole, each, state_note, limit);
}

}  // namespace dem_detail

template <int D>
DemMemory dem_memory(const DemDesc<D>& desc) {
  const dem_detail::ResolvedSizes r = dem_detail::resolve_sizes(desc);
  const auto n = static_cast<std::uint64_t>(desc.particles.size());
  const auto planes = static_cast<std::uint64_t>(desc.planes.size());
  // The host's totals of external contacts: entries of the planes' impulse and
  // history (state) and of their evaluation, start, weighted and step sums (workspace).
  const auto totals = static_cast<std::uint64_t>(std::max(desc.external_contact_totals, 0));
  constexpr std::uint64_t d = D, real = sizeof(double), index = sizeof(std::int32_t);
  DemMemory m;
  m.pairs = r.max_pairs;
  m.grid_cells = r.max_cells;
  // Model: mass, inv_mass, radius, stiffness, plane_eta; each plane's point and normal.
  m.model = 5 * n * real + 2 * planes * d * real;
  // State: x, v, x_ref, four history slots of v and a (external_force, and the
  // 2D external_torque, when on);
  // the pair list; each plane's offset, speed, impulse and four history forces.
  m.state = (3 + 8 + (desc.external_forces ? 1 : 0)) * d * n * real + (desc.external_torques ? n * real : 0) +
            static_cast<std::uint64_t>(r.max_pairs) * DemMemory::kBytesPerPair + 7 * planes * real + 5 * totals * real;
  // Workspace: ten stage columns, part 0's cross buffer, the planes' forces
  // (four per plane and two parts' shares), the grid's index, the network bound.
  m.workspace = 10 * d * n * real + d * (n - static_cast<std::uint64_t>(r.split)) * real + 6 * planes * real +
                4 * totals * real +
                n * (d * (d + 1) / 2) * real;
  if (r.broad_phase == BroadPhase::grid)
    m.workspace += static_cast<std::uint64_t>(r.max_cells + 1) * DemMemory::kBytesPerGridCell + 2 * n * index;
  const bool hertz = desc.law == ContactLaw::hertz;
  if (D > 1 && hertz) m.model += 2 * (n + planes) * real;  // each body's 1/E and 1/G terms
  if (dem_detail::rotates(desc)) {
    // Rotation: 1/I; ω, the history ring of ω and α (and the 2D angle), in the state
    // and as the step's trial copies; each pair record's and each particle–plane
    // contact's tangential spring; the grid's copy of the old records at a rebuild.
    constexpr std::uint64_t spin = spin_components(D), angle = D == 2 ? 1 : 0;
    const std::uint64_t pairs = static_cast<std::uint64_t>(r.max_pairs);
    m.model += n * real;
    m.state += (9 * spin + angle) * n * real + d * pairs * real + d * planes * n * real;  // ω, its 4-slot ring of ω and α
    m.workspace += (2 * spin + angle) * n * real + (3 * spin + 2 * angle) * n * real;  // trial; RK4 stages, sums
    m.workspace += spin * (n - static_cast<std::uint64_t>(r.split)) * real;  // part 0's cross buffer of α
    // abm4_events: the start of the remaining interval (a, ω, α, the 2D angle).
    if (desc.integrator == DemIntegrator::abm4_events) m.workspace += (d + 2 * spin + angle) * n * real;
    m.bytes_per_pair += d * real;
    if (r.broad_phase == BroadPhase::grid) m.workspace += pairs * (2 * index + d * real);
  }
  return m;
}

template DemMemory dem_memory<1>(const DemDesc<1>&);
template DemMemory dem_memory<2>(const DemDesc<2>&);
template DemMemory dem_memory<3>(const DemDesc<3>&);
template dem_detail::ResolvedSizes dem_detail::resolve_sizes<1>(const DemDesc<1>&);
template dem_detail::ResolvedSizes dem_detail::resolve_sizes<2>(const DemDesc<2>&);
template dem_detail::ResolvedSizes dem_detail::resolve_sizes<3>(const DemDesc<3>&);
template BuildResult dem_detail::memory_refusal<1>(const DemDesc<1>&, const DemMemory&, int, const char*, std::uint64_t, bool);
template BuildResult dem_detail::memory_refusal<2>(const DemDesc<2>&, const DemMemory&, int, const char*, std::uint64_t, bool);
template BuildResult dem_detail::memory_refusal<3>(const DemDesc<3>&, const DemMemory&, int, const char*, std::uint64_t, bool);

}  // namespace xfdem
