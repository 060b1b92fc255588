// The oriented splats (normal and radius per point) that splat-based methods need: taken from the
// cloud where it has them, estimated (PCA normals, k-th neighbour radii) where it does not or
// where the parameters ask to.
#pragma once

#include <vector>

#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/method.hpp"

namespace pcrt {

inline const Counter kSplatsGenerated{"splats_generated",
                                      "splats made by a method's own splat generation"};

// Items are stored in Morton (Z-curve) order of their centres, so the items of one leaf lie close
// together in memory: a leaf loop then reads a few cache lines instead of one per item (this alone
// is worth about 1.5x in rays per second at 10^6 points). Item k is the cloud's point point[k];
// a hit reports point[k] as its prim, and ties in t are broken on it, so results are those of the
// cloud's own order.
struct SplatSet {
  std::vector<uint32_t> point;  // index of each item in the arrays it was made from
  std::vector<Vec3> centres;    // item order
  std::vector<Vec3> normals;
  std::vector<float> radii;
  std::vector<Vec3> half_extents;   // of each disc's bounding box: r * sqrt(1 - n_a^2), padded
  std::vector<PackedSplat> packed;  // centre, radius, normal, cloud index (prim) in one record

  [[nodiscard]] size_t size() const { return point.size(); }
  [[nodiscard]] ItemSet items() const { return {centres, radii, half_extents}; }
};

// Normals from the cloud, or PCA over normal_k neighbours where it has none (or when asked).
struct NormalParams {
  size_t normal_k = 16;
  bool estimate_normals = false;
  static const ParamList<NormalParams>& list();
};

// Normals as above and radii from the radius_k-th neighbour distance: splat preparation.
struct SplatParams {
  NormalParams normals;
  size_t radius_k = 8;
  float radius_scale = 1;
  bool estimate_radii = false;
  static const ParamList<SplatParams>& list();
};

// Normals and radii from the cloud or estimated; `fixed_radius` (> 0) gives every splat that
// radius instead (methods whose paper uses one global radius; only params.normals is read).
SplatSet prepare_splats(const PointCloud& cloud, const SplatParams& params, PrepareContext& ctx,
                        float fixed_radius = 0);

// The normals and radii of a SplatSet made by prepare_splats, back in the cloud's order (for
// methods that derive their own splats from them).
void splat_attributes_by_point(const SplatSet& s, std::vector<Vec3>& normals,
                               std::vector<float>& radii);

// Lays out splats made by a method itself (fewer than the points, or fitted): item k is
// input point[k] and reports prim[point[k]] (a cloud index) as its hit primitive.
SplatSet make_splat_set(std::span<const Vec3> centres, std::span<const Vec3> normals,
                        std::span<const float> radii, std::span<const uint32_t> prim);

}  // namespace pcrt
