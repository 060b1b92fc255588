// The splats in blocks of eight in structure-of-arrays layout (DiscBlock), as the leaf code reads
// them once a structure is built (Method::bind_leaf_references). Two layouts (DiscBlockLayout):
// leaf order, a copy with one entry per leaf reference, so the discs of a leaf are contiguous and
// the leaf loop streams its blocks eight lanes at a time (the item-order arrays are then
// released); or item order, no copy at all: a leaf gathers its discs from the set's item arrays
// (the cloud's own, adapted) into blocks on the stack. Leaf order costs 28 bytes per reference: a
// structure that references each item about once (bvh, sphere_tree, brute_force) pays it once, the
// kd-tree (3.7 references per point on a 10^6 sphere), grid (2.4) and octree (up to 8) 67-230
// B/point. Before binding, a leaf (of a structure built by a test, say) is read one disc at a time
// from the item-order SplatSet.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/kernels/splat_set.hpp"

namespace pcrt {

enum class DiscBlockLayout : uint8_t {
  kAuto = 0,  // leaf order where the copy is cheap (SplatLeafBlocks::auto_leaf_order), else item
  kLeafOrder = 1,  // a copy per leaf reference: the fastest leaves, memory grows with references
  kItemOrder = 2,  // no copy: leaves gather their discs from the item arrays
};

// The parameter `disc_blocks` of the methods that trace disc blocks.
struct DiscBlockParams {
  DiscBlockLayout layout = DiscBlockLayout::kAuto;
  static const ParamList<DiscBlockParams>& list();
};

class SplatLeafBlocks {
 public:
  // kAuto's rule: leaf order while the structure references each item at most
  // kLeafOrderMaxRefsPerItem times (the kd-tree's 3.7 and the octree's 7 to 10 on a surface; not
  // a grid coarsened to its 32) and the copy, a 28-byte disc per reference, stays under
  // kLeafOrderMaxBytes (512 MiB: about 5x10^6 points on the kd-tree, 2x10^6 on the octree, above
  // every thesis sweep, below the scale runs' 10^7 and 10^8). Leaf order is up to twice as fast on
  // the kd-tree and part of the octree's gain in results/anchor/octree_boxes (issue 31); beyond
  // the cap memory, not speed, is what large clouds are short of. A sweep across the cap changes
  // layout (and time, not operation counts): fix `disc_blocks` to hold it.
  static constexpr double kLeafOrderMaxRefsPerItem = 12.0;
  static constexpr double kLeafOrderMaxBytes = double(uint64_t(1) << 29);
  static constexpr bool auto_leaf_order(double refs, double items) {
    return refs <= kLeafOrderMaxRefsPerItem * items &&
           refs * double(sizeof(DiscBlock) / kDiscGroup) <= kLeafOrderMaxBytes;
  }

  // Binds the splats of `splats` (item order) to the structure's leaf references: copies splat
  // refs[i] to position i (leaf order), or adapts the set's item arrays (item order; the set must
  // then keep them and outlive the blocks).
  void bind(std::span<const uint32_t> refs, const SplatSet& splats, DiscBlockLayout layout);
  [[nodiscard]] bool leaf_order() const { return leaf_order_; }
  // Leaf order: where the leaf's items start in the bound references; item order: 0 (positions
  // are the items themselves); -1 if the leaf cannot be read here (unbound, or not a piece of
  // the bound references).
  [[nodiscard]] int64_t offset_of(std::span<const uint32_t> items) const {
    if (kernel_ == nullptr) return -1;
    if (!leaf_order_) return 0;
    if (items.data() < base_ || items.data() + items.size() > base_ + count_) return -1;
    return items.data() - base_;
  }
  [[nodiscard]] const DiscBlock* blocks() const { return blocks_.data(); }
  // Copies the discs of items[0..n) (item order, n <= 64) to lanes 0..n of out[0..8); the rest
  // of the last block is zero (no disc).
  void gather(const uint32_t* items, uint32_t n, DiscBlock* out) const;
  [[nodiscard]] DiscKernel kernel() const { return kernel_; }
  // The copy's bytes (item order adapts, so 0).
  [[nodiscard]] size_t memory_bytes() const { return blocks_.capacity() * sizeof(DiscBlock); }

