// Octree (thesis section 5.4, figure 1.3; Schaufler and Jensen 2000 and most splat methods):
// the bounding cube of all footprints split regularly into eight equal children until a node
// holds at most leaf_size items, reaches max_depth, or splitting stops paying (footprints wider
// than the cells: the fullest child keeps over half of the items; such leaves exceed leaf_size).
// The splits go by the items' footprint boxes; a leaf references the items whose box overlaps it
// and, for discs the method hits only on the disc, whose plane cuts its cube (a quarter fewer
// references on a sphere); a child no item reaches is not stored. A leaf's references are 16-bit
// offsets from its lowest item where they fit (compact_refs; items are in Morton order, so a cell's
// neighbours are mostly near), decoded onto the stack when a ray reaches it. Each stored node also
// keeps the box of its items' footprints within its cell, 8 bits a side relative to the cell
// (child_bounds, for methods whose hits are points of their discs): a surface fills a thin slab of
// most cells it crosses, and a ray that crosses the cell but misses the slab does not visit it.
// Each leaf of such a method also keeps the slab of its discs along their mean normal (leaf_slabs):
// once the discs are wider than the cells their box fills the cell, but they stay nearly parallel,
// and a ray that misses the slab within its cell (from ItemSet::hits_before_leaf before it) is not
// handed the leaf.
// Traversal: depth first, the children a ray crosses sorted by where it enters their boxes, so
// leaves come front to back (cells, and so their boxes, are disjoint).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "core/offsets.hpp"
#include "structures/build_buffer.hpp"
#include "structures/leaf_slab.hpp"
#include "structures/loose_octree.hpp"
#include "structures/structure.hpp"
#include "structures/tree_nodes.hpp"
#include "structures/wide_node.hpp"

namespace pcrt {
namespace {

// The box of a node's footprints within its cell [lo, lo + side]: per axis lo + q * quantum with
// quantum = side / 254, so that q = 255 reaches past the cell's far side whatever the rounding
// (q = 0 is the cell's near side exactly). lo[0] > hi[0]: no footprint (a leaf the disc planes
// all missed).
struct CellBox {
  std::array<uint8_t, 3> lo{255, 255, 255};
  std::array<uint8_t, 3> hi{0, 0, 0};
  [[nodiscard]] bool empty() const { return lo[0] > hi[0]; }
};
static_assert(sizeof(CellBox) == 6);

// The CellBoxes of one node's k stored children (nodes first .. first + k - 1) at byte 6 * first,
// axis by axis: the lo bytes of axis a at a * k + rank, the hi bytes at (3 + a) * k + rank. The
// same 6 bytes a node as CellBoxes side by side, but the walk loads one axis of all siblings at
// once (8 bytes, the padding past the last group covering lanes beyond k). The root is a group of
// one at byte 0.
struct GroupBoxes {
  static constexpr size_t kPadding = 8;
  const uint8_t* bytes;  // the group's first byte
  uint32_t k;
  [[nodiscard]] CellBox box(uint32_t rank) const {
    CellBox b;
    for (size_t a = 0; a < 3; ++a) {
      b.lo[a] = bytes[a * k + rank];
      b.hi[a] = bytes[(3 + a) * k + rank];
    }
    return b;
  }
};

// The bits set in each byte: a child's rank among its stored siblings. The build has no -mpopcnt,
// so __builtin_popcount is a libgcc call, 8% of the walk's time per child pushed.
constexpr auto kBitsSet = [] {
  std::array<uint8_t, 256> t{};
  for (size_t i = 1; i < t.size(); ++i) t[i] = uint8_t(t[i >> 1] + (i & 1));
  return t;
}();
// For each child mask, child c's rank among the stored children (the siblings before it), for
// c = 0..7: the lane permutation from a group's ranks to child order.
alignas(8) constexpr auto kRankOf = [] {
  std::array<std::array<uint8_t, 8>, 256> t{};
  for (size_t m = 0; m < t.size(); ++m)
    for (size_t c = 0; c < 8; ++c) t[m][c] = kBitsSet[m & ((1u << c) - 1)];
  return t;
}();
constexpr float kInv254 = 1.0f / 254.0f;
// float(q) for every byte q: a load instead of a conversion per plane in the walk (exact).
constexpr auto kByteFloat = [] {
  std::array<float, 256> t{};
  for (int q = 0; q < 256; ++q) t[size_t(q)] = float(q);
  return t;
}();
inline float cell_quantum(float side) { return side * kInv254; }

// The growing arrays of a build with nodes N (OctNode32 or OctNode64, tree_nodes.hpp), and the
// references of the node being built: the top segment of `stack`, from a given start to the end.
// Building a node pops its segment; splitting one replaces it by its eight children's, child 0 on
// top, so that it is built first.
template <class N>
struct OctBuild {
  ChunkedArray<N> nodes;
  ChunkedArray<CellBox> boxes;  // one per node, pushed with it (same handles), if child_bounds
  ChunkedArray<LeafSlab> disc_slabs;  // likewise, if leaf_slabs (inner nodes' unused)
  ChunkedArray<uint32_t> refs;
  ChunkedArray<uint16_t> refs16;
  uint64_t references = 0;  // over all leaves, compact or not
  std::vector<uint32_t> stack;
  size_t stack_touched = 0;  // the most elements the stack has held since its pages were trimmed

