// Binned-SAH bounding volume hierarchy (Wald 2007, "On fast construction of SAH-based bounding
// volume hierarchies"; pbrt-v4's BVHAggregate): the industrial baseline. An object partition over
// the items' footprint boxes: every item sits in exactly one leaf, so no reference is duplicated.
// Build: at each node the item box centres are binned (kBins per axis) and the split with the
// least surface area heuristic cost is taken, until a node holds leaf_size items or fewer, so
// leaves hold what leaf_size says (by default sized to the method's leaf test: auto_leaf_size). The
// binary tree is then collapsed into 8-wide nodes (Embree's BVH8, wide_node.hpp). Traversal: a
// node's eight child boxes are tested at once (AVX2, else two SSE halves) when it is visited, the
// children hit are pushed farthest first so the nearest is walked next, and a waiting one is
// dropped once its entry lies beyond the hit so far (boxes overlap, so the walk cannot stop at the
// first hit).
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>

#include "core/offsets.hpp"
#include "structures/build_buffer.hpp"
#include "structures/structure.hpp"
#include "structures/wide_node.hpp"
#include "structures/wide_walk.hpp"

namespace pcrt {
namespace {

// 32 bytes; the left child follows its parent, so a node and its left child share a cache line
// half the time.
struct BvhNode {
  Vec3 lo;
  uint32_t index = 0;  // inner: right child; leaf: first item in order_
  Vec3 hi;
  uint32_t count = 0;  // leaf: items (> 0); inner: 0
};

constexpr int kBins = 16;
constexpr uint32_t kParallelBuildItems = 50000;
constexpr int kMaxDepth = kWideWalkMaxDepth;

// Nodes of a subtree, child indices relative to its own array; large subtrees are built in
// parallel and spliced in order (by moving their chunks: build_buffer.hpp), so the layout and
// every count are the same for any thread count.
struct Subtree {
  ChunkedArray<BvhNode> nodes;
  void append(Subtree&& sub) {
    (void)node_index32(nodes.size() + sub.nodes.size(), "bvh");  // every shifted index fits
    const auto base = uint32_t(nodes.size());
    nodes.splice(std::move(sub.nodes), [&](BvhNode& n) {
      if (n.count == 0) n.index += base;
    });
  }
};

struct BvhParams {
  uint32_t leaf_size = 0;
};
const ParamList<BvhParams>& bvh_params() {
  static const auto l = ParamList<BvhParams>().add(
      &BvhParams::leaf_size,
      {"leaf_size", 0, 0, 1e6,
       "largest leaf (K of the leaf-based methods; 0: at least 8 items and two of the method's "
       "leaf blocks, so 16 for the disc methods' blocks of eight)"});
  return l;
}

// The leaf size of leaf_size=0: 8 items, or two blocks of the method's leaf test where a block is
// larger (ItemSet::leaf_block). Each level of the tree is a node test on a ray's critical path and
// each leaf a call into the method, so the disc methods, which test a block of eight about as
// fast as one disc, trace faster with leaves of two blocks than of one, while the methods that
// test items one at a time (the Gaussian particles) trace slower with larger leaves
// (results/anchor/bvh_leaf).
constexpr uint32_t auto_leaf_size(uint32_t leaf_block) { return std::max(8u, 2 * leaf_block); }

class Bvh final : public Structure {
 public:
  explicit Bvh(const BvhParams& p) : params_(p) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    const auto n = uint32_t(set.size());
    items_ = set;
    leaf_size_ = params_.leaf_size > 0 ? params_.leaf_size : auto_leaf_size(set.leaf_block);
    order_.resize(n);
    for (uint32_t i = 0; i < n; ++i) order_[i] = i;
    Subtree tree;
    if (n > 0) build_node(tree, 0, n, 0);
    nodes_ = tree.nodes.flatten();
    counters.add(kBuildNodes, nodes_.size());
    counters.add(kBuildItemRefs, n);
    align_leaves();
    counters.add(kBuildItemVisits, nodes_.empty() ? 0 : item_visits(0, 1));
    // Traversal runs on the binary tree collapsed into 8-wide nodes (Embree's BVH8): a node's
    // eight child boxes are tested at once.
    wide_.clear();
    if (!nodes_.empty()) WideCollapse<Bvh>(*this, wide_).collapse(0);
    wide_.shrink_to_fit();
    release(nodes_);
    malloc_trim(0);  // the collapse's freed growth stays resident in the heap otherwise
  }

  bool closest_hit(const Ray& ray, const LeafIntersector& leaf, Hit& hit,
                   OpCounters& counters) const override {
    return avx2_ ? walk_avx2<false>(ray, leaf, hit, counters)
                 : walk<false, node_test_sse>(ray, leaf, hit, counters);
  }

