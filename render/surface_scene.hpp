// An exact surface as an intersector: what the accuracy tests and the furnace's floor row trace
// when the question is what the shape itself does, with no method in between.
#pragma once

#include "core/surfaces.hpp"
#include "render/scene.hpp"

namespace pcrt {

class SurfaceScene final : public SceneIntersector {
 public:
  explicit SurfaceScene(const Surface& surface) : surface_(surface) {}
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    counters.add(kRaysCast);
    float t = 0;
    Vec3 n;
    if (!surface_.intersect(ray, t, n) || t >= hit.t) return false;
    counters.add(kRayHits);
    hit = Hit{t, ray.at(t), n, 0, 0};
    return true;
  }

 private:
  const Surface& surface_;
};

}  // namespace pcrt
