// wald_seidel_2005: Wald and Seidel, "Interactive ray tracing of point-based models" (Symposium
// on Point-Based Graphics 2005), thesis [63], Algorithm 5: inside a kd-tree leaf the implicit
// function of the weighted-average plane, theta(a) = max(1 - a, 0), is sampled at k regular
// points; the interval of a sign change is sampled again at k points, until |f| < epsilon or I
// refinements. O(kIK). See README.md.
#include <algorithm>
#include <cmath>
#include <span>

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
inline const Counter kSampleRoots{
    "sample_roots", "root searches (Algorithm 5 on one run of supports): the iterative runs"};
inline const Counter kSupportTests{"support_tests", "ray-support ball tests before sampling"};
inline const Counter kSampleEvaluations{"sample_evaluations",
                                        "implicit function samples (k per pass)"};

struct WaldSeidelParams {
  NormalParams normals;
  float radius = 3.5f;  // in h
  int k = 4;
  float tolerance = 0.001f;  // in h
  int max_iterations = 8;
};
const ParamList<WaldSeidelParams>& wald_seidel_params() {
  using P = WaldSeidelParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::radius,
               {"radius", 3.5, 0.25, 50, "R of theta(d / R), in h: each point's support"})
          .add(&P::k, {"k", 4, 1, 1000, "regular samples per pass"})
          .add(&P::tolerance,
               {"tolerance", 0.001, 0, 10,
                "|f| that ends the search, in h (0: always run max_iterations passes)"})
          .add(&P::max_iterations,
               {"max_iterations", 8, 1, 100,
                "cap on the passes I; at the cap the last bracket's linear root is the hit"});
  return l;
}

class WaldSeidel final : public Method {
 public:
  explicit WaldSeidel(const WaldSeidelParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const float h = prepare_spacing(cloud, ctx);
    radius_ = params_.radius * h;
    tolerance_ = params_.tolerance * h;
    samples_ = params_.k;
    max_refinements_ = params_.max_iterations;
    splats_ = prepare_splats(cloud, SplatParams{params_.normals}, ctx, radius_);
    splats_.pack();
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    float lo = std::max(leaf.t_enter, ray.tmin);
    const float hi = std::min(leaf.t_exit, hit.t);
    if (!(lo <= hi) || leaf.items.empty()) return false;
    // Sample only where the points' supports meet the ray, one gap-free run of supports at a
    // time, front to back: k samples spread over the whole leaf (or over the span from the
    // first support to the last) step over the thin band around the front surface and find the
    // sign change of the surface behind it.
    float run_lo = 0, run_hi = 0, t_hit = kInfinity;
    Vec3 n_hit = Vec3::Zero();
    while (t_hit == kInfinity && support_run(ray, leaf.items, lo, hi, run_lo, run_hi, counters)) {
      t_hit = first_root(ray, leaf.items, run_lo, run_hi, n_hit, counters);
      lo = std::nextafter(run_hi, kInfinity);
    }
    if (t_hit == kInfinity) return false;
    const uint32_t prim = nearest_point(ray.at(t_hit), leaf.items, splats_.packed);
    if (!closer(t_hit, prim, hit)) return false;
    record_hit(ray, t_hit, prim, n_hit, radius_, hit);
    return true;
  }

 private:
  // The first stretch [run_lo, run_hi] of [lo, hi] that the items' supports cover without a gap;
  // false if no support meets [lo, hi]. Grows the run by passes over the items (each counted).
  bool support_run(const Ray& ray, std::span<const uint32_t> items, float lo, float hi,
                   float& run_lo, float& run_hi, OpCounters& counters) const {
    run_lo = kInfinity;
    for (uint32_t k : items) {
      float t0 = 0, t1 = 0;
      if (ball_chord(ray, splats_.packed[k].c, radius_, hi, t0, t1) && t1 >= lo)
        run_lo = std::min(run_lo, std::max(t0, lo));
    }
    counters.add(kSupportTests, items.size());
    if (run_lo == kInfinity) return false;
    run_hi = run_lo;
    for (bool grown = true; grown;) {
      grown = false;
      for (uint32_t k : items) {
        float t0 = 0, t1 = 0;
        if (ball_chord(ray, splats_.packed[k].c, radius_, hi, t0, t1) && t0 <= run_hi &&
            t1 > run_hi)
          run_hi = t1, grown = true;
      }
      counters.add(kSupportTests, items.size());
    }
    return true;
  }

