#include "harness/memory_estimate.hpp"

#include <algorithm>

#include "methods/kernels/splat_kernel.hpp"

namespace pcrt {
namespace {

bool needs(const MethodInfo& m, const std::string& what) {
  return std::find(m.needs.begin(), m.needs.end(), what) != m.needs.end();
}

// nanoflann's index: its permutation of indices and about one 40-byte node per 5 points.
constexpr size_t kKnnIndexBytes = sizeof(uint32_t) + 8;

}  // namespace

size_t prepared_bytes_per_point(const MethodInfo& method, const PointCloud& cloud,
                                const ParamValues& params) {
  if (!needs(method, "point normals")) {
    // The MLS methods: the k-NN index kept for queries, a ball radius and the spacing scratch.
    return kKnnIndexBytes + 2 * sizeof(float);
  }
  // The oriented splats: packed records, loose centres, normals, half extents, radii and the
  // point index, with the layout's Morton keys and the radii estimate as scratch.
  size_t bytes = sizeof(PackedSplat) + 3 * sizeof(Vec3) + sizeof(float) + sizeof(uint32_t) +
                 sizeof(uint64_t) + 2 * sizeof(uint32_t) + sizeof(float) + kKnnIndexBytes;
  const auto it = params.find("estimate_normals");
  if (!cloud.has_normals() || (it != params.end() && it->second != 0)) {
    // The k-NN graph of the orientation tree, its degrees and the normals themselves.
    const auto k = params.count("normal_k") ? size_t(params.at("normal_k")) : 16;
    bytes += k * sizeof(uint32_t) + 1 + sizeof(Vec3);
  }
  return bytes;
}

size_t structure_bytes_per_item(const std::string& structure) {
  // Final sizes measured at 10^6-10^7 points (structure_bytes in results/scale), with the build's
  // index arrays and spliced subtrees on top.
  if (structure == "brute_force") return sizeof(uint32_t);
  if (structure == "sphere_tree") return 24;
  if (structure == "octree") return 72;
  return 40;  // kd_tree, grid, bvh and structures of a method's own
}

size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params) {
  return cloud.size() * (prepared_bytes_per_point(method, cloud, method_params) +
                         structure_bytes_per_item(structure));
}

}  // namespace pcrt
