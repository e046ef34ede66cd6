// XFDEM_UNDER_ASAN: defined when the test is built with AddressSanitizer (GCC
// says so with __SANITIZE_ADDRESS__, clang with __has_feature), for the tests
// whose limits or timings the sanitizer changes.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define XFDEM_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define XFDEM_UNDER_ASAN 1
#endif
#endif

namespace xfdem::test {
/// Under the sanitizer the heaviest accuracy sweeps run a shorter share of
/// their loops (fewer trials, fewer steps, the coarser of two meshes): the
/// sanitizer checks memory, which the first cases reach as the rest do, and
/// the release build runs every sweep whole.
#ifdef XFDEM_UNDER_ASAN
inline constexpr bool kUnderAsan = true;
#else
inline constexpr bool kUnderAsan = false;
#endif
}  // namespace xfdem::test
