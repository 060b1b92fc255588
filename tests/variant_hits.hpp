// How closely a method's variant (a compressed form, say) finds the default's hits, on the
// accuracy harness's rays over a generated surface: shared by the compression tests.
#pragma once

#include <cmath>
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

inline VariantHits compare_variant_hits(const std::string& data, const std::string& method,
                                        const ParamValues& variant, double far_h, size_t rays) {
  const Dataset d = load_dataset(data);
  OpCounters c;
  const double h = mean_spacing(d.cloud.positions, c);
  Timings t;
  const PointScene plain(d.cloud, SceneOptions{method, "", {}}, c, t);
  const PointScene other(d.cloud, SceneOptions{method, "", variant}, c, t);
  VariantHits v;
  for (const Ray& r : accuracy_rays(*d.truth, h, rays, 5)) {
    Hit a, b;
    const bool ha = plain.closest_hit(r, a, c), hb = other.closest_hit(r, b, c);
    if (ha != hb) ++v.one;
    if (!(ha && hb)) continue;
    ++v.both;
    if (std::abs((a.p - b.p).dot(a.n)) > far_h * h) ++v.far;
  }
  return v;
}

}  // namespace pcrt::test
