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

// Eight consecutive leaf references' discs in structure-of-arrays layout, one 224-byte block
// (28 bytes a disc): a leaf's discs are a run of such blocks, read front to back, not seven
// arrays far apart. Unused lanes hold zero discs (never candidates: den = 0). The point index is
// not stored: it is the leaf reference itself (or the method's prim array of it).
constexpr uint32_t kDiscGroup = 8;
struct alignas(32) DiscBlock {
  float cx[kDiscGroup], cy[kDiscGroup], cz[kDiscGroup];
  float nx[kDiscGroup], ny[kDiscGroup], nz[kDiscGroup];
  float r[kDiscGroup];  // radius (squared by the kernel as r * r, like the scalar test)
};

struct DiscQuery {
  float o[3], d[3];
  float t_lo, t_hi;       // the candidate window, already widened by the caller
  float r2_scale = 1.0f;  // on r^2: above 1, a prefilter for a test of its own (exact at 1)
};

// One group of L::kWidth discs: a bit per lane that is a candidate.
template <class L>
inline uint32_t disc_group(const DiscQuery& q, L cx, L cy, L cz, L nx, L ny, L nz, L r) {
  const L vx = cx - L(q.o[0]), vy = cy - L(q.o[1]), vz = cz - L(q.o[2]);
  const L dx(q.d[0]), dy(q.d[1]), dz(q.d[2]);
  // Summed as Eigen's 3-vector dot, x + (y + z): the floats of the exact projection that the
  // blend's weight is computed from (at grazing incidence t = num / den magnifies a last bit).
  const L num = nx * vx + (ny * vy + nz * vz);
  const L den = nx * dx + (ny * dy + nz * dz);
  const L qx = num * dx - den * vx, qy = num * dy - den * vy, qz = num * dz - den * vz;
  const L q2 = (qx * qx + qy * qy) + qz * qz;
  const L num_abs = flip_sign(num, den), den_abs = abs(den);
  // den = 0 gives t_hi * 0 = NaN (t_hi = inf) or num_abs = 0 > 0 fails: a parallel ray misses.
  return mask(le(q2, ((r * r) * (den * den)) * L(q.r2_scale)) & le(L(q.t_lo) * den_abs, num_abs) &
              le(num_abs, L(q.t_hi) * den_abs) & gt(den_abs, L(0.0f)));
}

// The candidate bits of block b's lanes (L::kWidth at a time).
template <class L>
uint32_t disc_block(const DiscQuery& q, const DiscBlock& b) {
  uint32_t m = 0;
  for (uint32_t j = 0; j < kDiscGroup; j += L::kWidth)
    m |= disc_group<L>(q, L::load(b.cx + j), L::load(b.cy + j), L::load(b.cz + j),
                       L::load(b.nx + j), L::load(b.ny + j), L::load(b.nz + j), L::load(b.r + j))
         << j;
  return m;
}

// Sets bit i of *word (zeroed by the caller) for each candidate among the count <= 64 discs at
// positions first, first + 1, ... of the blocks (position p: block p / 8, lane p % 8).
template <class L>
void disc_candidates(const DiscBlock* blocks, uint32_t first, uint32_t count, const DiscQuery& q,
                     uint64_t* word) {
  const uint32_t end = first + count;
  uint64_t bits = 0;
  for (uint32_t g = first / kDiscGroup; g * kDiscGroup < end; ++g) {
    const uint64_t m = disc_block<L>(q, blocks[g]);
    const uint32_t p = g * kDiscGroup;  // the block's first position
    bits |= p >= first ? m << (p - first) : m >> (first - p);
  }
  *word = count < 64 ? bits & ((uint64_t(1) << count) - 1) : bits;
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

using DiscKernel = void (*)(const DiscBlock* blocks, uint32_t first, uint32_t count,
                            const DiscQuery& q, uint64_t* word);
// The disc_candidates of the widest lane type this CPU runs (AVX2: 8 lanes), chosen once.
DiscKernel best_disc_kernel();
inline void disc_candidates_best(const DiscBlock* blocks, uint32_t first, uint32_t count,
                                 const DiscQuery& q, uint64_t* word) {
  best_disc_kernel()(blocks, first, count, q, word);
}
// "avx2x8" or "scalar": what disc_candidates_best runs on this machine (for results' context).
const char* disc_lanes_name();

}  // namespace pcrt
