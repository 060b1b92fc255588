// Spatial kd-tree (thesis section 5.4; Wald and Seidel 2005, Hubo et al. 2006, Cai et al. 2011).
// Split: the axis of widest spread of the item centres (clamped to the cell), at their median,
// so depth grows like log2(N/K) and the build costs O(N log N) (nth_element per level). A node
// stays a leaf when over 40% of its items would straddle the plane (splitting would not pay).
// Empty space is cut off first: a side of the cell over 30% empty becomes an empty leaf. An item is
// referenced by every leaf its footprint box overlaps (inclusive), so no hit is lost at a plane.
// Traversal: front to back with a stack of (node, t_enter, t_exit), as in pbrt's KdTreeAggregate.
// Each leaf of a method hit on its discs may keep the slab of its discs along their mean normal
// (leaf_slabs, as the octree's): a ray that misses it within the leaf's interval (from
// ItemSet::hits_before_leaf before it) is not handed the leaf.
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "core/offsets.hpp"
#include "structures/build_buffer.hpp"
#include "structures/leaf_slab.hpp"
#include "structures/structure.hpp"
#include "structures/tree_nodes.hpp"

namespace pcrt {
namespace {

// A subtree's nodes and references, indices relative to its own arrays, and the references of
// the node being built: the top segment of `stack`, from a given start to the end. Building a
// node pops its segment; splitting one replaces it by its children's, the right below the left,
// so the left one is built first. Large subtrees are built in parallel, each into its own Subtree
// from a copy of its segment, and spliced in order, so the layout (and every count) is the same
// for any number of threads.
struct Subtree {
  ChunkedArray<KdNode> nodes;
  ChunkedArray<uint32_t> refs;
  std::vector<uint32_t> stack;

  void append(Subtree&& sub) {
    (void)node_index32(nodes.size() + sub.nodes.size(), "kd_tree");  // every shifted index fits
    const auto node_base = uint32_t(nodes.size());
    const uint64_t ref_base = refs.size();
    nodes.splice(std::move(sub.nodes), [&](KdNode& n) { n = n.shifted(node_base, ref_base); });
    refs.splice(std::move(sub.refs), [](uint32_t&) {});
  }
};

constexpr size_t kParallelBuildItems = 50000;

// Where a node splits (the parameter `split`).
enum class KdSplit : uint8_t {
  kMedian = 0,  // the papers' rule: the median item centre on the axis of widest spread
  kSah = 1,     // the surface area heuristic over the items' boxes clipped to the cell (binned)
};

struct KdTreeParams {
  size_t leaf_size = 8;
  int max_depth = 40;
  double max_straddle = 0.4;
  KdSplit split = KdSplit::kMedian;
  bool leaf_slabs = true;
};

// The SAH's costs of a traversal step and of an item test: Wald and Havran's (2006) 15 and 20,
// the item's divided by 8, as the leaf kernels test eight discs a pass (disc_lanes.hpp).
constexpr float kSahTraversal = 15.0f, kSahItem = 20.0f / 8.0f;
constexpr int kSahBins = 32;
const ParamList<KdTreeParams>& kd_tree_params() {
  using P = KdTreeParams;
  static const auto l =
      ParamList<P>()
          .add(&P::leaf_size, {"leaf_size", 8, 1, 1e6,
                               "stop splitting at this many items (K of the leaf-based methods)"})
          .add(&P::max_depth, {"max_depth", 40, 0, 100, "maximum depth"})
          .add(&P::max_straddle,
               {"max_straddle", 0.4, 0, 0.9,
                "stop splitting when more than this fraction of the items straddle the plane "
                "(median splits)"})
          .add(&P::split,
               {"split", 0, 0, 1,
                "0: the median item centre on the axis of widest spread (the papers' rule); 1: "
                "the surface area heuristic over the items' boxes clipped to the cell, 32 bins "
                "an axis (Wald and Havran 2006), a leaf where no split costs less"})
          .add(&P::leaf_slabs,
               {"leaf_slabs", 1, 0, 1,
                "1: for methods hit on their discs, a leaf whose discs lie in a slab thinner than "
                "half its cell keeps the slab (16 bytes a node) and a ray whose interval in the "
                "leaf misses it does not visit the leaf; 0: without"});
  return l;
}

class KdTree final : public Structure {
 public:
  explicit KdTree(const KdTreeParams& p)
      : leaf_size_(p.leaf_size),
        max_depth_(p.max_depth),
        max_straddle_(p.max_straddle),
        split_(p.split),
        leaf_slabs_(p.leaf_slabs) {}

