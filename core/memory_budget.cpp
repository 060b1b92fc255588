#include "core/memory_budget.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace pcrt {
namespace {

// A "Key:   value kB" line of a /proc file, in bytes; `fallback` when absent.
size_t proc_kb_field(const char* file, const std::string& key, size_t fallback) {
  std::ifstream in(file);
  const std::string prefix = key + ":";
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) return size_t(std::stoull(line.substr(prefix.size()))) * 1024;
  return fallback;
}

}  // namespace

size_t available_memory_bytes() {
  constexpr size_t kUnknown = std::numeric_limits<size_t>::max();
  size_t available = proc_kb_field("/proc/meminfo", "MemAvailable", kUnknown);
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const size_t used = proc_kb_field("/proc/self/status", "VmSize", 0);
    available = std::min(available, as.rlim_cur > used ? size_t(as.rlim_cur - used) : 0);
  }
  return available;
}

void require_memory(size_t bytes, const std::string& what) {
  const size_t available = available_memory_bytes();
  if (bytes <= available) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  input_error(
      "out of memory: {} is too large for this machine: about {:.2f} GiB needed (estimate), "
      "{:.2f} GiB available",
      what, double(bytes) / kGiB, double(available) / kGiB);
}

}  // namespace pcrt
