#include "methods/kernels/splat_blocks.hpp"

#include <tbb/parallel_for.h>

#include <cstdint>

namespace pcrt {

void SplatLeafBlocks::bind(std::span<const uint32_t> refs, const SplatSet& splats) {
  base_ = refs.data();
  count_ = refs.size();
  // Leaf-order positions are 32-bit (the lanes' `first`): past 2^32 references, item order,
  // whose positions are point indices.
  leaf_order_ = double(refs.size()) <= kLeafOrderMaxRefsPerItem * double(splats.size()) &&
                refs.size() <= size_t(UINT32_MAX) - 64;
  const size_t count = leaf_order_ ? refs.size() : splats.size();
  // One block past the last position, so that the block of any position exists.
  std::vector<DiscBlock>().swap(blocks_);
  blocks_.assign(count / kDiscGroup + 1, DiscBlock{});
  tbb::parallel_for(size_t(0), blocks_.size(), [&](size_t g) {
    DiscBlock& b = blocks_[g];
    for (size_t j = 0, i = g * kDiscGroup; j < kDiscGroup && i < count; ++j, ++i) {
      const PackedSplat s = splats.splat(leaf_order_ ? refs[i] : uint32_t(i));
      b.cx[j] = s.c.x(), b.cy[j] = s.c.y(), b.cz[j] = s.c.z();
      b.nx[j] = s.n.x(), b.ny[j] = s.n.y(), b.nz[j] = s.n.z();
      b.r[j] = s.r;
    }
  });
  kernel_ = best_disc_kernel();
}

void SplatLeafBlocks::gather(const uint32_t* items, uint32_t n, DiscBlock* out) const {
  for (uint32_t m = 0; m < n; ++m) {
    const DiscBlock& b = blocks_[items[m] / kDiscGroup];
    const uint32_t j = items[m] % kDiscGroup;
    DiscBlock& o = out[m / kDiscGroup];
    const uint32_t k = m % kDiscGroup;
    o.cx[k] = b.cx[j], o.cy[k] = b.cy[j], o.cz[k] = b.cz[j];
    o.nx[k] = b.nx[j], o.ny[k] = b.ny[j], o.nz[k] = b.nz[j];
    o.r[k] = b.r[j];
  }
  if (n % kDiscGroup == 0) return;
  DiscBlock& last = out[n / kDiscGroup];
  for (uint32_t k = n % kDiscGroup; k < kDiscGroup; ++k)
    last.cx[k] = last.cy[k] = last.cz[k] = last.nx[k] = last.ny[k] = last.nz[k] = last.r[k] = 0;
}

}  // namespace pcrt
