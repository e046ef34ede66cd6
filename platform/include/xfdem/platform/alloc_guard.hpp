// Global allocation counter for tests: proves that a step never touches the heap.
//
// Linking xfdem::alloc_guard replaces the global operator new/delete with
// versions that count every call (on every thread). Tests read the counter
// around a block of steps (AllocationCounter) and assert that it did not move.
// Cf. Eigen's EIGEN_RUNTIME_NO_MALLOC.
// ScopedAllocationLimit makes large allocations fail, as out of memory.
#pragma once
#include <cstddef>
#include <cstdint>

namespace xfdem::platform {

/// Number of calls to any global operator new since the program started.
std::uint64_t allocation_count() noexcept;
/// Number of calls to any global operator delete since the program started.
std::uint64_t deallocation_count() noexcept;

/// Counts allocations made while it is alive.
class AllocationCounter {
 public:
  AllocationCounter() noexcept : start_(allocation_count()) {}
  [[nodiscard]] std::uint64_t allocations() const noexcept { return allocation_count() - start_; }

 private:
  std::uint64_t start_;
};

/// While alive, every single allocation larger than `bytes` fails with
/// std::bad_alloc, as on a machine out of memory: for tests of what a build
/// does when the system refuses it. Not nestable.
class ScopedAllocationLimit {
 public:
  explicit ScopedAllocationLimit(std::size_t bytes) noexcept;
  ~ScopedAllocationLimit();
  ScopedAllocationLimit(const ScopedAllocationLimit&) = delete;
  ScopedAllocationLimit& operator=(const ScopedAllocationLimit&) = delete;
};

}  // namespace xfdem::platform