  // A split writes the children's references past the parent's (twice the items at the root)
  // and leaves pop theirs: the stack's pages past its top are handed back as it shrinks, so that
  // the peak is the tree built so far plus the stack in use (8 B/item less at 10^7).
  void trim_stack() {
    constexpr size_t kMinBytes = size_t(1) << 20;
    stack_touched = release_pages_past_size(stack, stack_touched, kMinBytes);
  }
};

// Thrown when a leaf's first reference does not fit 32 bits: the build starts again with
// OctNode64.
struct NeedsWideOffsets {};

// How a leaf stores its references (the parameter compact_refs).
enum class OctRefs : uint8_t {
  k32Bit = 0,    // one 32-bit array, which a method may copy its discs along (leaf order)
  kCompact = 1,  // 16-bit offsets from the leaf's lowest item where they fit
  kAuto = 2,     // 32-bit up to kCompactAbove items, compact beyond
};
// A node the walk is to visit: its cell, where the ray enters its box (`near`, what orders and
// ends the walk) and the ray's interval in its cell (what a leaf is handed).
struct OctTodo {
  uint32_t node;
  Vec3 lo;
  float side, near, t0, t1;
};

// Compact leaves hold at most this many items (decoded onto the walk's stack, 1 KiB).
constexpr size_t kOctCompactMax = 256;

// What the walk reads of a built octree: its cube and pointers into its arrays.
struct OctWalkData {
  Vec3 root_lo = Vec3::Zero();
  float root_side = 0;
  float hits_before_leaf = 0;  // ItemSet::hits_before_leaf
  size_t items = 0;
  const uint8_t* boxes = nullptr;        // GroupBoxes of every node, null without child boxes
  const LeafSlab* disc_slabs = nullptr;  // by node, for leaves with has_slab()
  const uint32_t* refs = nullptr;
  const uint16_t* refs16 = nullptr;
};

// Eight bytes of a group (one bound of one axis, by rank) as eight int lanes in child order.
__attribute__((target("avx2"), always_inline)) inline __m256i bytes_by_child(const uint8_t* at,
                                                                             __m256i rank) {
  const __m128i b = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(at));  // NOLINT: intrinsic
  return _mm256_permutevar8x32_epi32(_mm256_cvtepu8_epi32(b), rank);
}

// child_tests (octree_walk.hpp) in eight AVX2 lanes, cells and boxes: the cells as
// octant_test_avx2, then each child's box (its group's bytes permuted from rank to child order)
// as narrow_to_box computes it (the same IEEE operations in the same order, so the same children
// and t bit for bit).
__attribute__((target("avx2"), always_inline)) inline uint32_t cells_and_boxes_avx2(
    uint32_t children, const GroupBoxes& group, const Vec3& lo, float half, const RaySlabs& slabs,
    float tmax, float* t0s, float* t1s, float* nears) {
  const __m256 h = _mm256_set1_ps(half), quantum = _mm256_set1_ps(cell_quantum(half));
  __m256 tn = _mm256_set1_ps(slabs.tmin), tf = _mm256_set1_ps(tmax);
  __m256 clo[3];
  for (int a = 0; a < 3; ++a) {
    clo[a] = _mm256_add_ps(_mm256_set1_ps(lo[a]), _mm256_mul_ps(h, _mm256_load_ps(kOctantBit[a])));
    slab_axis_avx2(clo[a], _mm256_add_ps(clo[a], h), slabs, a, tn, tf);
  }
  _mm256_store_ps(t0s, tn);
  _mm256_store_ps(t1s, tf);
  const uint32_t cells = uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
  if ((cells & children) == 0) return 0;
  const __m256i rank = _mm256_cvtepu8_epi32(_mm_loadl_epi64(
      reinterpret_cast<const __m128i*>(kRankOf[children].data())));  // NOLINT: intrinsic load
  uint32_t empty = 0;
  for (uint32_t a = 0; a < 3; ++a) {
    const __m256i qlo = bytes_by_child(group.bytes + a * group.k, rank);
    const __m256i qhi = bytes_by_child(group.bytes + (3 + a) * group.k, rank);
    if (a == 0)
      empty = uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(qlo, qhi))));
    const __m256 blo = _mm256_add_ps(clo[a], _mm256_mul_ps(quantum, _mm256_cvtepi32_ps(qlo)));
    const __m256 bhi = _mm256_add_ps(clo[a], _mm256_mul_ps(quantum, _mm256_cvtepi32_ps(qhi)));
    slab_axis_avx2(blo, bhi, slabs, int(a), tn, tf);
  }
  _mm256_store_ps(nears, tn);
  return cells & children & ~empty &
         uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// The walk for any x86-64 (SSE lanes), and compiled for AVX2 as a whole (octree_walk.hpp says
