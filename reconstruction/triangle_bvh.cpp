// Our triangle BVH: binned surface-area-heuristic splits (16 bins over centroids, Wald 2007; a side
// costs its blocks of four triangles, as Embree's SAH for its four-wide leaves), at most 4
// triangles per leaf where a split pays (up to 16 where none does; any number at the depth cap),
// the binary tree collapsed into 8-wide nodes (Embree's BVH8, shared with the point bvh:
// structures/wide_node.hpp) whose eight boxes are tested at once when the node is visited, the
// children hit walked nearest first; triangles stored in leaf order with their vertices. It reports
// into the same counters as the point structures (nodes, leaves, triangle tests), so triangle
// tracing and direct point tracing are compared operation by operation.
#include <immintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "reconstruction/mesh_engine.hpp"
#include "structures/structure.hpp"
#include "structures/wide_node.hpp"

namespace pcrt {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kLeafSize = 4;

// The bin of a centroid coordinate `c` over [lo, lo + ext]. Clamped on both sides, and NaN goes
// to bin 0, so no rounding or overflow can index outside the bins.
int bin_of(float c, float lo, float ext) {
  const float b = float(kBins) * (c - lo) / ext;
  return b >= 0 ? int(std::min(b, float(kBins - 1))) : 0;
}

// Four triangles of a leaf in structure-of-arrays layout, as Moeller-Trumbore reads them: the
// first vertex a and the edges e1 = b - a, e2 = c - a (the same subtractions intersect_triangle
// makes), and the mesh index. Unused lanes are zero triangles (det = 0: never hit). 160 bytes.
constexpr uint32_t kLanes = 4;
struct alignas(16) TriangleBlock {
  float a[3][kLanes], e1[3][kLanes], e2[3][kLanes];
  uint32_t prim[kLanes] = {};
};

// intersect_triangle on four triangles at once: the same IEEE operations in the same order per
// lane (Eigen's cross, and its dot of three, which sums x + (y + z); no fused multiply-add), so a
// lane's t is bit for bit the scalar t, and the same acceptance (written as negated comparisons
// where the scalar code's NaN lets a triangle through). Returns a bit per lane hit in [tmin, tmax),
// t in ts.
inline uint32_t intersect_block(const __m128 o[3], const __m128 d[3], const TriangleBlock& b,
                                float tmin, float tmax, float* ts) {
  auto ld = [](const float* p) { return _mm_load_ps(p); };
  const __m128 e1x = ld(b.e1[0]), e1y = ld(b.e1[1]), e1z = ld(b.e1[2]);
  const __m128 e2x = ld(b.e2[0]), e2y = ld(b.e2[1]), e2z = ld(b.e2[2]);
  auto mul = _mm_mul_ps;
  auto sub = _mm_sub_ps;
  auto add = _mm_add_ps;
  const __m128 px = sub(mul(d[1], e2z), mul(d[2], e2y));
  const __m128 py = sub(mul(d[2], e2x), mul(d[0], e2z));
  const __m128 pz = sub(mul(d[0], e2y), mul(d[1], e2x));
  const __m128 det = add(mul(e1x, px), add(mul(e1y, py), mul(e1z, pz)));
  const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), det);
  const __m128 sx = sub(o[0], ld(b.a[0])), sy = sub(o[1], ld(b.a[1])), sz = sub(o[2], ld(b.a[2]));
  const __m128 u = mul(add(mul(sx, px), add(mul(sy, py), mul(sz, pz))), inv);
  const __m128 qx = sub(mul(sy, e1z), mul(sz, e1y));
  const __m128 qy = sub(mul(sz, e1x), mul(sx, e1z));
  const __m128 qz = sub(mul(sx, e1y), mul(sy, e1x));
  const __m128 v = mul(add(mul(d[0], qx), add(mul(d[1], qy), mul(d[2], qz))), inv);
  const __m128 t = mul(add(mul(e2x, qx), add(mul(e2y, qy), mul(e2z, qz))), inv);
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  __m128 ok = _mm_cmpneq_ps(det, zero);
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpnlt_ps(u, zero), _mm_cmpngt_ps(u, one)));
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpnlt_ps(v, zero), _mm_cmpngt_ps(add(u, v), one)));
  ok = _mm_and_ps(
      ok, _mm_and_ps(_mm_cmpge_ps(t, _mm_set1_ps(tmin)), _mm_cmplt_ps(t, _mm_set1_ps(tmax))));
  _mm_storeu_ps(ts, t);
  return uint32_t(_mm_movemask_ps(ok));
}

