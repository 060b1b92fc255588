// Spatial kd-tree (thesis section 5.4; Wald and Seidel 2005, Hubo et al. 2006, Cai et al. 2011).
// Split: the axis of widest spread of the item centres (clamped to the cell), at their median,
// so depth grows like log2(N/K) and the build costs O(N log N) (nth_element per level). A node
// stays a leaf when over 40% of its items would straddle the plane (splitting would not pay).
// Empty space is cut off first: a side of the cell over 30% empty becomes an empty leaf. An item is
// referenced by every leaf its footprint box overlaps (inclusive), so no hit is lost at a plane.
// Traversal: front to back with a stack of (node, t_enter, t_exit), as in pbrt's KdTreeAggregate.
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>

#include "core/offsets.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

struct KdNode {
  float split = 0;
  uint32_t axis = 3;  // 0..2 inner, 3 leaf
  uint32_t a =
      0;  // inner: index of the right child (the left one follows the node); leaf: first ref
  uint32_t b = 0;  // leaf: number of refs
};

// Nodes and references of a subtree, indices relative to its own arrays. Large subtrees are built
// in parallel into their own Subtree and spliced in order, so the layout (and every count) is the
// same for any number of threads.
struct Subtree {
  std::vector<KdNode> nodes;
  std::vector<uint32_t> refs;

  void append(const Subtree& sub) {
    (void)offset32(refs.size() + sub.refs.size(), "kd_tree");  // every shifted offset fits
    const auto node_base = uint32_t(nodes.size()), ref_base = uint32_t(refs.size());
    for (KdNode n : sub.nodes) {
      n.a += n.axis == 3 ? ref_base : node_base;
      nodes.push_back(n);
    }
    refs.insert(refs.end(), sub.refs.begin(), sub.refs.end());
  }
};

constexpr size_t kParallelBuildItems = 50000;

struct KdTreeParams {
  size_t leaf_size = 8;
  int max_depth = 40;
  double max_straddle = 0.4;
};
const ParamList<KdTreeParams>& kd_tree_params() {
  using P = KdTreeParams;
  static const auto l =
      ParamList<P>()
          .add(&P::leaf_size, {"leaf_size", 8, 1, 1e6,
                               "stop splitting at this many items (K of the leaf-based methods)"})
          .add(&P::max_depth, {"max_depth", 40, 0, 100, "maximum depth"})
          .add(&P::max_straddle,
               {"max_straddle", 0.4, 0, 0.9,
                "stop splitting when more than this fraction of the items straddle the plane"});
  return l;
}

class KdTree final : public Structure {
 public:
  explicit KdTree(const KdTreeParams& p)
      : leaf_size_(p.leaf_size), max_depth_(p.max_depth), max_straddle_(p.max_straddle) {}

  // Sum over leaves of references x levels from the root (the build's partitioning work).
  [[nodiscard]] uint64_t item_visits(uint32_t node, uint64_t level) const {
    if (nodes_.empty()) return 0;
    const KdNode& n = nodes_[node];
    if (n.axis == 3) return uint64_t(n.b) * level;
    return item_visits(node + 1, level + 1) + item_visits(n.a, level + 1);
  }

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    bounds_ = items_.bounds();
    std::vector<uint32_t> all(items_.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    Subtree tree;
    if (!all.empty()) build_node(tree, std::move(all), bounds_, 0);
    nodes_ = std::move(tree.nodes);
    refs_ = std::move(tree.refs);
    nodes_.shrink_to_fit();
    refs_.shrink_to_fit();
    counters.add(kBuildNodes, nodes_.size());
    counters.add(kBuildItemRefs, refs_.size());
    counters.add(kBuildItemVisits, item_visits(0, 1));
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

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return refs_; }
  [[nodiscard]] size_t memory_bytes() const override {
    return nodes_.capacity() * sizeof(KdNode) + refs_.capacity() * sizeof(uint32_t);
  }

