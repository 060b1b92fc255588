// The first seam of the thesis's cost split, T_query: a Structure indexes points (each with a
// bounding radius, since splats reach past their centres) and walks a ray front to back, handing
// each leaf it enters to a LeafIntersector (the second seam, T_int, implemented by methods).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/registry.hpp"

namespace pcrt {

// One leaf as a ray sees it: the items (point indices) stored there and the ray's parameter
// interval inside the leaf's bounds.
struct LeafVisit {
  std::span<const uint32_t> items;
  float t_enter = 0;
  float t_exit = kInfinity;
};

class LeafIntersector {
 public:
  virtual ~LeafIntersector() = default;
  // Intersects the ray with the leaf's items. May report any hit in [ray.tmin, hit.t) (also past
  // t_exit: a splat reaches into several leaves); on success it narrows hit and returns true.
  virtual bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit, OpCounters& counters) const = 0;
};

class Structure {
 public:
  virtual ~Structure() = default;
  // positions and radii stay the caller's and must outlive the structure (nanoflann's rule).
  virtual void build(std::span<const Vec3> positions, std::span<const float> radii, OpCounters& counters) = 0;
  // Visits leaves in front-to-back order of t_enter until the next leaf starts beyond hit.t.
  virtual bool closest_hit(const Ray& ray, const LeafIntersector& leaf_intersector, Hit& hit,
                           OpCounters& counters) const = 0;
  [[nodiscard]] virtual size_t memory_bytes() const = 0;
};

struct StructureInfo {
  std::string id;
  std::string description;
  std::string build_claim;  // construction complexity claimed by the thesis (Table 5.4)
  std::string query_claim;  // query complexity claimed by the thesis (section 5.4)
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Structure>(const ParamValues&)> create;
};

using StructureRegistry = Registry<StructureInfo>;

struct RegisterStructure {
  explicit RegisterStructure(StructureInfo info) { StructureRegistry::instance().add(std::move(info)); }
};

// Counters every structure reports into.
inline const Counter kNodesVisited{"nodes_visited", "structure nodes whose bounds were tested"};
inline const Counter kLeavesVisited{"leaves_visited", "leaves handed to the leaf intersector"};
inline const Counter kItemsVisited{"items_visited", "items (points) in the leaves handed over"};

}  // namespace pcrt
