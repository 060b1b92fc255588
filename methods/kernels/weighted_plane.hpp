// The distance-weighted average of a leaf's points and normals at an evaluation point x (thesis
// Eq. 3.22): p(x) = sum w_i p_i / sum w_i, n(x) = sum w_i n_i / sum w_i, with w_i = theta of the
// distance. The implicit surface of Adams et al. 2005, Wald and Seidel 2005 and Hubo et al. is
// f(x) = n(x) . (x - p(x)) (Eq. 3.24, with n normalized); the height difference of Cai et al. 2011
// is the average of the points' own plane distances, sum w_i n_i . (x - p_i) / sum w_i. One pass
// over the K items: O(K).
#pragma once

#include <span>

#include "core/counters.hpp"
#include "methods/kernels/splat_kernel.hpp"

namespace pcrt {

inline const Counter kWeightedEvaluations{"weighted_plane_evaluations",
                                          "weighted averages over a leaf's points (each O(K))"};
inline const Counter kWeightedPointTerms{"weighted_plane_terms",
                                         "point terms summed by weighted averages"};

struct WeightedPlane {
  Vec3 p = Vec3::Zero();
  Vec3 n = Vec3::Zero();  // not normalized
  float height = 0;       // sum w n_i . (x - p_i) / sum w
  float weight = 0;       // sum w: 0 means no point reaches x

  // Eq. 3.24's implicit function at x: the distance of x from the average plane.
  [[nodiscard]] float implicit(const Vec3& x) const {
    const float len = n.norm();
    return len > 0 ? n.dot(x - p) / len : 0.0f;
  }
};

// Theta(d2, splat) returns the weight of a point at squared distance d2 from x (0: no influence).
template <typename Theta>
WeightedPlane weighted_plane(const Vec3& x, std::span<const uint32_t> items,
                             std::span<const PackedSplat> points, Theta&& theta,
                             OpCounters& counters) {
  WeightedPlane out;
  for (uint32_t k : items) {
    const PackedSplat& s = points[k];
    const Vec3 d = x - s.c;
    const float w = theta(d.squaredNorm(), s);
    if (!(w > 0)) continue;
    out.weight += w;
    out.p += w * s.c;
    out.n += w * s.n;
    out.height += w * s.n.dot(d);
  }
  counters.add(kWeightedEvaluations);
  counters.add(kWeightedPointTerms, items.size());
  if (out.weight > 0) {
    out.p /= out.weight;
    out.n /= out.weight;
    out.height /= out.weight;
  }
  return out;
}

}  // namespace pcrt
