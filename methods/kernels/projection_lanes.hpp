// The prefilter of point projection (thesis 5.5.2, methods/kernels/ray_projection.hpp) over W
// points at once (W the lane type's width, as in disc_lanes.hpp), with neither division nor libm
// call: a point is a candidate when the ray crosses its tangent plane at t >= t_lo, and the
// crossing x lies within the point's radius r of it (|x - c|^2 <= r^2, scaled by r2_scale > 1 as
// a margin). The crossing is never divided out: with num = n.(c - o), den = n.d, it is tested as
// |num d - den (c - o)|^2 <= r^2 den^2 and num sign(den) >= t_lo |den|.
//
// num and den are summed in the order of Eigen's dot product of two 3-vectors, x + (y + z) (its
// unrolled reduction splits 3 as 1 + 2), so that they are the exact projection's own floats bit
// for bit: where the ray grazes the plane (den small) t = num / den magnifies any difference in
// num, and no margin on the radius could cover it. What remains differs from the exact test by a
// few roundings of the ray's and the point's coordinates, not by den (see projection_query).
// Every lane type evaluates exactly these IEEE operations (no fused multiply-add), so the scalar
// and the 8-wide kernels accept the same points. Free of library headers: it is also compiled
// for AVX2 in a translation unit of its own (disc_lanes_avx2.cpp).
#pragma once

#include <cstdint>

#include "methods/kernels/disc_lanes.hpp"

namespace pcrt {

// A point record as the lanes read it: PackedSplat's layout (c.x, c.y, c.z, r, n.x, n.y, n.z,
// index), 8 floats, 32-byte aligned (ray_projection.hpp checks that the two agree).
constexpr uint32_t kRecordFloats = 8;
enum RecordField : uint32_t { kCx, kCy, kCz, kR, kNx, kNy, kNz, kRecordFields };

struct ProjectionQuery {
  float o[3], d[3];
  float t_lo;             // the lowest crossing kept, already widened by the caller
  float r2_scale = 1.0f;  // on r^2: the prefilter's margin over the exact test's radius
};

// num = n.(c - o) and den = n.d in the exact projection's order (see above).
template <class L>
inline void plane_crossing(const ProjectionQuery& q, L vx, L vy, L vz, L nx, L ny, L nz, L& num,
                           L& den) {
  num = nx * vx + (ny * vy + nz * vz);
  den = nx * L(q.d[0]) + (ny * L(q.d[1]) + nz * L(q.d[2]));
}

// One group of L::kWidth points (f: their record fields, RecordField order): a bit per lane that
// is a candidate. den = 0 (a ray parallel to the plane, or a zero lane) is none: the exact
// projection rejects it too.
template <class L>
inline uint32_t projection_group(const ProjectionQuery& q, const L* f) {
  const L vx = f[kCx] - L(q.o[0]), vy = f[kCy] - L(q.o[1]), vz = f[kCz] - L(q.o[2]);
  L num, den;
  plane_crossing<L>(q, vx, vy, vz, f[kNx], f[kNy], f[kNz], num, den);
  const L qx = num * L(q.d[0]) - den * vx, qy = num * L(q.d[1]) - den * vy,
          qz = num * L(q.d[2]) - den * vz;
  const L q2 = qx * qx + (qy * qy + qz * qz);
  const L num_abs = flip_sign(num, den), den_abs = abs(den);
  return mask(le(q2, ((f[kR] * f[kR]) * (den * den)) * L(q.r2_scale)) &
              le(L(q.t_lo) * den_abs, num_abs) & gt(den_abs, L(0.0f)));
}

// The scalar lanes' record load: the fields of record items[0] (n is 1 here).
inline void load_record_lanes(const float* records, const uint32_t* items, uint32_t /*n*/,
                              Lane1* f) {
  const float* r = records + uint64_t(items[0]) * kRecordFloats;
  for (uint32_t k = 0; k < kRecordFields; ++k) f[k] = Lane1(r[k]);
}

// Sets bit i of *word for each candidate among the count <= 64 records items[0..count) of
// `records` (lanes past count, whatever a lane type loads there, are masked off).
template <class L>
void projection_candidates(const float* records, const uint32_t* items, uint32_t count,
                           const ProjectionQuery& q, uint64_t* word) {
  uint64_t bits = 0;
  for (uint32_t i = 0; i < count; i += L::kWidth) {
    L f[kRecordFields];
    const uint32_t n = count - i < L::kWidth ? count - i : L::kWidth;
    load_record_lanes(records, items + i, n, f);
    bits |= uint64_t(projection_group<L>(q, f)) << i;
  }
  *word = count < 64 ? bits & ((uint64_t(1) << count) - 1) : bits;
}

using ProjectionKernel = void (*)(const float* records, const uint32_t* items, uint32_t count,
                                  const ProjectionQuery& q, uint64_t* word);
// The projection_candidates of the lane type disc_lanes_name() names, chosen once.
ProjectionKernel best_projection_kernel();

}  // namespace pcrt