 private:
  const uint32_t* base_ = nullptr;
  size_t count_ = 0;
  bool leaf_order_ = true;
  std::vector<DiscBlock> blocks_;            // leaf order
  std::span<const Vec3> centres_, normals_;  // item order: the set's
  std::span<const float> radii_;
  DiscKernel kernel_ = nullptr;  // chosen at bind: no guard or lookup per leaf
};

// Lays the splats out for the structure just built; in leaf order the blocks are then the splats'
// one copy and the set's item arrays are released.
inline void bind_splat_blocks(SplatLeafBlocks& blocks, SplatSet& splats,
                              std::span<const uint32_t> refs, const DiscBlockParams& params) {
  blocks.bind(refs, splats, params.layout);
  if (blocks.leaf_order()) splats.release_item_data();
}

// The candidate window of a closest-hit query whose best hit so far is at `t_best`: [ray.tmin,
// t_best], widened by 1e-5 relative, so that rounding between num / den and the comparisons never
// drops a disc whose rounded t would tie or beat the best (the exact t decides afterwards).
inline DiscQuery disc_query(const Ray& ray, float t_best) {
  return {{ray.o.x(), ray.o.y(), ray.o.z()},
          {ray.d.x(), ray.d.y(), ray.d.z()},
          ray.tmin - 1e-5f * std::abs(ray.tmin) - 1e-30f,
          t_best * (1.0f + 1e-5f) + 1e-30f};
}

// Whether the one disc s is a candidate of q: the W = 1 kernel on it.
inline bool disc_candidate(const DiscQuery& q, const PackedSplat& s) {
  return disc_group<Lane1>(q, Lane1(s.c.x()), Lane1(s.c.y()), Lane1(s.c.z()), Lane1(s.n.x()),
                           Lane1(s.n.y()), Lane1(s.n.z()), Lane1(s.r)) != 0;
}

// The exact ray parameter of a candidate's plane crossing (the kernel's num / den, once per
// candidate rather than per disc).
inline float disc_t(const DiscQuery& q, float cx, float cy, float cz, float nx, float ny,
                    float nz) {
  const float vx = cx - q.o[0], vy = cy - q.o[1], vz = cz - q.o[2];
  const float num = nx * vx + (ny * vy + nz * vz);  // the lanes' order
  const float den = nx * q.d[0] + (ny * q.d[1] + nz * q.d[2]);
  return num / den;
}
inline float disc_t(const DiscQuery& q, const PackedSplat& s) {
  return disc_t(q, s.c.x(), s.c.y(), s.c.z(), s.n.x(), s.n.y(), s.n.z());
}
inline float disc_t(const DiscQuery& q, const DiscBlock& b, uint32_t j) {
  return disc_t(q, b.cx[j], b.cy[j], b.cz[j], b.nx[j], b.ny[j], b.nz[j]);
}

// A candidate disc of a leaf: its position i within the leaf, the exact t of its plane crossing,
// its point index, normal and radius (read from the block the kernel has just read, so a hit
// touches no other array).
struct DiscCandidate {
  uint32_t i;
  float t;
  uint32_t prim;
  Vec3 n;
  float r;
  Vec3 c;
};

// The item-order splat of a leaf not laid out in blocks; the set must still hold its item data.
inline PackedSplat unbound_splat(const SplatSet& splats, uint32_t item) {
  if (splats.centres.empty())
    throw std::logic_error("a leaf outside the bound structure after the splats were released");
  return splats.splat(item);
}

// Calls f(candidate) for each candidate (in leaf order) of the leaf's discs: through the bound
// leaf blocks with the widest lanes, else one disc at a time. Stops when f returns false.
template <typename F>
void for_each_disc_candidate(const SplatLeafBlocks& blocks, const SplatSet& splats,
                             std::span<const uint32_t> items, const DiscQuery& q, F&& f) {
  const int64_t off = blocks.offset_of(items);
  if (off < 0) {
    for (uint32_t i = 0; i < items.size(); ++i) {
      const PackedSplat s = unbound_splat(splats, items[i]);
      if (disc_candidate(q, s) && !f(DiscCandidate{i, disc_t(q, s), s.index, s.n, s.r, s.c}))
        return;
    }
    return;
  }
  // Candidates are collected 64 discs at a time, as the bits of one word: from the leaf-order
  // blocks in place, or from the item-order blocks gathered onto the stack.
  const bool in_place = blocks.leaf_order();
  const DiscKernel kernel = blocks.kernel();
  DiscBlock gathered[64 / kDiscGroup];
  for (uint32_t c = 0; c < items.size(); c += 64) {
    const uint32_t n = std::min<uint32_t>(64, uint32_t(items.size()) - c);
    const DiscBlock* b = in_place ? blocks.blocks() : gathered;
    const uint32_t first = in_place ? uint32_t(off) + c : 0;
    if (!in_place) blocks.gather(items.data() + c, n, gathered);
    uint64_t bits = 0;
    kernel(b, first, n, q, &bits);
    for (; bits; bits &= bits - 1) {
      const uint32_t bit = uint32_t(__builtin_ctzll(bits)), i = c + bit, p = first + bit;
      const DiscBlock& blk = b[p / kDiscGroup];
      const uint32_t j = p % kDiscGroup;
      if (!f(DiscCandidate{i, disc_t(q, blk, j), splats.prim_of(items[i]),
                           Vec3(blk.nx[j], blk.ny[j], blk.nz[j]), blk.r[j],
                           Vec3(blk.cx[j], blk.cy[j], blk.cz[j])}))
        return;
    }
  }
}

}  // namespace pcrt
