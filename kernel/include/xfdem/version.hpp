// Library version and the build fingerprint that snapshots carry.
#pragma once
#include <cstdint>

namespace xfdem {
inline constexpr int kVersionMajor = 0;
inline constexpr int kVersionMinor = 1;
inline constexpr int kVersionPatch = 0;
/// "0.1.0"
const char* version_string() noexcept;
}  // namespace xfdem
