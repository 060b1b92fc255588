// adams_2005: Adams, Keiser, Pauly, Guibas, Gross and Dutre, "Efficient raytracing of deforming
// point-sampled surfaces" (Computer Graphics Forum 24(3), 2005), thesis [1], Algorithm 6: surfels
// in a bounding sphere hierarchy; from where the ray enters a surfel's sphere, Newton steps on the
// implicit function of the distance-weighted average plane of the K nearest surfels
// (Eq. 3.22, 3.24). See README.md.
#include <array>
#include <optional>

#include "methods/kernels/ball_runs.hpp"
#include "methods/kernels/implicit_newton.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {
namespace {

constexpr size_t kMaxK = 64;

struct Adams2005Params {
  SplatParams splat;
  size_t K = 16;
  float support = 2;
  IterationParams iteration;
};
const ParamList<Adams2005Params>& adams_2005_params() {
  using P = Adams2005Params;
  static const auto l =
      ParamList<P>()
          .add(&P::splat, SplatParams::list())
          .add(&P::K, {"K", 16, 1, double(kMaxK), "surfels in each weighted average"})
          .add(&P::support,
               {"support", 2.0, 0.5, 10, "weight support of a surfel, in multiples of its radius"})
          .add(&P::iteration, IterationParams::list(1e-3, 1, "surfel radii (|f|)", 10));
  return l;
}

class Adams2005 final : public Method {
 public:
  explicit Adams2005(const Adams2005Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_.splat, ctx);
    splats_.pack();
    {
      ScopedTimer t(ctx.timings, "prepare/knn_build");
      knn_.emplace(splats_.centres);  // surfel order: k-NN results index splats_.packed
    }
    k_ = params_.K;
    support_ = params_.support;
    newton_ =
        newton_settings(params_.iteration, 1.0f);  // tolerance scaled per surfel in intersect_leaf
  }
  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    auto run = [&](uint32_t k, float t0, float t1, Vec3& n) {
      // Algorithm 6 from the ray's entry into the surfel's sphere.
      return newton_on_weighted_plane(
          ray, t0, t0, t1, [&](const Vec3& x) { return evaluate(x, counters); },
          {newton_.tolerance * splats_.packed[k].r, newton_.max_iterations}, n, counters);
    };
    return nearest_splat_ball_hit(ray, leaf.items, splats_.packed, run, hit);
  }

 private:
  // The weighted plane of the K surfels nearest x, weights (1 - d^2 / (support r_j)^2)^2.
  WeightedPlane evaluate(const Vec3& x, OpCounters& counters) const {
    std::array<uint32_t, kMaxK> idx;
    std::array<float, kMaxK> d2;
    const size_t found = knn_->knn(x, std::min(k_, kMaxK), idx.data(), d2.data(), counters);
    const float s2 = support_ * support_;
    auto theta = [s2](float dist2, const PackedSplat& p) {
      const float q = 1.0f - dist2 / (s2 * p.r * p.r);
      return q > 0 ? q * q : 0.0f;
    };
    return weighted_plane(x, std::span<const uint32_t>(idx.data(), found), splats_.packed, theta,
                          counters);
  }

  Adams2005Params params_;
  SplatSet splats_;
  std::optional<KnnIndex> knn_;
  size_t k_ = 16;
  float support_ = 2;
  NewtonSettings newton_;
};

}  // namespace

void register_adams_2005(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "adams_2005",
      .paper =
          "B. Adams, R. Keiser, M. Pauly, L. Guibas, M. Gross and P. Dutre, Efficient raytracing "
          "of deforming point-sampled surfaces, Computer Graphics Forum 24(3) (Eurographics 2005)",
      .thesis_ref = "[1]",
      .description =
          "surfels in a sphere hierarchy; Newton steps (Algorithm 6) on the weighted-average plane "
          "of the K nearest surfels, from the ray's entry into each surfel sphere",
      .structure = "sphere_tree",
      .needs = {"point normals", "surfel radii"},
      .params = adams_2005_params().specs(),
      .claims = {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = create_from<Adams2005>(adams_2005_params(), "adams_2005"),
      .work = {&kKnnResults, &kWeightedPointTerms},
      .iterative_claim = "Table 5.1",
      .iterations = {&kNewtonSteps, &kNewtonRuns},
      .cost = {.prepare_ns = 107, .ray_ns = 371},
      .designs = {{.experiment = "leaf_K_adams",
                   .variable = "K",
                   .param = "K",
                   .values = {4, 6, 8, 12, 16, 24, 32, 48, 64},
                   .metric = {&kWeightedPointTerms},
                   .per = &kNewtonRuns},
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
