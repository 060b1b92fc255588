// Octree (thesis section 5.4, figure 1.3; Schaufler and Jensen 2000 and most splat methods):
// the bounding cube of all footprints split regularly into eight equal children until a node
// holds at most leaf_size items, reaches max_depth, or splitting stops paying (footprints wider
// than the cells: the fullest child keeps over half of the items; such leaves exceed leaf_size). An
// item is referenced by every child its footprint box overlaps. Traversal: depth first, the
// children a ray crosses sorted by entry distance, so leaves come front to back (cells are
// disjoint).
#include <algorithm>
#include <array>

#include "core/offsets.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

struct OctNode {
  uint32_t first = 0;  // inner: index of 8 consecutive children; leaf: first ref
  uint32_t count = 0;  // leaf: number of refs; kInner for inner nodes
  static constexpr uint32_t kInner = ~uint32_t{0};
  [[nodiscard]] bool leaf() const { return count != kInner; }
};

struct OctreeParams {
  size_t leaf_size = 8;
  int max_depth = 21;
};
const ParamList<OctreeParams>& octree_params() {
  using P = OctreeParams;
  static const auto l =
      ParamList<P>()
          .add(&P::leaf_size, {"leaf_size", 8, 1, 1e6,
                               "stop splitting at this many items (K of the leaf-based methods)"})
          .add(&P::max_depth, {"max_depth", 21, 0, 30, "maximum depth"});
  return l;
}

class Octree final : public Structure {
 public:
  explicit Octree(const OctreeParams& p) : leaf_size_(p.leaf_size), max_depth_(p.max_depth) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    nodes_.assign(1, OctNode{});
    refs_.clear();
    const Aabb b = items_.bounds();
    // A cube around the bounds, a little larger and not centred on them, so that the mid-planes
    // of the first levels do not fall exactly on the symmetry planes of symmetric data (a line or
    // plane through the centre would straddle them at every level). A single point keeps a
    // zero-size cube and stays one leaf.
    const float side = b.empty() ? 0.0f : 1.0137f * b.extent().maxCoeff();
    root_lo_ = b.empty() ? Vec3::Zero() : Vec3(b.lo - Vec3::Constant(0.0049f * side));
    root_side_ = side;
    std::vector<uint32_t> all(items_.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    build_node(0, std::move(all), root_lo_, root_side_, 0);
    counters.add(kBuildNodes, nodes_.size());
    counters.add(kBuildItemRefs, refs_.size());
    counters.add(kBuildItemVisits, item_visits(0, 1));
  }

