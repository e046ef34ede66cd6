// What the command line is doing, for the report of an allocation the system
// refused outside the kernel (which reports its own by key): main() catches
// std::bad_alloc and says "out of memory while <stage>", exit code 2.
#pragma once

namespace xfdem::cli {
inline const char* stage = "starting";
}  // namespace xfdem::cli
