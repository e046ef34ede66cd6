// Status codes. The kernel reports, it never throws or aborts: a build returns a
// BuildResult (with a message naming the offending field), a step returns a set
// of StepStatus flags. Each flag's comment says what the stepper did and which
// capacity to raise.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstdarg>

namespace xfdem {

/// Bit flags returned by every step. `ok` is no flag. Flags marked "step not
/// taken" leave the State exactly as it was before the call.
enum class StepStatus : std::uint32_t {
  ok = 0,
  /// The pair list needs more entries than Capacities::max_pairs. Step not taken.
  pair_capacity = 1u << 0,
  /// A particle has more candidate neighbours than Capacities::max_neighbors_per_particle.
  /// Step not taken.
  neighbor_capacity = 1u << 1,
  /// The particles' bounding box needs more broad-phase cells than
  /// Capacities::max_grid_cells (particles spread too far apart). Step not taken.
  grid_capacity = 1u << 2,
  /// A NaN or an infinity in the state the step started from, in its inputs, or
  /// produced by the step: reported by the step that meets it (what each
  /// stepper checks, and the one exception, a pair cache the step never reads:
  /// docs/dem.md, "Non-finite values"). The step was taken; the state holds the
  /// non-finite values for inspection, but for a value the step overwrites
  /// (the time, recomputed from the step count).
  non_finite = 1u << 3,
  /// More contact events inside one step than Capacities::max_events_per_step
  /// (abm4_events only). The step was completed without locating the rest.
  event_capacity = 1u << 4,
  /// Two particle centres coincide, so the contact normal is undefined; the
  /// first axis was used. The step was taken.
  coincident_centres = 1u << 5,
  /// Continuum: the unilateral interface's active-set iteration did not settle
  /// within its iteration bound. The step was taken with the last active set.
  active_set_not_converged = 1u << 6,
  /// The model failed to build; nothing can be stepped.
  not_built = 1u << 7,
  /// A coupled step left the region where the staggered scheme is stable.
  coupling_unstable = 1u << 8,
  /// The model's time step is past its stated stable limit (built with
  /// DemDesc::reject_unstable_dt or CoupledDesc::reject_unstable_coupling off):
  /// the step was taken, but the energy bounds of docs/stability.md no longer
  /// hold. Raised on every step of such a model.
  unstable_time_step = 1u << 9,
  /// The energy balance check (EnergyCheck, docs/stability.md) found the total
  /// energy above its start plus the work done on the system by more than the
  /// check's tolerance: the method gained energy it cannot have been given. The
  /// step was taken; raised at that check and on every step after it, until
  /// the ledger is restarted.
  energy_growth = 1u << 10,
};

constexpr StepStatus operator|(StepStatus a, StepStatus b) {
  return static_cast<StepStatus>(static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b));
}
constexpr StepStatus& operator|=(StepStatus& a, StepStatus b) { return a = a | b; }
constexpr StepStatus operator&(StepStatus a, StepStatus b) {
  return static_cast<StepStatus>(static_cast<std::uint32_t>(a) & static_cast<std::uint32_t>(b));
}
constexpr bool has(StepStatus set, StepStatus flag) { return (set & flag) != StepStatus::ok; }
/// `set` with `flags` cleared.
constexpr StepStatus without(StepStatus set, StepStatus flags) {
  return static_cast<StepStatus>(static_cast<std::uint32_t>(set) & ~static_cast<std::uint32_t>(flags));
}
/// Flags after which the state was left unchanged.
constexpr StepStatus kStepNotTaken =
    StepStatus::pair_capacity | StepStatus::neighbor_capacity | StepStatus::grid_capacity | StepStatus::not_built;

/// Name of one flag ("pair_capacity"), or "ok".
const char* status_name(StepStatus single_flag) noexcept;
/// Writes "flag1|flag2" into buffer (always NUL-terminated); returns buffer.
const char* describe(StepStatus set, char* buffer, int buffer_size) noexcept;

/// Outcome of building a model. `message` names the field at fault.
struct BuildResult {
  /// `memory`: the arrays the description asks for take more than its memory
  /// budget (checked before anything is allocated), or the allocator could not
  /// provide them; nothing is left allocated.
  enum class Code : std::uint8_t { ok, invalid_argument, unstable_time_step, capacity, memory };
  Code code = Code::ok;
  char message[320] = {};

  [[nodiscard]] bool ok() const { return code == Code::ok; }
  static BuildResult success() { return {}; }
  /// printf-style failure message.
  static BuildResult failure(Code code, const char* format, ...) __attribute__((format(printf, 2, 3)));
};

}  // namespace xfdem
