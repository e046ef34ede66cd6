#include "xfdem/platform/clock.hpp"

#include <chrono>

namespace xfdem::platform {
std::int64_t monotonic_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace xfdem::platform
