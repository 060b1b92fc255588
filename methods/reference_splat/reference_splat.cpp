// reference_splat: every point an oriented disc of its radius facing its normal; the closest disc
// hit is the hit. Not a surveyed method: the oracle the renderer and the structures are checked
// with, and the baseline splat surface.
#include <cmath>

#include "methods/kernels/splat_kernel.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

class ReferenceSplat final : public Method {
 public:
  explicit ReferenceSplat(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    positions_ = cloud.positions;
    splats_ = prepare_splats(cloud, params_, ctx);
  }
  [[nodiscard]] std::span<const Vec3> item_positions() const override { return positions_; }
  [[nodiscard]] std::span<const float> item_radii() const override { return splats_.radii; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit, OpCounters& counters) const override {
    bool found = false;
    for (uint32_t i : leaf.items) {
      const float t = intersect_splat(ray, positions_[i], splats_.normals[i], splats_.radii[i], ray.tmin,
                                      std::nextafter(hit.t, kInfinity));
      if (t != kInfinity && closer(t, i, hit)) {
        hit.t = t;
        hit.prim = i;
        found = true;
      }
    }
    counters.add(kSplatTests, leaf.items.size());
    if (found) {
      hit.p = ray.at(hit.t);
      hit.n = splats_.normals[hit.prim];
      hit.footprint = splats_.radii[hit.prim];
    }
    return found;
  }

 private:
  ParamValues params_;
  std::span<const Vec3> positions_;
  SplatSet splats_;
};

const RegisterMethod kRegister{MethodInfo{
    "reference_splat",
    "none (oracle): flat oriented discs, as in Zwicker et al. 2001 surface splatting",
    "-",
    "each point is a disc of its radius facing its normal; the nearest disc hit wins",
    "brute_force",
    {"point normals", "point radii"},
    splat_params(),
    {{"leaf intersection", "O(K)", {"K"}, "splat intersection, section 5.5.2"}},
    [](const ParamValues& p) { return std::make_unique<ReferenceSplat>(p); }}};

}  // namespace
}  // namespace pcrt
