// How closely a method's variant (a compressed form, say) finds the default's hits, on the
// accuracy harness's rays over a generated surface: shared by the compression tests.
#pragma once

#include <cmath>
#include <span>
#include <string>

#include "core/dataset.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/accuracy.hpp"
#include "render/scene.hpp"

namespace pcrt::test {

struct VariantHits {
  size_t both = 0;  // rays both hit
  size_t one = 0;   // rays only one of them hits
  size_t far = 0;   // of `both`, hits more than far_h spacings apart along the surface normal
};

// The closest hits of two scenes on the same rays; `far_apart(a, b)` says when two hits count as
// far apart.
template <class FarApart>
VariantHits compare_scene_hits(const SceneIntersector& first, const SceneIntersector& second,
                               std::span<const Ray> rays, FarApart&& far_apart) {
  OpCounters c;
  VariantHits v;
  for (const Ray& r : rays) {
    Hit a, b;
    const bool ha = first.closest_hit(r, a, c), hb = second.closest_hit(r, b, c);
    if (ha != hb) ++v.one;
    if (!(ha && hb)) continue;
    ++v.both;
    if (far_apart(a, b)) ++v.far;
  }
  return v;
}

// Whether hit b lies more than `limit` from hit a along a's normal.
inline auto apart_along_normal(double limit) {
  return [limit](const Hit& a, const Hit& b) { return std::abs((a.p - b.p).dot(a.n)) > limit; };
}

inline VariantHits compare_variant_hits(const std::string& data, const std::string& method,
                                        const ParamValues& variant, double far_h, size_t rays) {
  const Dataset d = load_dataset(data);
  OpCounters c;
  const double h = mean_spacing(d.cloud.positions, c);
  Timings t;
  const PointScene plain(d.cloud, SceneOptions{method, "", {}}, c, t);
  const PointScene other(d.cloud, SceneOptions{method, "", variant}, c, t);
  return compare_scene_hits(plain, other, accuracy_rays(*d.truth, h, rays, 5),
                            apart_along_normal(far_h * h));
}

}  // namespace pcrt::test
