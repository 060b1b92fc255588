#include "methods/kernels/splat_blocks.hpp"

namespace pcrt {

void SplatLeafBlocks::bind(std::span<const uint32_t> refs, std::span<const PackedSplat> splats) {
  base_ = refs.data();
  count_ = refs.size();
  // Padded by one full lane group of zero discs (never candidates: den = 0), so that a group may
  // be read past the last reference.
  const size_t n = refs.size() + 8;
  for (auto* v : {&cx_, &cy_, &cz_, &nx_, &ny_, &nz_, &r2_}) v->assign(n, 0.0f);
  for (size_t i = 0; i < refs.size(); ++i) {
    const PackedSplat& s = splats[refs[i]];
    cx_[i] = s.c.x(), cy_[i] = s.c.y(), cz_[i] = s.c.z();
    nx_[i] = s.n.x(), ny_[i] = s.n.y(), nz_[i] = s.n.z();
    r2_[i] = s.r * s.r;
  }
  arrays_ = {cx_.data(), cy_.data(), cz_.data(), nx_.data(), ny_.data(), nz_.data(), r2_.data()};
  kernel_ = best_disc_kernel();
}

}  // namespace pcrt
