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