  // Algorithm 5 on [lo, hi]: k regular samples, the first sign-change interval sampled again,
  // until |f| < epsilon or the cap (then the linear root of the last bracket). The hit t and its
  // normal, or +inf when no pass finds a sign change.
  float first_root(const Ray& ray, std::span<const uint32_t> items, float lo, float hi, Vec3& n_hit,
                   OpCounters& counters) const {
    const TentWeight theta(radius_);
    counters.add(kSampleRoots);
    for (int pass = 0; pass < max_refinements_; ++pass) {
      counters.add(kSampleRefinements);
      const float step = (hi - lo) / float(samples_);
      bool have_prev = false, bracketed = false;
      float t_prev = lo, f_prev = 0;
      Vec3 n_prev = Vec3::Zero();
      for (int i = 0; i <= samples_; ++i) {
        const float t = i == samples_ ? hi : lo + step * float(i);
        const Vec3 x = ray.at(t);
        counters.add(kSampleEvaluations);
        const WeightedPlane w = weighted_plane(x, items, splats_.packed, theta, counters);
        if (!(w.weight > 0) || !(w.n.norm() > 0)) {
          have_prev = false;  // no point reaches x: no surface value, no bracket across it
          continue;
        }
        const float f = w.implicit(x);
        const Vec3 n = w.n.normalized();
        if (tolerance_ > 0 && std::abs(f) < tolerance_) {  // lines 12-15
          n_hit = n;
          return t;
        }
        if (have_prev && f * f_prev < 0) {     // lines 16-19: refine [t_prev, t]
          if (pass + 1 == max_refinements_) {  // the cap: the linear root of the last bracket
            n_hit = (n_prev + n).normalized();
            return t_prev + (t - t_prev) * f_prev / (f_prev - f);
          }
          lo = t_prev, hi = t;
          bracketed = true;
          break;
        }
        have_prev = true, t_prev = t, f_prev = f, n_prev = n;
      }
      if (!bracketed) return kInfinity;  // lines 20-23: no sign change
    }
    return kInfinity;
  }

  WaldSeidelParams params_;
  SplatSet splats_;
  float radius_ = 0, tolerance_ = 0;
  int samples_ = 4, max_refinements_ = 8;
};

}  // namespace

void register_wald_seidel_2005(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "wald_seidel_2005",
      .paper = "I. Wald and H.-P. Seidel, Interactive ray tracing of point-based models, Symposium "
               "on Point-Based Graphics 2005",
      .thesis_ref = "[63]",
      .description =
          "k regular samples of the weighted-average implicit function (theta(a) = max(1 - a, 0)) "
          "in a kd-tree leaf, the sign-change interval resampled until |f| < epsilon (Algorithm 5)",
      .structure = "kd_tree",
      .needs = {"point normals"},
      .params = wald_seidel_params().specs(),
      .claims =
          {{"leaf intersection", "O(kIK)", {"k", "I", "K"}, "Table 5.5"},
           {"frame", "O(SMB(log N + kIK))", {"S", "M", "B", "N", "k", "I", "K"}, "Table 6.1"}},
      .create = create_from<WaldSeidel>(wald_seidel_params(), "wald_seidel_2005"),
      .work = {&kSupportTests, &kSampleEvaluations, &kWeightedPointTerms},
      .real_time_claim = "Table 5.1",
      .iterative_claim = "Table 5.1",
      .iterations = {&kSampleRefinements, &kSampleRoots},
      .cost = {.prepare_ns = 77, .ray_ns = 203},
      .designs = {{.experiment = "leaf_K_kd_tree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128, 256, 512},
                   .N = 20000,
                   .metric = {&kWeightedPointTerms},
                   .per = &kLeavesVisited},
                  {.experiment = "leaf_k_wald_seidel",
                   .variable = "k",
                   .param = "k",
                   .values = {1, 2, 4, 8, 16, 32, 64},
                   .metric = {&kSampleEvaluations},
                   .per = &kSampleRefinements}}});
}

}  // namespace pcrt