// why): each of its functions carries PCRT_OCT_WALK_TARGET (an attribute, not GCC's target pragma,
// which clang ignores).
namespace oct_sse {
constexpr bool kWalkAvx2 = false;
#define PCRT_OCT_WALK_TARGET
#include "structures/octree_walk.hpp"  // NOLINT: included twice, by design
#undef PCRT_OCT_WALK_TARGET
}  // namespace oct_sse
namespace oct_avx2 {
constexpr bool kWalkAvx2 = true;
#define PCRT_OCT_WALK_TARGET __attribute__((target("avx2")))
#include "structures/octree_walk.hpp"  // NOLINT: included twice, by design
#undef PCRT_OCT_WALK_TARGET
}  // namespace oct_avx2

// Up to 2^21 items the octree's references (7 to 10 per item on a surface) copied as 28-byte
// discs stay near SplatLeafBlocks' 512 MiB cap for a leaf-order copy, which compact references
// rule out; beyond it no copy is made, and the compact ones halve the references' bytes.
constexpr size_t kCompactAbove = size_t(1) << 21;

struct OctreeParams {
  size_t leaf_size = 8;
  int max_depth = 21;
  double stop_refs = 3;
  OctRefs compact_refs = OctRefs::kAuto;
  bool child_bounds = true;
  bool leaf_slabs = true;
  bool loose = false;
};
const ParamList<OctreeParams>& octree_params() {
  using P = OctreeParams;
  static const auto l =
      ParamList<P>()
          .add(&P::leaf_size, {"leaf_size", 8, 1, 1e6,
                               "stop splitting at this many items (K of the leaf-based methods)"})
          .add(&P::max_depth, {"max_depth", 21, 0, 30, "maximum depth"})
          .add(&P::stop_refs,
               {"stop_refs", 3, 1.5, 3,
                "stop splitting where the children would hold this many references per item "
                "and the fullest child over half of the items (footprints wider than the cells; "
                "from 1.5, since near 1 a cloud with over half its points in one octant would "
                "stop at the root)"})
          .add(&P::compact_refs,
               {"compact_refs", 2, 0, 2,
                "1: a leaf's references as 16-bit offsets from its lowest item where they fit "
                "(half the bytes; leaves are decoded for the method, so no leaf-order disc "
                "copy, disc_blocks=1); 0: one 32-bit reference array; 2: 32-bit up to 2^21 "
                "items (where a leaf-order copy may fit), compact beyond"})
          .add(&P::child_bounds,
               {"child_bounds", 1, 0, 1,
                "1: for methods hit on their discs, each node keeps its footprints' box within "
                "its cell (6 bytes, 8 bits a side) and rays skip the children whose box they "
                "miss; 0: the cells alone"})
          .add(&P::leaf_slabs,
               {"leaf_slabs", 1, 0, 1,
                "1: for methods hit on their discs, each leaf keeps the slab of its discs along "
                "their mean normal (16 bytes a node) and a ray whose interval in the cell misses "
                "it does not visit the leaf; 0: without"})
          .add(&P::loose,
               {"loose", 0, 0, 1,
                "0: an item in every cell its footprint reaches (the papers' rule); 1: a loose "
                "octree, each item in the one cell holding its centre, each child's box grown to "
                "its items' whole footprints and walked as the bvh's 8-wide nodes (one reference "
                "per item; stop_refs, compact_refs, child_bounds and leaf_slabs set beside it are "
                "refused)"});
  return l;
}

