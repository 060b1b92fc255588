// ball_splat: a method written outside pcrt's tree. Every point is a ball of radius k h (h the
// cloud's mean spacing); the nearest ball hit is the hit, its normal the point's own where the
// cloud has normals (a ball's own normal is off the surface's by up to 90 degrees), else the
// ball's. Everything pcrt needs to know about it (parameters, claim, counter, structure) is
// declared here, once.
#include "ball_splat.hpp"

#include <cmath>

namespace {

using namespace pcrt;

const Counter kBallTests{"ball_tests", "ray-ball intersection tests (ball_splat)"};

struct BallParams {
  float radius_k = 1.5f;
  static const ParamList<BallParams>& list() {
    static const auto l = ParamList<BallParams>().add(
        &BallParams::radius_k, {"radius_k", 1.5, 0.05, 10, "ball radius, in mean spacings h"});
    return l;
  }
};

class BallSplat final : public Method {
 public:
  explicit BallSplat(const BallParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    cloud_ = &cloud;  // the data stays the caller's
    radius_ = params_.radius_k * prepare_spacing(cloud, ctx);
    radii_.assign(cloud.size(), radius_);
  }
  [[nodiscard]] ItemSet items() const override { return {cloud_->positions, radii_, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    counters.add(kBallTests, leaf.items.size());
    bool found = false;
    for (const uint32_t i : leaf.items) {
      const float t = entry(ray, cloud_->positions[i]);
      if (t >= ray.tmin && t < kInfinity && closer(t, i, hit)) {
        record_hit(ray, t, i, normal(ray, t, i), radius_, hit);
        found = true;
      }
    }
    return found;
  }

 private:
  [[nodiscard]] Vec3 normal(const Ray& ray, float t, uint32_t i) const {
    if (cloud_->has_normals()) return cloud_->normals[i];
    return (ray.at(t) - cloud_->positions[i]) / radius_;
  }

  // Where the ray enters the ball about c (or leaves it, from inside); +inf when it misses.
  [[nodiscard]] float entry(const Ray& ray, const Vec3& c) const {
    const Vec3 oc = ray.o - c;
    const float b = oc.dot(ray.d);
    const float q = (oc - b * ray.d).squaredNorm() - radius_ * radius_;
    if (q > 0) return kInfinity;
    const float s = std::sqrt(-q);
    return -b - s >= ray.tmin ? -b - s : -b + s;
  }

  BallParams params_;
  const PointCloud* cloud_ = nullptr;
  float radius_ = 0;
  std::vector<float> radii_;
};

}  // namespace

void register_ball_splat(pcrt::MethodRegistry& registry) {
  registry.add(pcrt::MethodInfo{
      .id = "ball_splat",
      .paper = "none (example): a method of one's own, outside pcrt's tree",
      .thesis_ref = "-",
      .description = "each point a ball of radius radius_k * h; the nearest ball hit wins",
      .structure = "kd_tree",
      .needs = {"mean spacing"},
      .params = BallParams::list().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "one test per ball in the leaf"}},
      .create = pcrt::create_from<BallSplat>(BallParams::list(), "ball_splat"),
      .work = {&kBallTests}});
}
