// The first seam of the thesis's cost split, T_query: a Structure indexes points (each with a
// bounding radius, since splats reach past their centres) and walks a ray front to back, handing
// each leaf it enters to a LeafIntersector (the second seam, T_int, implemented by methods).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/registry.hpp"

namespace pcrt {

// What a structure indexes: a position per item, a bounding radius (the footprint fits in the
// sphere of that radius), and optionally tighter axis half-extents: stored, or derived from a disc
// normal (a disc of radius r and normal n fits in the box of half-extents r * sqrt(1 - n_a^2):
// much thinner than the cube of side 2r along the normal, so far fewer cells reference it; derived
// per call rather than stored, 12 bytes an item less at the build's peak). The spans stay the
// method's.
struct ItemSet {
  std::span<const Vec3> positions;
  std::span<const float> radii;             // empty: points
  std::span<const Vec3> half_extents;       // empty: from disc_normals, else the cube of the radius
  std::span<const Vec3> disc_normals = {};  // non-empty: item i is a disc of its radius facing this
  // The method's leaf candidates are points of the discs (crossings within the radius), so a
  // structure may leave a disc out of a cell its plane does not cut (the octree does). Methods
  // whose hits may lie off the discs (implicit surfaces, projections) leave it false.
  bool hits_on_discs = false;
  // How far before a leaf's interval the crossings a leaf's hit is made of may lie (the splat
  // blends: a blend of the crossings within a window may land that far before the leaf, and is
  // recorded there). A structure that skips a leaf whose discs the ray does not cross (the octree's
  // leaf_slabs) looks this far back, so that skipping never changes a hit.
  float hits_before_leaf = 0;
  // How many items the method's leaf test takes in one pass (the disc methods' blocks of eight,
  // DiscBlock): a structure whose leaf size is engineering, not a paper's rule (the bvh), sizes
  // its leaves by it.
  uint32_t leaf_block = 1;

  // One axis of a disc's box: r * sqrt(1 - n_a^2), padded by 1e-4 r so rounding of a hit point on
  // the disc never leaves the box. The one formula for both forms below.
  static float disc_half_extent(float n_a, float r) {
    return r * (std::sqrt(std::max(1.0f - n_a * n_a, 0.0f)) + 1e-4f);
  }
  [[nodiscard]] size_t size() const { return positions.size(); }
  [[nodiscard]] float radius(uint32_t i) const { return radii.empty() ? 0.0f : radii[i]; }
  // Axis ax of half_extent(i) (one square root instead of three: the kd-tree build tests one axis
  // of every reference at every level).
  [[nodiscard]] float half_extent(uint32_t i, int ax) const {
    if (!half_extents.empty()) return half_extents[i][ax];
    if (disc_normals.empty()) return radius(i);
    return disc_half_extent(disc_normals[i][ax], radius(i));
  }
  [[nodiscard]] Vec3 half_extent(uint32_t i) const {
    if (!half_extents.empty()) return half_extents[i];
    return {half_extent(i, 0), half_extent(i, 1), half_extent(i, 2)};
  }
  [[nodiscard]] float box_lo(uint32_t i, int ax) const {
    return positions[i][ax] - half_extent(i, ax);
  }
  [[nodiscard]] float box_hi(uint32_t i, int ax) const {
    return positions[i][ax] + half_extent(i, ax);
  }
  [[nodiscard]] Aabb box(uint32_t i) const {
    const Vec3 e = half_extent(i);
    return Aabb{positions[i] - e, positions[i] + e};
  }
  [[nodiscard]] Aabb bounds() const {
    Aabb b;
    for (uint32_t i = 0; i < size(); ++i) b.extend(box(i));
    return b;
  }
};

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
  virtual bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                              OpCounters& counters) const = 0;
  // Whether any item of the leaf blocks the ray within [ray.tmin, t_max) (shadow rays): the leaf
  // may stop at its first hit. Reports true exactly when intersect_leaf, given a hit at t_max,
  // would. This default is that closest-hit query.
  virtual bool occluded_leaf(const Ray& ray, const LeafVisit& leaf, float t_max,
                             OpCounters& counters) const {
    Hit h;
    h.t = t_max;
    return intersect_leaf(ray, leaf, h, counters);
  }
};

