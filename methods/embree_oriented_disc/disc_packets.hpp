// Embree's oriented discs traced in packets (rtcIntersect8/16, rtcOccluded8/16): the second
// reference of `pcrt anchor`, next to embree_oriented_disc's one ray at a time. The discs are the
// method's own (same splat preparation, Morton order), so the two references differ only in how
// rays reach Embree. No Embree type leaks out of this header.
#pragma once

#include <cstdint>
#include <memory>

#include "core/geometry.hpp"
#include "core/point_cloud.hpp"
#include "methods/method.hpp"

namespace pcrt {

class EmbreeDiscPackets {
 public:
  // `width` is 8 or 16 rays per packet; anything else is an input error.
  EmbreeDiscPackets(const PointCloud& cloud, int width, PrepareContext& ctx);
  ~EmbreeDiscPackets();
  EmbreeDiscPackets(const EmbreeDiscPackets&) = delete;
  EmbreeDiscPackets& operator=(const EmbreeDiscPackets&) = delete;

  // Closest hits of rays[0, count), count <= width(), as one packet: hits[i].prim is kNoPrim where
  // ray i finds nothing. `coherent` tells Embree the rays start together and point alike.
  void closest_hits(const Ray* rays, int count, bool coherent, Hit* hits) const;
  // Whether anything lies within [tmin, tmax) of each ray, as one packet.
  void occluded(const Ray* rays, int count, bool coherent, char* blocked) const;

  [[nodiscard]] int width() const { return width_; }
  // Whether this CPU and Embree build trace packets of this width natively (else Embree splits
  // them): recorded beside every packet ratio.
  [[nodiscard]] bool native() const;

  struct Impl;  // the splats and Embree's scene, defined where Embree is included

 private:
  std::unique_ptr<Impl> impl_;
  int width_;
};

}  // namespace pcrt
