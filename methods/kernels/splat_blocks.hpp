// Splats laid out in a structure's leaf order (one entry per leaf reference, so the discs of a
// leaf are contiguous) in structure-of-arrays layout: the leaf loop streams seven float arrays
// W lanes at a time instead of chasing an index per disc. Made once the structure is built
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
  [[nodiscard]] const DiscArrays& arrays() const { return arrays_; }
  [[nodiscard]] DiscKernel kernel() const { return kernel_; }
  [[nodiscard]] size_t memory_bytes() const { return 7 * cx_.capacity() * sizeof(float); }

 private:
  const uint32_t* base_ = nullptr;
  size_t count_ = 0;
  std::vector<float> cx_, cy_, cz_, nx_, ny_, nz_, r2_;
  DiscArrays arrays_{};
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
                           Lane1(s.n.y()), Lane1(s.n.z()), Lane1(s.r * s.r)) != 0;
}

// The exact ray parameter of a candidate's plane crossing (the kernel's num / den, once per
// candidate rather than per disc).
inline float disc_t(const Ray& ray, const PackedSplat& s) {
  const float vx = s.c.x() - ray.o.x(), vy = s.c.y() - ray.o.y(), vz = s.c.z() - ray.o.z();
  const float num = (s.n.x() * vx + s.n.y() * vy) + s.n.z() * vz;
  const float den = (s.n.x() * ray.d.x() + s.n.y() * ray.d.y()) + s.n.z() * ray.d.z();
  return num / den;
}

// Calls f(i) for each candidate i (position within the leaf, in order) of the leaf's discs:
// through the bound leaf blocks with the widest lanes, else one disc at a time.
template <typename F>
void for_each_disc_candidate(const SplatLeafBlocks& blocks, std::span<const PackedSplat> splats,
                             std::span<const uint32_t> items, const DiscQuery& q, F&& f) {
  const int64_t off = blocks.offset_of(items);
  if (off < 0) {
    for (uint32_t i = 0; i < items.size(); ++i)
      if (disc_candidate(q, splats[items[i]]) && !f(i)) return;
    return;
  }
  // Candidates are collected 64 discs at a time, as the bits of one word.
  const DiscArrays& a = blocks.arrays();
  const DiscKernel kernel = blocks.kernel();
  for (uint32_t c = 0; c < items.size(); c += 64) {
    const uint32_t n = std::min<uint32_t>(64, uint32_t(items.size()) - c);
    uint64_t bits = 0;
    kernel(a, uint32_t(off) + c, n, q, &bits);
    for (; bits; bits &= bits - 1)
      if (!f(c + uint32_t(__builtin_ctzll(bits)))) return;
  }
}

}  // namespace pcrt
