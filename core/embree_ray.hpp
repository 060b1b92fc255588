// Our Ray as Embree 3's RTCRayHit (shared by the Embree splat reference and the Embree triangle
// engine). Include only from translation units that link Embree.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>

#include "core/geometry.hpp"

namespace pcrt {

// A closest-hit query for rays in [ray.tmin, min(ray.tmax, t_limit)].
inline RTCRayHit embree_ray(const Ray& ray, float t_limit) {
  RTCRayHit rh{};
  rh.ray.org_x = ray.o.x(), rh.ray.org_y = ray.o.y(), rh.ray.org_z = ray.o.z();
  rh.ray.dir_x = ray.d.x(), rh.ray.dir_y = ray.d.y(), rh.ray.dir_z = ray.d.z();
  rh.ray.tnear = ray.tmin;
  rh.ray.tfar = std::min(ray.tmax, t_limit);
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace pcrt
