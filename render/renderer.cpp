#include "render/renderer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>

#include "core/rng.hpp"

namespace pcrt {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kTile = 16;

struct Lighting {
  Vec3 light_pos;
  float light_intensity;  // radiant intensity, scaled so a white surface facing it at the
                          // scene's distance receives irradiance pi * 0.8
  bool point_light;
  float epsilon;
};

// The emitting sky: a vertical gradient, brighter towards +z.
Vec3 sky(const Vec3& d) {
  const float a = 0.5f * (d.z() + 1.0f);
  return (1.0f - a) * Vec3(0.35f, 0.33f, 0.30f) + a * Vec3(0.45f, 0.55f, 0.70f);
}

Vec3 albedo(const PointCloud& cloud, uint32_t prim) {
  if (!cloud.has_colours() || prim >= cloud.size()) return Vec3::Constant(0.75f);
  const Rgb8 c = cloud.colours[prim];
  auto lin = [](uint8_t v) { return std::pow(float(v) / 255.0f, 2.2f); };
  return Vec3(lin(c.r), lin(c.g), lin(c.b));
}

// Algorithm 2, unrolled: radiance along `ray` whose closest hit is `hit`.
Vec3 radiance(const SceneIntersector& scene, const PointCloud& cloud, Ray ray, Hit hit, bool found,
              int bounces, const Lighting& lighting, Rng& rng, OpCounters& counters) {
  Vec3 result = Vec3::Zero();
  Vec3 throughput = Vec3::Ones();
  for (int depth = 0;; ++depth) {
    if (!found) {
      // A camera ray that misses sees the sky; so does a bounce ray (the sky is the light source
      // of Algorithm 2, line 7).
      result += throughput.cwiseProduct(sky(ray.d));
      break;
    }
    const Vec3 n = hit.n.dot(ray.d) > 0 ? Vec3(-hit.n) : hit.n;  // shade the side the ray came from
    const Vec3 f = albedo(cloud, hit.prim) / kPi;                // Lambertian BRDF
    const Vec3 x = hit.p + std::max(lighting.epsilon, 0.5f * hit.footprint) * n;
    if (lighting.point_light) {
      const Vec3 to_light = lighting.light_pos - x;
      const float dist = to_light.norm();
      const Vec3 l = to_light / dist;
      const float cos_l = n.dot(l);
      if (cos_l > 0) {
        const Ray shadow{x, l, 0.0f, dist};
        counters.add(kShadowRays);
        if (!scene.any_hit(shadow, counters))
          result += throughput.cwiseProduct(f) * (lighting.light_intensity * cos_l / (dist * dist));
      }
    }
    if (depth == bounces) break;
    // Cosine-weighted sampling: pdf = cos/pi, so the estimator's weight is f * pi = albedo.
    ray = Ray{x, cosine_direction(n, rng), 0.0f, kInfinity};
    throughput = throughput.cwiseProduct(f * kPi);
    hit = Hit{};
    counters.add(kBounceRays);
    found = scene.closest_hit(ray, hit, counters);
  }
  return result;
}

}  // namespace

Vec3 cosine_direction(const Vec3& n, Rng& rng) {
  const float u1 = rng.uniform();
  const float phi = 2.0f * kPi * rng.uniform();
  const float r = std::sqrt(u1);
  Vec3 u, v;
  orthonormal_basis(n, u, v);
  return (r * std::cos(phi) * u + r * std::sin(phi) * v + std::sqrt(std::max(0.0f, 1.0f - u1)) * n)
      .normalized();
}

