#include "render/memory_estimate.hpp"

#include <algorithm>

#include "methods/kernels/splat_blocks.hpp"
#include "methods/kernels/splat_kernel.hpp"

namespace pcrt {
namespace {

bool needs(const MethodInfo& m, const std::string& what) {
  return std::find(m.needs.begin(), m.needs.end(), what) != m.needs.end();
}

// nanoflann's index: its permutation of indices and about one 40-byte node per 5 points.
constexpr size_t kKnnIndexBytes = sizeof(uint32_t) + 8;

// The parameter that chooses the disc blocks' layout, as DiscBlockParams declares it.
const std::string& disc_blocks_name() {
  static const std::string name = DiscBlockParams::list().specs().at(0).name;
  return name;
}

}  // namespace

size_t prepared_bytes_per_point(const MethodInfo& method, const PointCloud& cloud,
                                const ParamValues& params) {
  if (!needs(method, "point normals")) {
    // The MLS methods: the k-NN index kept for queries, ball radii and the spacing scratch (61
    // B/point measured at 10^7 with the cloud and a sphere tree).
    return kKnnIndexBytes + 4 * sizeof(float);
  }
  // The radii (the cloud's centres and normals are adapted, not copied), and for the methods
  // that read item-order records rather than disc blocks, one 32-byte record per point. The disc
  // blocks, where a layout copies them, are the structure's part (structure_footprint).
  size_t bytes = sizeof(float);
  if (!params.count(disc_blocks_name())) bytes += sizeof(PackedSplat);
  const auto it = params.find("estimate_normals");
  if (!cloud.has_normals() || (it != params.end() && it->second != 0)) {
    // The k-NN graph of the orientation tree, its degrees and the normals themselves.
    const auto k = params.count("normal_k") ? size_t(params.at("normal_k")) : 16;
    bytes += k * sizeof(uint32_t) + 1 + sizeof(Vec3);
  }
  return bytes;
}

StructureFootprint structure_footprint(const std::string& structure,
                                       const ParamValues& structure_params) {
  // Each structure's figures are per item over the cloud (24 B) and the radii (4): the process
  // peak of reference_splat on a 10^7-point sphere with the disc blocks in item order (no copy:
  // the structure's build peak or its final arrays, whichever is higher) and in leaf order (a
  // 28-byte disc per reference), from results/scale/layouts (scripts/scale.sh), plus 10% and
  // rounded up. References per item: the build_item_refs / N of the same structures at 10^6-10^7
  // (structure_memory.sh), the smaller where they differ, so that disc_blocks=0 is priced as leaf
  // order wherever it may choose it.
  for (const StructureInfo& info : StructureRegistry::instance().all())
    if (info.id == structure && info.footprint) return info.footprint(structure_params);
  return {80, 80, 1};  // structures of a method's own
}

size_t structure_bytes_per_item(const std::string& structure, size_t items,
                                const ParamValues& method_params,
                                const ParamValues& structure_params) {
  const StructureFootprint f = structure_footprint(structure, structure_params);
  const auto it = method_params.find(disc_blocks_name());
  if (it == method_params.end()) return f.by_boxes > 0 ? f.by_boxes : f.item_order;
  switch (DiscBlockLayout(int(it->second))) {
    case DiscBlockLayout::kLeafOrder:
      return f.leaf_order;
    case DiscBlockLayout::kItemOrder:
      return f.item_order;
    case DiscBlockLayout::kAuto:
      break;
  }
  // The footprint's references per item are the 10^6 sphere's; a scan's may be fewer (the
  // kd-tree's 3.4 per splat on the aerial tile against 3.7), which can take the copy under the
  // byte cap: priced for 20% fewer, so that near the cap the estimate errs high, never low.
  constexpr double kFewerRefs = 0.8;
  const double n = double(items);
  return SplatLeafBlocks::auto_leaf_order(kFewerRefs * f.references_per_item * n, n) ? f.leaf_order
                                                                                     : f.item_order;
}

size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params,
                            const ParamValues& structure_params) {
  if (method.own_bytes_per_point)
    if (const size_t own = method.own_bytes_per_point(cloud, method_params); own > 0)
      return cloud.size() * own;
  return cloud.size() *
         (prepared_bytes_per_point(method, cloud, method_params) +
          structure_bytes_per_item(structure, cloud.size(), method_params, structure_params) +
          method.own_data_bytes_per_point);
}

}  // namespace pcrt