  bool any_hit(const Ray& ray, const LeafIntersector& leaf, OpCounters& counters) const override {
    Hit hit;
    hit.t = ray.tmax;
    return avx2_ ? walk_avx2<true>(ray, leaf, hit, counters)
                 : walk<true, node_test_sse>(ray, leaf, hit, counters);
  }

  void any_hits(const Ray* rays, int n, const LeafIntersector& leaf, char* blocked,
                OpCounters& counters) const override {
    for (int i = 0; i < n; i += kWidePacket) {
      const int m = std::min(kWidePacket, n - i);
      if (avx2_)
        packet_avx2(rays + i, m, leaf, blocked + i, counters);
      else
        walk_wide_occluded<node_test_sse>(wide_, order_.data(), rays + i, m, leaf, blocked + i,
                                          counters);
    }
  }

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return order_; }
  [[nodiscard]] ParamValues resolved_params() const override {
    return {{"leaf_size", double(leaf_size_)}};
  }
  [[nodiscard]] size_t memory_bytes() const override {
    return wide_.capacity() * sizeof(WideNode) + order_.capacity() * sizeof(uint32_t);
  }

 private:
  friend class WideCollapse<Bvh>;

  // Sum over leaves of items x levels from the root (the build's partitioning work).
  [[nodiscard]] uint64_t item_visits(uint32_t node, uint64_t level) const {
    const BvhNode& n = nodes_[node];
    if (n.count > 0) return uint64_t(n.count) * level;
    return item_visits(node + 1, level + 1) + item_visits(n.index, level + 1);
  }

  // Lays the leaves out in order_ so that none touches more blocks of kBlock references than its
  // size needs (a leaf of up to kBlock items within one block, a larger one starting at a block):
  // methods that copy their data in leaf order in blocks of eight (DiscBlock) then read one block
  // per small leaf, not two. The gaps hold copies of the preceding reference (never visited:
  // leaves are (first, count) pieces), so leaf_references stays a list of valid items.
  void align_leaves() {
    constexpr uint32_t kBlock = 8;
    std::vector<uint32_t> out;
    out.reserve(order_.size() + order_.size() / 4);
    for (BvhNode& node : nodes_) {  // in build order, which is the order of order_
      if (node.count == 0) continue;
      const auto pos = uint32_t(out.size());
      const uint32_t in_block = pos % kBlock;
      if (in_block != 0 && (node.count > kBlock || in_block + node.count > kBlock))
        out.resize(pos + kBlock - in_block, out.back());
      const uint32_t first = node.index;
      node.index = uint32_t(out.size());
      out.insert(out.end(), order_.begin() + first, order_.begin() + first + node.count);
    }
    order_ = std::move(out);
  }

  // The binary tree as WideCollapse reads it.
  [[nodiscard]] uint32_t count(uint32_t b) const { return nodes_[b].count; }
  [[nodiscard]] uint32_t first(uint32_t b) const { return nodes_[b].index; }
  [[nodiscard]] uint32_t right(uint32_t b) const { return nodes_[b].index; }
  [[nodiscard]] Aabb box(uint32_t b) const { return Aabb{nodes_[b].lo, nodes_[b].hi}; }

  // The walk compiled for AVX2, so that the node test inlines into it (a function of another
  // target cannot be inlined into a generic one: a call per node otherwise).
  template <bool kAny>
  __attribute__((target("avx2"))) bool walk_avx2(const Ray& ray, const LeafIntersector& leaf,
                                                 Hit& hit, OpCounters& counters) const {
    return walk<kAny, node_test_avx2>(ray, leaf, hit, counters);
  }

  __attribute__((target("avx2"))) void packet_avx2(const Ray* rays, int n,
                                                   const LeafIntersector& leaf, char* blocked,
                                                   OpCounters& counters) const {
    walk_wide_occluded<node_test_avx2>(wide_, order_.data(), rays, n, leaf, blocked, counters);
  }

