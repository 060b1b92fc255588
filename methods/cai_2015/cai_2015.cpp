// cai_2015: Cai, Kong, Wang, Yin and Huo, "A K-neighbor-based ray tracing of point clouds"
// (JICS 2015), thesis [15] (section 5.5.2, "k-NN intersection"): inside a grid cell the ray is
// marched by sphere-tracing steps towards the nearest point; near a point, the fan of triangles
// it forms with its K nearest neighbours gives a normal, and the ray's crossing of that plane is
// the hit if it projects within reach of the point. Positions only. See README.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

inline const Counter kMarchSteps{"knn_march_steps", "k-NN march steps along rays (I)"};
inline const Counter kMarchRuns{"knn_march_runs",
                                "k-NN marches, one per leaf entered: the iterative runs"};
inline const Counter kNeighbourTests{"knn_point_tests",
                                     "point distance evaluations by the k-NN method"};
inline const Counter kFanTriangles{"fan_triangles", "triangles of k-NN fans"};

constexpr size_t kMaxFan = 32;

struct Cai2015Params {
  size_t K = 8;
  float reach = 3.5f;     // in h
  float min_step = 0.5f;  // in h
  int max_steps = 256;
};
const ParamList<Cai2015Params>& cai_2015_params() {
  using P = Cai2015Params;
  static const auto l =
      ParamList<P>()
          .add(&P::K, {"K", 8, 3, double(kMaxFan), "neighbours in the triangle fan"})
          .add(&P::reach, {"reach", 3.5, 0.5, 50,
                           "a sample surface lies within this distance of its nearest point, in h "
                           "(sphere-tracing bound and projected-distance test)"})
          .add(&P::min_step, {"min_step", 0.5, 0.01, 50, "smallest march step, in h"})
          .add(&P::max_steps, {"max_steps", 256, 1, 100000, "cap on the march steps I per leaf"});
  return l;
}

class Cai2015 final : public Method {
 public:
  explicit Cai2015(const Cai2015Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const float h = prepare_spacing(cloud, ctx);
    positions_ = cloud.positions;
    reach_ = params_.reach * h;
    min_step_ = params_.min_step * h;
    inv_unit_ = 1.0f / length_unit(reach_);
    k_ = params_.K;
    max_steps_ = params_.max_steps;
    radii_.assign(cloud.size(), reach_);
  }
  [[nodiscard]] ItemSet items() const override { return {positions_, radii_, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    if (leaf.items.empty()) return false;
    counters.add(kMarchRuns);
    float t = std::max(leaf.t_enter, ray.tmin);
    const float t_end = std::min(leaf.t_exit, hit.t);
    for (int step = 0; step < max_steps_ && t <= t_end; ++step) {
      counters.add(kMarchSteps);
      const Vec3 x = ray.at(t);
      const uint32_t p = nearest(x, leaf.items, counters);
      const float dist = (positions_[p] - x).norm();
      if (dist <= reach_) {
        const Vec3 n = fan_normal(p, leaf.items, counters);
        const float denom = n.dot(ray.d);
        if (denom != 0) {
          const float tp = t + n.dot(positions_[p] - x) / denom;
          // The projected-distance test: the plane crossing must lie within reach of the point.
          if (tp >= ray.tmin && tp >= leaf.t_enter - reach_ && tp <= t_end + reach_ &&
              (ray.at(tp) - positions_[p]).norm() <= reach_ && closer(tp, p, hit)) {
            record_hit(ray, tp, p, n, reach_, hit);
            return true;
          }
        }
      }
      // Sphere tracing: no sample surface is nearer than dist - reach.
      t += std::max(dist - reach_, min_step_);
    }
    return false;
  }

 private:
  uint32_t nearest(const Vec3& x, std::span<const uint32_t> items, OpCounters& counters) const {
    uint32_t best = items[0];
    float best_d2 = kInfinity;
    for (uint32_t i : items) {
      const float d2 = (positions_[i] - x).squaredNorm();
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) best_d2 = d2, best = i;
    }
    counters.add(kNeighbourTests, items.size());
    return best;
  }

