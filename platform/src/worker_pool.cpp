#include "xfdem/platform/worker_pool.hpp"

#include <pthread.h>
#include <sched.h>

namespace xfdem::platform {
namespace {
inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
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
  posted_.fetch_add(1, std::memory_order_release);
  posted_.notify_one();
  worker_.join();
}

void TwoWorkerPool::dispatch(void* host, void (*task)(void*, int), void* context, int parts) {
  auto* pool = static_cast<TwoWorkerPool*>(host);
  pool->task_ = task;
  pool->context_ = context;
  pool->parts_ = parts;
  const unsigned generation = pool->posted_.fetch_add(1, std::memory_order_acq_rel) + 1;
  pool->posted_.notify_one();
  // The caller takes part 0 and every part past 1, in order.
  task(context, 0);
  for (int p = 2; p < parts; ++p) task(context, p);
  for (int spin = 0;; ++spin) {
    const unsigned done = pool->finished_.load(std::memory_order_acquire);
    if (done == generation) break;
    if (spin < pool->spins_) {
      relax();
    } else {
      // Sleep only while the value is still the one just seen to differ: a
      // fresh load here could already be `generation`, and waiting on that
      // would miss the worker's one notification.
      pool->finished_.wait(done, std::memory_order_acquire);
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
        posted_.wait(seen, std::memory_order_acquire);
      }
      now = posted_.load(std::memory_order_acquire);
    }
    seen = now;
    if (stop_.load(std::memory_order_acquire)) return;
    if (parts_ > 1) task_(context_, 1);
    finished_.store(seen, std::memory_order_release);
    finished_.notify_one();
  }
}

}  // namespace xfdem::platform
