// schaufler_jensen_2000: Schaufler and Jensen, "Ray tracing point sampled geometry" (EGWR 2000),
// thesis [55], Algorithm 7 (whose caption cites [1]; the text says [55]). The ray is a cylinder of
// radius d; the points of the leaf within d of its axis are projected onto the ray through their
// tangent planes, and the front-most group of them is blended into one hit. See README.md for
// where this departs from the printed pseudocode.
#include <cmath>

#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

inline const Counter kCylinderCandidates{"cylinder_candidates",
                                         "points within the ray cylinder (S&J 2000)"};
inline const Counter kProjectionTests{"projection_tests",
                                      "points tested against the ray cylinder (S&J 2000)"};

class SchauflerJensen final : public Method {
 public:
  explicit SchauflerJensen(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    {
      ScopedTimer t(ctx.timings, "prepare/spacing");
      const KnnIndex knn(cloud.positions);
      h_ = float(mean_spacing(cloud.positions, knn, ctx.counters));
    }
    d_ = float(params_.at("cylinder_radius")) * std::max(h_, 1e-30f);
    depth_ = float(params_.at("front_depth")) * d_;
    // Every point reaches rays passing within d: its bounding radius is d.
    splats_ = prepare_splats(cloud, params_, ctx, d_);
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    counters.add(kProjectionTests, leaf.items.size());
    // Pass 1: candidates within the cylinder; the front-most tangent-plane crossing.
    float front = kInfinity;
    uint64_t candidates = 0;
    for (uint32_t k : leaf.items) {
      float t = 0, w = 0;
      if (!project(ray, splats_.packed[k], t, w)) continue;
      ++candidates;
      front = std::min(front, t);
    }
    counters.add(kCylinderCandidates, candidates);
    if (front == kInfinity) return false;
    // Pass 2: blend the group within depth_ behind the front, weights 1 - distance/d.
    float wsum = 0, tsum = 0, best_w = -1;
    Vec3 nsum = Vec3::Zero();
    uint32_t best = 0;
    for (uint32_t k : leaf.items) {
      float t = 0, w = 0;
      const PackedSplat& s = splats_.packed[k];
      if (!project(ray, s, t, w) || t > front + depth_) continue;
      wsum += w;
      tsum += w * t;
      nsum += w * s.n;
      if (w > best_w || (w == best_w && s.index < splats_.packed[best].index)) best_w = w, best = k;
    }
    if (!(wsum > 0)) return false;
    const float t_hit = tsum / wsum;
    // The cell rule of the paper: a hit belongs to the leaf whose span holds it (later leaves
    // blend their own group); a blend may land up to d before the leaf (rounding at its wall).
    if (t_hit > leaf.t_exit || t_hit < leaf.t_enter - d_ || t_hit < ray.tmin ||
        !closer(t_hit, splats_.packed[best].index, hit))
      return false;
    hit.t = t_hit;
    hit.prim = splats_.packed[best].index;
    hit.p = ray.at(t_hit);
    hit.n = nsum.norm() > 0 ? Vec3(nsum.normalized()) : splats_.packed[best].n;
    hit.footprint = d_;
    return true;
  }

 private:
  // Whether the point lies within the cylinder and the ray crosses its tangent plane within d of
  // it; the crossing t and the weight w. (Without the second test a ray grazing past a silhouette
  // within d would meet tangent planes far from their points and report a hit off the surface.)
  bool project(const Ray& ray, const PackedSplat& s, float& t, float& w) const {
    const Vec3 v = s.c - ray.o;
    const float along = v.dot(ray.d);
    const float dist2 = (v - along * ray.d).squaredNorm();
    if (dist2 >= d_ * d_) return false;
    const float denom = s.n.dot(ray.d);
    if (denom == 0) return false;
    t = s.n.dot(v) / denom;
    if (t < ray.tmin || (ray.at(t) - s.c).squaredNorm() >= d_ * d_) return false;
    w = 1.0f - std::sqrt(dist2) / d_;
    return true;
  }

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
    [](const ParamValues& p) { return std::make_unique<SchauflerJensen>(p); }}};

}  // namespace
}  // namespace pcrt
