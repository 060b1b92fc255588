// The k-buffer of 3D Gaussian Ray Tracing's march (methods/grt_2024, methods/ever_2024): the k
// nearest entries of one walk beyond the last one processed, sorted. Once full, its k-th entry
// bounds the walk, so later leaves and proxies are tested on a shorter segment.
#pragma once

#include <algorithm>
#include <array>

namespace pcrt {

// Entry: `before(o)`, a strict total order that does not depend on the walk (ties broken by the
// particle), and `same(o)`, the same entry met again from another leaf.
template <class Entry, int kMax>
struct KBuffer {
  std::array<Entry, size_t(kMax)> entries;
  int k = 0, n = 0;
  Entry after{};  // the last entry processed; only later ones are inserted
  bool has_after = false;

  [[nodiscard]] bool full() const { return n == k; }
  [[nodiscard]] const Entry& last() const { return entries[size_t(n - 1)]; }
  // Inserts e unless it is processed already, is in the buffer or lies beyond a full buffer's k-th.
  bool insert(const Entry& e) {
    if (has_after && !after.before(e)) return false;
    if (full() && !e.before(last())) return false;
    int pos = n;
    while (pos > 0 && e.before(entries[size_t(pos - 1)])) --pos;
    if (pos > 0 && entries[size_t(pos - 1)].same(e)) return false;
    const int end = full() ? n - 1 : n;
    for (int i = end; i > pos; --i) entries[size_t(i)] = entries[size_t(i - 1)];
    entries[size_t(pos)] = e;
    n = std::min(n + 1, k);
    return true;
  }
  // Starts the next walk after the last entry of this one.
  void restart() {
    after = last();
    has_after = true;
    n = 0;
  }
};

}  // namespace pcrt
