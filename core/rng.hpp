// PCG32 (O'Neill 2014). Seeded from (pixel, sample, stream) so that every random number of a
// path depends on nothing but which path it is: images do not change with thread count.
#pragma once

#include <cstdint>

namespace pcrt {

// SplitMix64 finaliser: decorrelates consecutive seeds.
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed, uint64_t stream = 0) {
    inc_ = (mix64(stream) << 1u) | 1u;
    state_ = 0;
    next_u32();
    state_ += mix64(seed);
    next_u32();
  }
  static Rng for_sample(uint64_t seed, uint64_t pixel, uint64_t sample) {
    return Rng(mix64(seed ^ mix64(pixel)), sample);
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
  }
  // Uniform in [0, 1).
  float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
  double uniform_double() {
    const uint64_t hi = next_u32();
    const uint64_t lo = next_u32();
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
  }
  // Uniform integer in [0, n).
  uint32_t below(uint32_t n) {
    const uint64_t wide = static_cast<uint64_t>(next_u32()) * static_cast<uint64_t>(n);
    return static_cast<uint32_t>(wide >> 32u);
  }

 private:
  uint64_t state_;
  uint64_t inc_;
};

}  // namespace pcrt
