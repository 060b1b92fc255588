// Exact surfaces behind the synthetic generators: the ground truth that accuracy checks compare a
// method's hits against. Sphere, plane patch and torus have exact signed distances; the bumpy
// sphere's is first-order (F/|grad F|), exact on the surface and to O(d^2) off it.
#pragma once

#include <memory>
#include <string>

#include "core/aabb.hpp"
#include "core/geometry.hpp"
#include "core/rng.hpp"

namespace pcrt {

class Surface {
 public:
  virtual ~Surface() = default;
  [[nodiscard]] virtual std::string describe() const = 0;
  // Positive outside (on the side normals point to).
  [[nodiscard]] virtual float signed_distance(const Vec3& x) const = 0;
  // Outward unit normal at (or of the surface point nearest to) x.
  [[nodiscard]] virtual Vec3 normal(const Vec3& x) const = 0;
  [[nodiscard]] virtual Aabb bounds() const = 0;
  // A point drawn uniformly by area, with its exact normal.
  virtual Vec3 sample(Rng& rng, Vec3& normal) const = 0;
  // First intersection in [ray.tmin, ray.tmax]. The default sphere-traces signed_distance (which
  // must be a lower bound on the true distance after division by lipschitz()) and bisects.
  virtual bool intersect(const Ray& ray, float& t, Vec3& n) const;
  // The largest angle in degrees between the surface's normals within the ball of `radius` around
  // its point nearest x: a mesh's face normals, two by two. Analytic surfaces answer 0: they are
  // smooth at every scale the evaluator judges, and have no faces to jump between.
  [[nodiscard]] virtual float normal_spread_deg(const Vec3& /*x*/, float /*radius*/) const {
    return 0;
  }
  // Faces further apart than this within a ball make a crease there.
  static constexpr float kSmoothAngleDeg = 15.0f;
  // Whether the surface is smooth within `radius` of its point nearest x, so that a normal there
  // can be judged (a mesh's face normal jumps at every crease).
  [[nodiscard]] bool smooth_at(const Vec3& x, float radius) const {
    return normal_spread_deg(x, radius) <= kSmoothAngleDeg;
  }
  // The normal of the smooth surface the samples stand for (a mesh: vertex normals interpolated).
  [[nodiscard]] virtual Vec3 smooth_normal(const Vec3& x) const { return normal(x); }
  // Where the surface's zero lies in its file's coordinates (a georeferenced mesh's local origin,
  // see kLocalOriginReach); clouds sampled on it share it.
  [[nodiscard]] virtual Vec3d origin() const { return Vec3d::Zero(); }

 protected:
  [[nodiscard]] virtual float lipschitz() const { return 1.0f; }
};

struct SphereSurface final : Surface {
  Vec3 center = Vec3::Zero();
  float radius = 1.0f;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] float signed_distance(const Vec3& x) const override {
    return (x - center).norm() - radius;
  }
  [[nodiscard]] Vec3 normal(const Vec3& x) const override { return (x - center).normalized(); }
  [[nodiscard]] Aabb bounds() const override;
  Vec3 sample(Rng& rng, Vec3& normal) const override;
  bool intersect(const Ray& ray, float& t, Vec3& n) const override;
};

// The square z = 0, |x|, |y| <= size/2, normal +z.
struct PlaneSurface final : Surface {
  float size = 2.0f;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] float signed_distance(const Vec3& x) const override;
  [[nodiscard]] Vec3 normal(const Vec3&) const override { return Vec3::UnitZ(); }
  [[nodiscard]] Aabb bounds() const override;
  Vec3 sample(Rng& rng, Vec3& normal) const override;
  bool intersect(const Ray& ray, float& t, Vec3& n) const override;
};

// Major radius R around the z axis, minor radius r.
struct TorusSurface final : Surface {
  float major = 1.0f;
  float minor = 0.25f;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] float signed_distance(const Vec3& x) const override;
  [[nodiscard]] Vec3 normal(const Vec3& x) const override;
  [[nodiscard]] Aabb bounds() const override;
  Vec3 sample(Rng& rng, Vec3& normal) const override;
};

// |x| = radius * (1 + amplitude * sin(f u_x) sin(f u_y) sin(f u_z)), u = x/|x|.
struct BumpySphereSurface final : Surface {
  float radius = 1.0f;
  float amplitude = 0.05f;
  float frequency = 6.0f;
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] float signed_distance(const Vec3& x) const override;
  [[nodiscard]] Vec3 normal(const Vec3& x) const override;
  [[nodiscard]] Aabb bounds() const override;
  Vec3 sample(Rng& rng, Vec3& normal) const override;

 protected:
  [[nodiscard]] float lipschitz() const override;

 private:
  [[nodiscard]] float implicit(const Vec3& x, Vec3* gradient) const;
};

}  // namespace pcrt
