// The ray-disc test over W discs at once (W a template parameter: the lane type), with neither
// division nor libm call: a disc is a candidate when its plane crossing t = num / den lies in
// [t_lo, t_hi] (compared as num * sign(den) against t * |den|) and the crossing lies within the
// radius (|num d - den (c - o)|^2 <= r^2 den^2, the squared distance scaled by den^2). Every lane
// type evaluates exactly these IEEE operations in this order (no fused multiply-add), so the
// scalar and the 8-wide kernels accept the same discs bit for bit. Kept free of library headers:
// it is also compiled for AVX2 in a translation unit of its own.
#pragma once

#include <cstdint>

namespace pcrt {

// The leaf references' discs in structure-of-arrays layout (raw views; the storage is the
// method's, padded so that a full lane group may be read past the last reference).
struct DiscArrays {
  const float* cx;
  const float* cy;
  const float* cz;
  const float* nx;
  const float* ny;
  const float* nz;
  const float* r2;  // squared radius
};

struct DiscQuery {
  float o[3], d[3];
  float t_lo, t_hi;  // the candidate window, already widened by the caller
};

// One group of L::kWidth discs: a bit per lane that is a candidate.
template <class L>
inline uint32_t disc_group(const DiscQuery& q, L cx, L cy, L cz, L nx, L ny, L nz, L r2) {
  const L vx = cx - L(q.o[0]), vy = cy - L(q.o[1]), vz = cz - L(q.o[2]);
  const L dx(q.d[0]), dy(q.d[1]), dz(q.d[2]);
  const L num = (nx * vx + ny * vy) + nz * vz;
  const L den = (nx * dx + ny * dy) + nz * dz;
  const L qx = num * dx - den * vx, qy = num * dy - den * vy, qz = num * dz - den * vz;
  const L q2 = (qx * qx + qy * qy) + qz * qz;
  const L num_abs = flip_sign(num, den), den_abs = abs(den);
  // den = 0 gives t_hi * 0 = NaN (t_hi = inf) or num_abs = 0 > 0 fails: a parallel ray misses.
  return mask(le(q2, r2 * (den * den)) & le(L(q.t_lo) * den_abs, num_abs) &
              le(num_abs, L(q.t_hi) * den_abs) & gt(den_abs, L(0.0f)));
}

// Sets bit i of words[] (zeroed by the caller) for each candidate among the `count` discs from
// `first` on.
template <class L>
void disc_candidates(const DiscArrays& a, uint32_t first, uint32_t count, const DiscQuery& q,
                     uint64_t* words) {
  for (uint32_t g = 0; g < count; g += L::kWidth) {
    const uint32_t k = first + g;
    uint32_t m =
        disc_group<L>(q, L::load(a.cx + k), L::load(a.cy + k), L::load(a.cz + k), L::load(a.nx + k),
                      L::load(a.ny + k), L::load(a.nz + k), L::load(a.r2 + k));
    if (count - g < L::kWidth) m &= (1u << (count - g)) - 1;
    words[g / 64] |= uint64_t(m) << (g % 64);
  }
}

// The scalar lane (W = 1) and its comparison result.
struct Mask1 {
  bool b;
  friend Mask1 operator&(Mask1 x, Mask1 y) { return {x.b && y.b}; }
  friend uint32_t mask(Mask1 m) { return m.b ? 1u : 0u; }
};

struct Lane1 {
  static constexpr uint32_t kWidth = 1;
  float v;
  Lane1() = default;
  explicit Lane1(float x) : v(x) {}
  static Lane1 load(const float* p) { return Lane1(*p); }
  friend Lane1 operator+(Lane1 a, Lane1 b) { return Lane1(a.v + b.v); }
  friend Lane1 operator-(Lane1 a, Lane1 b) { return Lane1(a.v - b.v); }
  friend Lane1 operator*(Lane1 a, Lane1 b) { return Lane1(a.v * b.v); }
  // At den = +-0 and NaN the lane fails gt(den_abs, 0) whatever the sign, so these two need not
  // match the sign-bit versions of the wide lanes there.
  friend Lane1 flip_sign(Lane1 a, Lane1 s) { return Lane1(s.v < 0 ? -a.v : a.v); }
  friend Lane1 abs(Lane1 a) { return Lane1(a.v < 0 ? -a.v : a.v); }
  friend Mask1 le(Lane1 a, Lane1 b) { return {a.v <= b.v}; }
  friend Mask1 gt(Lane1 a, Lane1 b) { return {a.v > b.v}; }
};

using DiscKernel = void (*)(const DiscArrays& a, uint32_t first, uint32_t count, const DiscQuery& q,
                            uint64_t* words);
// The disc_candidates of the widest lane type this CPU runs (AVX2: 8 lanes), chosen once.
DiscKernel best_disc_kernel();
inline void disc_candidates_best(const DiscArrays& a, uint32_t first, uint32_t count,
                                 const DiscQuery& q, uint64_t* words) {
  best_disc_kernel()(a, first, count, q, words);
}
// "avx2x8" or "scalar": what disc_candidates_best runs on this machine (for results' context).
const char* disc_lanes_name();

}  // namespace pcrt
