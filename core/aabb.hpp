// Axis-aligned bounding box with the slab ray test used by every box-based structure.
#pragma once

#include <algorithm>

#include "core/geometry.hpp"

namespace pcrt {

struct Aabb {
  Vec3 lo = Vec3::Constant(kInfinity);
  Vec3 hi = Vec3::Constant(-kInfinity);

  [[nodiscard]] bool empty() const { return (lo.array() > hi.array()).any(); }
  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Vec3& p, float r) {
    lo = lo.cwiseMin(p - Vec3::Constant(r));
    hi = hi.cwiseMax(p + Vec3::Constant(r));
  }
  void extend(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  [[nodiscard]] Vec3 center() const { return 0.5f * (lo + hi); }
  [[nodiscard]] Vec3 extent() const { return hi - lo; }
  [[nodiscard]] float diagonal() const { return empty() ? 0.0f : extent().norm(); }

  // Slab test against [ray.tmin, ray.tmax]; on a hit narrows [t0, t1] to the box's interval.
  // inv_d is 1/d per component (infinities for axis-parallel rays are handled by IEEE rules).
  [[nodiscard]] bool intersect(const Ray& ray, const Vec3& inv_d, float& t0, float& t1) const {
    float tn = ray.tmin;
    float tf = ray.tmax;
    for (int a = 0; a < 3; ++a) {
      float ta = (lo[a] - ray.o[a]) * inv_d[a];
      float tb = (hi[a] - ray.o[a]) * inv_d[a];
      if (ta > tb) std::swap(ta, tb);
      // NaN (0 * inf when the origin lies on a slab plane) must not shrink the interval.
      tn = ta > tn ? ta : tn;
      tf = tb < tf ? tb : tf;
    }
    t0 = tn;
    t1 = tf;
    return tn <= tf;
  }
};

}  // namespace pcrt
