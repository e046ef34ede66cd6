// The machine's memory, for hosts that give the kernel a memory budget
// (DemDesc::max_memory_bytes, CoupledDesc::max_memory_bytes). The kernel asks
// the operating system nothing itself.
#pragma once
#include <cstdint>

namespace xfdem::platform {
/// Bytes of physical memory (RAM) of this machine, 0 when the system does not say.
std::uint64_t physical_memory_bytes() noexcept;
}  // namespace xfdem::platform