  template <bool kAny, auto kTest>
  __attribute__((always_inline)) bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit,
                                           OpCounters& counters) const {
    return walk_wide<kAny, kTest>(wide_, order_.data(), ray, leaf, hit, counters);
  }

  // Recursion depth is bounded by kMaxDepth (then the node becomes a leaf).
  void build_node(Subtree& out, uint32_t begin, uint32_t end, int depth) {
    Aabb box, cbox;
    for (uint32_t k = begin; k < end; ++k) {
      box.extend(items_.box(order_[k]));
      cbox.extend(centre(order_[k]));
    }
    const auto me = out.nodes.push_back(BvhNode{box.lo, 0, box.hi, 0});
    const uint32_t n = end - begin;
    if (n <= leaf_size_ || depth >= kMaxDepth) {
      out.nodes[me].index = begin;
      out.nodes[me].count = n;
      return;
    }
    const uint32_t mid = split(begin, end, cbox);
    if (n < kParallelBuildItems) {
      build_node(out, begin, mid, depth + 1);
      out.nodes[me].index = node_index32(out.nodes.size(), "bvh");
      build_node(out, mid, end, depth + 1);
      return;
    }
    Subtree lsub, rsub;
    tbb::parallel_invoke([&] { build_node(lsub, begin, mid, depth + 1); },
                         [&] { build_node(rsub, mid, end, depth + 1); });
    out.append(std::move(lsub));
    out.nodes[me].index = node_index32(out.nodes.size(), "bvh");
    out.append(std::move(rsub));
  }

  // The centre of item i's box, computed where it is needed rather than stored (12 bytes per item
  // at the build's peak).
  [[nodiscard]] Vec3 centre(uint32_t i) const { return items_.box(i).center(); }

  // Partitions order_[begin, end) at the binned split of least SAH cost (by box centres) and
  // returns the first index of the right part. Where the centres coincide or every bin split
  // leaves a side empty, splits at the median index (an object partition always progresses).
  uint32_t split(uint32_t begin, uint32_t end, const Aabb& cbox) {
    const Vec3 ext = cbox.extent();
    float best_cost = kInfinity;
    int best_axis = -1, best_bin = 0;
    for (int ax = 0; ax < 3; ++ax) {
      if (!(ext[ax] > 0)) continue;
      const float scale = float(kBins) / ext[ax];
      std::array<Aabb, kBins> bins;
      std::array<uint32_t, kBins> counts{};
      for (uint32_t k = begin; k < end; ++k) {
        const uint32_t i = order_[k];
        const Aabb box = items_.box(i);
        const int b = bin_of(box.center()[ax], cbox.lo[ax], scale);
        bins[size_t(b)].extend(box);
        ++counts[size_t(b)];
      }
      // Sweep from the right for the right-side areas, then from the left for the costs.
      std::array<float, kBins> right_area{};
      std::array<uint32_t, kBins> right_count{};
      Aabb acc;
      uint32_t cnt = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bins[size_t(b)]);
        cnt += counts[size_t(b)];
        right_area[size_t(b)] = area(acc);
        right_count[size_t(b)] = cnt;
      }
      acc = Aabb{};
      cnt = 0;
      for (int b = 1; b < kBins; ++b) {
        acc.extend(bins[size_t(b - 1)]);
        cnt += counts[size_t(b - 1)];
        if (cnt == 0 || right_count[size_t(b)] == 0) continue;
        const float cost =
            float(cnt) * area(acc) + float(right_count[size_t(b)]) * right_area[size_t(b)];
        if (cost < best_cost) best_cost = cost, best_axis = ax, best_bin = b;
      }
    }
    const auto first = order_.begin() + begin, last = order_.begin() + end;
    if (best_axis >= 0) {
      const int ax = best_axis;
      const float scale = float(kBins) / ext[ax];
      const auto mid = std::stable_partition(first, last, [&](uint32_t i) {
        return bin_of(centre(i)[ax], cbox.lo[ax], scale) < best_bin;
      });
      return uint32_t(mid - order_.begin());
    }
    const uint32_t mid = begin + (end - begin) / 2;
    int ax = 0;
    if (ext.y() > ext[ax]) ax = 1;
    if (ext.z() > ext[ax]) ax = 2;
    std::nth_element(first, order_.begin() + mid, last, [&](uint32_t a, uint32_t b) {
      const float pa = centre(a)[ax], pb = centre(b)[ax];
      return pa < pb || (pa == pb && a < b);
    });
    return mid;
  }

  static int bin_of(float x, float lo, float scale) {
    return std::clamp(int((x - lo) * scale), 0, kBins - 1);
  }
  static float area(const Aabb& b) {
    if (b.empty()) return 0;
    const Vec3 e = b.extent();
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  }

  BvhParams params_;
  uint32_t leaf_size_ = 0;  // params_.leaf_size, or its automatic value for the items built
  bool avx2_ = wide_nodes_use_avx2();
  ItemSet items_;               // the caller's, read by the build only
  std::vector<BvhNode> nodes_;  // the binary tree, build only
  std::vector<WideNode> wide_;
  std::vector<uint32_t> order_;  // items in leaf order, each leaf contiguous (align_leaves)
};

}  // namespace

void register_bvh(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "bvh",
      .description = "binned-SAH bounding volume hierarchy over the item boxes, one leaf per item, "
                     "children tested at push and walked nearer first",
      .build_claim = "O(N log N)",
      .query_claim = "O(log N)",
      .params = bvh_params().specs(),
      .create = structure_from<Bvh>(bvh_params(), "bvh"),
      .footprint = fixed_footprint({.item_order = 55, .leaf_order = 60, .references_per_item = 1}),
  });
}

}  // namespace pcrt
