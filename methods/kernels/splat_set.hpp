// The oriented splats (normal and radius per point) that splat-based methods need: taken from the
// cloud where it has them, estimated (PCA normals, k-th neighbour radii) where it does not or
// where the parameters ask to.
#pragma once

#include <span>
#include <vector>

#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "methods/method.hpp"

namespace pcrt {

inline const Counter kSplatsGenerated{"splats_generated",
                                      "splats made by a method's own splat generation"};

// Items are in Morton (Z-curve) order of their centres, so the items of one leaf lie close
// together in memory. Item k is source splat point_of(k) and reports prim_of(k) (a cloud index)
// as its hit primitive; ties in t are broken on it, so results are those of the cloud's own order.
//
// One copy of each per-point array, nanoflann's rule: a cloud loaded in Morton order (every cloud
// is, at load) is its own item order, so centres and normals are the cloud's arrays, adapted, not
// copied, and point and prim are the identity (stored empty). Only what the cloud lacks (estimated
// normals, radii) or a reordered or generated set is held here. The structures derive each disc's
// box from its normal and radius (ItemSet::disc_normals), so no box extents are stored; methods
// that keep their own leaf-order copy of the splats (SplatLeafBlocks) release the item arrays
// (release_item_data).
struct SplatSet {
  std::span<const Vec3> centres;    // item order: the cloud's, or own_centres
  std::span<const Vec3> normals;    // item order: the cloud's, or own_normals
  std::span<const float> radii;     // item order: the cloud's, or own_radii
  std::vector<uint32_t> point;      // item k's index in the arrays it was made from; empty: k
  std::vector<uint32_t> prim;       // item k's hit primitive; empty: k
  std::vector<PackedSplat> packed;  // item-order records, only for methods that ask (pack())
  std::vector<Vec3> own_centres, own_normals;
  std::vector<float> own_radii;

  SplatSet() = default;
  // Moves keep the own arrays' buffers, so the spans stay valid; a copy would not.
  SplatSet(SplatSet&&) = default;
  SplatSet& operator=(SplatSet&&) = default;
  SplatSet(const SplatSet&) = delete;
  SplatSet& operator=(const SplatSet&) = delete;

  [[nodiscard]] size_t size() const { return centres.size(); }
  [[nodiscard]] ItemSet items() const { return {centres, radii, {}, normals}; }
  // The same for methods whose leaf candidates are points of the discs (ItemSet::hits_on_discs),
  // tested in blocks of kDiscGroup (SplatLeafBlocks).
  [[nodiscard]] ItemSet disc_items() const {
    ItemSet s{centres, radii, {}, normals, true};
    s.leaf_block = kDiscGroup;
    return s;
  }
  [[nodiscard]] uint32_t point_of(uint32_t k) const { return point.empty() ? k : point[k]; }
  [[nodiscard]] uint32_t prim_of(uint32_t k) const { return prim.empty() ? k : prim[k]; }
  [[nodiscard]] PackedSplat splat(uint32_t k) const {
    return {centres[k], radii[k], normals[k], prim_of(k)};
  }
  // Fills `packed` (32 B per item) for methods whose leaf code reads records by item index.
  void pack();
  // Frees everything but prim (and packed, if made): for methods that have copied the splats
  // into leaf-order blocks, which no leaf outside the bound structure may then ask for.
  void release_item_data();
  // Heap bytes held (not counting the cloud's arrays it adapts).
  [[nodiscard]] size_t memory_bytes() const;
};

// Normals from the cloud, or PCA over normal_k neighbours where it has none (or when asked).
struct NormalParams {
  size_t normal_k = 16;
  bool estimate_normals = false;
  static const ParamList<NormalParams>& list();
};

// Normals as above and radii from the radius_k-th neighbour distance: splat preparation.
struct SplatParams {
  NormalParams normals;
  size_t radius_k = 8;
  float radius_scale = 1;
  bool estimate_radii = false;
  static const ParamList<SplatParams>& list();
};

// Normals and radii from the cloud or estimated; `fixed_radius` (> 0) gives every splat that
// radius instead (methods whose paper uses one global radius; only params.normals is read).
// The cloud must outlive the set (its arrays may be the set's).
SplatSet prepare_splats(const PointCloud& cloud, const SplatParams& params, PrepareContext& ctx,
                        float fixed_radius = 0);

// The normals and radii of a SplatSet made by prepare_splats in the cloud's order (for methods
// that derive their own splats from them): the set's own arrays where its item order is the
// cloud's (every cloud loaded in Morton order: no copy), else copies put back in the cloud's order.
struct PointAttributes {
  std::span<const Vec3> normals;
  std::span<const float> radii;
  std::vector<Vec3> own_normals;  // only when the set is reordered
  std::vector<float> own_radii;

  PointAttributes() = default;
  PointAttributes(PointAttributes&&) = default;  // keeps the buffers the spans see
  PointAttributes(const PointAttributes&) = delete;
  PointAttributes& operator=(const PointAttributes&) = delete;
};
PointAttributes splat_attributes_by_point(const SplatSet& s);

// Lays out splats made by a method itself (fewer than the points, or fitted): item k is
// input point[k] and reports prim[point[k]] (a cloud index) as its hit primitive. Copies.
SplatSet make_splat_set(std::span<const Vec3> centres, std::span<const Vec3> normals,
                        std::span<const float> radii, std::span<const uint32_t> prim);

}  // namespace pcrt
