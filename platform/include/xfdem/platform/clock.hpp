// Monotonic clock for the tools and benchmarks. The kernel never reads a clock:
// the host passes time in (see docs/architecture.md).
#pragma once
#include <cstdint>

namespace xfdem::platform {
/// Nanoseconds from an arbitrary fixed origin, monotonic.
std::int64_t monotonic_ns() noexcept;
}  // namespace xfdem::platform
