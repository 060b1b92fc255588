// What the kd-tree implicit-surface methods (Wald and Seidel 2005, Hubo et al. 2006) share: the
// points of a leaf with a reach (their weight's support), a weighting function, and the start of a
// search inside the leaf.
#pragma once

#include <cmath>
#include <span>
#include <vector>

#include "core/params.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// Gaussian weight exp(-d^2 / (2 sigma^2)), cut off at `cutoff` sigma (Hubo et al. 2006, 2007).
struct GaussianWeight {
  float inv_two_sigma2 = 1, cut2 = 9;
  GaussianWeight(float sigma, float cutoff)
      : inv_two_sigma2(0.5f / (sigma * sigma)), cut2(cutoff * cutoff * sigma * sigma) {}
  float operator()(float d2, const PackedSplat& /*p*/) const {
    return d2 < cut2 ? std::exp(-d2 * inv_two_sigma2) : 0.0f;
  }
};

// The parameters of GaussianWeight, in mean spacings h.
struct GaussianParams {
  float sigma = 1;
  float cutoff = 3;
  static const ParamList<GaussianParams>& list() {
    using P = GaussianParams;
    static const auto l =
        ParamList<P>()
            .add(&P::sigma,
                 {"sigma", 1.0, 0.1, 50, "Gaussian standard deviation, in h (smoothness)"})
            .add(&P::cutoff, {"cutoff", 3.0, 1, 6, "Gaussian cut off at this many sigma"});
    return l;
  }
};

// theta(a) = max(1 - a, 0) with a = d / R (Wald and Seidel 2005).
struct TentWeight {
  float inv_r = 1;
  explicit TentWeight(float r) : inv_r(1.0f / r) {}
  float operator()(float d2, const PackedSplat& /*p*/) const {
    return std::max(1.0f - std::sqrt(d2) * inv_r, 0.0f);
  }
};

// A start inside the leaf: the crossing of the tangent plane of the front-most leaf point within
// `reach` of the ray axis whose plane the ray crosses at or after t_lo (or its nearest approach to
// the ray when that crossing is out of its reach), clamped to t_hi; false if there is none. O(K).
// The front-most, not the nearest to the axis: where a leaf holds two sheets of the surface (both
// walls of a thin part), the point nearest the axis may lie on the back one, and Newton from its
// plane converges there, behind the surface the ray meets first. Planes crossed before t_lo are
// skipped: they are surfaces the search has already left behind (the one a secondary ray starts
// from), and a start clamped to t_lo would run Newton back to them.
inline bool nearest_tangent_crossing(const Ray& ray, std::span<const uint32_t> items,
                                     std::span<const PackedSplat> points, float reach, float t_lo,
                                     float t_hi, float& t_start) {
  const float reach2 = reach * reach;
  float front = kInfinity;
  for (uint32_t k : items) {
    const PackedSplat& p = points[k];
    const Vec3 v = p.c - ray.o;
    const float along = v.dot(ray.d);
    if (along >= front || (v - along * ray.d).squaredNorm() >= reach2) continue;
    const float denom = p.n.dot(ray.d);
    float t = std::abs(denom) > 1e-6f ? p.n.dot(v) / denom : along;
    if (!(t >= t_lo)) continue;
    // A plane crossed beyond the point's reach (a plane tilted toward the ray) starts where no
    // weight is, and the search would end at once: start at the point's nearest approach then.
    if ((ray.at(t) - p.c).squaredNorm() >= reach2) t = std::max(along, t_lo);
    front = along;
    t_start = std::min(t, t_hi);
  }
  return front < kInfinity;
}

// The cloud index of the leaf point nearest x (a blended hit's colour comes from it). O(K).
inline uint32_t nearest_point(const Vec3& x, std::span<const uint32_t> items,
                              std::span<const PackedSplat> points) {
  uint32_t best = points[items[0]].index;
  float best_d2 = kInfinity;
  for (uint32_t k : items) {
    const float d2 = (points[k].c - x).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = points[k].index;
  }
  return best;
}

}  // namespace pcrt
