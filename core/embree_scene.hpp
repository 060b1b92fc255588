// One Embree 3 device and scene, shared by the Embree splat reference and the Embree triangle
// engine: started with a clear error, its allocations counted through Embree's memory monitor,
// one geometry committed with a high-quality BVH, and closest-hit queries in our Ray's terms.
// Include only from translation units that link Embree.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "core/error.hpp"
#include "core/geometry.hpp"

namespace pcrt {

class EmbreeScene {
 public:
  // `who` names the user in the error if Embree cannot start.
  explicit EmbreeScene(const char* who) {
    device_ = rtcNewDevice(nullptr);
    if (!device_)
      input_error("{}: Embree could not start (error {})", who, int(rtcGetDeviceError(nullptr)));
    rtcSetDeviceMemoryMonitorFunction(
        device_,
        [](void* user, ssize_t bytes, bool) {
          static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes);
          return true;
        },
        &bytes_);
    scene_ = rtcNewScene(device_);
  }
  ~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  [[nodiscard]] RTCGeometry new_geometry(RTCGeometryType type) const {
    return rtcNewGeometry(device_, type);
  }
  // Commits the geometry (whose buffers are set), attaches it and builds the scene.
  void build(RTCGeometry geom) {
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scene_);
  }
  // The closest hit with t in [ray.tmin, min(ray.tmax, t_limit)]: true with rh filled in.
  bool closest_hit(const Ray& ray, float t_limit, RTCRayHit& rh) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rh = RTCRayHit{};
    rh.ray.org_x = ray.o.x(), rh.ray.org_y = ray.o.y(), rh.ray.org_z = ray.o.z();
    rh.ray.dir_x = ray.d.x(), rh.ray.dir_y = ray.d.y(), rh.ray.dir_z = ray.d.z();
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = std::min(ray.tmax, t_limit);
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  // Whether anything lies within [ray.tmin, ray.tmax) (rtcOccluded1: stops at the first hit).
  bool occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r{};
    r.org_x = ray.o.x(), r.org_y = ray.o.y(), r.org_z = ray.o.z();
    r.dir_x = ray.d.x(), r.dir_y = ray.d.y(), r.dir_z = ray.d.z();
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.mask = ~0u;
    rtcOccluded1(scene_, &context, &r);
    return r.tfar < 0;  // Embree sets tfar to -inf on a hit
  }
  // The committed scene, for queries other than the ones above (packets).
  [[nodiscard]] RTCScene scene() const { return scene_; }
  // Whether Embree traces packets of `width` rays natively here (4, 8 or 16).
  [[nodiscard]] bool native_packets(int width) const {
    const RTCDeviceProperty p = width == 16  ? RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED
                                : width == 8 ? RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED
                                             : RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED;
    return rtcGetDeviceProperty(device_, p) != 0;
  }
  // Bytes Embree holds (its BVH above all).
  [[nodiscard]] size_t bytes() const { return size_t(std::max<int64_t>(bytes_.load(), 0)); }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::atomic<int64_t> bytes_{0};
};

}  // namespace pcrt
