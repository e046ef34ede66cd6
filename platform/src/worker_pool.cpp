#include "xfdem/platform/worker_pool.hpp"

#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>

namespace xfdem::platform {
namespace {
inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

static_assert(sizeof(std::atomic<unsigned>) == sizeof(int), "the futex word is the atomic itself");

/// Sleeps while `word` still holds `seen`: registers in `sleepers` first, so
/// that a notifier that stores after this check also sees the registration
/// and wakes it. The sleep is bounded (1 ms), so that even a wake-up the
/// kernel never delivers costs a millisecond, not a hang.
void sleep_while(std::atomic<unsigned>& word, unsigned seen, std::atomic<int>& sleepers) {
  sleepers.fetch_add(1, std::memory_order_seq_cst);
  if (word.load(std::memory_order_seq_cst) == seen) {
    timespec limit{0, 1'000'000};
    syscall(SYS_futex, reinterpret_cast<int*>(&word), FUTEX_WAIT_PRIVATE, static_cast<int>(seen), &limit, nullptr, 0);
  }
  sleepers.fetch_sub(1, std::memory_order_seq_cst);
}

/// Wakes a thread asleep on `word` (the store to it came before, sequentially consistent).
void wake(std::atomic<unsigned>& word, std::atomic<int>& sleepers) {
  if (sleepers.load(std::memory_order_seq_cst) > 0)
    syscall(SYS_futex, reinterpret_cast<int*>(&word), FUTEX_WAKE_PRIVATE, 1, nullptr, nullptr, 0);
}
}  // namespace

// Spinning before sleeping: a step's phases follow each other within
// microseconds, so a waiting thread usually sees the next task while spinning.
TwoWorkerPool::TwoWorkerPool(int pin_to_core, int spins) : spins_(spins), worker_([this] { worker_loop(); }) {
  if (pin_to_core >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<unsigned>(pin_to_core), &set);
    pthread_setaffinity_np(worker_.native_handle(), sizeof(set), &set);
  }
}

TwoWorkerPool::~TwoWorkerPool() {
  stop_.store(true, std::memory_order_release);
  posted_.fetch_add(1, std::memory_order_seq_cst);
  wake(posted_, posted_sleepers_);
  worker_.join();
}

void TwoWorkerPool::dispatch(void* host, void (*task)(void*, int), void* context, int parts) {
  auto* pool = static_cast<TwoWorkerPool*>(host);
  pool->task_ = task;
  pool->context_ = context;
  pool->parts_ = parts;
  const unsigned generation = pool->posted_.fetch_add(1, std::memory_order_seq_cst) + 1;
  wake(pool->posted_, pool->posted_sleepers_);
  // The caller takes part 0 and every part past 1, in order.
  task(context, 0);
  for (int p = 2; p < parts; ++p) task(context, p);
  for (int spin = 0;; ++spin) {
    const unsigned done = pool->finished_.load(std::memory_order_acquire);
    if (done == generation) break;
    if (spin < pool->spins_) {
      relax();
    } else {
      // Sleep only while the value is still the one just seen to differ.
      sleep_while(pool->finished_, done, pool->finished_sleepers_);
    }
  }
}

void TwoWorkerPool::worker_loop() {
  unsigned seen = 0;
  for (;;) {
    unsigned now = posted_.load(std::memory_order_acquire);
    for (int spin = 0; now == seen; ++spin) {
      if (spin < spins_) {
        relax();
      } else {
        sleep_while(posted_, seen, posted_sleepers_);
      }
      now = posted_.load(std::memory_order_acquire);
    }
    seen = now;
    if (stop_.load(std::memory_order_acquire)) return;
    if (parts_ > 1) task_(context_, 1);
    finished_.store(seen, std::memory_order_seq_cst);
    wake(finished_, finished_sleepers_);
  }
}

}  // namespace xfdem::platform
