// What the operating system counts for this process: CPU seconds (all threads, user + system) and
// peak resident memory. The scale benchmark reports setup cost and bytes per point from them.
#pragma once

#include <sys/resource.h>

#include <cstddef>

namespace pcrt {

inline double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto secs = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return secs(u.ru_utime) + secs(u.ru_stime);
}

inline size_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return size_t(u.ru_maxrss) * 1024;  // Linux reports kilobytes
}

}  // namespace pcrt
