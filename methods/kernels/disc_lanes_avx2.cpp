// The 8-wide AVX2 lane type and the disc and projection kernels instantiated with it. This
// translation unit alone is compiled with -mavx2 (no -mfma: the kernel must round like the scalar
// lanes) and includes no library header with inline functions, so no AVX2 code can leak into the
// rest of the binary; it runs only where the CPU reports AVX2 (disc_lanes.cpp).
#include <immintrin.h>

#include "methods/kernels/disc_lanes.hpp"
#include "methods/kernels/projection_lanes.hpp"

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

// Records items[0..n) (n <= 8) as lanes: one 32-byte load per record (a record is 8 floats) and
// an 8 x 8 transpose, so that lane j of field k is record j's field k. Lanes past n repeat record
// items[0] (no branch per lane; projection_candidates masks them off).
void load_record_lanes(const float* records, const uint32_t* items, uint32_t n, Lane8* f) {
  __m256 r[8];
  for (uint32_t j = 0; j < 8; ++j)
    r[j] = _mm256_load_ps(records + uint64_t(items[j < n ? j : 0]) * kRecordFloats);
  __m256 t[8], s[8];
  for (uint32_t j = 0; j < 8; j += 2) {
    t[j] = _mm256_unpacklo_ps(r[j], r[j + 1]);
    t[j + 1] = _mm256_unpackhi_ps(r[j], r[j + 1]);
  }
  for (uint32_t j = 0; j < 8; j += 4) {
    s[j] = _mm256_shuffle_ps(t[j], t[j + 2], _MM_SHUFFLE(1, 0, 1, 0));
    s[j + 1] = _mm256_shuffle_ps(t[j], t[j + 2], _MM_SHUFFLE(3, 2, 3, 2));
    s[j + 2] = _mm256_shuffle_ps(t[j + 1], t[j + 3], _MM_SHUFFLE(1, 0, 1, 0));
    s[j + 3] = _mm256_shuffle_ps(t[j + 1], t[j + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  // s[k] holds field k of records 0-3 in its low half and field k + 4 in its high half (for
  // k < 4); s[k + 4] the same for records 4-7.
  for (uint32_t k = 0; k < 4; ++k) f[k] = Lane8(_mm256_permute2f128_ps(s[k], s[k + 4], 0x20));
  for (uint32_t k = 4; k < kRecordFields; ++k)
    f[k] = Lane8(_mm256_permute2f128_ps(s[k - 4], s[k], 0x31));
}

}  // namespace

void projection_candidates_avx2(const float* records, const uint32_t* items, uint32_t count,
                                const ProjectionQuery& q, uint64_t* word) {
  projection_candidates<Lane8>(records, items, count, q, word);
}

void disc_candidates_avx2(const DiscBlock* blocks, uint32_t first, uint32_t count,
                          const DiscQuery& q, uint64_t* word) {
  disc_candidates<Lane8>(blocks, first, count, q, word);
}

}  // namespace pcrt