class Structure {
 public:
  virtual ~Structure() = default;
  // The item spans stay the caller's and must outlive the structure (nanoflann's rule).
  virtual void build(const ItemSet& items, OpCounters& counters) = 0;
  // Visits leaves in front-to-back order of t_enter until the next leaf starts beyond hit.t.
  virtual bool closest_hit(const Ray& ray, const LeafIntersector& leaf_intersector, Hit& hit,
                           OpCounters& counters) const = 0;
  // Whether anything blocks the ray within [ray.tmin, ray.tmax): the walk stops at the first leaf
  // that reports a hit (LeafIntersector::occluded_leaf). This default asks for a closest hit;
  // structures override it with an early exit.
  virtual bool any_hit(const Ray& ray, const LeafIntersector& leaf_intersector,
                       OpCounters& counters) const {
    Hit h;
    h.t = ray.tmax;
    return closest_hit(ray, leaf_intersector, h, counters);
  }
  // Occlusion of n <= 16 rays a caller traces together (a tile's shadow rays): blocked[i] as
  // any_hit(rays[i]) answers, with the same counts. This default asks ray by ray.
  virtual void any_hits(const Ray* rays, int n, const LeafIntersector& leaf_intersector,
                        char* blocked, OpCounters& counters) const {
    for (int i = 0; i < n; ++i) blocked[i] = char(any_hit(rays[i], leaf_intersector, counters));
  }
  [[nodiscard]] virtual size_t memory_bytes() const = 0;
  // The array every LeafVisit::items of this structure is a piece of (item references in leaf
  // order), so that a method may lay its data out in the same order (leaf blocks); empty where
  // the structure decodes its leaves for the method (the octree's compact references).
  [[nodiscard]] virtual std::span<const uint32_t> leaf_references() const = 0;
  // The parameters whose value the last build chose for its items (an automatic default: the
  // bvh's leaf_size=0), so that a run records what ran; empty where none was left to choose.
  [[nodiscard]] virtual ParamValues resolved_params() const { return {}; }
};

// What a structure adds per item at the process's peak (its build or its final arrays with the
// method's leaf data), as the memory estimate prices it before any work (render/memory_estimate):
// with the methods' disc blocks adapted in item order (also the figure for methods without disc
// blocks) or copied in leaf order, and the leaf references it stores per item. Each structure
// declares its own, measured by the scale benchmark (results/scale/).
struct StructureFootprint {
  size_t item_order = 0;
  size_t leaf_order = 0;
  double references_per_item = 1;
  // For methods without disc blocks, whose items a structure keeps by their boxes alone (no disc
  // plane test, ItemSet::hits_on_discs); 0: as item_order.
  size_t by_boxes = 0;
};

struct StructureInfo {
  std::string id;
  std::string description;
  std::string build_claim;  // construction complexity claimed by the thesis (Table 5.4)
  std::string query_claim;  // query complexity claimed by the thesis (section 5.4)
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<Structure>(const ParamValues&)> create;
  // The structure's own parameters count where they change its bytes (the octree's compact_refs).
  std::function<StructureFootprint(const ParamValues&)> footprint;
};

// A footprint that does not depend on the structure's parameters.
inline std::function<StructureFootprint(const ParamValues&)> fixed_footprint(StructureFootprint f) {
  return [f](const ParamValues&) { return f; };
}

// StructureInfo::create for a structure constructed from its typed parameters (declared by `list`).
template <class S, class P>
std::function<std::unique_ptr<Structure>(const ParamValues&)> structure_from(
    const ParamList<P>& list, const char* id) {
  return [&list, id](const ParamValues& given) -> std::unique_ptr<Structure> {
    return std::make_unique<S>(list.read(given, id));
  };
}

using StructureRegistry = Registry<StructureInfo>;

// The structures pcrt ships (structures/builtin_structures.cpp, the one list).
void register_builtins(StructureRegistry& registry);

// Counters every structure reports into.
inline const Counter kNodesVisited{"nodes_visited",
                                   "structure nodes (grid: cells) entered by a traversal"};
inline const Counter kLeavesVisited{"leaves_visited", "leaves handed to the leaf intersector"};
inline const Counter kItemsVisited{"items_visited", "items (points) in the leaves handed over"};
inline const Counter kBuildNodes{"build_nodes", "nodes (grid: cells) created by structure builds"};
inline const Counter kBuildItemRefs{"build_item_refs",
                                    "item references stored in leaves (duplicates included)"};
inline const Counter kBuildItemVisits{
    "build_item_visits",
    "item references handled by a build: each leaf reference once per level above it (the work "
    "of a top-down build; the grid: items + references)"};

// Whether a leaf entered at t_enter may still hold a hit nearer than hit_t. The slack absorbs
// rounding between a hit point and the cell planes, so that a hit exactly on a cell boundary is
// never skipped: structures must return exactly brute force's closest hit.
inline bool may_improve(float t_enter, float hit_t) {
  return t_enter <= hit_t * (1.0f + 1e-5f) + 1e-30f;
}

// Leaf-ordering tie-break shared by all leaf intersectors: the nearer t wins, and on equal t the
// lower point index, so the result does not depend on the order in which leaves are visited.
inline bool closer(float t, uint32_t prim, const Hit& hit) {
  return t < hit.t || (t == hit.t && prim < hit.prim);
}

// Records a hit found by a leaf intersector.
inline void record_hit(const Ray& ray, float t, uint32_t prim, const Vec3& normal, float footprint,
                       Hit& hit) {
  hit.t = t;
  hit.prim = prim;
  hit.p = ray.at(t);
  hit.n = normal;
  hit.footprint = footprint;
}

}  // namespace pcrt
