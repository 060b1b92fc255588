// schaufler_jensen_2000: Schaufler and Jensen, "Ray tracing point sampled geometry" (EGWR 2000),
// thesis [55], Algorithm 7 (whose caption cites [1]; the text says [55]). The ray is a cylinder of
// radius d; the points of the leaf within d of its axis are projected onto the ray through their
// tangent planes, and the front-most group of them is blended into one hit. See README.md for
// where this departs from the printed pseudocode.
#include <cmath>

#include "methods/kernels/ray_projection.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

class SchauflerJensen final : public Method {
 public:
  explicit SchauflerJensen(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    h_ = prepare_spacing(cloud, ctx);
    d_ = float(params_.at("cylinder_radius")) * std::max(h_, 1e-30f);
    depth_ = float(params_.at("front_depth")) * d_;
    // Every point reaches rays passing within d: its bounding radius is d.
    splats_ = prepare_splats(cloud, params_, ctx, d_);
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    // Candidates: within d of the ray axis, and the ray crosses the tangent plane within d of the
    // point (without the second test a ray grazing past a silhouette within d meets tangent planes
    // far from their points and reports a hit off the surface). Weight 1 - distance/d.
    const float d2 = d_ * d_;
    auto weight = [&](const Ray& r, const PackedSplat& p, float t, const Vec3& lateral) {
      const float dist2 = lateral.squaredNorm();
      if (dist2 >= d2 || (r.at(t) - p.c).squaredNorm() >= d2) return 0.0f;
      return 1.0f - std::sqrt(dist2) / d_;
    };
    const ProjectionSettings settings{depth_, 0.0f, d_, d_};
    return blend_projected_points(ray, leaf, splats_.packed, settings, weight, hit, counters);
  }

 private:
  ParamValues params_;
  SplatSet splats_;
  float h_ = 0, d_ = 0, depth_ = 0;
};

const RegisterMethod kRegister{MethodInfo{
    "schaufler_jensen_2000",
    "G. Schaufler and H. W. Jensen, Ray tracing point sampled geometry, EGWR 2000",
    "[55]",
    "ray cylinder of radius d; points within it projected onto the ray through their tangent "
    "planes; "
    "front group blended (Algorithm 7)",
    "octree",
    {"point normals"},
    [] {
      auto p = normal_params();
      p.push_back({"cylinder_radius", 3.0, 0.25, 50, "ray cylinder radius d in mean spacings h"});
      p.push_back({"front_depth", 1.0, 0.0, 20,
                   "blend the points within this many d behind the front-most"});
      return p;
    }(),
    {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
     {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
    [](const ParamValues& p) { return std::make_unique<SchauflerJensen>(p); },
    {},
    {&kProjectionTests},
    LeafFamily::kProjection}};

}  // namespace
}  // namespace pcrt
