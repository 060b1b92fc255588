// hubo_2006: Hubo, Mertens, Haber and Bekaert, "The quantized kd-tree: efficient ray tracing of
// compressed point clouds" (IEEE Symposium on Interactive Ray Tracing 2006), thesis [28]:
// Algorithm 6 (Newton on the weighted-average plane) with Gaussian weights over the points of a
// kd-tree leaf; with `quantized` 1, the same search over the paper's quantized kd-tree
// (quantized_kd_tree.hpp), decoded during traversal. See README.md.
#include <algorithm>
#include <array>
#include <numeric>

#include "methods/hubo_2006/quantized_kd_tree.hpp"
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
  bool quantized = false;
  size_t leaf_points = 16;
};
const ParamList<Hubo2006Params>& hubo_2006_params() {
  using P = Hubo2006Params;
  static const auto l = ParamList<P>()
                            .add(&P::normals, NormalParams::list())
                            .add(&P::gaussian, GaussianParams::list())
                            .add(&P::iteration, IterationParams::list(0.001, 10, "h (|f|)", 10))
                            .add(&P::quantized, {"quantized", 0, 0, 1,
                                                 "1: the paper's quantized kd-tree (its own walk; "
                                                 "the structure holds one item)"})
                            .add(&P::leaf_points, {"leaf_points", 16, 1, 256,
                                                   "quantized kd-tree: mean points per leaf"});
  return l;
}

// The Gaussian-weighted implicit surface both variants search, and the search: Algorithm 6 from
// the front-most tangent crossing on the ray's piece [t_lo, t_hi] over points[items].
struct GaussianSurface {
  float sigma = 0, cutoff = 3, reach = 0;  // absolute: sigma and reach in scene units
  NewtonSettings newton;

  GaussianSurface() = default;
  GaussianSurface(const Hubo2006Params& p, float h)
      : sigma(p.gaussian.sigma * h),
        cutoff(p.gaussian.cutoff),
        reach(sigma * cutoff),
        newton(newton_settings(p.iteration, h)) {}

  bool search(const Ray& ray, std::span<const uint32_t> items, std::span<const PackedSplat> points,
              float t_lo, float t_hi, Hit& hit, OpCounters& counters) const {
    float t = 0;
    if (!nearest_tangent_crossing(ray, items, points, reach, t_lo, t_hi, t)) return false;
    const GaussianWeight theta(sigma, cutoff);
    auto eval = [&](const Vec3& x) { return weighted_plane(x, items, points, theta, counters); };
    Vec3 n = Vec3::Zero();
    t = newton_on_weighted_plane(ray, t, t_lo, t_hi, eval, newton, n, counters);
    if (t == kInfinity) return false;
    const uint32_t prim = nearest_point(ray.at(t), items, points);
    if (!closer(t, prim, hit)) return false;
    record_hit(ray, t, prim, n, sigma, hit);
    return true;
  }
};

