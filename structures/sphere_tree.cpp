// Bounding sphere hierarchy (thesis section 5.4; Adamson and Alexa 2003, Adams et al. 2005):
// an object partition. Each node's items split at the median centre along the longest axis of
// their centres' box; every node holds a sphere enclosing its items' footprint spheres (centred
// on the box centre of the footprints, radius the largest reach: tight enough to prune, O(n) per
// node, O(N log N) in all). Each item sits in exactly one leaf. Traversal: the nearer child
// first, skipping any node whose sphere starts beyond the hit so far (siblings overlap, so the
// walk cannot stop at the first hit as the disjoint structures do).
#include <algorithm>
#include <array>
#include <cmath>

#include "structures/structure.hpp"

namespace pcrt {
namespace {

struct SphereNode {
  Vec3 centre = Vec3::Zero();
  float radius = 0;
  uint32_t first = 0;  // inner: right child (left follows); leaf: first item in order_
  uint32_t count = 0;  // leaf: items; 0 for inner nodes
};

// Entry and exit of the ray in the sphere, clamped to [ray.tmin, limit].
bool ray_sphere(const Ray& ray, const Vec3& c, float r, float limit, float& t0, float& t1) {
  // r^2 - |perpendicular offset|^2 rather than b^2 - (|oc|^2 - r^2): the latter cancels
  // catastrophically for small spheres seen from far away (ray.d is unit length).
  const Vec3 oc = ray.o - c;
  const float b = oc.dot(ray.d);
  const float disc = r * r - (oc - b * ray.d).squaredNorm();
  if (disc < 0) return false;
  const float s = std::sqrt(disc);
  // Pad by a relative epsilon: the sphere must not cut off a footprint through rounding.
  const float pad = 1e-6f * (std::abs(b) + r);
  t0 = std::max(-b - s - pad, ray.tmin);
  t1 = std::min(-b + s + pad, limit);
  return t0 <= t1;
}

struct SphereTreeParams {
  size_t leaf_size = 8;
  int max_depth = 64;
};
const ParamList<SphereTreeParams>& sphere_tree_params() {
  using P = SphereTreeParams;
  static const auto l = ParamList<P>()
                            .add(&P::leaf_size, {"leaf_size", 8, 1, 1e6,
                                                 "largest leaf (K of the leaf-based methods)"})
                            .add(&P::max_depth, {"max_depth", 64, 0, 64, "maximum depth"});
  return l;
}

class SphereTree final : public Structure {
 public:
  explicit SphereTree(const SphereTreeParams& p)
      : leaf_size_(p.leaf_size), max_depth_(p.max_depth) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    nodes_.clear();
    order_.resize(set.size());
    for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    if (!order_.empty()) build_node(0, uint32_t(order_.size()), 0);
    counters.add(kBuildNodes, nodes_.size());
    counters.add(kBuildItemRefs, order_.size());
    counters.add(kBuildItemVisits, nodes_.empty() ? 0 : item_visits(0, 1));
  }

  // Sum over leaves of items x levels from the root (the build's partitioning work).
  [[nodiscard]] uint64_t item_visits(uint32_t node, uint64_t level) const {
    const SphereNode& n = nodes_[node];
    if (n.count > 0) return uint64_t(n.count) * level;
    return item_visits(node + 1, level + 1) + item_visits(n.first, level + 1);
  }

  bool closest_hit(const Ray& ray, const LeafIntersector& leaf, Hit& hit,
                   OpCounters& counters) const override {
    return walk<false>(ray, leaf, hit, counters);
  }

  bool any_hit(const Ray& ray, const LeafIntersector& leaf, OpCounters& counters) const override {
    Hit hit;
    hit.t = ray.tmax;
    return walk<true>(ray, leaf, hit, counters);
  }

