// A deterministic CLOCK_MONOTONIC for the real-time harness tests, preloaded
// into xfdem_rt (LD_PRELOAD=libxfdem_fake_clock.so): every read of
// CLOCK_MONOTONIC returns the fake time and then advances it by
// XFDEM_FAKE_TICK_NS nanoseconds (default 1000), and nanosleep advances it by
// the time asked for and returns at once. Other clocks are the real ones.
// Single-threaded programs only (one unsynchronised counter).
#include <dlfcn.h>
#include <time.h>

#include <cstdint>
#include <cstdlib>

namespace {

std::int64_t fake_now_ns = 1'000'000'000;  // an arbitrary origin, as CLOCK_MONOTONIC's

std::int64_t tick_ns() {
  static const std::int64_t tick = [] {
    const char* text = std::getenv("XFDEM_FAKE_TICK_NS");
    return text ? std::atoll(text) : 1000LL;
  }();
  return tick;
}

}  // namespace

extern "C" int clock_gettime(clockid_t id, struct timespec* ts) {
  if (id != CLOCK_MONOTONIC) {
    using Real = int (*)(clockid_t, struct timespec*);
    static const Real real = reinterpret_cast<Real>(dlsym(RTLD_NEXT, "clock_gettime"));
    return real(id, ts);
  }
  ts->tv_sec = static_cast<time_t>(fake_now_ns / 1'000'000'000);
  ts->tv_nsec = static_cast<long>(fake_now_ns % 1'000'000'000);
  fake_now_ns += tick_ns();
  return 0;
}

extern "C" int nanosleep(const struct timespec* request, struct timespec* remaining) {
  fake_now_ns += static_cast<std::int64_t>(request->tv_sec) * 1'000'000'000 + request->tv_nsec;
  if (remaining) {
    remaining->tv_sec = 0;
    remaining->tv_nsec = 0;
  }
  return 0;
}
