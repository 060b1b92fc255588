// The caustic sample map (CSM) of Goradia et al. 2011, built as Jensen's caustic photon map: a
// prepass emits photons from the scene's point and sphere lights (environments and the sky emit
// none), follows each through delta (mirror, smooth glass) vertices by the material's sampled
// lobe, and stores it where it first lands on a non-delta surface after at least one specular
// vertex. The entries live in an octree over their positions (the paper's "CSM octree"); a
// lookup is the density estimate of the k nearest entries with the Epanechnikov filter.
//
// Photons are seeded by their index and kept in index order, so the map, its counters and every
// estimate are the same for any thread count. A lookup allocates nothing and calls nothing
// virtual.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/counters.hpp"
#include "methods/method.hpp"
#include "render/render_scene.hpp"
#include "render/sampling.hpp"

namespace pcrt {

inline const Counter kCsmPhotons{"csm_photons_traced",
                                 "photons the caustic sample map prepass emitted and traced"};
inline const Counter kCsmPhotonRays{
    "csm_photon_rays", "rays the caustic sample map prepass traced (also in rays_cast)"};
inline const Counter kCsmEntries{"csm_entries", "photons stored in the caustic sample map"};
inline const Counter kCsmOctreeNodes{"csm_octree_nodes", "nodes of the caustic sample map octree"};
inline const Counter kCsmLookups{"csm_lookups", "density estimates from the caustic sample map"};
inline const Counter kCsmNodesVisited{"csm_nodes_visited",
                                      "caustic sample map octree nodes visited by lookups"};
inline const Counter kCsmEntriesVisited{
    "csm_entries_visited", "caustic sample map entries whose distance a lookup computed"};

// One stored photon: where it landed, the direction it came from (unit, away from the surface,
// world space) and the flux it carries.
struct CausticPhoton {
  Vec3 p = Vec3::Zero();
  Vec3 wi = Vec3::UnitZ();
  Vec3 power = Vec3::Zero();
};

// What the prepass did with its photons (sums over photons, made in index order).
struct CausticMapStats {
  uint64_t photons = 0;        // emitted
  uint64_t stored = 0;         // landed on a non-delta surface after a specular vertex
  uint64_t diffuse_first = 0;  // landed on a non-delta surface first: direct light, not stored
  uint64_t escaped = 0;        // left the scene or ended on a sphere light
  uint64_t cut = 0;            // still specular after the chain bound
  Vec3d emitted_power = Vec3d::Zero();  // summed in double, photon by photon
  Vec3d stored_power = Vec3d::Zero();
  Vec3d cut_power = Vec3d::Zero();  // what the cut photons carried when cut
  double seconds = 0;
};

struct CausticMapSettings {
  CausticMapSpec spec;
  int max_specular = 1;  // the chain bound: specular vertices a photon may pass (the frame's B)
  uint64_t seed = 1;
  int threads = 0;    // 0: all cores
  float epsilon = 0;  // the lift of a secondary ray's origin; 0: 1e-3 * scene diagonal
};

class CausticMap {
 public:
  static constexpr int kMaxK = 1024;

  // Traces the photons through `scene` and builds the octree; the rays' work counts into
  // `counters` like any other ray's, with the kCsm* counters of the prepass.
  CausticMap(const RenderScene& scene, const CausticMapSettings& settings, OpCounters& counters);

  // The caustic radiance leaving p towards wo (local to `frame`, the shading frame of material
  // m): sum f(wo, wi_p) power_p K(d_p / r) / r^2 over the k nearest entries, K the Epanechnikov
  // kernel 2/pi (1 - u^2), r the k-th distance or the radius bound if that is smaller.
  [[nodiscard]] Vec3 radiance(const Vec3& p, const Frame3& frame, const Material& m, const Vec3& wo,
                              OpCounters& counters) const;
  // The k (at most kMaxK) entries nearest to q closer than sqrt(max_d2): indices into photons()
  // and squared distances, in no particular order. Returns how many.
  size_t nearest(const Vec3& q, int k, float max_d2, uint32_t* index, float* d2,
                 OpCounters& counters) const;

  [[nodiscard]] std::span<const CausticPhoton> photons() const { return photons_; }
  [[nodiscard]] const CausticMapStats& stats() const { return stats_; }
  [[nodiscard]] size_t node_count() const { return nodes_.size(); }
  [[nodiscard]] float radius_bound() const { return max_radius_; }

 private:
  struct Node {
    Vec3 lo, hi;                    // the tight bounds of its entries
    uint32_t first = 0, count = 0;  // leaves: entries; inner nodes: children in nodes_
    bool leaf = true;
  };
  struct Heap;
  void build(uint32_t id, uint32_t begin, uint32_t end, int depth);
  void visit(uint32_t id, const Vec3& q, Heap& heap) const;

  std::vector<CausticPhoton> photons_;  // in octree leaf order
  std::vector<Node> nodes_;
  int k_ = 1;
  float max_radius_ = 0;
  CausticMapStats stats_;
};

// The first caustic sample map an object of the scene declares (its method's), or null.
const CausticMapSpec* scene_caustic_map(const RenderScene& scene);
// Whether a caustic map of the scene can hold an entry: some object is delta (mirror or smooth
// glass), some other is not (where photons land) and some light emits photons. A frame skips
// the prepass when not.
bool caustic_map_possible(const RenderScene& scene);

}  // namespace pcrt
