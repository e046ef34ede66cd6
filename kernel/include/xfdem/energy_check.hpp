// The energy balance check a stepper runs on its own state (docs/stability.md,
// "Energy balance check"). A method that is stable for a linear system can still
// gain energy where the system is not linear (an interface that opens inside a
// step, an impact that the time step does not resolve) or where the state has
// left the method's range (a sliver cut's phantom mode). The check keeps the
// books E(t) ≤ E0 + W(t), with W the work done on the system from outside, and
// says StepStatus::energy_growth when a check finds the energy above them by
// more than `tolerance` times the largest energy in motion it has seen. What it
// detects is not removed: the state is what the method produced.
#pragma once
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "xfdem/status.hpp"

namespace xfdem {

/// How often, and how strictly, a stepper checks its energy balance.
struct EnergyCheck {
  /// Steps between checks (a check costs one energy evaluation: for a bar one
  /// banded product and a pass over its cells, for particles a pass over them,
  /// the planes and the listed pairs); 0: never checked (and the particles
  /// skip the O(n) book of their external forces' work).
  int interval = 16;
  /// Gain allowed before StepStatus::energy_growth, as a fraction of the
  /// largest energy in motion (kinetic and elastic) seen at a check. > 0.
  double tolerance = 0.05;
};

/// The books of the check. Part of the state, so a snapshot carries them.
struct EnergyLedger {
  double reference = 0;  ///< energy at the start (build, or the last restart), J
  double work = 0;       ///< work done on the system from outside since then, J
  double peak = 0;       ///< largest energy in motion at a check since then, J
  /// 1 from the first check that found the gain past the tolerance: every step
  /// after it says energy_growth, until the ledger is restarted.
  std::int32_t exceeded = 0;
};

/// Settings that switch the check off (a coupled model's halves: the coupled
/// check replaces theirs).
inline constexpr EnergyCheck kEnergyCheckOff{0, EnergyCheck{}.tolerance};

inline bool energy_check_due(const EnergyCheck& check, std::int64_t step) {
  return check.interval > 0 && step % check.interval == 0;
}

/// What a check weighs: the total the ledger's reference is comparable with,
/// its kinetic and elastic part, and the sum of the magnitudes the total was
/// summed from (its round-off floor: a potential energy's datum is arbitrary).
struct EnergyTotals {
  double total = 0, in_motion = 0, magnitude = 0;
};

/// One check: sets ledger.exceeded when the gain is past the tolerance.
inline void energy_check(EnergyLedger& ledger, const EnergyCheck& check, const EnergyTotals& now) {
  ledger.peak = std::max(ledger.peak, now.in_motion);
  const double allowed =
      check.tolerance * ledger.peak + 64.0 * DBL_EPSILON * (now.magnitude + std::fabs(ledger.work));
  // A NaN energy is not a gain: non_finite reports it.
  if (now.total - ledger.reference - ledger.work > allowed) ledger.exceeded = 1;
}

/// The start of new books at `now`.
inline void energy_restart(EnergyLedger& ledger, const EnergyTotals& now) {
  ledger = EnergyLedger{now.total, 0.0, now.in_motion, 0};
}

/// The build's validation of the settings; the message names the field.
inline BuildResult validate_energy_check(const EnergyCheck& check) {
  if (check.interval < 0)
    return BuildResult::failure(BuildResult::Code::invalid_argument,
                                "energy_check.interval: must be >= 0 steps (0: off), got %d", check.interval);
  if (!(std::isfinite(check.tolerance) && check.tolerance > 0.0))
    return BuildResult::failure(BuildResult::Code::invalid_argument,
                                "energy_check.tolerance: must be positive and finite (a fraction of the energy in "
                                "motion), got %g",
                                check.tolerance);
  return BuildResult::success();
}

}  // namespace xfdem
