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

struct SchauflerJensenParams {
  NormalParams normals;
  float cylinder_radius = 3;  // in h
  float front_depth = 1;      // in d
};
const ParamList<SchauflerJensenParams>& schaufler_jensen_params() {
  using P = SchauflerJensenParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::cylinder_radius,
               {"cylinder_radius", 3.0, 0.25, 50, "ray cylinder radius d in mean spacings h"})
          .add(&P::front_depth, {"front_depth", 1.0, 0.0, 20,
                                 "blend the points within this many d behind the front-most"});
  return l;
}

class SchauflerJensen final : public Method {
 public:
  explicit SchauflerJensen(const SchauflerJensenParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    h_ = prepare_spacing(cloud, ctx);
    d_ = params_.cylinder_radius * std::max(h_, 1e-30f);
    depth_ = params_.front_depth * d_;
    // Every point reaches rays passing within d: its bounding radius is d.
    splats_ = prepare_splats(cloud, SplatParams{params_.normals}, ctx, d_);
    splats_.pack();
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
    return blend_projected_points(ray, leaf, splats_.packed, kernel_, settings, weight, hit,
                                  counters);
  }

 private:
  SchauflerJensenParams params_;
  SplatSet splats_;
  ProjectionKernel kernel_ = best_projection_kernel();  // the widest lanes, chosen once
  float h_ = 0, d_ = 0, depth_ = 0;
};

}  // namespace

void register_schaufler_jensen_2000(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "schaufler_jensen_2000",
      .paper = "G. Schaufler and H. W. Jensen, Ray tracing point sampled geometry, EGWR 2000",
      .thesis_ref = "[55]",
      .description = "ray cylinder of radius d; points within it projected onto the ray through "
                     "their tangent planes; front group blended (Algorithm 7)",
      .structure = "octree",
      .needs = {"point normals"},
      .params = schaufler_jensen_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
      .create = create_from<SchauflerJensen>(schaufler_jensen_params(), "schaufler_jensen_2000"),
      .work = {&kProjectionTests},
      .family = LeafFamily::kProjection,
      .cost = {.prepare_ns = 130, .ray_ns = 60},
      .designs = {{.experiment = "leaf_K_octree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128},
                   .N = 20000,
                   .metric = {&kProjectionTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
