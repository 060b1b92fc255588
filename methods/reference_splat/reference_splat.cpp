// reference_splat: every point an oriented disc of its radius facing its normal; the closest disc
// hit is the hit. Not a surveyed method: the oracle the renderer and the structures are checked
// with, and the baseline splat surface.
#include "methods/kernels/splat_blocks.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

class ReferenceSplat final : public Method {
 public:
  explicit ReferenceSplat(const SplatParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_, ctx);
  }
  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  void bind_leaf_references(std::span<const uint32_t> refs) override {
    bind_splat_blocks(blocks_, splats_, refs);  // the blocks: the splats' one copy from here on
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
  SplatParams params_;
  SplatSet splats_;
  SplatLeafBlocks blocks_;
};

}  // namespace

void register_reference_splat(MethodRegistry& registry) {
  registry.add(
      MethodInfo{"reference_splat",
                 "none (oracle): flat oriented discs, as in Zwicker et al. 2001 surface splatting",
                 "-",
                 "each point is a disc of its radius facing its normal; the nearest disc hit wins",
                 "brute_force",
                 {"point normals", "point radii"},
                 SplatParams::list().specs(),
                 {{"leaf intersection", "O(K)", {"K"}, "splat intersection, section 5.5.2"}},
                 create_from<ReferenceSplat>(SplatParams::list(), "reference_splat"),
                 {},
                 {&kSplatTests},
                 LeafFamily::kDisc});
}

}  // namespace pcrt