namespace {

// The light above and to the left of the camera, in the frame the camera's up vector defines.
Lighting make_lighting(const Aabb& bounds, const RenderSettings& s) {
  const float diag = std::max(bounds.diagonal(), 1e-6f);
  Lighting lighting;
  lighting.point_light = s.point_light;
  const Vec3 up = s.up.normalized();
  const Vec3 side = s.view.normalized().cross(up).normalized();
  lighting.light_pos =
      bounds.center() + diag * (0.9f * s.view.normalized() + 1.2f * up - 0.6f * side);
  const float light_dist = (lighting.light_pos - bounds.center()).norm();
  lighting.light_intensity = 0.8f * kPi * light_dist * light_dist;
  lighting.epsilon = s.ray_epsilon > 0 ? s.ray_epsilon : 1e-3f * diag;
  return lighting;
}

// What every pixel of one frame shares, and the images it writes.
struct Frame {
  const SceneIntersector& scene;
  const PointCloud& cloud;
  const RenderSettings& s;
  Camera camera;
  Lighting lighting;
  const PrimaryPass* primary;  // the method's own primary pass, or null: camera rays are traced
  RenderResult& out;
  std::vector<float>& depth;
};

// The closest hit of a camera ray: from the method's primary pass if it has one (counted like a
// traced ray, so that rays_cast stays comparable), else traced.
bool primary_hit(const Frame& f, const Ray& ray, float px, float py, Hit& hit,
                 OpCounters& counters) {
  counters.add(kPrimaryRays);
  if (!f.primary) return f.scene.closest_hit(ray, hit, counters);
  counters.add(kRaysCast);
  const bool found = f.primary->closest_hit(ray, px, py, hit, counters);
  if (found) counters.add(kRayHits);
  return found;
}

// Algorithm 1 for one pixel: spp samples, the first through the pixel centre (it also feeds the
// depth and normal images), the others jittered over the pixel.
void render_pixel(const Frame& f, int x, int y, OpCounters& counters) {
  const RenderSettings& s = f.s;
  const uint64_t pixel = uint64_t(y) * uint64_t(s.width) + uint64_t(x);
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < s.spp; ++i) {
    Rng rng = Rng::for_sample(s.seed, pixel, uint64_t(i));
    const float jx = i == 0 ? 0.5f : rng.uniform(), jy = i == 0 ? 0.5f : rng.uniform();
    const Ray ray = f.camera.ray(float(x) + jx, float(y) + jy);
    Hit hit;
    const bool found = primary_hit(f, ray, float(x) + jx, float(y) + jy, hit, counters);
    if (i == 0 && found) {
      f.depth[pixel] = hit.t;
      const Vec3 n = hit.n.dot(ray.d) > 0 ? Vec3(-hit.n) : hit.n;
      f.out.normals.at(x, y) = 0.5f * (n + Vec3::Ones());
      f.out.primary_n[pixel] = n;
    }
    sum += radiance(f.scene, f.cloud, ray, hit, found, s.bounces, f.lighting, rng, counters);
  }
  f.out.image.at(x, y) = sum / float(s.spp);
}

// Every pixel in 16x16 tiles on the threads the settings allow; counters per thread, summed.
void render_tiles(const Frame& f, OpCounters& total) {
  const RenderSettings& s = f.s;
  const int tiles_x = (s.width + kTile - 1) / kTile;
  const int tiles_y = (s.height + kTile - 1) / kTile;
  tbb::combinable<OpCounters> per_thread;
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const auto& r) {
      OpCounters& counters = per_thread.local();
      for (int tile = r.begin(); tile != r.end(); ++tile) {
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        for (int y = y0; y < std::min(y0 + kTile, s.height); ++y)
          for (int x = x0; x < std::min(x0 + kTile, s.width); ++x) render_pixel(f, x, y, counters);
      }
    });
  });
  per_thread.combine_each([&](const OpCounters& c) { total.merge(c); });
}

// The normalised depth image: near is bright, far is dark, background black.
void shade_depth(std::span<const float> depth, Image& image) {
  float dmin = kInfinity, dmax = 0;
  for (float d : depth)
    if (std::isfinite(d)) dmin = std::min(dmin, d), dmax = std::max(dmax, d);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const float d = depth[size_t(y) * size_t(image.width()) + size_t(x)];
      const float v =
          std::isfinite(d) ? 1.0f - 0.8f * (d - dmin) / std::max(dmax - dmin, 1e-30f) : 0.0f;
      image.at(x, y) = Vec3::Constant(v);
    }
}

}  // namespace

RenderResult render(const SceneIntersector& scene, const PointCloud& cloud,
                    const RenderSettings& s) {
  const Aabb bounds = cloud.bounds();
  const Camera camera =
      s.camera ? *s.camera : Camera::framing(bounds, s.width, s.height, s.view, s.up);
  RenderResult out{
      Image(s.width, s.height), Image(s.width, s.height), Image(s.width, s.height), {}, 0, {}, {}};
  std::vector<float> depth(size_t(s.width) * s.height, kInfinity);
  out.primary_n.assign(depth.size(), Vec3::Zero());
  const auto start = std::chrono::steady_clock::now();
  OpCounters frame_counters;
  const std::unique_ptr<PrimaryPass> primary = scene.primary_pass(camera, frame_counters);
  const Frame frame{scene, cloud, s, camera, make_lighting(bounds, s), primary.get(), out, depth};
  render_tiles(frame, out.counters);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.counters.merge(frame_counters);
  shade_depth(depth, out.depth);
  out.primary_t = std::move(depth);
  return out;
}

}  // namespace pcrt
