// reference_splat: every point an oriented disc of its radius facing its normal; the closest disc
// hit is the hit. Not a surveyed method: the oracle the renderer and the structures are checked
// with, and the baseline splat surface.
#include "methods/kernels/splat_blocks.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

struct ReferenceSplatParams {
  SplatParams splat;
  DiscBlockParams blocks;
};
const ParamList<ReferenceSplatParams>& reference_splat_params() {
  using P = ReferenceSplatParams;
  static const auto l =
      ParamList<P>().add(&P::splat, SplatParams::list()).add(&P::blocks, DiscBlockParams::list());
  return l;
}

class ReferenceSplat final : public Method {
 public:
  explicit ReferenceSplat(const ReferenceSplatParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_.splat, ctx);
  }
  [[nodiscard]] ItemSet items() const override { return splats_.disc_items(); }

  void bind_leaf_references(std::span<const uint32_t> refs) override {
    bind_splat_blocks(blocks_, splats_, refs, params_.blocks);
  }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    counters.add(kSplatTests, leaf.items.size());
    bool found = false;
    for_each_disc_candidate(blocks_, splats_, leaf.items, disc_query(ray, hit.t),
                            [&](const DiscCandidate& c) {
                              if (c.t >= ray.tmin && closer(c.t, c.prim, hit)) {
                                record_hit(ray, c.t, c.prim, c.n, c.r, hit);
                                found = true;
                              }
                              return true;
                            });
    return found;
  }

  // Stops at the first disc that blocks; counts the whole leaf, as the lanes test it whole.
  bool occluded_leaf(const Ray& ray, const LeafVisit& leaf, float t_max,
                     OpCounters& counters) const override {
    counters.add(kSplatTests, leaf.items.size());
    bool blocked = false;
    for_each_disc_candidate(blocks_, splats_, leaf.items, disc_query(ray, t_max),
                            [&](const DiscCandidate& c) {
                              blocked = c.t >= ray.tmin && c.t <= t_max;
                              return !blocked;
                            });
    return blocked;
  }

 private:
  ReferenceSplatParams params_;
  SplatSet splats_;
  SplatLeafBlocks blocks_;
};

}  // namespace

void register_reference_splat(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "reference_splat",
      .paper = "none (oracle): flat oriented discs, as in Zwicker et al. 2001 surface splatting",
      .thesis_ref = "-",
      .description =
          "each point is a disc of its radius facing its normal; the nearest disc hit wins",
      .structure = "brute_force",
      .needs = {"point normals", "point radii"},
      .params = reference_splat_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "splat intersection, section 5.5.2"}},
      .create = create_from<ReferenceSplat>(reference_splat_params(), "reference_splat"),
      .work = {&kSplatTests},
      .family = LeafFamily::kDisc,
      .cost = {.prepare_ns = 97, .ray_ns = 41},
      // A flat disc carries its centre's normal to its rim: on the torus's tube (radius 0.25) a
      // disc of 8th-neighbour radius tilts about 3 degrees there.
      .accuracy_misses = {{"torus", "normal median"}},
      // Its own structure lists every item in one leaf: K is swept on a kd-tree's leaves.
      .designs = {{.experiment = "leaf_K_reference",
                   .structure = "kd_tree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128, 256, 512},
                   .N = 20000,
                   .metric = {&kSplatTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