  // Sum over leaves of references x levels from the root (the build's partitioning work).
  [[nodiscard]] uint64_t item_visits(uint32_t node, uint64_t level) const {
    if (nodes_.empty()) return 0;
    const KdNode& n = nodes_[node];
    if (n.is_leaf()) return uint64_t(n.count()) * level;
    return item_visits(node + 1, level + 1) + item_visits(n.a, level + 1);
  }

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    bounds_ = items_.bounds();
    Subtree tree;
    tree.stack.resize(items_.size());
    for (uint32_t i = 0; i < tree.stack.size(); ++i) tree.stack[i] = i;
    if (!tree.stack.empty()) build_node(tree, 0, bounds_, 0);
    release(tree.stack);
    nodes_ = tree.nodes.flatten();
    refs_ = tree.refs.flatten();
    slabs_.clear();
    if (leaf_slabs_ && items_.hits_on_discs && !items_.disc_normals.empty() && !nodes_.empty()) {
      slabs_.assign(nodes_.size(), LeafSlab{});
      keep_thin_slabs(0, bounds_);
    }
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
    return nodes_.capacity() * sizeof(KdNode) + refs_.capacity() * sizeof(uint32_t) +
           slabs_.capacity() * sizeof(LeafSlab);
  }

 private:
  struct Todo {
    uint32_t node;
    float tmin, tmax;
  };

