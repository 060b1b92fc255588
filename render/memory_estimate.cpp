#include "render/memory_estimate.hpp"

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
    // The MLS methods: the k-NN index kept for queries, ball radii and the spacing scratch (61
    // B/point measured at 10^7 with the cloud and a sphere tree).
    return kKnnIndexBytes + 4 * sizeof(float);
  }
  // The oriented splats at their peak, when the structure is built and the splats are copied into
  // its leaf blocks (or packed records): one 28-32-byte record per point besides the radii they
  // are made from (freed after). Centres and normals are the cloud's until then; the box extents
  // (12 bytes) are freed before the copy is made, and with the k-NN index and the layout's Morton
  // check they are smaller.
  size_t bytes = sizeof(PackedSplat) + sizeof(float);
  const auto it = params.find("estimate_normals");
  if (!cloud.has_normals() || (it != params.end() && it->second != 0)) {
    // The k-NN graph of the orientation tree, its degrees and the normals themselves.
    const auto k = params.count("normal_k") ? size_t(params.at("normal_k")) : 16;
    bytes += k * sizeof(uint32_t) + 1 + sizeof(Vec3);
  }
  return bytes;
}

size_t structure_bytes_per_item(const std::string& structure) {
  // Peak growth over the cloud and the prepared splats (36 bytes a point), per item: the larger
  // of two measurements at 10^7 points, the structure build's own peak above what was resident
  // before it (scripts/structure_memory.sh, results/scale/structmem/builds.jsonl) and the whole
  // process's peak with reference_splat and goradia_2010 on a sphere (scripts/scale.sh,
  // results/scale/splatmem/ and results/scale/merged/), where the leaf blocks made on top of the
  // structure can be the peak.
  if (structure == "brute_force") return sizeof(uint32_t);
  if (structure == "grid") return 12;
  if (structure == "sphere_tree") return 17;
  if (structure == "kd_tree") return 44;
  if (structure == "octree") return 67;
  if (structure == "bvh") return 71;
  return 80;  // structures of a method's own
}

double structure_references_per_item(const std::string& structure) {
  // build_item_refs / N in the same runs (references_per_item), the larger of the two sizes
  // rounded up.
  if (structure == "kd_tree") return 3.7;
  if (structure == "octree") return 9.8;
  if (structure == "grid") return 1.9;
  return 1;  // object partitions (sphere_tree, bvh) and brute_force
}

size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params) {
  if (method.own_bytes_per_point)
    if (const size_t own = method.own_bytes_per_point(cloud, method_params); own > 0)
      return cloud.size() * own;
  return cloud.size() * (prepared_bytes_per_point(method, cloud, method_params) +
                         structure_bytes_per_item(structure));
}

}  // namespace pcrt
