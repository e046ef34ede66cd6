#include "xfdem/version.hpp"

namespace xfdem {
const char* version_string() noexcept { return "0.1.0"; }
}  // namespace xfdem