 private:
  // kAny: an occlusion query, ended by the first leaf that reports a hit.
  template <bool kAny>
  bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit, OpCounters& counters) const {
    if (nodes_.empty()) return false;
    const Vec3 inv = ray.d.cwiseInverse();
    float tmin = 0, tmax = 0;
    if (!bounds_.intersect(ray, inv, tmin, tmax)) return false;
    struct Todo {
      uint32_t node;
      float tmin, tmax;
    };
    std::array<Todo, 128> stack;
    int top = 0;
    uint32_t node = 0;
    bool found = false;
    while (true) {
      if (!may_improve(tmin, hit.t)) break;  // cells are disjoint: everything left is further
      counters.add(kNodesVisited);
      const KdNode& n = nodes_[node];
      if (n.axis < 3) {
        const int ax = int(n.axis);
        const bool below_first = ray.o[ax] < n.split || (ray.o[ax] == n.split && ray.d[ax] <= 0);
        const uint32_t first = below_first ? node + 1 : n.a;
        const uint32_t second = below_first ? n.a : node + 1;
        if (ray.d[ax] == 0) {
          node = first;
          continue;
        }
        const float tplane = (n.split - ray.o[ax]) * inv[ax];
        if (tplane > tmax || tplane <= 0) {
          node = first;
        } else if (tplane < tmin) {
          node = second;
        } else {
          stack[size_t(top++)] = Todo{second, tplane, tmax};
          node = first;
          tmax = tplane;
        }
        continue;
      }
      if (n.b > 0) {
        counters.add(kLeavesVisited);
        counters.add(kItemsVisited, n.b);
        const LeafVisit visit{{refs_.data() + n.a, n.b}, tmin, tmax};
        if constexpr (kAny) {
          if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
        } else {
          found |= leaf.intersect_leaf(ray, visit, hit, counters);
        }
      }
      if (top == 0) break;
      const Todo& t = stack[size_t(--top)];
      node = t.node;
      tmin = t.tmin;
      tmax = t.tmax;
    }
    return found;
  }

  static void make_leaf(Subtree& out, const std::vector<uint32_t>& items) {
    out.nodes.push_back(KdNode{0, 3, offset32(out.refs.size(), "kd_tree"), uint32_t(items.size())});
    out.refs.insert(out.refs.end(), items.begin(), items.end());
  }

  // Recursion depth is bounded by max_depth (at most 100, see the parameter range).
  void build_node(Subtree& out, std::vector<uint32_t> items, const Aabb& cell, int depth) const {
    if (depth >= max_depth_) return make_leaf(out, items);
    if (cut_empty_space(out, items, cell, depth)) return;
    if (items.size() <= leaf_size_) return make_leaf(out, items);
    // The axis along which the item centres (clamped to the cell) spread most: on a surface
    // patch that is a tangent direction. Splitting the cell's longest axis instead would cut
    // along the normal, through the surface, where every footprint straddles the plane.
    Aabb spread;
    for (uint32_t i : items) spread.extend(items_.positions[i].cwiseMax(cell.lo).cwiseMin(cell.hi));
    const Vec3 ext = spread.extent();
    int ax = 0;
    if (ext.y() > ext[ax]) ax = 1;
    if (ext.z() > ext[ax]) ax = 2;
    if (!(ext[ax] > 0)) return make_leaf(out, items);
    auto key = [&](uint32_t i) {
      return std::clamp(items_.positions[i][ax], cell.lo[ax], cell.hi[ax]);
    };
    auto mid = items.begin() + long(items.size() / 2);
    std::nth_element(items.begin(), mid, items.end(),
                     [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    float split = key(*mid);
    // A median on the cell's wall would give an empty side; take the cell's middle instead.
    if (split <= cell.lo[ax] || split >= cell.hi[ax]) split = cell.center()[ax];
    std::vector<uint32_t> left, right;
    left.reserve(items.size() * 3 / 4);
    right.reserve(items.size() * 3 / 4);
    for (uint32_t i : items) {
      const Aabb b = items_.box(i);
      if (b.lo[ax] <= split) left.push_back(i);
      if (b.hi[ax] >= split) right.push_back(i);
    }
    // A split must pay: if over max_straddle of the items straddle the plane (footprints wider
    // than the cell, or identical points) the children would only duplicate references; stop
    // here (such leaves exceed leaf_size) rather than recurse to max_depth.
    if (left.size() + right.size() > items.size() + size_t(double(items.size()) * max_straddle_))
      return make_leaf(out, items);
    items.clear();
    items.shrink_to_fit();
    Aabb lcell = cell, rcell = cell;
    lcell.hi[ax] = split;
    rcell.lo[ax] = split;
    const size_t me = out.nodes.size();
    out.nodes.push_back(KdNode{split, uint32_t(ax), 0, 0});
    if (left.size() + right.size() < kParallelBuildItems) {
      build_node(out, std::move(left), lcell, depth + 1);
      out.nodes[me].a = uint32_t(out.nodes.size());
      build_node(out, std::move(right), rcell, depth + 1);
      return;
    }
    Subtree lsub, rsub;
    tbb::parallel_invoke([&] { build_node(lsub, std::move(left), lcell, depth + 1); },
                         [&] { build_node(rsub, std::move(right), rcell, depth + 1); });
    out.append(lsub);
    out.nodes[me].a = uint32_t(out.nodes.size());
    out.append(rsub);
  }

  // Where the items' footprints leave over 30% of the cell empty along an axis, split there first
  // (the empty side becomes an empty leaf). Without this, cells on a surface become needles along
  // the normal, and an oblique ray crosses ever more of them as N grows.
  bool cut_empty_space(Subtree& out, std::vector<uint32_t>& items, const Aabb& cell,
                       int depth) const {
    Aabb reach;
    for (uint32_t i : items) reach.extend(items_.box(i));
    reach.lo = reach.lo.cwiseMax(cell.lo);
    reach.hi = reach.hi.cwiseMin(cell.hi);
    const Vec3 ext = cell.extent();
    int best_axis = -1;
    bool low_side = false;
    float best = 0.3f;
    for (int a = 0; a < 3; ++a) {
      if (!(ext[a] > 0)) continue;
      const float lo_gap = (reach.lo[a] - cell.lo[a]) / ext[a],
                  hi_gap = (cell.hi[a] - reach.hi[a]) / ext[a];
      if (lo_gap > best) best = lo_gap, best_axis = a, low_side = true;
      if (hi_gap > best) best = hi_gap, best_axis = a, low_side = false;
    }
    if (best_axis < 0) return false;
    const int ax = best_axis;
    const float split = low_side ? reach.lo[ax] : reach.hi[ax];
    Aabb lcell = cell, rcell = cell;
    lcell.hi[ax] = split;
    rcell.lo[ax] = split;
    const size_t me = out.nodes.size();
    out.nodes.push_back(KdNode{split, uint32_t(ax), 0, 0});
    if (low_side) {
      make_leaf(out, {});
      out.nodes[me].a = uint32_t(out.nodes.size());
      build_node(out, std::move(items), rcell, depth + 1);
    } else {
      build_node(out, std::move(items), lcell, depth + 1);
      out.nodes[me].a = uint32_t(out.nodes.size());
      make_leaf(out, {});
    }
    return true;
  }

  size_t leaf_size_;
  int max_depth_;
  double max_straddle_;
  ItemSet items_;
  Aabb bounds_;
  std::vector<KdNode> nodes_;
  std::vector<uint32_t> refs_;
};

}  // namespace

void register_kd_tree(StructureRegistry& registry) {
  registry.add(
      StructureInfo{"kd_tree",
                    "spatial kd-tree, median split of the longest axis, items referenced in every "
                    "leaf they overlap",
                    "O(N log N)", "O(log N)", kd_tree_params().specs(),
                    structure_from<KdTree>(kd_tree_params(), "kd_tree")});
}

}  // namespace pcrt
