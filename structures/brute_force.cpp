// The oracle: one leaf holding every point, so each ray costs O(N). Any method traced through it
// gives the exact closest hit of its own leaf intersector, which the real structures must match.
#include <numeric>

#include "structures/structure.hpp"

namespace pcrt {
namespace {

class BruteForce final : public Structure {
 public:
  void build(const ItemSet& set, OpCounters&) override {
    items_.resize(set.size());
    std::iota(items_.begin(), items_.end(), 0u);
  }
  bool closest_hit(const Ray& ray, const LeafIntersector& leaf_intersector, Hit& hit,
                   OpCounters& counters) const override {
    counters.add(kLeavesVisited);
    counters.add(kItemsVisited, items_.size());
    return leaf_intersector.intersect_leaf(ray, LeafVisit{items_, ray.tmin, ray.tmax}, hit,
                                           counters);
  }
  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return items_; }
  [[nodiscard]] size_t memory_bytes() const override { return items_.size() * sizeof(uint32_t); }

 private:
  std::vector<uint32_t> items_;
};

}  // namespace

void register_brute_force(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "brute_force",
      .description =
          "every point in one leaf; O(N) per ray; the oracle other structures are checked against",
      .build_claim = "O(N)",
      .query_claim = "O(N)",
      .params = {},
      .create = [](const ParamValues&) { return std::make_unique<BruteForce>(); },
      // One reference per item; a leaf-order copy adds its 28-byte disc.
      .footprint = fixed_footprint({.item_order = sizeof(uint32_t),
                                    .leaf_order = sizeof(uint32_t) + 28,
                                    .references_per_item = 1}),
  });
}

}  // namespace pcrt
