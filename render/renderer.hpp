// The generic renderer of thesis section 5.5.1: Algorithm 1 (S samples over M pixels) and
// Algorithm 2 (recursive rendering equation, B bounces) as an iterative path tracer over a
// RenderScene: the objects' materials sampled by their BSDFs (render/bsdf.hpp), every sampled
// light reached by a shadow ray at each non-specular vertex (next event estimation, section
// 4.1.1), and both strategies weighted by the power heuristic where a sampled direction can also
// reach a light. No Russian roulette: every path runs its B bounces unless it leaves the scene.
// A tile's shadow rays are traced once its paths (up to 1024 samples at a time) are drawn,
// kShadowPacket at a time.
#pragma once

#include <atomic>
#include <optional>
#include <vector>

#include "core/camera.hpp"
#include "core/counters.hpp"
#include "core/image.hpp"
#include "core/point_cloud.hpp"
#include "core/rng.hpp"
#include "render/render_scene.hpp"
#include "render/scene.hpp"

namespace pcrt {

// Shadow rays a frame traces at once (SceneIntersector::any_hits): sixteen neighbouring samples'
// rays, as Embree's packets of 16.
inline constexpr size_t kShadowPacket = 16;

// What a frame may ask for, wherever it is asked (the command line, the Python module).
struct FrameLimits {
  static constexpr int kMaxSide = 16384;   // pixels per image side
  static constexpr int kMaxSpp = 1 << 16;  // S
  static constexpr int kMaxBounces = 64;   // B
  static constexpr int kMaxThreads = 1024;
};

struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 1;      // S
  int bounces = 1;  // B: BRDF-sampled rays after the primary hit
  int threads = 0;  // 0: all cores
  uint64_t seed = 1;
  bool point_light = true;
  float ray_epsilon =
      0;  // offset of secondary ray origins along the normal; 0: 1e-3 * scene diagonal
  Vec3 view = Vec3(0.55f, -0.75f, 0.4f);  // direction from the cloud's centre to the camera
  Vec3 up = Vec3::UnitZ();
  std::optional<Camera> camera;  // default: Camera::framing of the cloud's bounds along view/up
  // When set and true, the pixels not yet rendered are skipped: the caller abandons the frame
  // (Ctrl-C in Python). Read once per pixel.
  const std::atomic<bool>* stop = nullptr;
};

struct RenderResult {
  Image image;
  Image depth;    // primary-hit distance of the centre sample, scaled to [0,1] over the image
  Image normals;  // primary-hit normal of the centre sample as (n + 1) / 2
  OpCounters counters;
  double seconds = 0;      // the whole frame, the caustic map's prepass included
  double csm_seconds = 0;  // the caustic map's prepass (photons and octree), when the scene has one
  // Per pixel (row-major) the centre sample's primary hit distance (+inf: no hit) and its normal
  // facing the camera: what `pcrt compare` judges against a mesh rendered with the same camera.
  std::vector<float> primary_t;
  std::vector<Vec3> primary_n;
};

// The shading normal of a hit: towards the incoming ray for one-sided materials; dielectrics keep
// the surface's own (outward) normal, so that wo.z < 0 says the ray arrived from inside.
Vec3 shading_normal(const Hit& hit, const Ray& ray, const Material& m);

// A direction around the unit normal n with density cos/pi (the renderer's bounce rays).
Vec3 cosine_direction(const Vec3& n, Rng& rng);

// Where a secondary ray leaving the hit towards `dir` starts: lifted off the surface along the
// normal, to the side `dir` leaves on, by the larger of epsilon and half the hit's footprint
// (neighbouring splats of a curved surface stand above the hit by up to radius^2 * curvature).
Vec3 spawn_point(const Hit& hit, const Vec3& n, const Vec3& dir, float epsilon);

// The default frame of one object (single_object_scene): what `pcrt render --method`, the sweeps
// and the Python module render.
RenderResult render(const SceneIntersector& scene, const PointCloud& cloud,
                    const RenderSettings& settings);
// A frame of a whole scene; settings.camera (or framing of the scene's bounds along view/up),
// settings.point_light is not used (the scene's lights are).
RenderResult render(const RenderScene& scene, const RenderSettings& settings);

}  // namespace pcrt