class Octree final : public Structure {
 public:
  explicit Octree(const OctreeParams& p)
      : leaf_size_(p.leaf_size),
        max_depth_(p.max_depth),
        stop_refs_(p.stop_refs),
        refs_mode_(p.compact_refs),
        child_bounds_(p.child_bounds),
        leaf_slabs_(p.leaf_slabs) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    // A single point keeps a zero-size cube and stays one leaf.
    const OctreeCube cube = octree_root_cube(items_.bounds());
    root_lo_ = cube.lo;
    root_side_ = cube.side;
    compact_ = refs_mode_ == OctRefs::kCompact ||
               (refs_mode_ == OctRefs::kAuto && items_.size() > kCompactAbove);
    // Implicit-surface methods search a leaf's whole cell interval, where their surface may lie off
    // every footprint: only hits on the discs are sure to lie within the boxes.
    keeps_boxes_ = child_bounds_ && culls_by_plane();
    keeps_slabs_ = leaf_slabs_ && culls_by_plane();
    try {
      build_all(nodes32_);
      release(nodes64_);
    } catch (const NeedsWideOffsets&) {
      release(nodes32_);
      build_all(nodes64_);
    }
    walk_data_ = walk_data();
    counters.add(kBuildNodes, nodes32_.size() + nodes64_.size());
    counters.add(kBuildItemRefs, references_);
    counters.add(kBuildItemVisits,
                 wide() ? item_visits(nodes64_, 0, 1) : item_visits(nodes32_, 0, 1));
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

  // Compact leaves are decoded for the method, so they are no pieces of one array.
  [[nodiscard]] std::span<const uint32_t> leaf_references() const override {
    return compact_ ? std::span<const uint32_t>{} : std::span<const uint32_t>(refs_);
  }
  [[nodiscard]] size_t memory_bytes() const override {
    return nodes32_.capacity() * sizeof(OctNode32) + nodes64_.capacity() * sizeof(OctNode64) +
           boxes_.capacity() + disc_slabs_.capacity() * sizeof(LeafSlab) +
           refs_.capacity() * sizeof(uint32_t) + refs16_.capacity() * sizeof(uint16_t);
  }

 private:
  [[nodiscard]] bool wide() const { return !nodes64_.empty(); }

