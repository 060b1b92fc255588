// hubo_2006: Hubo, Mertens, Haber and Bekaert, "The quantized kd-tree: efficient ray tracing of
// compressed point clouds" (IEEE Symposium on Interactive Ray Tracing 2006), thesis [28]:
// Algorithm 6 (Newton on the weighted-average plane) with Gaussian weights over the points of a
// kd-tree leaf. The quantized (compressed) kd-tree is not implemented: see README.md.
#include <algorithm>

#include "methods/kernels/implicit_newton.hpp"
#include "methods/kernels/leaf_implicit.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

struct Hubo2006Params {
  NormalParams normals;
  GaussianParams gaussian;
  IterationParams iteration;
};
const ParamList<Hubo2006Params>& hubo_2006_params() {
  using P = Hubo2006Params;
  static const auto l = ParamList<P>()
                            .add(&P::normals, NormalParams::list())
                            .add(&P::gaussian, GaussianParams::list())
                            .add(&P::iteration, IterationParams::list(0.001, 10, "h (|f|)", 10));
  return l;
}

class Hubo2006 final : public Method {
 public:
  explicit Hubo2006(const Hubo2006Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const float h = prepare_spacing(cloud, ctx);
    sigma_ = params_.gaussian.sigma * h;
    cutoff_ = params_.gaussian.cutoff;
    reach_ = sigma_ * cutoff_;
    newton_ = newton_settings(params_.iteration, h);
    splats_ = prepare_splats(cloud, SplatParams{params_.normals}, ctx,
                             reach_);  // item radius: the weight's reach
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    const float t_lo = std::max(leaf.t_enter - reach_, ray.tmin);
    const float t_hi = std::min(leaf.t_exit, hit.t);
    float t = 0;
    if (!(t_lo <= t_hi) ||
        !nearest_tangent_crossing(ray, leaf.items, splats_.packed, reach_, t_lo, t_hi, t))
      return false;
    const GaussianWeight theta(sigma_, cutoff_);
    auto eval = [&](const Vec3& x) {
      return weighted_plane(x, leaf.items, splats_.packed, theta, counters);
    };
    Vec3 n = Vec3::Zero();
    t = newton_on_weighted_plane(ray, t, t_lo, t_hi, eval, newton_, n, counters);
    if (t == kInfinity) return false;
    const uint32_t prim = nearest_point(ray.at(t), leaf.items, splats_.packed);
    if (!closer(t, prim, hit)) return false;
    record_hit(ray, t, prim, n, sigma_, hit);
    return true;
  }

 private:
  Hubo2006Params params_;
  SplatSet splats_;
  float sigma_ = 0, cutoff_ = 3, reach_ = 0;
  NewtonSettings newton_;
};

}  // namespace

void register_hubo_2006(MethodRegistry& registry) {
  registry.add(MethodInfo{
      "hubo_2006",
      "E. Hubo, T. Mertens, T. Haber and P. Bekaert, The quantized kd-tree: efficient ray tracing "
      "of compressed point clouds, IEEE Symposium on Interactive Ray Tracing 2006",
      "[28]",
      "Newton steps (Algorithm 6) on the Gaussian-weighted average plane of a kd-tree leaf's "
      "points "
      "(the quantized kd-tree's compression is not implemented)",
      "kd_tree",
      {"point normals"},
      hubo_2006_params().specs(),
      {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
       {"frame", "O(SMB(log N + IK))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      create_from<Hubo2006>(hubo_2006_params(), "hubo_2006"),
      {},
      {&kWeightedPointTerms}});
}

}  // namespace pcrt
