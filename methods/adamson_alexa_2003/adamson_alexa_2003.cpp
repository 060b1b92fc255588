// adamson_alexa_2003: Adamson and Alexa, "Ray tracing point set surfaces" (Shape Modeling
// International 2003), thesis [2], section 5.1.2 and Algorithm 3: balls around the points, kept
// in a bounding sphere hierarchy, start an iterated MLS intersection (reference plane, bivariate
// quadratic, ray-polynomial root) that is repeated until the hit point stops moving. Positions
// only: no normals. See README.md.
#include <memory>
#include <optional>

#include "methods/kernels/mls_method_params.hpp"
#include "methods/kernels/mls_surface.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

// Iterated MLS: up to 10 iterations, stopping at 0.01 h.
const ParamList<MlsParams>& adamson_alexa_params() {
  static const auto l = MlsParams::list(10, 0.01);
  return l;
}

class AdamsonAlexa final : public Method {
 public:
  explicit AdamsonAlexa(const MlsParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    mls_.prepare(cloud, params_, ctx.counters, ctx.timings);
  }
  [[nodiscard]] ItemSet items() const override { return {mls_.positions, mls_.radii, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return mls_intersect_leaf(ray, leaf, mls_.positions, mls_.ball, *mls_.surface, hit, counters);
  }

 private:
  MlsParams params_;
  MlsPoints mls_;
};

}  // namespace

void register_adamson_alexa_2003(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "adamson_alexa_2003",
      .paper = "A. Adamson and M. Alexa, Ray tracing point set surfaces, Shape Modeling "
               "International 2003",
      .thesis_ref = "[2]",
      .description =
          "balls around the points in a sphere hierarchy; iterated MLS (weighted plane, bivariate "
          "quadratic, ray-polynomial root) until the hit stops moving (Algorithm 3)",
      .structure = "sphere_tree",
      .needs = {"positions only"},
      .params = adamson_alexa_params().specs(),
      .claims = {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = create_from<AdamsonAlexa>(adamson_alexa_params(), "adamson_alexa_2003"),
      .work = {&kKnnResults, &kMlsNeighbours},
      .iterative_claim = "Table 5.1",
      .iterations = {&kMlsFits, &kMlsRuns},
      .cost = {.prepare_ns = 58, .ray_ns = 777},
      .designs = {{.experiment = "leaf_K_mls",
                   .variable = "K",
                   .param = "K",
                   .values = {6, 8, 12, 16, 24, 32, 48, 64, 96, 128},
                   .metric = {&kMlsNeighbours},
                   .per = &kMlsRuns},
                  {.experiment = "leaf_I_mls",
                   .variable = "I",
                   .param = "max_iterations",
                   .values = {1, 2, 3, 4, 6, 8, 12},
                   .metric = {&kMlsNeighbours},
                   .per = &kMlsRuns,
                   .x = "I_run",
                   .fixed = {{"tolerance", 0}},
                   .replicates = 1}}});
}

}  // namespace pcrt