  // The K nearest leaf points of p, sorted by angle around p in their least-squares plane; the
  // normals of the fan triangles (p, q_a, q_a+1), oriented alike and summed (area-weighted).
  Vec3 fan_normal(uint32_t p, std::span<const uint32_t> items, OpCounters& counters) const {
    std::array<std::pair<float, uint32_t>, kMaxFan + 1> knn;
    size_t found = 0;
    const size_t k = std::min(k_, kMaxFan);
    for (uint32_t i : items) {  // insertion into a sorted array of the K+1 nearest (p itself too)
      const float d2 = (positions_[i] - positions_[p]).squaredNorm();
      if (found == k + 1 && d2 >= knn[k].first) continue;
      size_t j = std::min(found, k);
      while (j > 0 && knn[j - 1].first > d2) knn[j] = knn[j - 1], --j;
      knn[j] = {d2, i};
      found = std::min(found + 1, k + 1);
    }
    counters.add(kNeighbourTests, items.size());
    std::array<uint32_t, kMaxFan + 1> ids;
    for (size_t j = 0; j < found; ++j) ids[j] = knn[j].second;
    const Vec3 plane_n = pca_normal(positions_, std::span<const uint32_t>(ids.data(), found));
    if (found < 3) return plane_n;
    Vec3 u, v;
    orthonormal_basis(plane_n, u, v);
    std::array<std::pair<float, uint32_t>, kMaxFan> fan;
    size_t m = 0;
    for (size_t j = 0; j < found; ++j) {
      if (ids[j] == p) continue;
      const Vec3 d = positions_[ids[j]] - positions_[p];
      fan[m++] = {std::atan2(d.dot(v), d.dot(u)), ids[j]};
    }
    std::sort(fan.begin(), fan.begin() + long(m));
    // The edges in a unit near the reach: the sum's squared norm is a fourth power of a length.
    Vec3 sum = Vec3::Zero();
    for (size_t a = 0; a < m; ++a) {
      const Vec3 e0 = (positions_[fan[a].second] - positions_[p]) * inv_unit_;
      const Vec3 e1 = (positions_[fan[(a + 1) % m].second] - positions_[p]) * inv_unit_;
      const Vec3 c = e0.cross(e1);
      sum += c.dot(plane_n) >= 0 ? c : Vec3(-c);
    }
    counters.add(kFanTriangles, m);
    return sum.norm() > 0 ? Vec3(sum.normalized()) : plane_n;
  }

  Cai2015Params params_;
  std::span<const Vec3> positions_;
  std::vector<float> radii_;
  float reach_ = 0, min_step_ = 0, inv_unit_ = 1;
  size_t k_ = 8;
  int max_steps_ = 256;
};

}  // namespace

void register_cai_2015(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "cai_2015",
      .paper = "P. Cai, D. Kong, S. Wang, B. Yin and Y. Huo, A K-neighbor-based ray tracing of "
               "point clouds, Journal of Information & Computational Science 12.13 (2015)",
      .thesis_ref = "[15]",
      .description =
          "sphere-tracing march to the nearest point in a grid cell; fan of triangles among its K "
          "nearest neighbours for the normal; projected-distance test on that plane",
      .structure = "grid",
      .needs = {"positions only"},
      .params = cai_2015_params().specs(),
      .claims = {{"leaf intersection", "O(IK^2)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK^2))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = create_from<Cai2015>(cai_2015_params(), "cai_2015"),
      .work = {&kNeighbourTests, &kFanTriangles},
      .iterative_claim = "Table 5.1",
      .iterations = {&kMarchSteps, &kMarchRuns},
      .cost = {.prepare_ns = 46, .ray_ns = 327},
      .other_claims = {{"fan",
                        "(K-1)K/2 triangles of the k-NN fan per step",
                        "O(K^2)",
                        {"K"},
                        "section 5.5.2"}},
      .designs = {{.experiment = "leaf_K_cai_2015",
                   .variable = "K",
                   .param = "K",
                   .values = {3, 4, 6, 8, 12, 16, 24, 32},
                   .metric = {&kNeighbourTests, &kFanTriangles},
                   .per = &kMarchSteps},
                  {.claim = "fan",
                   .experiment = "leaf_K_cai_2015",
                   .variable = "K",
                   .param = "K",
                   .values = {3, 4, 6, 8, 12, 16, 24, 32},
                   .metric = {&kFanTriangles},
                   .per = &kMarchSteps}}});
}

}  // namespace pcrt
