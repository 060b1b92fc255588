// The loose octree (octree loose=1; loose_octree.hpp): the octree's cells and leaf rule (split at
// the cell centre while a cell holds over leaf_size items, to max_depth), each item placed once,
// by its centre, and the child boxes grown to the footprints they hold. A cell's occupied octants
// are one 8-wide node's children (wide_node.hpp), walked as the bvh walks its nodes.
#include "structures/loose_octree.hpp"

#include <algorithm>
#include <array>
#include <numeric>

#include "core/offsets.hpp"
#include "structures/build_buffer.hpp"
#include "structures/wide_walk.hpp"

namespace pcrt {
namespace {

// A cell of the build: its footprints' box and, for a leaf, its first reference and count; for a
// cell split further, count 0 and its stored children, cells_[kids, kids + nkids).
struct Cell {
  Aabb box;
  uint32_t first = 0;
  uint32_t count = 0;
  uint32_t kids = 0;
  uint32_t nkids = 0;
};

// Where references are laid out in blocks of this many (DiscBlock's lanes): a leaf of up to
// kBlock items never straddles two, as in the bvh (align_leaves).
constexpr uint32_t kBlock = 8;

class LooseOctree final : public Structure {
 public:
  LooseOctree(size_t leaf_size, int max_depth)
      : leaf_size_(std::max<size_t>(leaf_size, 1)),
        max_depth_(std::min(max_depth, kWideWalkMaxDepth - 1)) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    const auto n = uint32_t(set.size());
    wide_.clear();
    refs_.clear();
    cells_.clear();
    cells_made_ = visits_ = 0;
    if (n > 0) {
      order_.resize(n);
      std::iota(order_.begin(), order_.end(), 0u);
      octant_.resize(n);
      scratch_.resize(n);
      refs_.reserve(n + n / 4);
      const OctreeCube cube = octree_root_cube(set.bounds());
      cells_.emplace_back();
      make_cell(0, 0, n, cube.lo, cube.side, 0);
      release(order_);
      release(octant_);
      release(scratch_);
      emit(0);
      release(cells_);
    }
    wide_.shrink_to_fit();
    refs_.shrink_to_fit();
    counters.add(kBuildNodes, cells_made_);
    counters.add(kBuildItemRefs, n);
    counters.add(kBuildItemVisits, visits_);
  }

  bool closest_hit(const Ray& ray, const LeafIntersector& leaf, Hit& hit,
                   OpCounters& counters) const override {
    return avx2_ ? walk_avx2<false>(ray, leaf, hit, counters)
                 : walk_wide<false, node_test_sse>(wide_, refs_.data(), ray, leaf, hit, counters);
  }

  bool any_hit(const Ray& ray, const LeafIntersector& leaf, OpCounters& counters) const override {
    Hit hit;
    hit.t = ray.tmax;
    return avx2_ ? walk_avx2<true>(ray, leaf, hit, counters)
                 : walk_wide<true, node_test_sse>(wide_, refs_.data(), ray, leaf, hit, counters);
  }

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return refs_; }
  [[nodiscard]] size_t memory_bytes() const override {
    return wide_.capacity() * sizeof(WideNode) + refs_.capacity() * sizeof(uint32_t);
  }

 private:
  // The walk compiled for AVX2, so that the node test inlines into it.
  template <bool kAny>
  __attribute__((target("avx2"))) bool walk_avx2(const Ray& ray, const LeafIntersector& leaf,
                                                 Hit& hit, OpCounters& counters) const {
    return walk_wide<kAny, node_test_avx2>(wide_, refs_.data(), ray, leaf, hit, counters);
  }

  // Builds cells_[me], the cell [lo, lo + side] of the items order_[begin, end) (their centres
  // lie in it). A cell whose items all lie in one octant is no node (the walk would test one box
  // for nothing): the octant takes its place, a level deeper. A split cell's stored children are
  // made one block, then built in child order.
  void make_cell(uint32_t me, uint32_t begin, uint32_t end, Vec3 lo, float side, int depth) {
    std::array<uint32_t, 8> count{};
    bool split = false;
    while (!split && end - begin > leaf_size_ && depth < max_depth_ && side > 0) {
      count = octant_counts(begin, end, lo, 0.5f * side);
      const auto only = uint32_t(
          std::find_if(count.begin(), count.end(), [&](uint32_t c) { return c == end - begin; }) -
          count.begin());
      split = only == 8;
      if (!split) lo = octant_lo(lo, 0.5f * side, only), side *= 0.5f, ++depth;
    }
    ++cells_made_;
    if (!split) return make_leaf(me, begin, end, depth);
    partition(begin, end, count);
    const auto kids = node_index32(cells_.size(), "octree (loose)");
    const auto nkids = uint32_t(8 - std::count(count.begin(), count.end(), 0u));
    cells_.resize(cells_.size() + nkids);
    cells_[me].kids = kids, cells_[me].nkids = nkids;
    const float half = 0.5f * side;
    uint32_t at = begin, k = kids;
    for (uint32_t c = 0; c < 8; ++c) {
      if (count[c] == 0) continue;
      make_cell(k, at, at + count[c], octant_lo(lo, half, c), half, depth + 1);
      cells_[me].box.extend(cells_[k++].box);
      at += count[c];
    }
  }

