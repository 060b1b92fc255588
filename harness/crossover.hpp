// The end-to-end comparison of thesis chapter 7, shared by `pcrt crossover` and the sweep:
// reconstruct + build + trace against a direct method's prepare + build + trace on the same cloud
// and the same camera.
#pragma once

#include <optional>
#include <string>

#include "core/point_cloud.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

namespace pcrt {

struct CrossoverResult {
  std::string method, structure, reconstruction, engine;
  size_t triangles = 0;
  double direct_prepare_s = 0, direct_build_s = 0, direct_frame_s = 0;
  double reconstruct_s = 0, mesh_build_s = 0, mesh_frame_s = 0;
  // Frames after which reconstruct-then-trace is ahead; empty if its frames are not faster.
  std::optional<double> crossover_frames;
  [[nodiscard]] double direct_setup_s() const { return direct_prepare_s + direct_build_s; }
  [[nodiscard]] double mesh_setup_s() const { return reconstruct_s + mesh_build_s; }
};

// Frame times are medians over `reps` frames.
CrossoverResult measure_crossover(const PointCloud& cloud, const SceneOptions& direct,
                                  const std::string& reconstruction, const std::string& engine,
                                  RenderSettings rs, int reps);

}  // namespace pcrt
