// Table 5.3 preconditions computed from positions: PCA normals with a consistent orientation,
// splat radii from neighbour distances, and the mean spacing h used to scale tolerances.
// Each counts its k-NN queries; callers time them.
#pragma once

#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

inline const Counter kNormalsEstimated{"normals_estimated", "PCA normal fits"};
inline const Counter kOrientationFlips{"normal_orientation_flips",
                                       "normals flipped to agree with the MST"};

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