  // The wide node of split cell c (or, for a leaf root, one holding just it): its children are
  // c's, the largest split one replaced by its own children while they fit in the eight slots
  // (as WideCollapse gathers a binary tree's), so a node's slots are not half empty where a
  // surface crosses half of a cell's octants. The leaves, and so every leaf visit, are the
  // cells'. Returns the node's index.
  uint32_t emit(uint32_t c) {
    std::array<uint32_t, kWideWidth> slots{};
    uint32_t m = 0;
    if (cells_[c].count > 0) slots[m++] = c;
    for (uint32_t k = 0; cells_[c].count == 0 && k < cells_[c].nkids; ++k)
      slots[m++] = cells_[c].kids + k;
    while (true) {
      int open = -1;
      float best = -1;
      for (uint32_t k = 0; k < m; ++k) {
        const Cell& x = cells_[slots[k]];
        const float a = half_area(x.box);
        if (x.count == 0 && m - 1 + x.nkids <= kWideWidth && a > best) best = a, open = int(k);
      }
      if (open < 0) break;
      const Cell x = cells_[slots[size_t(open)]];
      slots[size_t(open)] = x.kids;
      for (uint32_t k = 1; k < x.nkids; ++k) slots[m++] = x.kids + k;
    }
    const uint32_t me = new_node();
    for (uint32_t k = 0; k < m; ++k) {
      const Cell& x = cells_[slots[k]];
      put(me, int(k), x.box, x.count > 0 ? x.first : 0, x.count);
    }
    for (uint32_t k = 0; k < m; ++k)
      if (cells_[slots[k]].count == 0) wide_[me].child[k] = emit(slots[k]);
    return me;
  }

  static float half_area(const Aabb& b) {
    if (b.empty()) return 0;
    const Vec3 e = b.extent();
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  }

  static Vec3 octant_lo(const Vec3& lo, float half, uint32_t c) {
    return lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
  }

  // Each item's octant of the cell at lo (bit a: at or above the mid-plane of axis a) into
  // octant_, and how many items each octant holds.
  std::array<uint32_t, 8> octant_counts(uint32_t begin, uint32_t end, const Vec3& lo, float half) {
    const Vec3 mid = lo + Vec3::Constant(half);
    std::array<uint32_t, 8> count{};
    for (uint32_t k = begin; k < end; ++k) {
      const Vec3& p = items_.positions[order_[k]];
      const auto c = uint8_t(uint32_t(p.x() >= mid.x()) | uint32_t(p.y() >= mid.y()) << 1 |
                             uint32_t(p.z() >= mid.z()) << 2);
      octant_[k] = c;
      ++count[c];
    }
    return count;
  }

  // Sorts order_[begin, end) by octant, keeping the order within each (a counting sort).
  void partition(uint32_t begin, uint32_t end, const std::array<uint32_t, 8>& count) {
    std::array<uint32_t, 8> at{};
    for (uint32_t c = 1; c < 8; ++c) at[c] = at[c - 1] + count[c - 1];
    for (uint32_t k = begin; k < end; ++k) scratch_[begin + at[octant_[k]]++] = order_[k];
    std::copy(scratch_.begin() + begin, scratch_.begin() + end, order_.begin() + begin);
  }

  // A leaf of order_[begin, end) at this depth, its references appended to refs_ so that none
  // touches more blocks of kBlock than its size needs (the gap holds copies of the reference before
  // it, never visited: leaves are (first, count) pieces).
  void make_leaf(uint32_t me, uint32_t begin, uint32_t end, int depth) {
    const uint32_t count = end - begin;
    const size_t pos = refs_.size();
    const auto in_block = uint32_t(pos % kBlock);
    if (in_block != 0 && (count > kBlock || in_block + count > kBlock))
      refs_.resize(pos + kBlock - in_block, refs_.back());
    Cell& leaf = cells_[me];
    leaf.first = node_index32(refs_.size(), "octree (loose) references");
    leaf.count = count;
    for (uint32_t k = begin; k < end; ++k) {
      refs_.push_back(order_[k]);
      leaf.box.extend(items_.box(order_[k]));
    }
    visits_ += uint64_t(count) * uint64_t(depth + 1);
  }

  // A new wide node, every slot empty (child 0 and count 0; the root is no one's child).
  uint32_t new_node() {
    const uint32_t me = node_index32(wide_.size(), "octree (loose)");
    WideNode& w = wide_.emplace_back();
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < kWideWidth; ++k) w.lo[a][k] = kInfinity, w.hi[a][k] = -kInfinity;
    return me;
  }

  void put(uint32_t node, int k, const Aabb& box, uint32_t child, uint32_t count) {
    WideNode& w = wide_[node];
    for (int a = 0; a < 3; ++a) w.lo[a][k] = box.lo[a], w.hi[a][k] = box.hi[a];
    w.child[k] = child;
    w.count[k] = count;
  }

  size_t leaf_size_;
  int max_depth_;
  bool avx2_ = wide_nodes_use_avx2();
  ItemSet items_;  // the caller's, read by the build only
  std::vector<WideNode> wide_;
  std::vector<uint32_t> refs_;  // items in leaf order, each leaf contiguous
  std::vector<uint32_t> order_, scratch_;
  std::vector<uint8_t> octant_;
  std::vector<Cell> cells_;  // the build's tree, emitted into wide_
  uint64_t cells_made_ = 0, visits_ = 0;
};

}  // namespace

std::unique_ptr<Structure> make_loose_octree(size_t leaf_size, int max_depth) {
  return std::make_unique<LooseOctree>(leaf_size, max_depth);
}

}  // namespace pcrt
