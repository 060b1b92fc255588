// The 8-wide AVX2 lane type and the disc kernel instantiated with it. This translation unit alone
// is compiled with -mavx2 (no -mfma: the kernel must round like the scalar lanes) and includes
// no library header with inline functions, so no AVX2 code can leak into the rest of the binary;
// it runs only where the CPU reports AVX2 (disc_lanes.cpp).
#include <immintrin.h>

#include "methods/kernels/disc_lanes.hpp"

namespace pcrt {
namespace {

struct Lane8 {
  static constexpr uint32_t kWidth = 8;
  __m256 v;
  Lane8() = default;
  explicit Lane8(float x) : v(_mm256_set1_ps(x)) {}
  explicit Lane8(__m256 x) : v(x) {}
  static Lane8 load(const float* p) { return Lane8(_mm256_load_ps(p)); }
  friend Lane8 operator+(Lane8 a, Lane8 b) { return Lane8(_mm256_add_ps(a.v, b.v)); }
  friend Lane8 operator-(Lane8 a, Lane8 b) { return Lane8(_mm256_sub_ps(a.v, b.v)); }
  friend Lane8 operator*(Lane8 a, Lane8 b) { return Lane8(_mm256_mul_ps(a.v, b.v)); }
  friend Lane8 flip_sign(Lane8 a, Lane8 s) {
    return Lane8(_mm256_xor_ps(a.v, _mm256_and_ps(s.v, _mm256_set1_ps(-0.0f))));
  }
  friend Lane8 abs(Lane8 a) { return Lane8(_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)); }
  friend Lane8 le(Lane8 a, Lane8 b) { return Lane8(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
  friend Lane8 gt(Lane8 a, Lane8 b) { return Lane8(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)); }
  friend Lane8 operator&(Lane8 a, Lane8 b) { return Lane8(_mm256_and_ps(a.v, b.v)); }
  friend uint32_t mask(Lane8 m) { return uint32_t(_mm256_movemask_ps(m.v)); }
};

}  // namespace

void disc_candidates_avx2(const DiscBlock* blocks, uint32_t first, uint32_t count,
                          const DiscQuery& q, uint64_t* word) {
  disc_candidates<Lane8>(blocks, first, count, q, word);
}

}  // namespace pcrt
