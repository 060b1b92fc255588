// Refusing work that will not fit before doing it: a cloud too large for the machine is a one-line
// error with the estimate, not a process the operating system kills halfway through a build.
#pragma once

#include <cstddef>
#include <string>

namespace pcrt {

// What this process may still allocate: the smaller of the system's available memory
// (MemAvailable in /proc/meminfo) and the room left under the address-space limit (ulimit -v).
size_t available_memory_bytes();

// Throws InputError "out of memory: WHAT is too large for this machine: about X GiB needed
// (estimate), Y GiB available" when `bytes` exceeds available_memory_bytes().
void require_memory(size_t bytes, const std::string& what);

}  // namespace pcrt
