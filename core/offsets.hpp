// Structures keep offsets into their reference arrays in 32 bits: at 3-4 references per point that
// is half the bytes of 64-bit offsets, and it suffices up to about 10^9 points. Beyond 2^32 - 1
// references a build stops with a one-line error instead of wrapping around silently.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/error.hpp"

namespace pcrt {

inline uint32_t offset32(size_t n, const char* structure) {
  if (n > size_t(UINT32_MAX))
    input_error(
        "{}: {} references exceed its 32-bit offsets (2^32 - 1); use fewer points or "
        "larger leaves",
        structure, n);
  return uint32_t(n);
}

}  // namespace pcrt
