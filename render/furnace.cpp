#include "render/furnace.hpp"

#include <cmath>

namespace pcrt {
namespace {

// The accuracy table's false-hit distance, in h.
constexpr double kFalseHitH = 5.0;

RenderScene furnace_scene(const SceneIntersector& geometry, const PointCloud& cloud) {
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
  return scene;
}

// Whether the centre sample's hit at distance t along `ray` is where the exact surface is.
bool on_surface(const FurnaceTruth& truth, const Ray& ray, float t) {
  float exact = 0;
  Vec3 n;
  if (!truth.surface.intersect(ray, exact, n)) return false;
  return std::abs(double(t) - double(exact)) <= kFalseHitH * truth.h;
}

// Every dark pixel by its centre sample (render_pixel's first sample, through the pixel centre).
FurnaceCauses dark_causes(const FurnaceResult& r, const std::vector<bool>& dark,
                          const Camera& camera, const FurnaceTruth& truth) {
  FurnaceCauses causes;
  const int width = r.frame.image.width();
  for (size_t i = 0; i < dark.size(); ++i) {
    if (!dark[i]) continue;
    const Ray ray = camera.ray(float(i % width) + 0.5f, float(i / width) + 0.5f);
    ++(on_surface(truth, ray, r.frame.primary_t[i]) ? causes.secondary : causes.primary);
  }
  return causes;
}

}  // namespace

FurnaceResult white_furnace(const SceneIntersector& geometry, const PointCloud& cloud,
                            const RenderSettings& settings,
                            const std::optional<FurnaceTruth>& truth) {
  const RenderScene scene = furnace_scene(geometry, cloud);
  RenderSettings s = settings;
  if (!s.camera) s.camera = Camera::framing(scene.bounds(), s.width, s.height, s.view, s.up);
  FurnaceResult r{render(scene, s), 0, 0, 0, std::nullopt};
  // A pixel that lost one of its S paths is at most 1 - 1/S; half of that step separates them.
  const float full = 1.0f - 0.5f / float(s.spp);
  std::vector<bool> dark(r.frame.primary_t.size(), false);
  double sum = 0;
  for (size_t i = 0; i < r.frame.primary_t.size(); ++i) {
    if (!std::isfinite(r.frame.primary_t[i])) continue;
    const float v = r.frame.image.pixels()[i].mean();
    ++r.object_pixels;
    sum += v;
    if (v < full) ++r.dark_pixels, dark[i] = true;
  }
  r.mean = r.object_pixels ? sum / double(r.object_pixels) : 0.0;
  if (truth) r.causes = dark_causes(r, dark, *s.camera, *truth);
  return r;
}

}  // namespace pcrt
