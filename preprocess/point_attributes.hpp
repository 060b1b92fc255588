// Table 5.3 preconditions computed from positions: PCA normals with a consistent orientation,
// splat radii from neighbour distances, and the mean spacing h used to scale tolerances.
// Each counts its k-NN queries; callers time them.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

inline const Counter kNormalsEstimated{"normals_estimated", "PCA normal fits"};
inline const Counter kOrientationFlips{"normal_orientation_flips",
                                       "normals flipped to agree with the MST"};

// A k-NN query per query point in parallel: body(s, nbrs, d2) for the point query_point(s), s in
// [0, count). The counter totals are added once, afterwards: they are exactly `count` queries
// whatever the split, so thread count cannot change them.
template <typename QueryPoint, typename Body>
void for_each_knn(size_t count, QueryPoint query_point, const KnnIndex& knn, size_t k,
                  OpCounters& counters, Body body) {
  k = std::min(k, knn.size());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
        std::vector<uint32_t> idx(k);
        std::vector<float> d2(k);
        OpCounters local;
        for (size_t s = r.begin(); s != r.end(); ++s) {
          const size_t found = knn.knn(query_point(s), k, idx.data(), d2.data(), local);
          body(s, std::span<const uint32_t>(idx.data(), found),
               std::span<const float>(d2.data(), found));
        }
      });
  counters.add(kKnnQueries, count);
  counters.add(kKnnResults, count * k);
}

// The same for every point of the indexed cloud, each its own query.
template <typename Body>
void for_each_point_knn(std::span<const Vec3> positions, const KnnIndex& knn, size_t k,
                        OpCounters& counters, Body body) {
  for_each_knn(
      positions.size(), [&](size_t i) -> const Vec3& { return positions[i]; }, knn,
      std::min(k, positions.size()), counters, body);
}

// Unit normal of the least-squares plane through the given points (smallest eigenvector of their
// covariance); +z when it is undefined. Unoriented.
Vec3 pca_normal(std::span<const Vec3> positions, std::span<const uint32_t> nbrs);

// Normal of each point: the eigenvector of the smallest eigenvalue of the covariance of its k
// nearest neighbours (itself included). Orientation: Hoppe et al. 1992, a minimum spanning tree
// over the k-NN graph weighted 1 - |n_i . n_j|, grown from the highest point (its normal made to
// point up, +z) and flipping each new normal to agree with its parent. Each connected component
// is started the same way, from its highest point.
std::vector<Vec3> estimate_normals(std::span<const Vec3> positions, const KnnIndex& knn, size_t k,
                                   OpCounters& counters);

// Splat radius of each point: scale * distance to its k-th nearest other point, so that discs
// overlap their neighbours (holes appear below about the 4th neighbour on random samplings).
std::vector<float> estimate_radii(std::span<const Vec3> positions, const KnnIndex& knn, size_t k,
                                  float scale, OpCounters& counters);

// Mean over points of the distance to the nearest other point (h in the accuracy bounds).
double mean_spacing(std::span<const Vec3> positions, const KnnIndex& knn, OpCounters& counters);
// The same with an index built for the purpose (counted like any other k-NN work).
double mean_spacing(std::span<const Vec3> positions, OpCounters& counters);

}  // namespace pcrt