// A ray's origin and direction broadcast to the four lanes of a block test.
struct RayLanes {
  __m128 o[3], d[3];
  explicit RayLanes(const Ray& ray)
      : o{_mm_set1_ps(ray.o.x()), _mm_set1_ps(ray.o.y()), _mm_set1_ps(ray.o.z())},
        d{_mm_set1_ps(ray.d.x()), _mm_set1_ps(ray.d.y()), _mm_set1_ps(ray.d.z())} {}
};

// The next float above t (std::nextafter(t, inf) without the library call).
inline float next_up(float t) {
  if (!(t < kInfinity)) return t;
  if (t == 0) return std::numeric_limits<float>::denorm_min();
  const auto b = std::bit_cast<uint32_t>(t);
  return std::bit_cast<float>(t > 0 ? b + 1 : b - 1);
}

struct Node {
  Aabb box;
  uint32_t first = 0;  // leaf: first triangle in order_; inner: right child (left is next)
  uint32_t count = 0;  // leaf: triangles; inner: 0
};

class TriangleBvh final : public MeshEngine {
 public:
  TriangleBvh(const TriangleMesh& mesh, OpCounters& counters) : mesh_(mesh) {
    const size_t n = mesh.triangles.size();
    order_.resize(n);
    boxes_.resize(n);
    centroids_.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      order_[i] = i;
      for (uint32_t v : mesh.triangles[i]) boxes_[i].extend(mesh.vertices[v]);
      centroids_[i] = boxes_[i].center();
    }
    nodes_.reserve(2 * n / kLeafSize + 1);
    build(0, uint32_t(n), 0);
    make_blocks(mesh);
    order_ = {};
    boxes_ = {};
    centroids_ = {};
    counters.add(kBuildNodes, nodes_.size());
    counters.add(kBuildItemRefs, n);
    if (!nodes_.empty()) WideCollapse<TriangleBvh>(*this, wide_).collapse(0);
    nodes_ = {};
  }

  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    return avx2_ ? walk_avx2<false>(ray, hit, counters)
                 : walk<node_test_sse, false>(ray, hit, counters);
  }
  // Stops at the first triangle within [ray.tmin, ray.tmax), as rtcOccluded1 does.
  bool any_hit(const Ray& ray, OpCounters& counters) const override {
    Hit unused;
    return avx2_ ? walk_avx2<true>(ray, unused, counters)
                 : walk<node_test_sse, true>(ray, unused, counters);
  }

  [[nodiscard]] size_t memory_bytes() const override {
    return wide_.size() * sizeof(WideNode) + blocks_.size() * sizeof(TriangleBlock);
  }

 private:
  friend class WideCollapse<TriangleBvh>;

  // The triangles copied in leaf order into blocks of four, each leaf starting a block: a leaf
  // reads one contiguous run instead of an index, a triangle and three vertices each. Leaves
  // then index blocks (first: the leaf's first block).
  void make_blocks(const TriangleMesh& mesh) {
    for (Node& node : nodes_) {
      if (node.count == 0) continue;
      const auto first = uint32_t(blocks_.size());
      blocks_.resize(first + (node.count + kLanes - 1) / kLanes);
      for (uint32_t k = 0; k < node.count; ++k) {
        const uint32_t tri = order_[node.first + k];
        const auto& t = mesh.triangles[tri];
        const Vec3 a = mesh.vertices[t[0]];
        const Vec3 e1 = mesh.vertices[t[1]] - a, e2 = mesh.vertices[t[2]] - a;
        TriangleBlock& b = blocks_[first + k / kLanes];
        for (int c = 0; c < 3; ++c)
          b.a[c][k % kLanes] = a[c], b.e1[c][k % kLanes] = e1[c], b.e2[c][k % kLanes] = e2[c];
        b.prim[k % kLanes] = tri;
      }
      node.first = first;
    }
  }
  // The binary tree as WideCollapse reads it.
  [[nodiscard]] uint32_t count(uint32_t b) const { return nodes_[b].count; }
  [[nodiscard]] uint32_t first(uint32_t b) const { return nodes_[b].first; }
  [[nodiscard]] uint32_t right(uint32_t b) const { return nodes_[b].first; }
  [[nodiscard]] Aabb box(uint32_t b) const { return nodes_[b].box; }

  // The walk compiled for AVX2, so that the node test (and all else) inlines into it: a call per
  // node otherwise, as a function of another target cannot be inlined into a generic one.
  template <bool kAny>
  __attribute__((target("avx2"))) bool walk_avx2(const Ray& ray, Hit& hit,
                                                 OpCounters& counters) const {
    return walk<node_test_avx2_offsets, kAny>(ray, hit, counters);
  }

  // kAny: an occlusion query, ended by the first leaf with a triangle in [ray.tmin, ray.tmax).
  template <auto kTest, bool kAny>
  __attribute__((always_inline)) bool walk(const Ray& ray, Hit& hit, OpCounters& counters) const {
    if (wide_.empty()) return false;
    const RaySlabs slabs(ray);
    std::array<WideTodo, (kWideWidth - 1) * 64 + kWideWidth> stack;
    int top = 0;
    float t_max = kAny ? ray.tmax : std::min(ray.tmax, hit.t);
    WideTodo cur{0, 0, ray.tmin, t_max};  // the next node, kept out of the stack
    bool found = false;
    uint32_t hit_at = 0;  // the closest hit's block * kLanes + lane
    uint64_t nodes = 0, leaves = 0, tests = 0;
    while (true) {
      if (cur.t0 <= t_max) {  // else entered beyond the hit found since it was pushed
        ++nodes;
        if (cur.count > 0) {
          ++leaves;
          tests += cur.count;
          if constexpr (kAny) {
            if ((found = occludes_leaf(ray, cur.index, cur.count, t_max))) break;
          } else {
            found |= intersect_leaf(ray, cur.index, cur.count, t_max, hit, hit_at);
          }
        } else {
          alignas(32) float t0s[kWideWidth], t1s[kWideWidth];
          const WideNode& n = wide_[cur.index];
          const uint32_t mask = kTest(n, slabs, t_max * kWiden, t0s, t1s);
          if (next_children<kAny>(n, mask, t0s, t1s, stack.data(), top, cur)) continue;
        }
      }
      if (top == 0) break;
      cur = stack[size_t(--top)];
    }
    counters.add(kNodesVisited, nodes);
    counters.add(kLeavesVisited, leaves);
    counters.add(kTriangleTests, tests);
    if (!kAny && found) {
      hit.p = ray.at(hit.t);
      hit.n = block_normal(blocks_[hit_at / kLanes], hit_at % kLanes);
      hit.footprint = 0;
    }
    return found;
  }

  // TriangleMesh::normal of lane k's triangle from its block: e1 x e2 are the floats it computes
  // from the vertices (the same subtractions), so the same normal, without reading the mesh's
  // indices and vertices (four cache misses per hit on a large mesh).
  static Vec3 block_normal(const TriangleBlock& b, uint32_t k) {
    const Vec3 e1(b.e1[0][k], b.e1[1][k], b.e1[2][k]), e2(b.e2[0][k], b.e2[1][k], b.e2[2][k]);
    return triangle_normal(e1, e2);
  }

  // The leaf's triangles against [ray.tmin, t_max]; narrows t_max and hit.t, hit.prim. Four at
  // a time against the t_max the block starts with, then lane by lane in leaf order against the
  // narrowed one, so the result is the scalar loop's.
  bool intersect_leaf(const Ray& ray, uint32_t first, uint32_t count, float& t_max, Hit& hit,
                      uint32_t& hit_at) const {
    const RayLanes r(ray);
    bool found = false;
    for (uint32_t g = 0; g * kLanes < count; ++g) {
      const TriangleBlock& b = blocks_[first + g];
      alignas(16) float ts[kLanes];
      // Up to and including t_max, so that a tie in t goes to the lower triangle index whatever
      // the traversal order.
      uint32_t mask = intersect_block(r.o, r.d, b, ray.tmin, next_up(t_max), ts);
      for (; mask; mask &= mask - 1) {
        const int k = __builtin_ctz(mask);
        const float t = ts[k];
        if (!(t < next_up(t_max)) || (t == t_max && b.prim[k] > hit.prim)) continue;
        t_max = t, hit.t = t, hit.prim = b.prim[k], found = true;
        hit_at = (first + g) * kLanes + uint32_t(k);
      }
    }
    return found;
  }

  // Whether a triangle of the leaf lies within [ray.tmin, t_max): the first block with one ends it.
  bool occludes_leaf(const Ray& ray, uint32_t first, uint32_t count, float t_max) const {
    const RayLanes r(ray);
    alignas(16) float ts[kLanes];
    for (uint32_t g = 0; g * kLanes < count; ++g)
      if (intersect_block(r.o, r.d, blocks_[first + g], ray.tmin, t_max, ts) != 0) return true;
    return false;
  }

  // Depth is capped well below the traversal stack's 64 entries.
  uint32_t build(uint32_t begin, uint32_t end, int depth) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.emplace_back();
    Aabb box, cbox;
    for (uint32_t k = begin; k < end; ++k)
      box.extend(boxes_[order_[k]]), cbox.extend(centroids_[order_[k]]);
    nodes_[index].box = box;
    int axis = 0;
    uint32_t mid = 0;
    if (end - begin <= kLeafSize || depth >= 48 || !find_split(begin, end, box, cbox, axis, mid)) {
      nodes_[index].first = begin;
      nodes_[index].count = end - begin;
      return index;
    }
    build(begin, mid, depth + 1);
    const uint32_t right = build(mid, end, depth + 1);
    nodes_[index].first = right;
    return index;
  }

  // Binned SAH over centroids; false when no split beats a leaf (or all centroids coincide),
  // in which case a large node is halved by count instead.
  bool find_split(uint32_t begin, uint32_t end, const Aabb& box, const Aabb& cbox, int& axis,
                  uint32_t& mid) {
    auto area = [](const Aabb& b) {
      if (b.empty()) return 0.0f;
      const Vec3 e = b.extent();
      return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
    };
    // Triangles are tested four at a time: a side costs its blocks of four, not its triangles.
    auto blocks = [](uint32_t n) { return float((n + kLanes - 1) / kLanes); };
    float best = kInfinity;
    int best_bin = -1;
    for (int a = 0; a < 3; ++a) {
      const float lo = cbox.lo[a], ext = cbox.hi[a] - cbox.lo[a];
      if (!(ext > 0) || !std::isfinite(ext)) continue;  // flat, or beyond float's range
      std::array<Aabb, kBins> bins;
      std::array<uint32_t, kBins> counts{};
      for (uint32_t k = begin; k < end; ++k) {
        const int b = bin_of(centroids_[order_[k]][a], lo, ext);
        bins[size_t(b)].extend(boxes_[order_[k]]);
        ++counts[size_t(b)];
      }
      std::array<float, kBins> right_cost{};
      Aabb acc;
      uint32_t cnt = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bins[size_t(b)]);
        cnt += counts[size_t(b)];
        right_cost[size_t(b)] = area(acc) * blocks(cnt);
      }
      acc = Aabb{};
      cnt = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        acc.extend(bins[size_t(b)]);
        cnt += counts[size_t(b)];
        const float cost = area(acc) * blocks(cnt) + right_cost[size_t(b + 1)];
        if (cnt > 0 && cnt < end - begin && cost < best) best = cost, axis = a, best_bin = b;
      }
    }
    if (best_bin >= 0 && best < area(box) * blocks(end - begin)) {
      const float lo = cbox.lo[axis], ext = cbox.hi[axis] - cbox.lo[axis];
      uint32_t* m = std::partition(order_.data() + begin, order_.data() + end, [&](uint32_t i) {
        return bin_of(centroids_[i][axis], lo, ext) <= best_bin;
      });
      mid = uint32_t(m - order_.data());
      return true;
    }
    if (end - begin <= 4 * kLeafSize) return false;
    // No SAH gain but too many triangles for a leaf: median split on the widest axis.
    axis = 0;
    const Vec3 e = cbox.extent();
    if (e.y() > e[axis]) axis = 1;
    if (e.z() > e[axis]) axis = 2;
    mid = (begin + end) / 2;
    std::nth_element(
        order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
        [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    return true;
  }

  const TriangleMesh& mesh_;
  bool avx2_ = wide_nodes_use_avx2();
  std::vector<Node> nodes_;  // the binary tree, build only
  std::vector<WideNode> wide_;
  std::vector<TriangleBlock> blocks_;
  std::vector<uint32_t> order_;
  std::vector<Aabb> boxes_;
  std::vector<Vec3> centroids_;
};

}  // namespace

void register_triangle_bvh(MeshEngineRegistry& registry) {
  registry.add(MeshEngineInfo{
      "bvh",
      "pcrt's triangle BVH: binned SAH (16 bins, costed in blocks of 4 triangles), at most 4 "
      "triangles per leaf where a split pays, 8-wide nodes, counted like the point structures",
      [](const TriangleMesh& mesh, OpCounters& counters, Timings& timings) {
        ScopedTimer t(timings, "build");
        return std::unique_ptr<MeshEngine>(std::make_unique<TriangleBvh>(mesh, counters));
      }});
}

}  // namespace pcrt