  // Sum over leaves of references x levels from the root (the build's partitioning work).
  [[nodiscard]] uint64_t item_visits(uint32_t node, uint64_t level) const {
    const OctNode& n = nodes_[node];
    if (n.leaf()) return uint64_t(n.count) * level;
    uint64_t sum = 0;
    for (uint32_t c = 0; c < 8; ++c) sum += item_visits(n.first + c, level + 1);
    return sum;
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
    if ((items_.size() == 0)) return false;
    const Vec3 inv = ray.d.cwiseInverse();
    struct Todo {
      uint32_t node;
      Vec3 lo;
      float side, t0, t1;
    };
    std::array<Todo, 8 * 32> stack;  // at most 7 siblings waiting per level, max_depth <= 30
    int top = 0;
    float t0 = 0, t1 = 0;
    if (!Aabb{root_lo_, root_lo_ + Vec3::Constant(root_side_)}.intersect(ray, inv, t0, t1))
      return false;
    stack[size_t(top++)] = Todo{0, root_lo_, root_side_, t0, t1};
    bool found = false;
    while (top > 0) {
      const Todo cur = stack[size_t(--top)];
      if (!may_improve(cur.t0, hit.t))
        break;  // disjoint cells in depth-first order: the rest is further
      counters.add(kNodesVisited);
      const OctNode& n = nodes_[cur.node];
      if (n.leaf()) {
        if (n.count > 0) {
          counters.add(kLeavesVisited);
          counters.add(kItemsVisited, n.count);
          const LeafVisit visit{{refs_.data() + n.first, n.count}, cur.t0, cur.t1};
          if constexpr (kAny) {
            if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
          } else {
            found |= leaf.intersect_leaf(ray, visit, hit, counters);
          }
        }
        continue;
      }
      // Children the ray crosses, pushed far to near so the nearest is popped first.
      std::array<Todo, 8> kids;
      int nk = 0;
      const float half = 0.5f * cur.side;
      for (uint32_t c = 0; c < 8; ++c) {
        const OctNode& child = nodes_[n.first + c];
        if (child.count == 0) continue;
        const Vec3 lo =
            cur.lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
        float a = 0, b = 0;
        if (Aabb{lo, lo + Vec3::Constant(half)}.intersect(ray, inv, a, b))
          kids[size_t(nk++)] = Todo{n.first + c, lo, half, a, b};
      }
      // Insertion sort, far first: at most 8 entries (a ray crosses at most 4 children).
      for (int k = 1; k < nk; ++k) {
        const Todo x = kids[size_t(k)];
        int j = k - 1;
        for (; j >= 0 && (kids[size_t(j)].t0 < x.t0 ||
                          (kids[size_t(j)].t0 == x.t0 && kids[size_t(j)].node < x.node));
             --j)
          kids[size_t(j + 1)] = kids[size_t(j)];
        kids[size_t(j + 1)] = x;
      }
      for (int k = 0; k < nk; ++k) stack[size_t(top++)] = kids[size_t(k)];
    }
    return found;
  }

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return refs_; }
  [[nodiscard]] size_t memory_bytes() const override {
    return nodes_.capacity() * sizeof(OctNode) + refs_.capacity() * sizeof(uint32_t);
  }

 private:
  void build_node(uint32_t node, std::vector<uint32_t> items, const Vec3& lo, float side,
                  int depth) {
    if (items.size() <= leaf_size_ || depth >= max_depth_ || !(side > 0))
      return make_leaf(node, items);
    const float half = 0.5f * side;
    std::array<std::vector<uint32_t>, 8> kids;
    for (uint32_t i : items) {
      const Aabb b = items_.box(i);
      const Vec3 mid = lo + Vec3::Constant(half);
      for (uint32_t c = 0; c < 8; ++c) {
        bool in = true;
        for (int a = 0; a < 3 && in; ++a)
          in = ((c >> a) & 1) ? b.hi[a] >= mid[a] : b.lo[a] <= mid[a];
        if (in) kids[c].push_back(i);
      }
    }
    // A split must pay: once footprints are wider than the cells, each item lands in several
    // children and the fullest child keeps most of them, so every further level only multiplies
    // references (identical points, or a dense plane of wide splats, would recurse to max_depth).
    // Stop when both hold: 3 references per item and over half of the items in one child. (All
    // items in one child alone is progress: the rest of the cell was empty.)
    size_t refs = 0, fullest = 0;
    for (const auto& k : kids) refs += k.size(), fullest = std::max(fullest, k.size());
    if (refs >= 3 * items.size() && 2 * fullest > items.size()) return make_leaf(node, items);
    items.clear();
    items.shrink_to_fit();
    const auto first = uint32_t(nodes_.size());
    nodes_[node] = OctNode{first, OctNode::kInner};
    nodes_.resize(nodes_.size() + 8);
    for (uint32_t c = 0; c < 8; ++c) {
      const Vec3 clo = lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
      build_node(first + c, std::move(kids[c]), clo, half, depth + 1);
    }
  }

  void make_leaf(uint32_t node, const std::vector<uint32_t>& items) {
    nodes_[node] = OctNode{offset32(refs_.size(), "octree"), uint32_t(items.size())};
    refs_.insert(refs_.end(), items.begin(), items.end());
  }

  size_t leaf_size_;
  int max_depth_;
  ItemSet items_;
  Vec3 root_lo_ = Vec3::Zero();
  float root_side_ = 0;
  std::vector<OctNode> nodes_;
  std::vector<uint32_t> refs_;
};

}  // namespace

void register_octree(StructureRegistry& registry) {
  registry.add(StructureInfo{
      "octree",
      "regular octree over the bounding cube, items referenced in every child they overlap",
      "O(N log N)", "O(log N)", octree_params().specs(),
      structure_from<Octree>(octree_params(), "octree")});
}

}  // namespace pcrt
