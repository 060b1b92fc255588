// Scene files (JSON, in Tungsten's layout): named materials, objects (point clouds traced by any
// method on any structure, triangle meshes, a built-in quad) each with a transform and a
// material, lights and an optional camera. The image size, S and B stay the command line's, as
// for every render, so that sweeps set them the same way with or without a scene. A sweep's run
// puts its own cloud and method into the point-cloud objects marked "swept": true (all of them
// share one structure); rendered alone, they trace their own. Every malformed value is an
// InputError naming the file and the key.
#pragma once

#include <deque>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.hpp"
#include "core/counters.hpp"
#include "core/dataset.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/triangle_mesh.hpp"
#include "render/render_scene.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

namespace pcrt {

struct CameraSpec {
  Vec3 eye, target, up = Vec3::UnitZ();
  float fov_degrees = 40;
};

// Everything a scene file's frame needs, kept alive together (objects point into the members).
struct SceneFile {
  std::deque<Dataset> clouds;
  std::deque<TriangleMesh> meshes;
  std::vector<std::unique_ptr<SceneIntersector>> geometry;
  OpCounters prepare;
  Timings timings;
  RenderScene scene;
  std::optional<CameraSpec> camera;
  std::vector<std::string> files;  // what it read (clouds, meshes, maps): never an output
  nlohmann::json params;  // what --stats records: the file and each object's method or engine
  const PointScene* swept = nullptr;  // the sweep's geometry, when it was given one
  // Where the renderer's zero lies in the file's coordinates: the first georeferenced object's
  // local origin (kLocalOriginReach), or zero. Positions in the file (camera, lights,
  // translations) are taken relative to it.
  Vec3d origin = Vec3d::Zero();
};

// What a sweep's run traces in the objects marked "swept": its cloud and its method.
struct SweptCloud {
  const PointCloud& cloud;
  SceneOptions options;
};

// `swept`: the run's cloud and method replace every swept object's own (the file must mark one).
std::unique_ptr<SceneFile> load_scene_file(const std::string& path,
                                           const SweptCloud* swept = nullptr);

// The file's camera at the settings' image size, or none (the renderer frames the scene).
void apply_scene_camera(const SceneFile& file, RenderSettings& settings);

// Whether a scene file can serve a sweep, without loading its geometry: a JSON object whose
// "objects" mark at least one point cloud "swept": true. An InputError naming the file if not.
void check_sweep_scene(const std::string& path);

// Two triangles: the square of side `size` in the z = 0 plane about the origin, normal +z.
TriangleMesh quad_mesh(float size);

}  // namespace pcrt
