// Ray against an oriented disc (a splat): the leaf kernel shared by the splat methods and the
// reference oracle. Two-sided: a splat is hit from either side.
#pragma once

#include "core/counters.hpp"
#include "core/geometry.hpp"

namespace pcrt {

inline const Counter kSplatTests{"splat_tests", "ray-disc intersection tests"};

// Returns the ray parameter of the hit with the disc (centre c, unit normal n, radius r) if it is
// in [tmin, tmax) and within the radius, else +inf. Rays parallel to the disc miss it.
inline float intersect_splat(const Ray& ray, const Vec3& c, const Vec3& n, float r, float tmin,
                             float tmax) {
  const float denom = n.dot(ray.d);
  if (denom == 0.0f) return kInfinity;
  const float t = n.dot(c - ray.o) / denom;
  if (!(t >= tmin && t < tmax)) return kInfinity;
  if ((ray.at(t) - c).squaredNorm() > r * r) return kInfinity;
  return t;
}

// A splat packed into one 32-byte record: a leaf loop touches one cache line per item instead of
// three arrays.
struct alignas(32) PackedSplat {
  Vec3 c;
  float r;
  Vec3 n;
  uint32_t index;
};

inline float intersect_splat(const Ray& ray, const PackedSplat& s, float tmin, float tmax) {
  return intersect_splat(ray, s.c, s.n, s.r, tmin, tmax);
}

}  // namespace pcrt
