// Weighted splat intersection (thesis section 5.5.2, "Splat intersection"): every splat of the
// leaf that the ray hits within its radius is a candidate; the hits within a depth window behind
// the front-most are averaged, weighted by their distance from the splat centres, into one hit
// point and normal. Shared by Linsen et al. 2007, Kashyap et al. 2010 and Goradia et al. 2010,
// which differ in how the splats are made. Built on the projection kernel: a splat hit is the
// crossing of the splat's plane, kept when it lies within the radius. O(K).
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "core/params.hpp"
#include "methods/kernels/ray_projection.hpp"
#include "methods/kernels/splat_blocks.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/kernels/splat_set.hpp"

namespace pcrt {

struct SplatBlendSettings {
  float depth = 0;         // blend the hits within this distance behind the front-most
  float early_margin = 0;  // the largest splat radius: a blend may land that far before the leaf
  float footprint = 0;
};

// The window is `front_depth` median splat radii deep; the margin is the largest radius.
inline SplatBlendSettings splat_blend_settings(std::span<const float> radii, float front_depth) {
  if (radii.empty()) return {};
  std::vector<float> r(radii.begin(), radii.end());
  const float max_r = *std::max_element(r.begin(), r.end());
  std::nth_element(r.begin(), r.begin() + std::ptrdiff_t(r.size() / 2), r.end());
  const float median_r = r[r.size() / 2];
  return {front_depth * median_r, max_r, median_r};
}

// The blend methods' items: their discs, with how far before a leaf a blend may land
// (ItemSet::hits_before_leaf): the window's depth behind its front-most crossing, and the margin
// a hit may lie before the leaf (record_blend).
inline ItemSet blend_items(const SplatSet& splats, const SplatBlendSettings& s) {
  ItemSet items = splats.disc_items();
  items.hits_before_leaf = s.early_margin + s.depth;
  return items;
}

// The blend window parameter of the splat methods.
inline ParamSpec front_depth_spec() {
  return {"front_depth", 0.5, 0, 20,
          "blend the splat hits within this many median splat radii behind the front-most"};
}

// Weight of a splat hit at squared distance q * r^2 from the centre: 1 - q, falling to 0 at the
// rim, so that overlapping splats hand over smoothly.
inline float splat_hit_weight(float q) { return q < 1.0f ? 1.0f - q : 0.0f; }

// The disc lanes as the blend's prefilter: r^2 widened by 10% (5% on the radius), so that no
// splat the exact weight accepts (1 - |x - c|^2 / r^2 > 0, rounded another way) is dropped; the
// rounding of either radius test is a few ulps of the ray's distance, below 0.1% of a splat radius
// on the clouds measured. The window is [tmin, inf): the groups' windows are the blend's own.
inline DiscQuery blend_prefilter(const Ray& ray) {
  DiscQuery q = disc_query(ray, kInfinity);
  q.r2_scale = 1.1f;
  return q;
}

// The blend over the leaf's splats, those the disc lanes let through (the exact weight decides),
// read from the bound leaf blocks (the splats' only copy once bound), else from the item-order
// set one at a time, each with the crossing the lanes computed. NormalAt(k, splat, x) as in
// blend_projected. Work counts as one splat test per leaf item, as the lanes test them all.
template <typename NormalAt>
bool blend_splat_hits(const Ray& ray, const LeafVisit& leaf, const SplatLeafBlocks& blocks,
                      const SplatSet& splats, const SplatBlendSettings& s, NormalAt&& normal_at,
                      Hit& hit, OpCounters& counters) {
  auto weight = [](const Ray& r, const PackedSplat& p, float t, const Vec3& /*lateral*/) {
    return splat_hit_weight((r.at(t) - p.c).squaredNorm() / (p.r * p.r));
  };
  counters.add(kSplatTests, leaf.items.size());
  const ProjectionSettings projection{s.depth, 0.0f, s.early_margin, s.footprint};
  const DiscQuery q = blend_prefilter(ray);
  auto each = [&](auto&& f) {
    for_each_disc_candidate(blocks, splats, leaf.items, q, [&](const DiscCandidate& c) {
      f(leaf.items[c.i], PackedSplat{c.c, c.r, c.n, c.prim}, c.t);
      return true;
    });
  };
  return blend_crossings(ray, leaf, each, projection, weight, normal_at, hit, counters);
}

inline bool blend_splat_hits(const Ray& ray, const LeafVisit& leaf, const SplatLeafBlocks& blocks,
                             const SplatSet& splats, const SplatBlendSettings& s, Hit& hit,
                             OpCounters& counters) {
  auto own_normal = [](uint32_t, const PackedSplat& p, const Vec3&) { return p.n; };
  return blend_splat_hits(ray, leaf, blocks, splats, s, own_normal, hit, counters);
}

}  // namespace pcrt
