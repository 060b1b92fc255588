#include "structures/wide_node.hpp"

#include <immintrin.h>

namespace pcrt {

uint32_t node_test_sse(const WideNode& n, const RaySlabs& r, float limit, float* t0s, float* t1s) {
  uint32_t mask = 0;
  for (int h = 0; h < kWideWidth; h += 4) {
    __m128 tn = _mm_set1_ps(r.tmin), tf = _mm_set1_ps(limit);
    for (int a = 0; a < 3; ++a) {
      const __m128 o = _mm_set1_ps(r.o[a]), inv = _mm_set1_ps(r.inv[a]);
      const __m128 lo = _mm_load_ps(n.lo[a] + h), hi = _mm_load_ps(n.hi[a] + h);
      const __m128 near = _mm_mul_ps(_mm_sub_ps(r.neg[a] ? hi : lo, o), inv);
      const __m128 far = _mm_mul_ps(_mm_sub_ps(r.neg[a] ? lo : hi, o), inv);
      tn = _mm_max_ps(near, tn);
      tf = _mm_min_ps(_mm_mul_ps(far, _mm_set1_ps(kWiden)), tf);
    }
    _mm_storeu_ps(t0s + h, tn);
    _mm_storeu_ps(t1s + h, tf);
    mask |= uint32_t(_mm_movemask_ps(_mm_cmple_ps(tn, tf))) << h;
  }
  return mask;
}

__attribute__((target("avx2"))) uint32_t node_test_avx2(const WideNode& n, const RaySlabs& r,
                                                        float limit, float* t0s, float* t1s) {
  __m256 tn = _mm256_set1_ps(r.tmin), tf = _mm256_set1_ps(limit);
  for (int a = 0; a < 3; ++a) {
    const __m256 o = _mm256_set1_ps(r.o[a]), inv = _mm256_set1_ps(r.inv[a]);
    const __m256 lo = _mm256_load_ps(n.lo[a]), hi = _mm256_load_ps(n.hi[a]);
    const __m256 near = _mm256_mul_ps(_mm256_sub_ps(r.neg[a] ? hi : lo, o), inv);
    const __m256 far = _mm256_mul_ps(_mm256_sub_ps(r.neg[a] ? lo : hi, o), inv);
    tn = _mm256_max_ps(near, tn);
    tf = _mm256_min_ps(_mm256_mul_ps(far, _mm256_set1_ps(kWiden)), tf);
  }
  _mm256_storeu_ps(t0s, tn);
  _mm256_storeu_ps(t1s, tf);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

bool wide_nodes_use_avx2() {
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2;
}

}  // namespace pcrt
