// cai_2011: Cai, Kong, Wang and Yin, "A height-difference-based ray tracing of point models"
// (VRCAI 2011), thesis [14] (section 5.5.2, "height-difference based intersection"):
// every splat of a kd-tree leaf whose bounding sphere the ray crosses starts an iteration at the
// midpoint of that crossing; each step averages, over the leaf's splats, their normals and their
// height differences to the current point, and moves along the ray by the Newton step
// -height / (n . d) until the height is under the tolerance. I steps each scanning the K splats,
// from up to K starts: O(IK^2). See README.md.
#include <cmath>

#include "methods/kernels/ball_runs.hpp"
#include "methods/kernels/implicit_newton.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/kernels/weighted_plane.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

inline const Counter kHeightStarts{"height_starts", "height-difference iterations started"};
inline const Counter kHeightSteps{"height_steps", "height-difference steps (each scans the leaf)"};
inline const Counter kHeightConverged{"height_converged", "height-difference runs converged"};

struct Cai2011Params {
  SplatParams splat;
  IterationParams iteration;
};
const ParamList<Cai2011Params>& cai_2011_params() {
  using P = Cai2011Params;
  static const auto l =
      ParamList<P>()
          .add(&P::splat, SplatParams::list())
          .add(&P::iteration, IterationParams::list(1e-3, 1, "start-splat radii (|height|)", 8));
  return l;
}

class Cai2011 final : public Method {
 public:
  explicit Cai2011(const Cai2011Params& params)
      : params_(params),
        tolerance_(params.iteration.tolerance),
        max_iterations_(params.iteration.max_iterations) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_.splat, ctx);
    splats_.pack();
  }
  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    auto run = [&](uint32_t k, float t0, float t1, Vec3& n) {
      return iterate(ray, leaf, splats_.packed[k], t0, t1, n, counters);
    };
    return nearest_splat_ball_hit(ray, leaf.items, splats_.packed, run, hit);
  }

 private:
  // From the midpoint of the start splat's chord; the result must stay inside that chord.
  float iterate(const Ray& ray, const LeafVisit& leaf, const PackedSplat& start, float t0, float t1,
                Vec3& normal, OpCounters& counters) const {
    counters.add(kHeightStarts);
    auto theta = [](float d2, const PackedSplat& p) {
      const float q = d2 / (p.r * p.r);
      return q < 1.0f ? 1.0f - q : 0.0f;
    };
    float t = 0.5f * (t0 + t1);
    NewtonBracket bracket;  // the steps' slope ignores how the average moves: see implicit_newton
    for (int i = 0; i < max_iterations_; ++i) {
      counters.add(kHeightSteps);
      const WeightedPlane w =
          weighted_plane(ray.at(t), leaf.items, splats_.packed, theta, counters);
      const float slope = w.n.dot(ray.d);
      if (!(w.weight > 0) || std::abs(slope) < 1e-6f * w.n.norm()) return kInfinity;
      normal = w.n.normalized();
      if (tolerance_ > 0 && std::abs(w.height) <= tolerance_ * start.r) {
        counters.add(kHeightConverged);
        return t;
      }
      if (w.height != 0) bracket.add(t, w.height);
      t = bracket.safeguard(t - w.height / slope);
      if (!(t >= t0 && t <= t1)) return kInfinity;
    }
    return tolerance_ > 0 ? kInfinity : t;  // tolerance 0: exactly I steps, then the last point
  }

  Cai2011Params params_;
  SplatSet splats_;
  float tolerance_;
  int max_iterations_;
};

}  // namespace

void register_cai_2011(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "cai_2011",
      .paper = "P. Cai, D. Kong, S. Wang and B. Yin, A height-difference-based ray tracing of "
               "point models, VRCAI 2011",
      .thesis_ref = "[14]",
      .description =
          "bounding spheres of splats; from each crossed sphere's midpoint, Newton steps on the "
          "leaf's weighted average height difference along the averaged normal",
      .structure = "kd_tree",
      .needs = {"point normals", "splat radii"},
      .params = cai_2011_params().specs(),
      .claims = {{"leaf intersection", "O(IK^2)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK^2))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = create_from<Cai2011>(cai_2011_params(), "cai_2011"),
      .work = {&kWeightedPointTerms},
      .real_time_claim = "Table 5.1",
      .iterative_claim = "Table 5.1",
      .iterations = {&kHeightSteps, &kHeightStarts},
      .cost = {.prepare_ns = 116, .ray_ns = 149},
      .designs = {{.experiment = "leaf_K_kd_tree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128, 256, 512},
                   .N = 20000,
                   .metric = {&kWeightedPointTerms},
                   .per = &kLeavesVisited},
                  {.experiment = "leaf_I_cai_2011",
                   .variable = "I",
                   .param = "max_iterations",
                   .values = {1, 2, 3, 4, 6, 8, 12},
                   .metric = {&kHeightSteps},
                   .per = &kHeightStarts,
                   .x = "I_run",
                   .fixed = {{"tolerance", 0}},
                   .replicates = 1}}});
}

}  // namespace pcrt
