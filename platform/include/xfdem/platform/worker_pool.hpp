// A pool of two workers for the kernel's ParallelFor: the calling thread runs
// part 0, one background thread (created once, optionally pinned to a core)
// runs part 1. Handing over a task is two atomic stores and a wait on an
// atomic: no allocation and no mutex per call. A waiting thread spins
// briefly, then sleeps on the atomic (futex, at most a millisecond at a time)
// until the next task or its end.
#pragma once
#include <atomic>
#include <thread>

#include "xfdem/parallel.hpp"

namespace xfdem::platform {

class TwoWorkerPool {
 public:
  /// pin_to_core >= 0 pins the background worker to that core (and the caller
  /// is left alone); -1 does not pin. `spins`: how long a waiting thread spins
  /// (pause instructions) before it sleeps on the atomic. Long spins suit
  /// dedicated cores (a real-time loop); short ones a shared machine, where a
  /// spinning thread would take the core from the one it waits for.
  explicit TwoWorkerPool(int pin_to_core = -1, int spins = 2000);
  ~TwoWorkerPool();
  TwoWorkerPool(const TwoWorkerPool&) = delete;
  TwoWorkerPool& operator=(const TwoWorkerPool&) = delete;

  /// The hook to install in a kernel workspace.
  ParallelFor parallel_for() { return {&TwoWorkerPool::dispatch, this}; }

 private:
  static void dispatch(void* host, void (*task)(void*, int), void* context, int parts);
  void worker_loop();

  void (*task_)(void*, int) = nullptr;
  void* context_ = nullptr;
  int parts_ = 0;
  std::atomic<unsigned> posted_{0};    // generation of the last task handed over
  std::atomic<unsigned> finished_{0};  // generation the worker last completed
  std::atomic<bool> stop_{false};
  // Threads asleep on posted_ / finished_: a notifier calls the kernel only
  // when one is (the store and this count's load are both sequentially
  // consistent, so a sleeper that missed the store is seen).
  std::atomic<int> posted_sleepers_{0};
  std::atomic<int> finished_sleepers_{0};
  int spins_;
  std::thread worker_;
};

}  // namespace xfdem::platform
