#include "methods/kernels/splat_blocks.hpp"

#include <tbb/parallel_for.h>

#include <cstdint>

#include "core/error.hpp"

namespace pcrt {

const ParamList<DiscBlockParams>& DiscBlockParams::list() {
  using P = DiscBlockParams;
  static const auto l = ParamList<P>().add(
      &P::layout, {"disc_blocks", 0, 0, 2,
                   "disc layout for the leaves: 0 leaf order where the structure references "
                   "each disc at most 12 times and the copy stays under 512 MiB, else item "
                   "order; 1 leaf order (a copy per "
                   "reference, fastest); 2 item order (no copy, leaves gather)"});
  return l;
}

namespace {

bool use_leaf_order(DiscBlockLayout layout, size_t refs, size_t items) {
  // Leaf-order positions are 32-bit (the lanes' `first`): past 2^32 references, item order,
  // whose positions are point indices.
  if (refs > size_t(UINT32_MAX) - 64) return false;
  switch (layout) {
    case DiscBlockLayout::kLeafOrder:
      return true;
    case DiscBlockLayout::kItemOrder:
      return false;
    case DiscBlockLayout::kAuto:
      break;
  }
  return SplatLeafBlocks::auto_leaf_order(double(refs), double(items));
}

}  // namespace

void SplatLeafBlocks::bind(std::span<const uint32_t> refs, const SplatSet& splats,
                           DiscBlockLayout layout) {
  // No references for items: the structure decodes its leaves (the octree's compact_refs), so
  // there is no leaf order to copy.
  const bool decoded_leaves = refs.empty() && splats.size() > 0;
  if (decoded_leaves && layout == DiscBlockLayout::kLeafOrder)
    input_error(
        "disc_blocks=1 (leaf order) needs the structure's leaves as pieces of one reference "
        "array; the octree's compact references are decoded per leaf (set compact_refs=0)");
  base_ = refs.data();
  count_ = refs.size();
  leaf_order_ = !decoded_leaves && use_leaf_order(layout, refs.size(), splats.size());
  kernel_ = best_disc_kernel();
  std::vector<DiscBlock>().swap(blocks_);
  if (!leaf_order_) {
    centres_ = splats.centres, normals_ = splats.normals, radii_ = splats.radii;
    return;
  }
  // One block past the last position, so that the block of any position exists.
  blocks_.assign(count_ / kDiscGroup + 1, DiscBlock{});
  tbb::parallel_for(size_t(0), blocks_.size(), [&](size_t g) {
    DiscBlock& b = blocks_[g];
    for (size_t j = 0, i = g * kDiscGroup; j < kDiscGroup && i < count_; ++j, ++i) {
      const PackedSplat s = splats.splat(refs[i]);
      b.cx[j] = s.c.x(), b.cy[j] = s.c.y(), b.cz[j] = s.c.z();
      b.nx[j] = s.n.x(), b.ny[j] = s.n.y(), b.nz[j] = s.n.z();
      b.r[j] = s.r;
    }
  });
}

void SplatLeafBlocks::gather(const uint32_t* items, uint32_t n, DiscBlock* out) const {
  for (uint32_t m = 0; m < n; ++m) {
    const uint32_t item = items[m];
    const Vec3& c = centres_[item];
    const Vec3& nn = normals_[item];
    DiscBlock& o = out[m / kDiscGroup];
    const uint32_t k = m % kDiscGroup;
    o.cx[k] = c.x(), o.cy[k] = c.y(), o.cz[k] = c.z();
    o.nx[k] = nn.x(), o.ny[k] = nn.y(), o.nz[k] = nn.z();
    o.r[k] = radii_[item];
  }
  if (n % kDiscGroup == 0) return;
  DiscBlock& last = out[n / kDiscGroup];
  for (uint32_t k = n % kDiscGroup; k < kDiscGroup; ++k)
    last.cx[k] = last.cy[k] = last.cz[k] = last.nx[k] = last.ny[k] = last.nz[k] = last.r[k] = 0;
}

}  // namespace pcrt
