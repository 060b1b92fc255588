// Morton (Z-curve) order of a cloud: points near each other in space near each other in memory.
// Every cloud is put in this order once, at load, so that k-NN, normals, radii and the structure
// builds all walk memory coherently (the same k-NN queries run 5x faster than in a scan's or a
// generator's random order) and so that nothing downstream depends on the input's order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.hpp"
#include "core/point_cloud.hpp"

namespace pcrt {

// The 63-bit key of p: 21 bits per axis over `bounds`, bits interleaved x, y, z from the lowest.
// The splat layout (methods/kernels/splat_set.cpp) orders splats with morton_order too, so a
// sorted cloud's splats keep its order.
uint64_t morton_key(const Vec3& p, const Aabb& bounds);

// The permutation that sorts `positions` by key, ties by x, y, z and then by index: for distinct
// positions it depends on the set of points alone, not on their order.
std::vector<uint32_t> morton_order(std::span<const Vec3> positions);

// Sorts every per-point array of the cloud into morton_order, one array at a time (at most one
// array's worth of extra memory besides the permutation). Returns the permutation: point k of the
// sorted cloud was point order[k].
std::vector<uint32_t> morton_sort(PointCloud& cloud);
// The scratch memory morton_sort needs for n points at its peak.
size_t morton_sort_bytes(size_t n);

}  // namespace pcrt