class Hubo2006 final : public Method {
 public:
  explicit Hubo2006(const Hubo2006Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    surface_ = GaussianSurface(params_, prepare_spacing(cloud, ctx));
    // Item radius: the weight's reach.
    splats_ = prepare_splats(cloud, SplatParams{params_.normals}, ctx, surface_.reach);
    splats_.pack();
  }
  [[nodiscard]] ItemSet items() const override { return {splats_.centres, splats_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    const float t_lo = std::max(leaf.t_enter - surface_.reach, ray.tmin);
    const float t_hi = std::min(leaf.t_exit, hit.t);
    if (!(t_lo <= t_hi)) return false;
    return surface_.search(ray, leaf.items, splats_.packed, t_lo, t_hi, hit, counters);
  }

 private:
  Hubo2006Params params_;
  SplatSet splats_;
  GaussianSurface surface_;
};

// The quantized variant: the points live only in the quantized kd-tree, which this method walks
// itself. The harness's structure is handed one item (the cloud's bounding ball), whose one leaf
// starts that walk; it adds one node, leaf and item visit per ray to the counters.
class Hubo2006Quantized final : public Method {
 public:
  explicit Hubo2006Quantized(const Hubo2006Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    surface_ = GaussianSurface(params_, prepare_spacing(cloud, ctx));
    std::vector<Vec3> estimated;
    if (!cloud.has_normals() || params_.normals.estimate_normals) {
      ScopedTimer t(ctx.timings, "prepare/normals");
      const KnnIndex knn(cloud.positions);
      estimated = estimate_normals(cloud.positions, knn, params_.normals.normal_k, ctx.counters);
    }
    ScopedTimer t(ctx.timings, "prepare/quantized_kd_tree");
    tree_.build(cloud.positions, estimated.empty() ? cloud.normals : estimated, params_.leaf_points,
                ctx.counters);
    bound_tree();
  }
  // The stream's points go straight into the tree; the spacing h is then sampled from the
  // decoded tree (kSpacingSamples nearest-neighbour distances) instead of the whole cloud's.
  void prepare_stream(const PointStream& stream, PrepareContext& ctx) override {
    {
      ScopedTimer t(ctx.timings, "prepare/quantized_kd_tree");
      tree_.build(stream, params_.leaf_points, ctx.counters);
    }
    ScopedTimer t(ctx.timings, "prepare/spacing");
    const double h = tree_.sampled_mean_spacing(kSpacingSamples, ctx.counters);
    surface_ = GaussianSurface(params_, std::max(float(h), 1e-30f));
    bound_tree();
  }
  [[nodiscard]] ItemSet items() const override { return {ball_centre_, ball_radius_, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& /*leaf*/, Hit& hit,
                      OpCounters& counters) const override {
    bool found = false;
    tree_.walk(
        ray, surface_.reach, &hit.t,
        [&](float t_enter, float t_exit) {
          found |= search_cell(ray, t_enter, t_exit, hit, counters);
        },
        counters);
    return found;
  }

 private:
  // 2^16 samples: the mean's standard error is about 0.2% of h on a uniform surface.
  static constexpr size_t kSpacingSamples = size_t(1) << 16;

  void bound_tree() {
    ball_centre_[0] = tree_.bounds().center();
    ball_radius_[0] = 0.5f * tree_.bounds().diagonal() + surface_.reach;
  }
  // hubo_2006's leaf search over the ray's piece near one leaf (its point box grown by the
  // reach), on the points decoded within reach of that piece (every point whose weight reaches
  // it, from any leaf).
  bool search_cell(const Ray& ray, float t_enter, float t_exit, Hit& hit,
                   OpCounters& counters) const {
    const float t_lo = std::max(t_enter, ray.tmin);
    const float t_hi = std::min(t_exit, hit.t);
    if (!(t_lo <= t_hi)) return false;
    Aabb near;
    near.extend(ray.at(t_lo), surface_.reach);
    near.extend(ray.at(t_hi), surface_.reach);
    thread_local std::vector<PackedSplat> points;  // per thread: no allocation once warm
    thread_local std::vector<uint32_t> items;
    points.clear();
    tree_.gather(near, points, counters);
    counters.add(kItemsVisited, points.size());
    if (points.empty()) return false;
    items.resize(points.size());
    std::iota(items.begin(), items.end(), 0u);
    return surface_.search(ray, items, points, t_lo, t_hi, hit, counters);
  }

  Hubo2006Params params_;
  QuantizedKdTree tree_;
  std::array<Vec3, 1> ball_centre_{Vec3::Zero()};
  std::array<float, 1> ball_radius_{0.0f};
  GaussianSurface surface_;
};

}  // namespace

void register_hubo_2006(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "hubo_2006",
      .paper = "E. Hubo, T. Mertens, T. Haber and P. Bekaert, The quantized kd-tree: efficient ray "
               "tracing of compressed point clouds, IEEE Symposium on Interactive Ray Tracing 2006",
      .thesis_ref = "[28]",
      .description =
          "Newton steps (Algorithm 6) on the Gaussian-weighted average plane of a kd-tree leaf's "
          "points (quantized=1: over the paper's quantized kd-tree, decoded during traversal)",
      .structure = "kd_tree",
      .needs = {"point normals"},
      .params = hubo_2006_params().specs(),
      .claims = {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = [](const ParamValues& given) -> std::unique_ptr<Method> {
        const Hubo2006Params p = hubo_2006_params().read(given, "hubo_2006");
        if (p.quantized) return std::make_unique<Hubo2006Quantized>(p);
        return std::make_unique<Hubo2006>(p);
      },
      .work = {&kWeightedPointTerms},
      .family = LeafFamily::kOther,
      // quantized=1: its quantized kd-tree (<= 16 B/point), no splats and no structure (21
      // B/point over the cloud measured at 10^7), and the normal estimation's graph where it runs.
      .own_bytes_per_point = [](const PointCloud& cloud, const ParamValues& given) -> size_t {
        if (!hubo_2006_params().read(given, "hubo_2006").quantized) return 0;
        return 24 + (cloud.has_normals() ? 0 : 16 * sizeof(uint32_t) + 1 + 12);
      },
      // quantized=1 with the stream's own normals: its 16-byte records (core/point_stream.hpp)
      // and the tree's nodes, about 26 bytes a leaf of leaf_points points.
      .stream_bytes_per_point = [](const ParamValues& given) -> size_t {
        const Hubo2006Params p = hubo_2006_params().read(given, "hubo_2006");
        if (!p.quantized || p.normals.estimate_normals) return 0;
        return 16 + (26 + p.leaf_points - 1) / p.leaf_points;
      },
      .iterative_claim = "Table 5.1",
      .iterations = {&kNewtonSteps, &kNewtonRuns},
      .cost = {.prepare_ns = 79, .ray_ns = 58},
      .designs = {{.experiment = "leaf_K_kd_tree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128, 256, 512},
                   .N = 20000,
                   .metric = {&kWeightedPointTerms},
                   .per = &kLeavesVisited},
                  {.experiment = "leaf_I_newton",
                   .variable = "I",
                   .param = "max_iterations",
                   .values = {1, 2, 3, 4, 6, 8, 12},
                   .metric = {&kNewtonSteps},
                   .per = &kNewtonRuns,
                   .x = "I_run",
                   .fixed = {{"tolerance", 0}},
                   .replicates = 1}}});
}

}  // namespace pcrt
