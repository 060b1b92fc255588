#include "render/furnace.hpp"

#include <cmath>

namespace pcrt {

FurnaceResult white_furnace(const SceneIntersector& geometry, const PointCloud& cloud,
                            const RenderSettings& settings) {
  RenderScene scene;
  Material white;
  white.albedo = Vec3::Ones();
  // No point colours: the furnace's albedo is 1 whatever the file carries.
  scene.objects.push_back(
      SceneObject{&geometry, nullptr, white, Transform{}, cloud.bounds(), "furnace"});
  Light environment;
  environment.kind = LightKind::kEnvironment;
  environment.sampled = false;  // reached by bounce rays only: every escaping path carries 1
  scene.lights.push_back(environment);
  FurnaceResult r{render(scene, settings)};
  // A pixel that lost one of its S paths is at most 1 - 1/S; half of that step separates them.
  const float full = 1.0f - 0.5f / float(settings.spp);
  double sum = 0;
  for (size_t i = 0; i < r.frame.primary_t.size(); ++i) {
    if (!std::isfinite(r.frame.primary_t[i])) continue;
    const float v = r.frame.image.pixels()[i].mean();
    ++r.object_pixels;
    sum += v;
    if (v < full) ++r.dark_pixels;
  }
  r.mean = r.object_pixels ? sum / double(r.object_pixels) : 0.0;
  return r;
}

}  // namespace pcrt