  // kAny: an occlusion query, ended by the first leaf that reports a hit.
  template <bool kAny>
  bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit, OpCounters& counters) const {
    if (nodes_.empty()) return false;
    const Vec3 inv = ray.d.cwiseInverse();
    float tmin = 0, tmax = 0;
    if (!bounds_.intersect(ray, inv, tmin, tmax)) return false;
    std::array<Todo, 128> stack;
    int top = 0;
    uint32_t node = 0;
    bool found = false;
    while (true) {
      // Front to back, a cell past the hit ends the walk: everything left is further. An
      // occlusion walk goes far side first, so there only this cell is skipped.
      const bool beyond = !may_improve(tmin, hit.t);
      if (beyond && !kAny) break;
      if (!beyond) {
        counters.add(kNodesVisited);
        const KdNode& n = nodes_[node];
        if (n.axis < 3) {
          node = descend<kAny>(node, n, ray, inv, tmin, tmax, stack.data(), top);
          continue;
        }
        if (n.b > 0 &&
            (!n.tests_slab() || crosses_slab(slabs_[node], ray, slab_interval(ray, tmin, tmax)))) {
          counters.add(kLeavesVisited);
          counters.add(kItemsVisited, n.b);
          const LeafVisit visit{{refs_.data() + n.first(), n.b}, tmin, tmax};
          if constexpr (kAny) {
            if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
          } else {
            found |= leaf.intersect_leaf(ray, visit, hit, counters);
          }
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

  // The ray interval whose crossings leaf [tmin, tmax] may report: from hits_before_leaf before
  // it (crossings before ray.tmin are no hits). Neighbouring leaves share the plane's t, so no
  // gap is left between their intervals (the octree's cells, summed from the root, may leave one).
  [[nodiscard]] std::pair<float, float> slab_interval(const Ray& ray, float tmin,
                                                      float tmax) const {
    return {std::max(tmin - items_.hits_before_leaf, ray.tmin), tmax};
  }

  // Marks the leaves of the subtree at `node` (cell `cell`) whose discs lie in a thin slab, and
  // keeps their slabs. Recursion depth is bounded by max_depth (at most 100).
  void keep_thin_slabs(uint32_t node, const Aabb& cell) {
    KdNode& n = nodes_[node];
    if (n.is_leaf()) {
      if (n.b == 0) return;
      const LeafSlab slab = slab_of(items_, {refs_.data() + n.first(), n.b});
      if (!slab.thin(slab.normal().cwiseAbs().dot(cell.extent()))) return;
      slabs_[node] = slab;
      n.axis = KdNode::kLeafSlab;
      return;
    }
    const int ax = int(n.axis);
    Aabb lcell = cell, rcell = cell;
    lcell.hi[ax] = n.split;
    rcell.lo[ax] = n.split;
    const uint32_t right = n.a;
    keep_thin_slabs(node + 1, lcell);
    keep_thin_slabs(right, rcell);
  }

  // Steps into inner node n, which the ray crosses over [tmin, tmax]: returns the child to walk
  // next, narrowing the interval to it, and pushes the other child where the ray reaches both.
  // Closest hits take the near side first; occlusion the far side (a shadow ray leaves a surface
  // whose own discs fill the near cells and rarely block it; an unblocked ray visits both).
  template <bool kAny>
  uint32_t descend(uint32_t node, const KdNode& n, const Ray& ray, const Vec3& inv, float& tmin,
                   float& tmax, Todo* stack, int& top) const {
    const int ax = int(n.axis);
    const bool below_first = ray.o[ax] < n.split || (ray.o[ax] == n.split && ray.d[ax] <= 0);
    const uint32_t first = below_first ? node + 1 : n.a;
    const uint32_t second = below_first ? n.a : node + 1;
    if (ray.d[ax] == 0) return first;
    const float tplane = (n.split - ray.o[ax]) * inv[ax];
    if (tplane > tmax || tplane <= 0) return first;
    if (tplane < tmin) return second;
    if (kAny) {
      stack[top++] = Todo{first, tmin, tplane};
      tmin = tplane;
      return second;
    }
    stack[top++] = Todo{second, tplane, tmax};
    tmax = tplane;
    return first;
  }

  // The node's references as a leaf, popped from the stack.
  static void make_leaf(Subtree& out, size_t begin) {
    const size_t n = out.stack.size() - begin;
    out.nodes.push_back(KdNode::leaf(out.refs.size(), uint32_t(n)));
    out.refs.append({out.stack.data() + begin, n});
    out.stack.resize(begin);
  }
  static void make_empty_leaf(Subtree& out) {
    out.nodes.push_back(KdNode::leaf(out.refs.size(), 0));
  }

  [[nodiscard]] float lo(uint32_t i, int ax) const { return items_.box_lo(i, ax); }
  [[nodiscard]] float hi(uint32_t i, int ax) const { return items_.box_hi(i, ax); }

  // Builds the subtree of the references stack[begin, end) and pops them. Recursion depth is
  // bounded by max_depth (at most 100, see the parameter range).
  void build_node(Subtree& out, size_t begin, const Aabb& cell, int depth) const {
    std::vector<uint32_t>& st = out.stack;
    const size_t n = st.size() - begin;
    if (depth >= max_depth_) return make_leaf(out, begin);
    if (cut_empty_space(out, begin, cell, depth)) return;
    if (n <= leaf_size_) return make_leaf(out, begin);
    const Plane plane =
        split_ == KdSplit::kSah ? sah_split(st, begin, cell) : median_split(st, begin, cell);
    if (plane.axis < 0) return make_leaf(out, begin);
    const int ax = plane.axis;
    const float split = plane.at;
    size_t nl = 0, nr = 0;
    for (size_t k = begin; k < st.size(); ++k) {
      nl += lo(st[k], ax) <= split;
      nr += hi(st[k], ax) >= split;
    }
    // A split must pay: if over max_straddle of the items straddle the plane (footprints wider
    // than the cell, or identical points) the children would only duplicate references; stop
    // here (such leaves exceed leaf_size) rather than recurse to max_depth. (The SAH weighs the
    // duplicates itself.)
    if (split_ == KdSplit::kMedian && nl + nr > n + size_t(double(n) * max_straddle_))
      return make_leaf(out, begin);
    Aabb lcell = cell, rcell = cell;
    lcell.hi[ax] = split;
    rcell.lo[ax] = split;
    const auto me = out.nodes.push_back(KdNode::inner(split, ax));
    if (nl + nr < kParallelBuildItems) {
      split_in_place(st, begin, ax, split, nl);
      build_node(out, begin + nr, lcell, depth + 1);
      out.nodes[me].a = node_index32(out.nodes.size(), "kd_tree");
      build_node(out, begin, rcell, depth + 1);
      return;
    }
    Subtree lsub, rsub;
    lsub.stack.reserve(nl);
    rsub.stack.reserve(nr);
    for (size_t k = begin; k < st.size(); ++k) {
      if (lo(st[k], ax) <= split) lsub.stack.push_back(st[k]);
      if (hi(st[k], ax) >= split) rsub.stack.push_back(st[k]);
    }
    st.resize(begin);
    if (begin == 0) release(st);  // nothing below: free it while children build
    tbb::parallel_invoke([&] { build_node(lsub, 0, lcell, depth + 1); },
                         [&] { build_node(rsub, 0, rcell, depth + 1); });
    out.append(std::move(lsub));
    out.nodes[me].a = node_index32(out.nodes.size(), "kd_tree");
    out.append(std::move(rsub));
  }

  struct Plane {
    int axis = -1;  // -1: no split (a leaf)
    float at = 0;
  };

  // The papers' plane: the median item centre (clamped to the cell) on the axis of widest spread.
  Plane median_split(std::vector<uint32_t>& st, size_t begin, const Aabb& cell) const {
    const int ax = spread_axis(st, begin, cell);
    if (ax < 0) return {};
    auto key = [&](uint32_t i) {
      return std::clamp(items_.positions[i][ax], cell.lo[ax], cell.hi[ax]);
    };
    const auto first = st.begin() + long(begin), mid = first + long((st.size() - begin) / 2);
    std::nth_element(first, mid, st.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    float split = key(*mid);
    // A median on the cell's wall would give an empty side; take the cell's middle instead.
    if (split <= cell.lo[ax] || split >= cell.hi[ax]) split = cell.center()[ax];
    return {ax, split};
  }

  // The SAH's plane: on each axis, the items' boxes clipped to the cell counted into kSahBins
  // bins by where they start and end; the bin boundary whose children cost least, a leaf if none
  // costs less than testing every item here (cost = traversal + item cost x the children's items
  // weighted by their share of the cell's surface).
  Plane sah_split(const std::vector<uint32_t>& st, size_t begin, const Aabb& cell) const {
    const Vec3 ext = cell.extent();
    const auto half_area = [](const Vec3& e) {
      return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
    };
    const float area = half_area(ext);
    if (!(area > 0)) return {};
    Plane best;
    float best_cost = kSahItem * float(st.size() - begin);
    for (int ax = 0; ax < 3; ++ax) {
      if (!(ext[ax] > 0)) continue;
      std::array<uint32_t, kSahBins> starts{}, ends{};
      const float scale = float(kSahBins) / ext[ax];
      const auto bin = [&](float x) {
        const float b = (x - cell.lo[ax]) * scale;
        return b > 0 ? std::min(int(b), kSahBins - 1) : 0;  // NaN and below: bin 0
      };
      for (size_t k = begin; k < st.size(); ++k) {
        ++starts[size_t(bin(lo(st[k], ax)))];
        ++ends[size_t(bin(hi(st[k], ax)))];
      }
      const float step = ext[ax] / float(kSahBins);
      uint32_t left = 0, right = uint32_t(st.size() - begin);
      for (int j = 1; j < kSahBins; ++j) {  // the plane between bins j - 1 and j
        left += starts[size_t(j - 1)];
        right -= ends[size_t(j - 1)];
        const float at = cell.lo[ax] + float(j) * step;
        Vec3 le = ext, re = ext;
        le[ax] = at - cell.lo[ax];
        re[ax] = cell.hi[ax] - at;
        const float cost =
            kSahTraversal +
            kSahItem * (half_area(le) * float(left) + half_area(re) * float(right)) / area;
        if (cost < best_cost) best_cost = cost, best = {ax, at};
      }
    }
    return best;
  }

  // The axis along which the item centres (clamped to the cell) spread most, or -1 if they do
  // not spread: on a surface patch that is a tangent direction. Splitting the cell's longest axis
  // instead would cut along the normal, through the surface, where every footprint straddles.
  int spread_axis(const std::vector<uint32_t>& st, size_t begin, const Aabb& cell) const {
    Aabb spread;
    for (size_t k = begin; k < st.size(); ++k)
      spread.extend(items_.positions[st[k]].cwiseMax(cell.lo).cwiseMin(cell.hi));
    const Vec3 ext = spread.extent();
    int ax = 0;
    if (ext.y() > ext[ax]) ax = 1;
    if (ext.z() > ext[ax]) ax = 2;
    return ext[ax] > 0 ? ax : -1;
  }

  // Replaces stack[begin, end) by the references of the right child (boxes reaching the plane
  // from above) and above them those of the left child (from below), each in its order there: the
  // left list is written past the end, the right one compacted in place, the left moved down.
  void split_in_place(std::vector<uint32_t>& st, size_t begin, int ax, float split,
                      size_t nl) const {
    const size_t end = st.size();
    st.resize(end + nl);
    size_t w = end;
    for (size_t k = begin; k < end; ++k)
      if (lo(st[k], ax) <= split) st[w++] = st[k];
    size_t r = begin;
    for (size_t k = begin; k < end; ++k)
      if (hi(st[k], ax) >= split) st[r++] = st[k];
    std::memmove(st.data() + r, st.data() + end, nl * sizeof(uint32_t));
    st.resize(r + nl);
  }

  // Where the items' footprints leave over 30% of the cell empty along an axis, split there first
  // (the empty side becomes an empty leaf). Without this, cells on a surface become needles along
  // the normal, and an oblique ray crosses ever more of them as N grows.
  bool cut_empty_space(Subtree& out, size_t begin, const Aabb& cell, int depth) const {
    Aabb reach;
    for (size_t k = begin; k < out.stack.size(); ++k) reach.extend(items_.box(out.stack[k]));
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
    const auto me = out.nodes.push_back(KdNode::inner(split, ax));
    if (low_side) {
      make_empty_leaf(out);
      out.nodes[me].a = node_index32(out.nodes.size(), "kd_tree");
      build_node(out, begin, rcell, depth + 1);
    } else {
      build_node(out, begin, lcell, depth + 1);
      out.nodes[me].a = node_index32(out.nodes.size(), "kd_tree");
      make_empty_leaf(out);
    }
    return true;
  }

  size_t leaf_size_;
  int max_depth_;
  double max_straddle_;
  KdSplit split_;
  bool leaf_slabs_;
  ItemSet items_;
  Aabb bounds_;
  std::vector<KdNode> nodes_;
  std::vector<uint32_t> refs_;
  std::vector<LeafSlab> slabs_;  // by node, if leaf_slabs (read for leaves marked kLeafSlab)
};

}  // namespace

namespace {

// Item order from results/scale/lean (its build's chunks grow: the larger of 10^7 and 10^8). The
// leaf slabs of methods hit on their discs add 16 B a node: goradia_2010's splats on the 10^7
// sphere, structure +4.5 B/item, peak +2.3 (results/scale/kd_slab), priced as 5 whichever the
// method (the estimate does not know whether it keeps them).
StructureFootprint kd_tree_footprint(const ParamValues& params) {
  const auto slabs = params.find("leaf_slabs");
  const size_t slab_bytes = slabs != params.end() && slabs->second == 0 ? 0 : 5;
  return {.item_order = 25 + slab_bytes,
          .leaf_order = 138 + slab_bytes,
          .references_per_item = 3.7};
}

}  // namespace

void register_kd_tree(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "kd_tree",
      .description = "spatial kd-tree, median split of the longest axis, items referenced in every "
                     "leaf they overlap",
      .build_claim = "O(N log N)",
      .query_claim = "O(log N)",
      .params = kd_tree_params().specs(),
      .create = structure_from<KdTree>(kd_tree_params(), "kd_tree"),
      .footprint = kd_tree_footprint,
  });
}

}  // namespace pcrt
