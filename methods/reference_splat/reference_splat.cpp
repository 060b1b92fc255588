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
    splats_ = prepare_splats(cloud, params_, ctx);
  }
  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    int best = -1;
    float t_limit = std::nextafter(hit.t, kInfinity);  // ties are resolved by closer()
    for (uint32_t k : leaf.items) {
      const PackedSplat& s = splats_.packed[k];
      const float t = intersect_splat(ray, s, ray.tmin, t_limit);
      if (t != kInfinity && closer(t, s.index, hit)) {
        hit.t = t;
        hit.prim = s.index;
        best = int(k);
        t_limit = std::nextafter(t, kInfinity);
      }
    }
    counters.add(kSplatTests, leaf.items.size());
    if (best < 0) return false;
    hit.p = ray.at(hit.t);
    hit.n = splats_.normals[size_t(best)];
    hit.footprint = splats_.radii[size_t(best)];
    return true;
  }

 private:
  ParamValues params_;
  SplatSet splats_;
};

const RegisterMethod kRegister{
    MethodInfo{"reference_splat",
               "none (oracle): flat oriented discs, as in Zwicker et al. 2001 surface splatting",
               "-",
               "each point is a disc of its radius facing its normal; the nearest disc hit wins",
               "brute_force",
               {"point normals", "point radii"},
               splat_params(),
               {{"leaf intersection", "O(K)", {"K"}, "splat intersection, section 5.5.2"}},
               [](const ParamValues& p) { return std::make_unique<ReferenceSplat>(p); },
               {},
               {&kSplatTests},
               LeafFamily::kSplat}};

}  // namespace
}  // namespace pcrt
