// Lights (thesis section 4.1.1), in pbrt-v4's shape: a light samples a direction from a shading
// point with its solid-angle pdf and reports that pdf for directions other strategies drew, so
// the integrator can weight both by multiple importance sampling. A Light is a small tagged value.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "render/sampling.hpp"

namespace pcrt {

// A latitude-longitude radiance image about +z (row 0 at the zenith, u = phi / 2 pi), sampled in
// proportion to luminance times sin(theta) so that its pdf is exact over solid angle.
class EnvironmentMap {
 public:
  // `path`: an EXR with R, G and B channels; InputError naming it when it cannot be read.
  static std::shared_ptr<const EnvironmentMap> load(const std::string& path);
  EnvironmentMap(int width, int height, std::vector<Vec3> texels);

  [[nodiscard]] Vec3 radiance(const Vec3& d) const;
  // A direction and its solid-angle pdf (0 for a black map).
  [[nodiscard]] Vec3 sample(const Vec2& u, float& pdf) const;
  [[nodiscard]] float pdf(const Vec3& d) const;

 private:
  [[nodiscard]] int texel_of(const Vec3& d) const;
  int width_, height_;
  std::vector<Vec3> texels_;
  std::vector<float> row_cdf_;    // height_ + 1 entries, over rows
  std::vector<float> texel_cdf_;  // (width_ + 1) per row, over the row's texels
  std::vector<float> texel_pdf_;  // per texel, over the unit square (integrates to 1)
};

enum class LightKind : uint8_t {
  kPoint,        // intensity `power` (W/sr) at `position`
  kSphere,       // a sphere of `radius` at `position` emitting radiance `power` outwards
  kEnvironment,  // radiance `power` from every direction, times `map` when one is given
  kSky,          // the renderer's default sky: a vertical gradient, brighter towards +z
};

struct Light {
  LightKind kind = LightKind::kPoint;
  Vec3 position = Vec3::Zero();
  float radius = 0;
  Vec3 power = Vec3::Ones();
  std::shared_ptr<const EnvironmentMap> map;
  // Sampled by next event estimation; a light that is not is reached only by BSDF-sampled rays
  // (the default sky, as in Algorithm 2), with weight 1.
  bool sampled = true;
};

struct LightSample {
  Vec3 wi = Vec3::UnitZ();
  Vec3 radiance = Vec3::Zero();  // incident radiance (for a point light: intensity / d^2)
  float pdf = 0;                 // solid angle; 1 for a point light
  float distance = kInfinity;    // to the sampled point; infinite for environments
  bool delta = false;
};

[[nodiscard]] bool is_environment(const Light& light);
// A direction from p towards the light; empty when the light cannot be reached from p.
[[nodiscard]] std::optional<LightSample> sample_light(const Light& light, const Vec3& p,
                                                      const Vec2& u);
// The solid-angle pdf with which sample_light draws wi from p (0 for a point light).
[[nodiscard]] float light_pdf(const Light& light, const Vec3& p, const Vec3& wi);
// The distance along the ray to a sphere light's surface, or +inf (other lights have no surface).
[[nodiscard]] float intersect_light(const Light& light, const Ray& ray);
// Radiance a ray receives from the light it reached: the sphere's, or the environment's along d.
[[nodiscard]] Vec3 light_radiance(const Light& light, const Vec3& d);

}  // namespace pcrt
