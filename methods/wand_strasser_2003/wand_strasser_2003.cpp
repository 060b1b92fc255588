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

class WandStrasser final : public Method {
 public:
  explicit WandStrasser(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    h_ = prepare_spacing(cloud, ctx);
    sigma0_ = float(params_.at("cone_radius")) * h_;
    spread_ = float(params_.at("cone_spread"));
    sigma_max_ = float(params_.at("max_cone_radius")) * h_;
    aspect_ = float(params_.at("aspect"));
    cutoff_ = float(params_.at("cutoff"));
    // A point reaches rays whose cone (cut off at cutoff sigma) passes it: its bounding radius.
    reach_ = cutoff_ * sigma_max_ * std::max(1.0f, aspect_);
    splats_ = prepare_splats(cloud, params_, ctx, reach_);
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
    const ProjectionSettings settings{float(params_.at("front_depth")) * reach_,
                                      float(params_.at("min_weight")), reach_, reach_};
    return blend_projected_points(ray, leaf, splats_.packed, settings, weight, hit, counters);
  }

 private:
  ParamValues params_;
  SplatSet splats_;
  float h_ = 0, sigma0_ = 0, spread_ = 0, sigma_max_ = 0, aspect_ = 1, cutoff_ = 3, reach_ = 0;
};

const RegisterMethod kRegister{MethodInfo{
    "wand_strasser_2003",
    "M. Wand and W. Strasser, Multi-resolution point-sample raytracing, Graphics Interface 2003",
    "[64]",
    "ray cone with two radii growing with t; Gaussian weights of the points' offsets in ray "
    "coordinates; "
    "tangent-plane projection and blending",
    "octree",
    {"point normals"},
    [] {
      auto p = normal_params();
      p.push_back({"cone_radius", 1.0, 0.1, 50,
                   "cone radius (Gaussian sigma along u) at the ray origin, in mean spacings h"});
      p.push_back(
          {"cone_spread", 0.0012, 0, 1,
           "growth of the radius per unit t (about one 512-pixel pixel's angle at 35 deg)"});
      p.push_back({"max_cone_radius", 2.0, 0.1, 100,
                   "cap on the radius, in h (bounds each point's reach for the structure)"});
      p.push_back(
          {"aspect", 1.0, 0.1, 10, "radius along v over radius along u (1: a circular cone)"});
      p.push_back({"cutoff", 3.0, 1, 6, "Gaussian cut off at this many sigma"});
      p.push_back({"min_weight", 0.5, 0, 100,
                   "blended weight a hit needs (coverage): 1 = one point on the axis"});
      p.push_back({"front_depth", 0.5, 0, 20,
                   "blend the points within this many reaches behind the front-most"});
      return p;
    }(),
    {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
     {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
    [](const ParamValues& p) { return std::make_unique<WandStrasser>(p); },
    {},
    {&kProjectionTests},
    LeafFamily::kProjection}};

}  // namespace
}  // namespace pcrt
