// What a frame renders: objects (a point method on a structure, or a triangle mesh, each with a
// transform and a material), lights and the bounds the default camera frames. The top level is
// a list: every object is asked for each ray, which is exact and cheap for the few objects a
// scene file holds (the methods' own structures carry the per-point work).
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/counters.hpp"
#include "core/point_cloud.hpp"
#include "render/bsdf.hpp"
#include "render/light.hpp"
#include "render/scene.hpp"

namespace pcrt {

inline const Counter kLightHits{"light_hits", "rays that reached a sphere light's surface"};

// world = translate + scale * rotate * object: rigid motion with uniform scale, so distances
// scale by one factor and normals only rotate.
struct Transform {
  Vec3 translate = Vec3::Zero();
  Eigen::Matrix3f rotate = Eigen::Matrix3f::Identity();
  float scale = 1;

  [[nodiscard]] bool identity() const {
    return translate.isZero(0) && rotate.isIdentity(0) && scale == 1;
  }
  [[nodiscard]] Ray to_object(const Ray& ray) const;
  void hit_to_world(Hit& hit) const;
  [[nodiscard]] Aabb to_world(const Aabb& box) const;
};

struct SceneObject {
  const SceneIntersector* geometry = nullptr;
  const PointCloud* points = nullptr;  // point objects: colours become the diffuse albedo
  Material material;
  Transform transform;
  Aabb bounds;  // world space
  std::string name;
};

struct RenderScene {
  std::vector<SceneObject> objects;
  std::vector<Light> lights;

  [[nodiscard]] Aabb bounds() const;
  // The closest hit over every object (world space), its object's index in `object`.
  bool closest_hit(const Ray& ray, Hit& hit, uint32_t& object, OpCounters& counters) const;
  bool any_hit(const Ray& ray, OpCounters& counters) const;
  // n <= 16 rays' any_hit, traced together when the scene is one object (SceneIntersector::
  // any_hits): the same answers and counts.
  void any_hits(const Ray* rays, int n, char* blocked, OpCounters& counters) const;
  // The material at a hit: the object's, with a point's colour as the diffuse albedo.
  [[nodiscard]] Material material_at(uint32_t object, uint32_t prim) const;
};

// The scene the default render shows: one object, untransformed, diffuse (its points' colours
// or 0.75 grey), lit by a point light above the camera (when `point_light`) and the gradient sky
// reached by bounce rays.
RenderScene single_object_scene(const SceneIntersector& scene, const PointCloud& cloud,
                                const Vec3& view, const Vec3& up, bool point_light);
// The same for an object known only by its bounds and name (a streamed cloud, never in memory:
// no colours, 0.75 grey).
RenderScene single_object_scene(const SceneIntersector& scene, const Aabb& bounds,
                                const std::string& name, const Vec3& view, const Vec3& up,
                                bool point_light);

}  // namespace pcrt
