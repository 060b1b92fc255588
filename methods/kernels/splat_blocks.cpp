#include "methods/kernels/splat_blocks.hpp"

namespace pcrt {

void SplatLeafBlocks::bind(std::span<const uint32_t> refs, std::span<const PackedSplat> splats) {
  base_ = refs.data();
  count_ = refs.size();
  // One block past the last reference, so that the block of any position exists.
  blocks_.assign(refs.size() / kDiscGroup + 1, DiscBlock{});
  for (size_t i = 0; i < refs.size(); ++i) {
    const PackedSplat& s = splats[refs[i]];
    DiscBlock& b = blocks_[i / kDiscGroup];
    const size_t j = i % kDiscGroup;
    b.cx[j] = s.c.x(), b.cy[j] = s.c.y(), b.cz[j] = s.c.z();
    b.nx[j] = s.n.x(), b.ny[j] = s.n.y(), b.nz[j] = s.n.z();
    b.r[j] = s.r;
    b.index[j] = s.index;
  }
  kernel_ = best_disc_kernel();
}

}  // namespace pcrt
