// Splats laid out in a structure's leaf order (one entry per leaf reference, so the discs of a
// leaf are contiguous) in blocks of eight in structure-of-arrays layout (DiscBlock): the leaf loop
// streams a leaf's blocks eight lanes at a time instead of chasing an index per disc, and a
// candidate's exact t and point index come from the same blocks. Made once the structure is built
// (Method::bind_leaf_references); leaves that are not pieces of the bound references (a structure
// built by a test, say) fall back to the same test one disc at a time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/geometry.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "methods/kernels/splat_kernel.hpp"

namespace pcrt {

class SplatLeafBlocks {
 public:
  // Copies splat refs[i] of `splats` (item order) to position i.
  void bind(std::span<const uint32_t> refs, std::span<const PackedSplat> splats);
  // Where the leaf's items start in the bound references, or -1 if they are not a piece of them.
  [[nodiscard]] int64_t offset_of(std::span<const uint32_t> items) const {
    if (base_ == nullptr || items.data() < base_ || items.data() + items.size() > base_ + count_)
      return -1;
    return items.data() - base_;
  }
  [[nodiscard]] const DiscBlock* blocks() const { return blocks_.data(); }
  [[nodiscard]] DiscKernel kernel() const { return kernel_; }
  [[nodiscard]] size_t memory_bytes() const { return blocks_.capacity() * sizeof(DiscBlock); }

 private:
  const uint32_t* base_ = nullptr;
  size_t count_ = 0;
  std::vector<DiscBlock> blocks_;
  DiscKernel kernel_ = nullptr;  // chosen at bind: no guard or lookup per leaf
};

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
  const float num = (nx * vx + ny * vy) + nz * vz;
  const float den = (nx * q.d[0] + ny * q.d[1]) + nz * q.d[2];
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
};

// Calls f(candidate) for each candidate (in leaf order) of the leaf's discs: through the bound
// leaf blocks with the widest lanes, else one disc at a time. Stops when f returns false.
template <typename F>
void for_each_disc_candidate(const SplatLeafBlocks& blocks, std::span<const PackedSplat> splats,
                             std::span<const uint32_t> items, const DiscQuery& q, F&& f) {
  const int64_t off = blocks.offset_of(items);
  if (off < 0) {
    for (uint32_t i = 0; i < items.size(); ++i) {
      const PackedSplat& s = splats[items[i]];
      if (disc_candidate(q, s) && !f(DiscCandidate{i, disc_t(q, s), s.index, s.n, s.r})) return;
    }
    return;
  }
  // Candidates are collected 64 discs at a time, as the bits of one word.
  const DiscBlock* b = blocks.blocks();
  const DiscKernel kernel = blocks.kernel();
  for (uint32_t c = 0; c < items.size(); c += 64) {
    const uint32_t n = std::min<uint32_t>(64, uint32_t(items.size()) - c);
    uint64_t bits = 0;
    kernel(b, uint32_t(off) + c, n, q, &bits);
    for (; bits; bits &= bits - 1) {
      const uint32_t i = c + uint32_t(__builtin_ctzll(bits));
      const uint32_t p = uint32_t(off) + i;
      const DiscBlock& blk = b[p / kDiscGroup];
      const uint32_t j = p % kDiscGroup;
      if (!f(DiscCandidate{i, disc_t(q, blk, j), blk.index[j],
                           Vec3(blk.nx[j], blk.ny[j], blk.nz[j]), blk.r[j]}))
        return;
    }
  }
}

}  // namespace pcrt
