#include "methods/kernels/splat_set.hpp"

#include <algorithm>
#include <optional>

#include "core/morton.hpp"
#include "preprocess/point_attributes.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

const ParamList<NormalParams>& NormalParams::list() {
  using P = NormalParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normal_k, {"normal_k", 16, 3, 256, "neighbours in the PCA normal fit"})
          .add(&P::estimate_normals,
               {"estimate_normals", 0, 0, 1, "1: estimate normals even if the cloud has them"});
  return l;
}

const ParamList<SplatParams>& SplatParams::list() {
  using P = SplatParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::radius_k, {"radius_k", 8, 1, 256,
                              "splat radius = radius_scale * distance to the radius_k-th "
                              "neighbour"})
          .add(&P::radius_scale, {"radius_scale", 1.0, 0.01, 100,
                                  "factor on the neighbour distance for the splat radius"})
          .add(&P::estimate_radii,
               {"estimate_radii", 0, 0, 1, "1: estimate radii even if the cloud has them"});
  return l;
}

SplatSet prepare_splats(const PointCloud& cloud, const SplatParams& params, PrepareContext& ctx,
                        float fixed_radius) {
  const bool need_normals = !cloud.has_normals() || params.normals.estimate_normals;
  const bool need_radii = fixed_radius <= 0 && (!cloud.has_radii() || params.estimate_radii);
  std::optional<KnnIndex> knn;
  if (need_normals || need_radii) {
    ScopedTimer t(ctx.timings, "prepare/knn_build");
    knn.emplace(cloud.positions);
  }
  std::vector<Vec3> normals;
  std::vector<float> radii;
  if (need_normals) {
    ScopedTimer t(ctx.timings, "prepare/normals");
    normals = estimate_normals(cloud.positions, *knn, params.normals.normal_k, ctx.counters);
  }
  if (need_radii) {
    ScopedTimer t(ctx.timings, "prepare/radii");
    radii =
        estimate_radii(cloud.positions, *knn, params.radius_k, params.radius_scale, ctx.counters);
  }
  knn.reset();  // build-only: freed before the layout's own peak
  const std::vector<Vec3>& n_src = need_normals ? normals : cloud.normals;
  if (fixed_radius > 0) radii.assign(cloud.size(), fixed_radius);
  const std::vector<float>& r_src = need_radii || fixed_radius > 0 ? radii : cloud.radii;

  ScopedTimer t(ctx.timings, "prepare/splat_layout");
  std::vector<uint32_t> identity(cloud.size());
  for (uint32_t i = 0; i < identity.size(); ++i) identity[i] = i;
  return make_splat_set(cloud.positions, n_src, r_src, identity);
}

SplatSet make_splat_set(std::span<const Vec3> centres, std::span<const Vec3> normals,
                        std::span<const float> radii, std::span<const uint32_t> prim) {
  SplatSet s;
  s.point = morton_order(centres);
  const size_t n = s.point.size();
  s.centres.resize(n);
  s.normals.resize(n);
  s.radii.resize(n);
  s.half_extents.resize(n);
  s.packed.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = s.point[k];
    const Vec3& nn = normals[i];
    s.centres[k] = centres[i];
    s.normals[k] = nn;
    s.radii[k] = radii[i];
    // Padded by 1e-4 r so rounding of the hit point never leaves the box.
    s.half_extents[k] =
        radii[i] *
        ((Vec3::Ones() - nn.cwiseProduct(nn)).cwiseMax(0.0f).cwiseSqrt() + Vec3::Constant(1e-4f));
    s.packed[k] = PackedSplat{s.centres[k], s.radii[k], nn, prim[i]};
  }
  return s;
}

void splat_attributes_by_point(const SplatSet& s, std::vector<Vec3>& normals,
                               std::vector<float>& radii) {
  normals.resize(s.size());
  radii.resize(s.size());
  for (size_t k = 0; k < s.size(); ++k) {
    normals[s.point[k]] = s.normals[k];
    radii[s.point[k]] = s.radii[k];
  }
}

float prepare_spacing(const PointCloud& cloud, PrepareContext& ctx) {
  ScopedTimer t(ctx.timings, "prepare/spacing");
  return std::max(float(mean_spacing(cloud.positions, ctx.counters)), 1e-30f);
}

}  // namespace pcrt
