// The oriented splats (normal and radius per point) that splat-based methods need: taken from the
// cloud where it has them, estimated (PCA normals, k-th neighbour radii) where it does not or
// where the parameters ask to.
#pragma once

#include <vector>

#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/method.hpp"

namespace pcrt {

struct SplatSet {
  std::vector<Vec3> normals;
  std::vector<float> radii;
};

// The parameters that control splat preparation, for a method's parameter list.
std::vector<ParamSpec> splat_params();

SplatSet prepare_splats(const PointCloud& cloud, const ParamValues& params, PrepareContext& ctx);

}  // namespace pcrt
