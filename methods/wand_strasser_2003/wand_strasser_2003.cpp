// wand_strasser_2003: Wand and Strasser, "Multi-resolution point-sample raytracing" (Graphics
// Interface 2003), thesis [64]: the ray is a cone whose two radii along an orthonormal frame (u, v)
// perpendicular to it grow linearly with t; points are weighted by a Gaussian of their offset in
// (u, v) with the radii as standard deviations, and blended. Projection and blending are the kernel
// shared with Schaufler and Jensen 2000 (methods/kernels/ray_projection.hpp). See README.md.
#include <cmath>

#include "methods/kernels/ray_projection.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

struct WandStrasserParams {
  NormalParams normals;
  float cone_radius = 1;  // in h
  float cone_spread = 0.0012f;
  float max_cone_radius = 2;  // in h
  float aspect = 1;
  float cutoff = 3;
  float min_weight = 0.5f;
  float front_depth = 0.5f;  // in reaches
};
const ParamList<WandStrasserParams>& wand_strasser_params() {
  using P = WandStrasserParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::cone_radius,
               {"cone_radius", 1.0, 0.1, 50,
                "cone radius (Gaussian sigma along u) at the ray origin, in mean spacings h"})
          .add(&P::cone_spread,
               {"cone_spread", 0.0012, 0, 1,
                "growth of the radius per unit t (about one 512-pixel pixel's angle at 35 deg)"})
          .add(&P::max_cone_radius,
               {"max_cone_radius", 2.0, 0.1, 100,
                "cap on the radius, in h (bounds each point's reach for the structure)"})
          .add(&P::aspect,
               {"aspect", 1.0, 0.1, 10, "radius along v over radius along u (1: a circular cone)"})
          .add(&P::cutoff, {"cutoff", 3.0, 1, 6, "Gaussian cut off at this many sigma"})
          .add(&P::min_weight, {"min_weight", 0.5, 0, 100,
                                "blended weight a hit needs (coverage): 1 = one point on the axis"})
          .add(&P::front_depth,
               {"front_depth", 0.5, 0, 20,
                "blend the points within this many reaches behind the front-most"});
  return l;
}

class WandStrasser final : public Method {
 public:
  explicit WandStrasser(const WandStrasserParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    h_ = prepare_spacing(cloud, ctx);
    sigma0_ = params_.cone_radius * h_;
    spread_ = params_.cone_spread;
    sigma_max_ = params_.max_cone_radius * h_;
    aspect_ = params_.aspect;
    cutoff_ = params_.cutoff;
    // A point reaches rays whose cone (cut off at cutoff sigma) passes it: its bounding radius.
    reach_ = cutoff_ * sigma_max_ * std::max(1.0f, aspect_);
    splats_ = prepare_splats(cloud, SplatParams{params_.normals}, ctx, reach_);
    splats_.pack();
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    Vec3 u, v;
    orthonormal_basis(ray.d, u, v);
    const float c2 = cutoff_ * cutoff_;
    auto weight = [&](const Ray& r, const PackedSplat& p, float t, const Vec3& lateral) {
      // The cone's radii at the point's depth: linear in t, capped (see README).
      const float su = std::min(sigma0_ + spread_ * std::max(t - r.tmin, 0.0f), sigma_max_);
      const float sv = aspect_ * su;
      const float a = lateral.dot(u) / su, b = lateral.dot(v) / sv;
      const float q = a * a + b * b;
      if (q >= c2) return 0.0f;
      // The crossing must lie within the cone's reach of the point, as for the cylinder.
      const float reach = cutoff_ * std::max(su, sv);
      if ((r.at(t) - p.c).squaredNorm() >= reach * reach) return 0.0f;
      return std::exp(-0.5f * q);
    };
    const ProjectionSettings settings{params_.front_depth * reach_, params_.min_weight, reach_,
                                      reach_};
    return blend_projected_points(ray, leaf, splats_.packed, kernel_, settings, weight, hit,
                                  counters);
  }

 private:
  WandStrasserParams params_;
  SplatSet splats_;
  ProjectionKernel kernel_ = best_projection_kernel();  // the widest lanes, chosen once
  float h_ = 0, sigma0_ = 0, spread_ = 0, sigma_max_ = 0, aspect_ = 1, cutoff_ = 3, reach_ = 0;
};

}  // namespace

void register_wand_strasser_2003(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "wand_strasser_2003",
      .paper = "M. Wand and W. Strasser, Multi-resolution point-sample raytracing, Graphics "
               "Interface 2003",
      .thesis_ref = "[64]",
      .description = "ray cone with two radii growing with t; Gaussian weights of the points' "
                     "offsets in ray coordinates; tangent-plane projection and blending",
      .structure = "octree",
      .needs = {"point normals"},
      .params = wand_strasser_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
      .create = create_from<WandStrasser>(wand_strasser_params(), "wand_strasser_2003"),
      .work = {&kProjectionTests},
      .family = LeafFamily::kProjection,
      .cost = {.prepare_ns = 110, .ray_ns = 165},
      .designs = {{.experiment = "leaf_K_octree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128},
                   .N = 20000,
                   .metric = {&kProjectionTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
