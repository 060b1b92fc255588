#include "methods/kernels/splat_set.hpp"

#include <optional>

#include "preprocess/point_attributes.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

std::vector<ParamSpec> splat_params() {
  return {{"normal_k", 16, 3, 256, "neighbours in the PCA normal fit", true},
          {"radius_k", 8, 1, 256, "splat radius = radius_scale * distance to the radius_k-th neighbour", true},
          {"radius_scale", 1.0, 0.01, 100, "factor on the neighbour distance for the splat radius"},
          {"estimate_normals", 0, 0, 1, "1: estimate normals even if the cloud has them", true},
          {"estimate_radii", 0, 0, 1, "1: estimate radii even if the cloud has them", true}};
}

SplatSet prepare_splats(const PointCloud& cloud, const ParamValues& params, PrepareContext& ctx) {
  SplatSet s;
  const bool need_normals = !cloud.has_normals() || params.at("estimate_normals") != 0;
  const bool need_radii = !cloud.has_radii() || params.at("estimate_radii") != 0;
  std::optional<KnnIndex> knn;
  if (need_normals || need_radii) {
    ScopedTimer t(ctx.timings, "prepare/knn_build");
    knn.emplace(cloud.positions);
  }
  if (need_normals) {
    ScopedTimer t(ctx.timings, "prepare/normals");
    s.normals = estimate_normals(cloud.positions, *knn, static_cast<size_t>(params.at("normal_k")), ctx.counters);
  } else {
    s.normals = cloud.normals;
  }
  if (need_radii) {
    ScopedTimer t(ctx.timings, "prepare/radii");
    s.radii = estimate_radii(cloud.positions, *knn, static_cast<size_t>(params.at("radius_k")),
                             static_cast<float>(params.at("radius_scale")), ctx.counters);
  } else {
    s.radii = cloud.radii;
  }
  return s;
}

}  // namespace pcrt
