// Ray against an oriented disc (a splat): the leaf kernel shared by the splat methods and the
// reference oracle. Two-sided: a splat is hit from either side.
#pragma once

#include "core/counters.hpp"
#include "core/geometry.hpp"

namespace pcrt {

inline const Counter kSplatTests{"splat_tests", "ray-disc intersection tests"};

// Returns the ray parameter of the hit with the disc (centre c, unit normal n, radius r) if it is
// in [tmin, tmax) and within the radius, else +inf. Rays parallel to the disc miss it.
inline float intersect_splat(const Ray& ray, const Vec3& c, const Vec3& n, float r, float tmin, float tmax) {
  const float denom = n.dot(ray.d);
  if (denom == 0.0f) return kInfinity;
  const float t = n.dot(c - ray.o) / denom;
  if (!(t >= tmin && t < tmax)) return kInfinity;
  if ((ray.at(t) - c).squaredNorm() > r * r) return kInfinity;
  return t;
}

}  // namespace pcrt