  // kAny: an occlusion query, ended by the first leaf that reports a hit.
  template <bool kAny>
  bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit, OpCounters& counters) const {
    if (nodes_.empty()) return false;
    struct Todo {
      uint32_t node;
      float t0, t1;
    };
    std::array<Todo, 80> stack;  // one waiting sibling per level, max_depth <= 64
    int top = 0;
    float t0 = 0, t1 = 0;
    if (!ray_sphere(ray, nodes_[0].centre, nodes_[0].radius, ray.tmax, t0, t1)) return false;
    stack[size_t(top++)] = Todo{0, t0, t1};
    bool found = false;
    while (top > 0) {
      const Todo cur = stack[size_t(--top)];
      if (!may_improve(cur.t0, hit.t)) continue;
      counters.add(kNodesVisited);
      const SphereNode& n = nodes_[cur.node];
      if (n.count > 0) {
        counters.add(kLeavesVisited);
        counters.add(kItemsVisited, n.count);
        const LeafVisit visit{{order_.data() + n.first, n.count}, cur.t0, cur.t1};
        if constexpr (kAny) {
          if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
        } else {
          found |= leaf.intersect_leaf(ray, visit, hit, counters);
        }
        continue;
      }
      Todo kids[2];
      int nk = 0;
      for (uint32_t c : {cur.node + 1, n.first}) {
        float a = 0, b = 0;
        if (ray_sphere(ray, nodes_[c].centre, nodes_[c].radius,
                       std::min(ray.tmax, hit.t * (1.0f + 1e-5f)), a, b))
          kids[nk++] = Todo{c, a, b};
      }
      if (nk == 2 && kids[0].t0 < kids[1].t0) std::swap(kids[0], kids[1]);
      for (int k = 0; k < nk; ++k) stack[size_t(top++)] = kids[k];
    }
    return found;
  }

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return order_; }
  [[nodiscard]] size_t memory_bytes() const override {
    return nodes_.capacity() * sizeof(SphereNode) + order_.capacity() * sizeof(uint32_t);
  }

 private:
  void build_node(uint32_t begin, uint32_t end, int depth) {
    const auto me = uint32_t(nodes_.size());
    nodes_.emplace_back();
    Aabb reach, centres;
    for (uint32_t k = begin; k < end; ++k) {
      reach.extend(items_.box(order_[k]));
      centres.extend(items_.positions[order_[k]]);
    }
    const Vec3 c = reach.center();
    float r = 0;
    for (uint32_t k = begin; k < end; ++k)
      r = std::max(r, (items_.positions[order_[k]] - c).norm() + items_.radius(order_[k]));
    nodes_[me].centre = c;
    nodes_[me].radius = r;
    const uint32_t n = end - begin;
    if (n <= leaf_size_ || depth >= max_depth_) {
      nodes_[me].first = begin;
      nodes_[me].count = n;
      return;
    }
    // Median split by index even when all centres coincide: an object partition always progresses.
    int ax = 0;
    const Vec3 ext = centres.extent();
    if (ext.y() > ext[ax]) ax = 1;
    if (ext.z() > ext[ax]) ax = 2;
    const uint32_t mid = begin + n / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) {
                       const float pa = items_.positions[a][ax], pb = items_.positions[b][ax];
                       return pa < pb || (pa == pb && a < b);
                     });
    build_node(begin, mid, depth + 1);
    nodes_[me].first = uint32_t(nodes_.size());
    build_node(mid, end, depth + 1);
  }

  size_t leaf_size_;
  int max_depth_;
  ItemSet items_;
  std::vector<SphereNode> nodes_;
  std::vector<uint32_t> order_;  // items, permuted so each leaf's are contiguous
};

}  // namespace

void register_sphere_tree(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "sphere_tree",
      .description = "bounding sphere hierarchy, median object split, one leaf per item",
      .build_claim = "O(N log N)",
      .query_claim = "O(log N)",
      .params = sphere_tree_params().specs(),
      .create = structure_from<SphereTree>(sphere_tree_params(), "sphere_tree"),
      .footprint = fixed_footprint({.item_order = 23, .leaf_order = 54, .references_per_item = 1}),
  });
}

}  // namespace pcrt
