#include "xfdem/status.hpp"

#include <cstring>

namespace xfdem {

const char* status_name(StepStatus flag) noexcept {
  switch (flag) {
    case StepStatus::ok: return "ok";
    case StepStatus::pair_capacity: return "pair_capacity";
    case StepStatus::neighbor_capacity: return "neighbor_capacity";
    case StepStatus::grid_capacity: return "grid_capacity";
    case StepStatus::non_finite: return "non_finite";
    case StepStatus::event_capacity: return "event_capacity";
    case StepStatus::coincident_centres: return "coincident_centres";
    case StepStatus::active_set_not_converged: return "active_set_not_converged";
    case StepStatus::not_built: return "not_built";
    case StepStatus::coupling_unstable: return "coupling_unstable";
    case StepStatus::unstable_time_step: return "unstable_time_step";
    case StepStatus::energy_growth: return "energy_growth";
  }
  return "unknown";
}

const char* describe(StepStatus set, char* buffer, int buffer_size) noexcept {
  if (buffer_size <= 0) return buffer;
  buffer[0] = '\0';
  if (set == StepStatus::ok) {
    std::snprintf(buffer, static_cast<std::size_t>(buffer_size), "ok");
    return buffer;
  }
  int used = 0;
  for (std::uint32_t bit = 1; bit != 0; bit <<= 1) {
    const auto flag = static_cast<StepStatus>(bit);
    if (!has(set, flag)) continue;
    const int written = std::snprintf(buffer + used, static_cast<std::size_t>(buffer_size - used), "%s%s",
                                      used > 0 ? "|" : "", status_name(flag));
    if (written < 0 || used + written >= buffer_size) break;
    used += written;
  }
  return buffer;
}

BuildResult BuildResult::failure(Code code, const char* format, ...) {
  BuildResult result;
  result.code = code;
  va_list args;
  va_start(args, format);
  std::vsnprintf(result.message, sizeof(result.message), format, args);
  va_end(args);
  return result;
}

}  // namespace xfdem
