// goradia_2010: Goradia, Kashyap, Chaudhuri and Chandran, "GPU-based ray tracing of splats"
// (Pacific Graphics 2010), thesis [24]: one oriented splat per point in an octree refined until
// its leaves hold few splats; the splats a ray hits in a leaf are blended by their distance from
// the splat centres (thesis 5.5.2, "Splat intersection"). See README.md.
#include "methods/kernels/splat_blend.hpp"
#include "methods/kernels/splat_blocks.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

struct Goradia2010Params {
  SplatParams splat;
  float front_depth = 0.5f;
  DiscBlockParams blocks;
};
const ParamList<Goradia2010Params>& goradia_2010_params() {
  using P = Goradia2010Params;
  static const auto l = ParamList<P>()
                            .add(&P::splat, SplatParams::list())
                            .add(&P::front_depth, front_depth_spec())
                            .add(&P::blocks, DiscBlockParams::list());
  return l;
}

class Goradia2010 final : public Method {
 public:
  explicit Goradia2010(const Goradia2010Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_.splat, ctx);
    settings_ = splat_blend_settings(splats_.radii, params_.front_depth);
  }
  [[nodiscard]] ItemSet items() const override { return blend_items(splats_, settings_); }
  void bind_leaf_references(std::span<const uint32_t> refs) override {
    bind_splat_blocks(blocks_, splats_, refs, params_.blocks);
  }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return blend_splat_hits(ray, leaf, blocks_, splats_, settings_, hit, counters);
  }

 private:
  Goradia2010Params params_;
  SplatSet splats_;
  SplatLeafBlocks blocks_;
  SplatBlendSettings settings_;
};

}  // namespace

void register_goradia_2010(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "goradia_2010",
      .paper = "R. Goradia, S. Kashyap, P. Chaudhuri and S. Chandran, GPU-based ray tracing of "
               "splats, Pacific Graphics 2010",
      .thesis_ref = "[24]",
      .description = "one splat per point (PCA normal, neighbour-distance radius) in a refined "
                     "octree; the splats hit in a leaf are blended by distance from their centres",
      .structure = "octree",
      .needs = {"point normals", "splat radii"},
      .params = goradia_2010_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
      .create = create_from<Goradia2010>(goradia_2010_params(), "goradia_2010"),
      .work = {&kProjectionTests, &kSplatTests},
      .family = LeafFamily::kSplatBlend,
      .real_time_claim = "Table 5.1",
      .cost = {.prepare_ns = 165, .ray_ns = 47},
      .designs = {{.experiment = "leaf_K_octree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128},
                   .N = 20000,
                   .metric = {&kSplatTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
