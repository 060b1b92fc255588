// Triangle ray tracing engines (the reconstruction side of the thesis's comparison): our binned
// SAH BVH, CGAL's AABB_tree and Embree 3, each registered like a structure and chosen with
// --engine. MeshScene makes any of them a SceneIntersector, so the renderer, `pcrt trace` and the
// accuracy evaluator treat a mesh exactly like a point method.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "core/counters.hpp"
#include "core/error.hpp"
#include "core/point_cloud.hpp"
#include "core/registry.hpp"
#include "reconstruction/triangle_mesh.hpp"
#include "render/scene.hpp"

namespace pcrt {

inline const Counter kTriangleTests{"triangle_tests", "ray-triangle intersection tests"};

class MeshEngine {
 public:
  virtual ~MeshEngine() = default;
  // Closest hit with t in [ray.tmin, min(ray.tmax, hit.t)); prim = triangle index, n = its normal.
  virtual bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const = 0;
  // Whether any triangle lies within [ray.tmin, ray.tmax) (shadow rays: pbrt's IntersectP). This
  // default asks for a closest hit; engines that can stop at the first hit override it.
  virtual bool any_hit(const Ray& ray, OpCounters& counters) const {
    Hit h;
    h.t = ray.tmax;
    return closest_hit(ray, h, counters);
  }
  [[nodiscard]] virtual size_t memory_bytes() const = 0;
};

struct MeshEngineInfo {
  std::string id;
  std::string description;
  // The mesh stays the caller's and must outlive the engine. Counts and times ("build") its build.
  std::function<std::unique_ptr<MeshEngine>(const TriangleMesh&, OpCounters&, Timings&)> create;
};

using MeshEngineRegistry = Registry<MeshEngineInfo>;

// The mesh engines pcrt ships (reconstruction/builtin_reconstruction.cpp, the one list).
void register_builtins(MeshEngineRegistry& registry);

class MeshScene final : public SceneIntersector {
 public:
  MeshScene(const TriangleMesh& mesh, const std::string& engine, OpCounters& counters,
            Timings& timings)
      : info_(&MeshEngineRegistry::instance().get(engine, "mesh engine")),
        engine_(info_->create(checked(mesh), counters, timings)) {}
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    counters.add(kRaysCast);
    const bool found = engine_->closest_hit(ray, hit, counters);
    if (found) counters.add(kRayHits);
    return found;
  }
  bool any_hit(const Ray& ray, OpCounters& counters) const override {
    counters.add(kRaysCast);
    counters.add(kAnyHitRays);
    const bool found = engine_->any_hit(ray, counters);
    if (found) counters.add(kRaysOccluded);
    return found;
  }
  [[nodiscard]] const std::string& engine_id() const { return info_->id; }
  [[nodiscard]] size_t memory_bytes() const { return engine_->memory_bytes(); }

 private:
  // No engine is handed coordinates it cannot take (mesh files are checked when read; this
  // covers meshes made in memory). The bound is on the file's coordinates; local ones lie within
  // twice it.
  static const TriangleMesh& checked(const TriangleMesh& mesh) {
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      if (!within_coordinate_range(to_world(mesh.vertices[i], mesh.origin)))
        input_error("mesh vertex {} has a coordinate beyond +-{:g}", i, kMaxCoordinate);
    return mesh;
  }

  const MeshEngineInfo* info_;
  std::unique_ptr<MeshEngine> engine_;
};

// Moeller-Trumbore, two-sided: the t of the hit in [tmin, tmax), or +inf.
inline float intersect_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c,
                                float tmin, float tmax) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = ray.d.cross(e2);
  const float det = e1.dot(p);
  if (det == 0.0f) return kInfinity;
  const float inv = 1.0f / det;
  const Vec3 s = ray.o - a;
  const float u = s.dot(p) * inv;
  if (u < 0.0f || u > 1.0f) return kInfinity;
  const Vec3 q = s.cross(e1);
  const float v = ray.d.dot(q) * inv;
  if (v < 0.0f || u + v > 1.0f) return kInfinity;
  const float t = e2.dot(q) * inv;
  return t >= tmin && t < tmax ? t : kInfinity;
}

}  // namespace pcrt
