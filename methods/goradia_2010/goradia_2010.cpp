// goradia_2010: Goradia, Kashyap, Chaudhuri and Chandran, "GPU-based ray tracing of splats"
// (Pacific Graphics 2010), thesis [24]: one oriented splat per point in an octree refined until
// its leaves hold few splats; the splats a ray hits in a leaf are blended by their distance from
// the splat centres (thesis 5.5.2, "Splat intersection"). See README.md.
#include "methods/kernels/splat_blend.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

class Goradia2010 final : public Method {
 public:
  explicit Goradia2010(ParamValues params) : params_(std::move(params)) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_, ctx);
    settings_ = splat_blend_settings(splats_.radii, float(params_.at("front_depth")));
  }
  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return blend_splat_hits(ray, leaf, splats_.packed, settings_, hit, counters);
  }

 private:
  ParamValues params_;
  SplatSet splats_;
  SplatBlendSettings settings_;
};

const RegisterMethod kRegister{MethodInfo{
    "goradia_2010",
    "R. Goradia, S. Kashyap, P. Chaudhuri and S. Chandran, GPU-based ray tracing of splats, "
    "Pacific Graphics 2010",
    "[24]",
    "one splat per point (PCA normal, neighbour-distance radius) in a refined octree; the splats "
    "hit in a leaf are blended by distance from their centres",
    "octree",
    {"point normals", "splat radii"},
    [] {
      auto p = splat_params();
      p.push_back(front_depth_param());
      return p;
    }(),
    {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
     {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
    [](const ParamValues& p) { return std::make_unique<Goradia2010>(p); },
    {},
    {&kProjectionTests, &kSplatTests},
    LeafFamily::kSplatBlend}};

}  // namespace
}  // namespace pcrt