  // The walk of the nodes built, in AVX2 lanes where the CPU has them (octree_walk.hpp), compiled
  // apart with and without child boxes (each instance then holds one child test).
  template <bool kAny>
  bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit, OpCounters& counters) const {
    return walk_data_.boxes != nullptr ? walk<kAny, true>(ray, leaf, hit, counters)
                                       : walk<kAny, false>(ray, leaf, hit, counters);
  }
  template <bool kAny, bool kBoxes>
  bool walk(const Ray& ray, const LeafIntersector& leaf, Hit& hit, OpCounters& counters) const {
    const OctWalkData& w = walk_data_;
    if (avx2_)
      return wide() ? oct_avx2::walk<kAny, kBoxes>(w, nodes64_.data(), ray, leaf, hit, counters)
                    : oct_avx2::walk<kAny, kBoxes>(w, nodes32_.data(), ray, leaf, hit, counters);
    return wide() ? oct_sse::walk<kAny, kBoxes>(w, nodes64_.data(), ray, leaf, hit, counters)
                  : oct_sse::walk<kAny, kBoxes>(w, nodes32_.data(), ray, leaf, hit, counters);
  }

  // Where the walk finds the arrays just built.
  [[nodiscard]] OctWalkData walk_data() const {
    return {root_lo_,
            root_side_,
            items_.hits_before_leaf,
            items_.size(),
            boxes_.empty() ? nullptr : boxes_.data(),
            disc_slabs_.data(),
            refs_.data(),
            refs16_.data()};
  }

  // Sum over leaves of their references x levels from the root: the build's partitioning work as
  // the leaves keep it (references a leaf drops by the plane test are not counted).
  template <class N>
  static uint64_t item_visits(const std::vector<N>& nodes, uint32_t node, uint64_t level) {
    const N& n = nodes[node];
    if (n.leaf()) return uint64_t(n.leaf_count()) * level;
    uint64_t sum = 0;
    const uint32_t kids = uint32_t(__builtin_popcount(n.child_mask()));
    for (uint32_t k = 0; k < kids; ++k)
      sum += item_visits(nodes, uint32_t(n.first()) + k, level + 1);
    return sum;
  }

  // The quantized box of `b` (a box within the cell [lo, lo + side]) for narrow_to_box: the
  // smallest one whose planes, computed as narrow_to_box computes them, hold b.
  static CellBox quantize(const Aabb& b, const Vec3& lo, float side) {
    CellBox q;
    if (b.empty()) return q;
    const float quantum = cell_quantum(side);
    for (size_t a = 0; a < 3; ++a) {
      const auto at = [&](int k) { return lo[long(a)] + quantum * float(k); };
      const float rel_lo = quantum > 0 ? (b.lo[long(a)] - lo[long(a)]) / quantum : 0.0f;
      const float rel_hi = quantum > 0 ? (b.hi[long(a)] - lo[long(a)]) / quantum : 255.0f;
      int k_lo = int(std::clamp(std::floor(rel_lo), 0.0f, 255.0f));
      int k_hi = int(std::clamp(std::ceil(rel_hi), 0.0f, 255.0f));
      while (k_lo > 0 && at(k_lo) > b.lo[long(a)]) --k_lo;
      while (k_hi < 255 && at(k_hi) < b.hi[long(a)]) ++k_hi;
      // One step more each way where there is room: a build whose multiply-adds fuse rounds the
      // planes differently (k = 0 and 255 hold the cell whatever the rounding).
      q.lo[a] = uint8_t(std::max(k_lo - 1, 0));
      q.hi[a] = uint8_t(std::min(k_hi + 1, 255));
    }
    return q;
  }

  // The CellBoxes of a build (one per node) regrouped by siblings (GroupBoxes), with the
  // padding of the last group's load.
  template <class N>
  static std::vector<uint8_t> group_boxes(const std::vector<N>& nodes,
                                          const std::vector<CellBox>& boxes) {
    std::vector<uint8_t> out(6 * boxes.size() + GroupBoxes::kPadding, 0);
    const auto put = [&](size_t first, uint32_t k) {
      uint8_t* g = out.data() + 6 * first;
      for (uint32_t r = 0; r < k; ++r)
        for (size_t a = 0; a < 3; ++a) {
          g[a * k + r] = boxes[first + r].lo[a];
          g[(3 + a) * k + r] = boxes[first + r].hi[a];
        }
    };
    put(0, 1);
    for (const N& n : nodes)
      if (!n.leaf()) put(n.first(), kBitsSet[n.child_mask()]);
    return out;
  }

  // The whole tree with nodes N, flattened into `nodes` and refs_.
  template <class N>
  void build_all(std::vector<N>& nodes) {
    OctBuild<N> b;
    b.stack.resize(items_.size());
    b.stack_touched = b.stack.size();
    for (uint32_t i = 0; i < b.stack.size(); ++i) b.stack[i] = i;
    const auto root = b.nodes.push_back(N{});
    if (keeps_boxes_) b.boxes.push_back(CellBox{});
    if (keeps_slabs_) b.disc_slabs.push_back(LeafSlab{});
    build_node(b, root, 0, root_lo_, root_side_, 0);
    release(b.stack);
    nodes = b.nodes.flatten();
    boxes_ = keeps_boxes_ ? group_boxes(nodes, b.boxes.flatten()) : std::vector<uint8_t>{};
    disc_slabs_ = keeps_slabs_ ? b.disc_slabs.flatten() : std::vector<LeafSlab>{};
    refs_ = b.refs.flatten();
    refs16_ = b.refs16.flatten();
    references_ = b.references;
  }

  // Which children the box of item i overlaps (bit c for child c): a footprint on a mid-plane
  // belongs to both sides.
  [[nodiscard]] uint32_t children_of(uint32_t i, const Vec3& mid) const {
    const Aabb b = items_.box(i);
    uint32_t mask = 0;
    for (uint32_t c = 0; c < 8; ++c) {
      bool in = true;
      for (int a = 0; a < 3 && in; ++a) in = ((c >> a) & 1) ? b.hi[a] >= mid[a] : b.lo[a] <= mid[a];
      mask |= uint32_t(in) << c;
    }
    return mask;
  }

  // How many references each child's box test gives, and which children are reached at all: a
  // child whose cube no disc plane cuts would hold only empty leaves, so it is not stored.
  struct ChildCounts {
    std::array<size_t, 8> count{};
    uint32_t reached = 0;
  };
  [[nodiscard]] ChildCounts count_children(const std::vector<uint32_t>& st, size_t begin,
                                           const Vec3& mid, float half) const {
    ChildCounts out;
    const bool discs = culls_by_plane();
    for (size_t k = begin; k < st.size(); ++k) {
      const uint32_t boxes = children_of(st[k], mid);
      out.reached |= discs ? boxes & disc_plane_cuts_children(st[k], mid, half) : boxes;
      for (uint32_t mask = boxes; mask; mask &= mask - 1) ++out.count[size_t(__builtin_ctz(mask))];
    }
    return out;
  }

  // Builds the subtree of the references stack[begin, end) into `node` and pops them, keeping the
  // box of its footprints within the cell (if child_bounds); returns that box.
  template <class N>
  Aabb build_node(OctBuild<N>& b, typename ChunkedArray<N>::Handle node, size_t begin,
                  const Vec3& lo, float side, int depth) {
    const Aabb box = build_subtree(b, node, begin, lo, side, depth);
    if (keeps_boxes_) b.boxes[{node.chunk, node.pos}] = quantize(box, lo, side);
    return box;
  }

  template <class N>
  Aabb build_subtree(OctBuild<N>& b, typename ChunkedArray<N>::Handle node, size_t begin,
                     const Vec3& lo, float side, int depth) {
    std::vector<uint32_t>& st = b.stack;
    const size_t n = st.size() - begin;
    if (n <= leaf_size_ || depth >= max_depth_ || !(side > 0))
      return make_leaf(b, node, begin, lo, side);
    const float half = 0.5f * side;
    const Vec3 mid = lo + Vec3::Constant(half);
    const ChildCounts counts = count_children(st, begin, mid, half);
    // A split must pay: once footprints are wider than the cells, each item lands in several
    // children and the fullest child keeps most of them, so every further level only multiplies
    // references (identical points, or a dense plane of wide splats, would recurse to max_depth).
    // Stop when both hold: stop_refs (3) references per item and over half of the items in one
    // child. (All items in one child alone is progress: the rest of the cell was empty.)
    size_t refs = 0, fullest = 0;
    for (size_t k : counts.count) {
      refs += k;
      fullest = std::max(fullest, k);
    }
    if (double(refs) >= stop_refs_ * double(n) && 2 * fullest > n)
      return make_leaf(b, node, begin, lo, side);
    const std::array<size_t, 8> at = split_in_place(b, begin, mid, counts.count);
    b.nodes[node] = N::make(node_index32(b.nodes.size(), "octree"), oct_inner(counts.reached));
    const size_t stored = size_t(__builtin_popcount(counts.reached));
    const auto kids = b.nodes.push_n(stored, N{});
    if (keeps_boxes_) b.boxes.push_n(stored, CellBox{});  // the same chunks, so the same handles
    if (keeps_slabs_) b.disc_slabs.push_n(stored, LeafSlab{});
    size_t rank = 0;
    Aabb box;
    for (uint32_t c = 0; c < 8; ++c) {  // child 0's references are on top
      if (!((counts.reached >> c) & 1)) {
        st.resize(at[c]);
        continue;
      }
      const Vec3 clo = lo + half * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
      box.extend(build_node(b, {kids.chunk, kids.pos + rank++}, at[c], clo, half, depth + 1));
    }
    return box;
  }

  // Replaces stack[begin, end) by the children's references, child 7's lowest and child 0's on
  // top, each in its order there (written past the end, then moved down); returns where each
  // child's start.
  template <class N>
  [[nodiscard]] std::array<size_t, 8> split_in_place(OctBuild<N>& b, size_t begin, const Vec3& mid,
                                                     const std::array<size_t, 8>& count) const {
    std::vector<uint32_t>& st = b.stack;
    const size_t end = st.size();
    std::array<size_t, 8> at{}, w{};
    size_t refs = 0;
    for (int c = 7; c >= 0; --c) at[size_t(c)] = begin + refs, refs += count[size_t(c)];
    st.resize(end + refs);
    b.stack_touched = std::max(b.stack_touched, st.size());
    for (size_t c = 0; c < 8; ++c) w[c] = at[c] - begin + end;
    for (size_t k = begin; k < end; ++k)
      for (uint32_t mask = children_of(st[k], mid); mask; mask &= mask - 1)
        st[w[size_t(__builtin_ctz(mask))]++] = st[k];
    std::memmove(st.data() + begin, st.data() + end, refs * sizeof(uint32_t));
    st.resize(begin + refs);
    b.trim_stack();
    return at;
  }

  // A leaf keeps the references on the top of the stack whose footprint reaches into its cube,
  // compact where they fit; returns the box of their footprints within the cube.
  template <class N>
  Aabb make_leaf(OctBuild<N>& b, typename ChunkedArray<N>::Handle node, size_t begin,
                 const Vec3& lo, float side) {
    if (culls_by_plane()) keep_discs_cutting(b.stack, begin, lo, side);
    const std::span<const uint32_t> items{b.stack.data() + begin, b.stack.size() - begin};
    const Aabb box = keeps_boxes_ ? footprint_within(items, lo, side) : Aabb{};
    uint32_t flags = 0;
    if (keeps_slabs_) {
      const LeafSlab slab = slab_of(items_, items);
      b.disc_slabs[{node.chunk, node.pos}] = slab;
      flags = slab_flag(slab, side);
    }
    if (items.size() >= kOctSlab) throw std::length_error("octree: a leaf of 2^29 references");
    const auto n = uint32_t(items.size());
    b.references += n;
    std::array<uint16_t, kOctCompactMax + 2> packed;
    if (compact_ && pack_compact(items, packed)) {
      const size_t first = b.refs16.size();
      if (!N::kWide && !fits_narrow_offset(first)) throw NeedsWideOffsets{};
      b.nodes[node] = N::make(first, n | kOctCompact | flags);
      b.refs16.append({packed.data(), n + 2});
    } else {
      const size_t first = b.refs.size();
      if (!N::kWide && !fits_narrow_offset(first)) throw NeedsWideOffsets{};
      b.nodes[node] = N::make(first, n | flags);
      b.refs.append(items);
    }
    b.stack.resize(begin);
    b.trim_stack();
    return box;
  }

  // kOctSlab for a leaf whose walk tests its slab (LeafSlab::thin). Testing every leaf instead:
  // goradia_2010's leaves visited per bounce ray of the aerial tile 1.27 -> 1.42, linsen_2007
  // 0.01-0.04 faster there, the sphere and building unchanged within the spread
  // (results/anchor/oct_slab).
  static uint32_t slab_flag(const LeafSlab& slab, float side) {
    return slab.thin(side * slab.normal().cwiseAbs().sum()) ? kOctSlab : 0;
  }
  // The box of the items' footprints clipped to the cube [lo, lo + side] (its far planes computed
  // as the child test computes them); empty for no items.
  [[nodiscard]] Aabb footprint_within(std::span<const uint32_t> items, const Vec3& lo,
                                      float side) const {
    Aabb box;
    for (const uint32_t i : items) box.extend(items_.box(i));
    if (box.empty()) return box;
    const Vec3 hi = lo + Vec3::Constant(side);
    box.lo = box.lo.cwiseMax(lo);
    box.hi = box.hi.cwiseMin(hi);
    return box;
  }

  // A leaf's items as its lowest item (two 16-bit halves) and each item's offset from it, in the
  // leaf's order: where there are at most kOctCompactMax items within 2^16 of each other (most
  // leaves: items are in Morton order, so a cell's neighbours are mostly near in it).
  static bool pack_compact(std::span<const uint32_t> items,
                           std::array<uint16_t, kOctCompactMax + 2>& out) {
    if (items.empty() || items.size() > kOctCompactMax) return false;
    const auto [lo, hi] = std::minmax_element(items.begin(), items.end());
    if (*hi - *lo > 0xFFFFu) return false;
    out[0] = uint16_t(*lo & 0xFFFFu);
    out[1] = uint16_t(*lo >> 16);
    for (size_t k = 0; k < items.size(); ++k) out[k + 2] = uint16_t(items[k] - *lo);
    return true;
  }

  // Whether leaves may drop the discs whose plane misses them: the items are discs and the
  // method's candidates are points of them (ItemSet::hits_on_discs).
  [[nodiscard]] bool culls_by_plane() const {
    return items_.hits_on_discs && !items_.disc_normals.empty();
  }

  // Drops from stack[begin, end) the discs whose plane misses the cube [lo, lo + side]: a tilted
  // disc's box reaches into cells above and below the disc (a quarter of the references on a
  // sphere). The splits still go by the boxes, so the tree is the one they make.
  void keep_discs_cutting(std::vector<uint32_t>& st, size_t begin, const Vec3& lo,
                          float side) const {
    const float q = 0.5f * side;
    const Vec3 centre = lo + Vec3::Constant(q);
    size_t kept = begin;
    for (size_t k = begin; k < st.size(); ++k)
      if (disc_plane_cuts_cube(st[k], centre, q)) st[kept++] = st[k];
    st.resize(kept);
  }

  // Whether the plane of disc i meets the cube of this centre and half side q: |n . (centre - p)|
  // <= q |n|_1, with a margin for the rounding of the dot product over these coordinates and for
  // hit points just off the disc (the 1e-4 r of its box). Conservative: a cube holding a point of
  // the disc always passes.
  [[nodiscard]] bool disc_plane_cuts_cube(uint32_t i, const Vec3& centre, float q) const {
    const Vec3& n = items_.disc_normals[i];
    const Vec3& p = items_.positions[i];
    return std::abs(n.dot(centre - p)) <= disc_plane_reach(i, centre, q);
  }
  [[nodiscard]] float disc_plane_reach(uint32_t i, const Vec3& centre, float q) const {
    const Vec3& n = items_.disc_normals[i];
    const float scale =
        centre.cwiseAbs().maxCoeff() + items_.positions[i].cwiseAbs().maxCoeff() + q;
    return q * n.cwiseAbs().sum() + 1e-4f * items_.radius(i) + 1e-6f * scale;
  }
  // The same test for the eight children of a cell split at mid (child side `half`): bit c for
  // child c. The children's centres are mid +- half / 2 per axis.
  [[nodiscard]] uint32_t disc_plane_cuts_children(uint32_t i, const Vec3& mid, float half) const {
    const Vec3& n = items_.disc_normals[i];
    const float q = 0.5f * half;
    const float at_mid = n.dot(mid - items_.positions[i]);
    // A child's centre is within q of mid per axis, so this covers the margin at each of them.
    const float reach = disc_plane_reach(i, mid, q) + 1e-6f * q;
    uint32_t mask = 0;
    for (uint32_t c = 0; c < 8; ++c) {
      const float to_centre = q * ((c & 1 ? n.x() : -n.x()) + ((c >> 1) & 1 ? n.y() : -n.y()) +
                                   ((c >> 2) & 1 ? n.z() : -n.z()));
      mask |= uint32_t(std::abs(at_mid + to_centre) <= reach) << c;
    }
    return mask;
  }

  size_t leaf_size_;
  int max_depth_;
  double stop_refs_;  // exact for the integers it is compared with (refs, n < 2^53)
  OctRefs refs_mode_;
  bool compact_ = false;  // as refs_mode_ decides for this build
  bool child_bounds_;
  bool avx2_ = wide_nodes_use_avx2();
  bool leaf_slabs_;
  bool keeps_boxes_ = false;  // child_bounds_, for items hit only on their discs
  bool keeps_slabs_ = false;  // leaf_slabs_, likewise
  uint64_t references_ = 0;
  ItemSet items_;
  Vec3 root_lo_ = Vec3::Zero();
  float root_side_ = 0;
  std::vector<OctNode32> nodes32_;  // while every leaf's first reference fits 32 bits
  std::vector<OctNode64> nodes64_;  // otherwise
  std::vector<uint32_t> refs_;      // leaves of 32-bit items
  std::vector<uint16_t> refs16_;    // compact leaves: base item halves, then offsets
  // If child_bounds: each node's footprint box within its cell (CellBox), grouped by siblings
  // (GroupBoxes): 6 bytes a node, as CellBoxes, plus the padding of one 8-byte load.
  std::vector<uint8_t> boxes_;
  // If leaf_slabs: each node's LeafSlab, by node index (inner nodes' unused; tested for the
  // leaves flagged kOctSlab).
  std::vector<LeafSlab> disc_slabs_;
  OctWalkData walk_data_;  // set at the end of build
};

}  // namespace

