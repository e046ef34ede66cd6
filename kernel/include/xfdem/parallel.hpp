// How the kernel uses more than one thread without owning any: the host
// installs a ParallelFor in the workspace (platform/'s TwoWorkerPool provides
// one), and the kernel hands it a task split into a fixed number of parts.
//
// Determinism: the split is decided by the model (by particle count, at build),
// never by the number of threads. Each part writes only its own particles or
// its own buffers, and parts are combined in part order, so one worker running
// the parts one after the other and two workers running them side by side give
// the same bits.
#pragma once
#include <type_traits>

namespace xfdem {

struct ParallelFor {
  /// Runs task(context, part) for every part in [0, parts) and returns when all
  /// are done. nullptr: the kernel runs the parts itself, in order.
  void (*run)(void* host, void (*task)(void* context, int part), void* context, int parts) = nullptr;
  void* host = nullptr;
};

/// Runs f(part) for part in [0, parts) through `parallel` (or in order).
template <class F>
void for_parts(const ParallelFor& parallel, int parts, F&& f) {
  if (parts <= 1 || parallel.run == nullptr) {
    for (int p = 0; p < parts; ++p) f(p);
    return;
  }
  using Fn = std::remove_reference_t<F>;
  parallel.run(
      parallel.host, [](void* context, int part) { (*static_cast<Fn*>(context))(part); }, &f, parts);
}

}  // namespace xfdem
