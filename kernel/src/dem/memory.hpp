// What build_dem() sizes, resolved from a description before anything is
// allocated: the broad phase, the split into parts, the capacities, and the
// refusal of a description whose arrays exceed its memory budget.
#pragma once
#include <cstddef>
#include <cstdint>

#include "xfdem/dem.hpp"

namespace xfdem::dem_detail {

/// The sizes build_dem() gives a description (capacities with the defaults filled in).
struct ResolvedSizes {
  BroadPhase broad_phase = BroadPhase::none;
  std::int32_t parts = 1, split = 0;
  std::int64_t max_pairs = 0;  ///< entries of the pair list (0 without pairs)
  std::int64_t max_cells = 0;  ///< cells of the grid (0 without a grid)
  std::int64_t max_neighbors = 0, max_events = 0;
};

template <int D>
ResolvedSizes resolve_sizes(const DemDesc<D>& desc);

/// Whether the contact law turns the particles: friction, rolling friction or
/// the hertz law (2D and 3D).
template <int D>
bool law_rotates(const DemDesc<D>& desc) {
  return D > 1 && (desc.friction > 0 || desc.rolling_friction > 0 || desc.law == ContactLaw::hertz);
}

/// Whether a particle is given a non-zero angular velocity (2D and 3D).
template <int D>
bool spins(const DemDesc<D>& desc) {
  for (const auto& p : desc.particles)
    for (double w : p.angular_velocity)
      if (w != 0.0) return true;
  return false;
}

/// Whether the model rotates (DemFeatures::rotation): its law turns the
/// particles, or a particle is given a spin, which it keeps (a frictionless
/// contact exerts no torque) and whose ½ I ω² the books count. A frictionless
/// model without spin keeps the plain step, bit for bit.
template <int D>
bool rotates(const DemDesc<D>& desc) {
  return law_rotates(desc) || (D > 1 && spins(desc));
}

/// Largest max_grid_cells an int32 cell index can count to (the grid keeps
/// cells + 1 offsets).
inline constexpr std::int64_t kMaxGridCells = 2147483646;

/// "9.6 GB": decimal units, three significant digits.
void format_bytes(double bytes, char* out, std::size_t size);
/// "632 m/s", "1.58 km/s".
void format_speed(double speed, char* out, std::size_t size);

/// The refusal of a description whose arrays, the state counted `states`
/// times, exceed `budget` (allocator_failed false), or that the allocator could
/// not provide (true). It names the capacity the description gave, or the
/// particle count, whose arrays take the most. `state_note` says where the
/// state's copies are (", in the state and ..."), or is empty.
template <int D>
BuildResult memory_refusal(const DemDesc<D>& desc, const DemMemory& memory, int states, const char* state_note,
                           std::uint64_t budget, bool allocator_failed);

}  // namespace xfdem::dem_detail
