// wald_seidel_2005: Wald and Seidel, "Interactive ray tracing of point-based models" (Symposium
// on Point-Based Graphics 2005), thesis [63], Algorithm 5: inside a kd-tree leaf the implicit
// function of the weighted-average plane, theta(a) = max(1 - a, 0), is sampled at k regular
// points; the interval of a sign change is sampled again at k points, until |f| < epsilon or I
// refinements. O(kIK). See README.md.
#include <algorithm>

#include "methods/kernels/ball_runs.hpp"
#include "methods/kernels/leaf_implicit.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/kernels/weighted_plane.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

inline const Counter kSampleRefinements{"sample_refinements",
                                        "sampling passes over an interval (I, Algorithm 5)"};
inline const Counter kSupportTests{"support_tests", "ray-support ball tests before sampling"};
inline const Counter kSampleEvaluations{"sample_evaluations",
                                        "implicit function samples (k per pass)"};

class WaldSeidel final : public Method {
 public:
  explicit WaldSeidel(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const float h = prepare_spacing(cloud, ctx);
    radius_ = float(params_.at("radius")) * h;
    tolerance_ = float(params_.at("tolerance")) * h;
    samples_ = int(params_.at("k"));
    max_refinements_ = int(params_.at("max_iterations"));
    splats_ = prepare_splats(cloud, params_, ctx, radius_);
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    float lo = std::max(leaf.t_enter, ray.tmin), hi = std::min(leaf.t_exit, hit.t);
    if (!(lo <= hi) || leaf.items.empty()) return false;
    // Sample only where some point's support meets the ray: over a whole leaf, k samples can
    // all fall outside the thin band around the surface where f is defined.
    float s_lo = kInfinity, s_hi = -kInfinity;
    for (uint32_t k : leaf.items) {
      float t0 = 0, t1 = 0;
      if (ball_chord(ray, splats_.packed[k].c, radius_, hi, t0, t1))
        s_lo = std::min(s_lo, t0), s_hi = std::max(s_hi, t1);
    }
    counters.add(kSupportTests, leaf.items.size());
    lo = std::max(lo, s_lo), hi = std::min(hi, s_hi);
    if (!(lo <= hi)) return false;
    const TentWeight theta(radius_);
    float t_hit = kInfinity;
    Vec3 n_hit = Vec3::Zero();
    for (int pass = 0; pass < max_refinements_ && t_hit == kInfinity; ++pass) {
      counters.add(kSampleRefinements);
      const float step = (hi - lo) / float(samples_);
      bool have_prev = false, bracketed = false;
      float t_prev = lo, f_prev = 0;
      Vec3 n_prev = Vec3::Zero();
      for (int i = 0; i <= samples_; ++i) {
        const float t = i == samples_ ? hi : lo + step * float(i);
        const Vec3 x = ray.at(t);
        counters.add(kSampleEvaluations);
        const WeightedPlane w = weighted_plane(x, leaf.items, splats_.packed, theta, counters);
        if (!(w.weight > 0) || !(w.n.norm() > 0)) {
          have_prev = false;  // no point reaches x: no surface value, no bracket across it
          continue;
        }
        const float f = w.implicit(x);
        const Vec3 n = w.n.normalized();
        if (tolerance_ > 0 && std::abs(f) < tolerance_) {  // lines 12-15
          t_hit = t, n_hit = n;
          break;
        }
        if (have_prev && f * f_prev < 0) {     // lines 16-19: refine [t_prev, t]
          if (pass + 1 == max_refinements_) {  // the cap: the linear root of the last bracket
            t_hit = t_prev + (t - t_prev) * f_prev / (f_prev - f);
            n_hit = (n_prev + n).normalized();
          }
          lo = t_prev, hi = t;
          bracketed = true;
          break;
        }
        have_prev = true, t_prev = t, f_prev = f, n_prev = n;
      }
      if (!bracketed && t_hit == kInfinity) return false;  // lines 20-23: no sign change
    }
    if (t_hit == kInfinity) return false;
    const uint32_t prim = nearest_point(ray.at(t_hit), leaf.items, splats_.packed);
    if (!closer(t_hit, prim, hit)) return false;
    record_hit(ray, t_hit, prim, n_hit, radius_, hit);
    return true;
  }

 private:
  ParamValues params_;
  SplatSet splats_;
  float radius_ = 0, tolerance_ = 0;
  int samples_ = 4, max_refinements_ = 8;
};

const RegisterMethod kRegister{MethodInfo{
    "wald_seidel_2005",
    "I. Wald and H.-P. Seidel, Interactive ray tracing of point-based models, Symposium on "
    "Point-Based Graphics 2005",
    "[63]",
    "k regular samples of the weighted-average implicit function (theta(a) = max(1 - a, 0)) in a "
    "kd-tree leaf, the sign-change interval resampled until |f| < epsilon (Algorithm 5)",
    "kd_tree",
    {"point normals"},
    [] {
      auto p = normal_params();
      p.push_back({"radius", 3.5, 0.25, 50, "R of theta(d / R), in h: each point's support"});
      p.push_back({"k", 4, 1, 1000, "regular samples per pass", true});
      p.push_back({"tolerance", 0.001, 0, 10,
                   "|f| that ends the search, in h (0: always run max_iterations passes)"});
      p.push_back({"max_iterations", 8, 1, 100,
                   "cap on the passes I; at the cap the last bracket's linear root is the hit",
                   true});
      return p;
    }(),
    {{"leaf intersection", "O(kIK)", {"k", "I", "K"}, "Table 5.5"},
     {"frame", "O(SMB(log N + kIK))", {"S", "M", "B", "N", "k", "I", "K"}, "Table 6.1"}},
    [](const ParamValues& p) { return std::make_unique<WaldSeidel>(p); },
    {},
    {&kSupportTests, &kSampleEvaluations, &kWeightedPointTerms}}};

}  // namespace
}  // namespace pcrt
