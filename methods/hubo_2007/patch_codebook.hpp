// Self-similarity compression of point patches after Hubo, Mertens, Haber and Bekaert 2007
// ("Self-similarity-based compression of point clouds, with application to ray tracing", thesis
// [29]), as built here: each patch is put in a canonical frame (its centre, mean normal, the
// in-plane axis of largest spread, its radius as scale), described by a 4x4 height field over its
// tangent square, and the descriptors are clustered (k-means); each cluster's representative is
// its member nearest the cluster mean, kept as local points. A patch is then stored as an instance:
// its frame, its cluster, and a residual (4x4 heights, 8 bits each) that moves the representative's
// points onto its own height field, and its footprint (the representative's points in cells the
// patch has none of are left out). Decoding one patch needs only its instance and its
// representative (random access). See README.md for the layout and bytes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/counters.hpp"
#include "methods/kernels/splat_kernel.hpp"

namespace pcrt {

inline const Counter kCodebookPointsDecoded{
    "codebook_points_decoded", "patch points decoded from a representative (instance transforms)"};
inline const Counter kCodebookKmeansTerms{
    "codebook_kmeans_terms", "patch-to-cluster descriptor distances computed by k-means"};
inline const Counter kCodebookBytes{
    "codebook_bytes",
    "bytes the compressed patches hold: instances, representatives, patch spheres (a size)"};

// A patch to encode: its points' range in the points array, its centre and mean normal.
struct PatchInput {
  uint32_t begin, end;
  Vec3 centre, normal;
};

class PatchCodebook {
 public:
  // Encodes the patches (points: centre, normal, index) with at most `clusters` representatives.
  void build(std::span<const PackedSplat> points, std::span<const PatchInput> patches,
             size_t clusters, int iterations, OpCounters& counters);
  // Appends patch k's decoded points (index: the cloud point nearest the patch's centre).
  void decode(uint32_t k, const Vec3& centre, std::vector<PackedSplat>& out,
              OpCounters& counters) const;
  [[nodiscard]] size_t memory_bytes() const;
  [[nodiscard]] size_t representatives() const { return rep_begin_.size() - 1; }
  [[nodiscard]] uint32_t prim(uint32_t k) const { return instances_[k].prim; }

  static constexpr int kGrid = 4;  // the height field's cells per side
  struct LocalPoint {
    float x, y, z, nx, ny, nz;  // in the patch frame, lengths in the patch's scale
  };
  struct Instance {
    float scale;                  // the patch's radius
    uint16_t normal_u, normal_v;  // octahedral, 16 bits each
    uint16_t angle;               // the in-plane axis around the normal, 16 bits of a turn
    uint16_t cluster;
    uint16_t footprint;              // the cells the patch has points in (decoded: only those)
    int8_t residual[kGrid * kGrid];  // height corrections in 1/127 of the scale
    uint32_t prim;                   // the cloud point nearest the centre (the hit's colour)
  };

 private:
  void set_residual(size_t k, uint32_t rep, const PatchInput& p, std::span<const LocalPoint> local);

  std::vector<Instance> instances_;
  std::vector<uint32_t> rep_begin_;  // per representative (and one past) in rep_points_
  std::vector<LocalPoint> rep_points_;
};

}  // namespace pcrt
