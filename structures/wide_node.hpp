// 8-wide BVH nodes (Embree's BVH8) shared by the point bvh and the triangle BVH: a binary tree
// collapsed into nodes of up to eight children whose boxes are tested at once (AVX2 where the CPU
// has it, chosen once, else two SSE halves with the same IEEE operations per lane, so both hit the
// same children bit for bit).
#pragma once

#include <immintrin.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/aabb.hpp"
#include "core/geometry.hpp"

namespace pcrt {

constexpr int kWideWidth = 8;

// Eight children's boxes in structure-of-arrays layout (lo[axis][child]); 256 bytes, four cache
// lines.
struct alignas(64) WideNode {
  float lo[3][kWideWidth];
  float hi[3][kWideWidth];
  uint32_t child[kWideWidth] = {};  // inner child: wide node index; leaf child: its first item
  uint32_t count[kWideWidth] = {};  // leaf child: items (> 0); inner child or empty slot: 0
};

// What a ray needs for the slab test (once per ray). near_at[a] and far_at[a]: where a WideNode's
// entry and exit planes of axis a start among its floats (lo[a] or hi[a] by the sign of d[a]), so
// that the node test loads them without a branch per axis (Embree's nearX/farX offsets).
struct RaySlabs {
  float o[3], inv[3];
  bool neg[3];
  float tmin;
  uint32_t near_at[3], far_at[3];
  RaySlabs() = default;
  explicit RaySlabs(const Ray& ray) : tmin(ray.tmin) {
    for (int a = 0; a < 3; ++a) {
      o[a] = ray.o[a];
      inv[a] = 1.0f / ray.d[a];
      neg[a] = inv[a] < 0;
      const auto lo = uint32_t(a * kWideWidth), hi = uint32_t((3 + a) * kWideWidth);
      near_at[a] = neg[a] ? hi : lo;
      far_at[a] = neg[a] ? lo : hi;
    }
  }
};

// The floats of a node's boxes, lo[3][8] then hi[3][8], as RaySlabs::near_at indexes them.
inline const float* node_planes(const WideNode& n) { return &n.lo[0][0]; }
static_assert(offsetof(WideNode, hi) == 3 * kWideWidth * sizeof(float));

// 1 + 2 gamma(3) (pbrt-v4, section 6.8.2): (plane - o) * inv is within gamma(3) of the exact
// (plane - o) / d, so an exit t scaled by this is never below the exact one, and an entry t
// compared with a limit scaled by it never culls a box the exact test keeps.
constexpr float kWiden = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// The slab test of a node's eight boxes against [slabs.tmin, limit]: a bit per child hit, and each
// child's entry and exit t in t0s, t1s (t = (plane - o) * inv, near and far planes chosen by the
// sign of each direction component; the exit widened by kWiden; NaN, 0 * inf, keeps the interval).
// Axis a of the slab test on four boxes [lo, hi]: narrows their entry tn and exit tf (the exit
// widened by kWiden). Shared by the bvh's SSE node test and the octree's child test.
inline void slab_planes_sse(__m128 near_plane, __m128 far_plane, const RaySlabs& r, int a,
                            __m128& tn, __m128& tf) {
  const __m128 o = _mm_set1_ps(r.o[a]), inv = _mm_set1_ps(r.inv[a]);
  const __m128 near = _mm_mul_ps(_mm_sub_ps(near_plane, o), inv);
  const __m128 far = _mm_mul_ps(_mm_sub_ps(far_plane, o), inv);
  tn = _mm_max_ps(near, tn);
  tf = _mm_min_ps(_mm_mul_ps(far, _mm_set1_ps(kWiden)), tf);
}
inline void slab_axis_sse(__m128 lo, __m128 hi, const RaySlabs& r, int a, __m128& tn, __m128& tf) {
  slab_planes_sse(r.neg[a] ? hi : lo, r.neg[a] ? lo : hi, r, a, tn, tf);
}

inline uint32_t node_test_sse(const WideNode& n, const RaySlabs& r, float limit, float* t0s,
                              float* t1s) {
  uint32_t mask = 0;
  for (int h = 0; h < kWideWidth; h += 4) {
    __m128 tn = _mm_set1_ps(r.tmin), tf = _mm_set1_ps(limit);
    for (int a = 0; a < 3; ++a)
      slab_axis_sse(_mm_load_ps(n.lo[a] + h), _mm_load_ps(n.hi[a] + h), r, a, tn, tf);
    _mm_storeu_ps(t0s + h, tn);
    _mm_storeu_ps(t1s + h, tf);
    mask |= uint32_t(_mm_movemask_ps(_mm_cmple_ps(tn, tf))) << h;
  }
  return mask;
}

// slab_axis_sse on eight boxes (the same operations per lane). Shared by the bvh's AVX2 node test
// and the octree's AVX2 child test.
__attribute__((target("avx2"))) inline void slab_planes_avx2(__m256 near_plane, __m256 far_plane,
                                                             const RaySlabs& r, int a, __m256& tn,
                                                             __m256& tf) {
  const __m256 o = _mm256_set1_ps(r.o[a]), inv = _mm256_set1_ps(r.inv[a]);
  const __m256 near = _mm256_mul_ps(_mm256_sub_ps(near_plane, o), inv);
  const __m256 far = _mm256_mul_ps(_mm256_sub_ps(far_plane, o), inv);
  tn = _mm256_max_ps(near, tn);
  tf = _mm256_min_ps(_mm256_mul_ps(far, _mm256_set1_ps(kWiden)), tf);
}
__attribute__((target("avx2"))) inline void slab_axis_avx2(__m256 lo, __m256 hi, const RaySlabs& r,
                                                           int a, __m256& tn, __m256& tf) {
  slab_planes_avx2(r.neg[a] ? hi : lo, r.neg[a] ? lo : hi, r, a, tn, tf);
}
__attribute__((target("avx2"))) inline uint32_t node_test_avx2(const WideNode& n, const RaySlabs& r,
                                                               float limit, float* t0s,
                                                               float* t1s) {
  __m256 tn = _mm256_set1_ps(r.tmin), tf = _mm256_set1_ps(limit);
  for (int a = 0; a < 3; ++a)
    slab_axis_avx2(_mm256_load_ps(n.lo[a]), _mm256_load_ps(n.hi[a]), r, a, tn, tf);
  _mm256_storeu_ps(t0s, tn);
  _mm256_storeu_ps(t1s, tf);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// node_test_avx2 with each axis's planes loaded at the ray's offsets (RaySlabs::near_at), not
// chosen by a branch per axis and node: the same planes, so the same children and t bit for bit.
// Which is faster depends on the walk (one AVX2 EPYC, alternated runs, results/anchor/tri_planes):
// the triangle BVH's bounce rays gain (their directions change from ray to ray, so the branches
// mispredict), while the point bvh's coherent shadow rays lost about 5% (a load address to compute
// where a predicted branch cost nothing), so only the triangle BVH uses this one.
__attribute__((target("avx2"))) inline uint32_t node_test_avx2_offsets(const WideNode& n,
                                                                       const RaySlabs& r,
                                                                       float limit, float* t0s,
                                                                       float* t1s) {
  __m256 tn = _mm256_set1_ps(r.tmin), tf = _mm256_set1_ps(limit);
  for (int a = 0; a < 3; ++a)
    slab_planes_avx2(_mm256_load_ps(node_planes(n) + r.near_at[a]),
                     _mm256_load_ps(node_planes(n) + r.far_at[a]), r, a, tn, tf);
  _mm256_storeu_ps(t0s, tn);
  _mm256_storeu_ps(t1s, tf);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// The octree's child test: the slab test of the eight octants of the cube at `lo` (octants of
// side `half`; octant c starts half further along axis a where bit a of c is set) against
// [r.tmin, limit]: a bit per octant hit, entry and exit t in t0s, t1s (aligned to 32 bytes). NaN
// (0 * inf) keeps the interval. Two SSE halves, or one AVX2 pass with the same operations per
// lane, so both hit the same octants with the same t bit for bit.
alignas(32) inline constexpr float kOctantBit[3][8] = {
    {0, 1, 0, 1, 0, 1, 0, 1}, {0, 0, 1, 1, 0, 0, 1, 1}, {0, 0, 0, 0, 1, 1, 1, 1}};

inline uint32_t octant_test_sse(const Vec3& lo, float half, const RaySlabs& r, float limit,
                                float* t0s, float* t1s) {
  const __m128 h = _mm_set1_ps(half);
  uint32_t mask = 0;
  for (int q = 0; q < 8; q += 4) {
    __m128 tn = _mm_set1_ps(r.tmin), tf = _mm_set1_ps(limit);
    for (int a = 0; a < 3; ++a) {
      const __m128 clo =
          _mm_add_ps(_mm_set1_ps(lo[a]), _mm_mul_ps(h, _mm_load_ps(kOctantBit[a] + q)));
      slab_axis_sse(clo, _mm_add_ps(clo, h), r, a, tn, tf);
    }
    _mm_store_ps(t0s + q, tn);
    _mm_store_ps(t1s + q, tf);
    mask |= uint32_t(_mm_movemask_ps(_mm_cmple_ps(tn, tf))) << q;
  }
  return mask;
}

__attribute__((target("avx2"))) inline uint32_t octant_test_avx2(const Vec3& lo, float half,
                                                                 const RaySlabs& r, float limit,
                                                                 float* t0s, float* t1s) {
  const __m256 h = _mm256_set1_ps(half);
  __m256 tn = _mm256_set1_ps(r.tmin), tf = _mm256_set1_ps(limit);
  for (int a = 0; a < 3; ++a) {
    const __m256 clo =
        _mm256_add_ps(_mm256_set1_ps(lo[a]), _mm256_mul_ps(h, _mm256_load_ps(kOctantBit[a])));
    slab_axis_avx2(clo, _mm256_add_ps(clo, h), r, a, tn, tf);
  }
  _mm256_store_ps(t0s, tn);
  _mm256_store_ps(t1s, tf);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// Whether this CPU runs node_test_avx2 (checked once).
bool wide_nodes_use_avx2();

// A binary tree in the layout both builders make: node b's left child is b + 1, its right child
// right(b); a leaf has count(b) > 0 items starting at first(b).
template <class Binary>
class WideCollapse {
 public:
  WideCollapse(const Binary& tree, std::vector<WideNode>& out) : tree_(tree), out_(out) {}

  // Makes the wide node for binary inner node b (or, for a leaf root, one holding just it): its
  // children are b's children, the largest-area inner one replaced by its own two children until
  // eight are gathered. Returns the wide node's index.
  uint32_t collapse(uint32_t b) {
    std::array<uint32_t, kWideWidth> kids{};
    int nk = 0;
    if (tree_.count(b) > 0) {
      kids[size_t(nk++)] = b;
    } else {
      kids[size_t(nk++)] = b + 1;
      kids[size_t(nk++)] = tree_.right(b);
    }
    while (nk < kWideWidth) {
      int open = -1;
      float best = -1;
      for (int k = 0; k < nk; ++k) {
        const float a = half_area(tree_.box(kids[size_t(k)]));
        if (tree_.count(kids[size_t(k)]) == 0 && a > best) best = a, open = k;
      }
      if (open < 0) break;
      const uint32_t c = kids[size_t(open)];
      kids[size_t(open)] = c + 1;
      kids[size_t(nk++)] = tree_.right(c);
    }
    const auto me = uint32_t(out_.size());
    out_.emplace_back();
    for (int k = 0; k < kWideWidth; ++k) {
      WideNode& w = out_[me];
      if (k >= nk) {  // an empty slot: child 0 and count 0 (the root is no one's child)
        for (int a = 0; a < 3; ++a) w.lo[a][k] = kInfinity, w.hi[a][k] = -kInfinity;
        continue;
      }
      const uint32_t c = kids[size_t(k)];
      const Aabb box = tree_.box(c);
      for (int a = 0; a < 3; ++a) w.lo[a][k] = box.lo[a], w.hi[a][k] = box.hi[a];
      w.count[k] = tree_.count(c);
      w.child[k] = tree_.count(c) > 0 ? tree_.first(c) : 0;
    }
    for (int k = 0; k < nk; ++k) {
      const uint32_t c = kids[size_t(k)];
      if (tree_.count(c) == 0) {
        const uint32_t child = collapse(c);
        out_[me].child[k] = child;
      }
    }
    return me;
  }

  static float half_area(const Aabb& b) {
    if (b.empty()) return 0;
    const Vec3 e = b.extent();
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  }

 private:
  const Binary& tree_;
  std::vector<WideNode>& out_;
};

// A child a walk has yet to enter: a wide node (count 0) or a leaf's items.
struct WideTodo {
  uint32_t index;
  uint32_t count;
  float t0, t1;
};

// The children of n hit by the ray (bits of mask, entry and exit t in t0s, t1s) in the order a
// stack pops them: nearest first (ties: the higher slot first), or for kAny the higher slot first
// without a sort (any blocker ends an occlusion query, and a ray nothing blocks visits every child
// it crosses whatever the order: Embree's any-hit traversal). The first goes to `next`, the others
// onto stack[top...]: popping a WideTodo just written field by field stalled store forwarding.
// Empty slots (which NaN may let pass) are skipped. False when no child is left.
template <bool kAny>
inline bool next_children(const WideNode& n, uint32_t mask, const float* t0s, const float* t1s,
                          WideTodo* stack, int& top, WideTodo& next) {
  const auto todo = [&](int k) { return WideTodo{n.child[k], n.count[k], t0s[k], t1s[k]}; };
  const auto empty = [&](int k) { return n.child[k] == 0 && n.count[k] == 0; };
  const uint32_t rest = mask & (mask - 1);
  if (!kAny && rest != 0 && (rest & (rest - 1)) == 0) {
    // Two children, ordered by a select rather than a branch: which one the ray enters first is
    // a coin toss the branch predictor loses half the time.
    const int k0 = __builtin_ctz(mask), k1 = __builtin_ctz(rest);
    if (!empty(k0) && !empty(k1)) {
      const bool k0_first = t0s[k0] < t0s[k1];  // ties: the higher slot first
      stack[top++] = todo(k0_first ? k1 : k0);
      next = todo(k0_first ? k0 : k1);
      return true;
    }
  }
  std::array<int, kWideWidth> order;  // bottom of the stack to top
  int m = 0;
  for (; mask; mask &= mask - 1) {
    const int k = __builtin_ctz(mask);
    if (empty(k)) continue;
    int j = m++;
    if constexpr (!kAny)
      for (; j > 0 && t0s[order[size_t(j - 1)]] < t0s[k]; --j)
        order[size_t(j)] = order[size_t(j - 1)];
    order[size_t(j)] = k;
  }
  if (m == 0) return false;
  for (int i = 0; i + 1 < m; ++i) stack[top++] = todo(order[size_t(i)]);
  next = todo(order[size_t(m - 1)]);
  return true;
}

}  // namespace pcrt
