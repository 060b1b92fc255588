// Offsets into reference arrays. The structures that duplicate references (kd-tree, octree,
// grid) can hold more than 2^32 of them: at 3-4 references per point that happens above about
// 1.15x10^9 points. They keep 32-bit offsets while the count fits (half the bytes of 64-bit ones)
// and switch to 64 bits beyond: the grid knows its count before it stores anything and picks its
// offset type then; the octree builds with 32-bit leaf offsets and, on overflow, again with 64-bit
// ones; the kd-tree's leaves hold 64-bit offsets in the bytes an inner node uses for its plane.
// Point indices stay 32-bit (at most 2^32 - 1 points, morton_order refuses more), and so do node
// indices (a tree has fewer nodes than references; node_index32 refuses more).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/error.hpp"

namespace pcrt {

// The largest count kept in 32-bit offsets: 2^32 - 1, lowered only by NarrowOffsetLimit (tests), so
// that the 64-bit layouts can be exercised on small inputs.
inline uint64_t& narrow_offset_limit() {
  static uint64_t limit = UINT32_MAX;
  return limit;
}
inline bool fits_narrow_offset(uint64_t n) { return n <= narrow_offset_limit(); }

// Lowers narrow_offset_limit for its lifetime (tests only; not thread-safe against a build).
class NarrowOffsetLimit {
 public:
  explicit NarrowOffsetLimit(uint64_t limit) : saved_(narrow_offset_limit()) {
    narrow_offset_limit() = limit;
  }
  ~NarrowOffsetLimit() { narrow_offset_limit() = saved_; }
  NarrowOffsetLimit(const NarrowOffsetLimit&) = delete;
  NarrowOffsetLimit& operator=(const NarrowOffsetLimit&) = delete;

 private:
  uint64_t saved_;
};

// A 32-bit offset where a layout has no 64-bit form (hubo_2006's quantized kd-tree): beyond
// 2^32 - 1 a build stops with a one-line error instead of wrapping around silently.
inline uint32_t offset32(size_t n, const char* structure) {
  if (n > size_t(UINT32_MAX))
    input_error(
        "{}: {} references exceed its 32-bit offsets (2^32 - 1); use fewer points or "
        "larger leaves",
        structure, n);
  return uint32_t(n);
}

// A node index (32 bits in every tree).
inline uint32_t node_index32(size_t n, const char* structure) {
  if (n > size_t(UINT32_MAX))
    input_error("{}: {} nodes exceed its 32-bit node indices (2^32 - 1); use larger leaves",
                structure, n);
  return uint32_t(n);
}

}  // namespace pcrt