namespace {

// The parameters of the papers' octree mean nothing to the loose one: set away from their
// defaults beside loose=1, they are a contradiction, not a choice to ignore.
void check_loose_alone(const OctreeParams& p) {
  const OctreeParams defaults;
  if (p.stop_refs != defaults.stop_refs || p.compact_refs != defaults.compact_refs ||
      p.child_bounds != defaults.child_bounds || p.leaf_slabs != defaults.leaf_slabs)
    input_error(
        "structure octree: loose=1 places each item once; stop_refs, compact_refs, "
        "child_bounds and leaf_slabs apply to loose=0 only");
}

// From results/scale/octree at 6b7fb5f (compact references or not) and its leaf order at 667aa3e.
StructureFootprint octree_footprint(const ParamValues& params) {
  // Compact references or 32-bit ones, which the leaf-order copy needs. The default (kAuto) is
  // priced as 32-bit: what it builds where a copy may be chosen, high by 14 B/item beyond.
  // The loose octree: one reference per item; reference_splat's peak on the 10^7 sphere, 89.2 and
  // 93.6 B/item in item and leaf order (results/scale/oct_loose), over the cloud and radii, + 10%.
  const auto loose = params.find("loose");
  if (loose != params.end() && loose->second != 0) return {68, 73, 1, 0};
  const auto mode = params.find("compact_refs");
  const bool is_compact = mode != params.end() && OctRefs(int(mode->second)) == OctRefs::kCompact;
  // With compact references a leaf-order copy is refused when the method binds (there is no
  // array to copy along), so it is priced as item order: the refusal, not a memory error.
  // Methods without disc blocks keep every box reference: schaufler_jensen_2000's peak at 10^7
  // over its cloud, radii and records (results/scale/octree at 4f1fe68), plus 10%. The footprint
  // boxes of methods hit on their discs (child_bounds) add 2.4 B/item to the peak at 10^7
  // (reference_splat on the sphere: 48.8 -> 51.2 B/item, results/scale/octree_boxes). Their
  // leaf slabs (leaf_slabs) add 16 B a node: 7.1 B/item for goradia_2010's and reference_splat's
  // splats on the 10^6 sphere (442 567 nodes; structure 35.6 -> 42.7 MB), priced as 8.
  return is_compact ? StructureFootprint{34, 34, 7.2, 41} : StructureFootprint{48, 260, 7.2, 60};
}

}  // namespace

void register_octree(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "octree",
      .description =
          "regular octree over the bounding cube, items referenced in every child they overlap",
      .build_claim = "O(N log N)",
      .query_claim = "O(log N)",
      .params = octree_params().specs(),
      .create = [](const ParamValues& given) -> std::unique_ptr<Structure> {
        const OctreeParams p = octree_params().read(given, "octree");
        if (!p.loose) return std::make_unique<Octree>(p);
        check_loose_alone(p);
        return make_loose_octree(p.leaf_size, p.max_depth);
      },
      .footprint = octree_footprint,
  });
}

}  // namespace pcrt
