// Recursive octree partition of point indices (Kashyap et al.'s splat octree, Hubo et al. 2007's
// patches): a cell is split into its 8 children until `is_leaf(begin, end, depth)` accepts its
// points, which are then handed to `on_leaf(begin, end)`. The index range is permuted in place so
// that every leaf's points are contiguous. Empty cells are dropped.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>

#include "core/aabb.hpp"
#include "core/counters.hpp"
#include "core/geometry.hpp"

namespace pcrt {

inline const Counter kPartitionCells{"octree_partition_cells",
                                     "cells examined by octree partitions of points"};

namespace detail {
template <typename IsLeaf, typename OnLeaf>
void partition_cell(std::span<const Vec3> p, uint32_t* begin, uint32_t* end, const Vec3& lo,
                    float side, int depth, IsLeaf& is_leaf, OnLeaf& on_leaf, OpCounters& counters) {
  if (begin == end) return;
  counters.add(kPartitionCells);
  if (is_leaf(begin, end, depth)) {
    on_leaf(begin, end);
    return;
  }
  const Vec3 mid = lo + Vec3::Constant(side / 2);
  uint32_t* cut[9];
  cut[0] = begin;
  cut[8] = end;
  cut[4] = std::partition(begin, end, [&](uint32_t i) { return p[i].z() < mid.z(); });
  for (int z = 0; z < 2; ++z) {
    cut[4 * z + 2] =
        std::partition(cut[4 * z], cut[4 * z + 4], [&](uint32_t i) { return p[i].y() < mid.y(); });
    for (int y = 0; y < 2; ++y) {
      const int a = 4 * z + 2 * y;
      cut[a + 1] =
          std::partition(cut[a], cut[a + 2], [&](uint32_t i) { return p[i].x() < mid.x(); });
    }
  }
  for (int c = 0; c < 8; ++c) {
    const Vec3 child = lo + Vec3(float(c & 1), float((c >> 1) & 1), float(c >> 2)) * (side / 2);
    partition_cell(p, cut[c], cut[c + 1], child, side / 2, depth + 1, is_leaf, on_leaf, counters);
  }
}
}  // namespace detail

// `indices` (usually 0..n-1) is permuted; the root is the bounding cube of the points.
template <typename IsLeaf, typename OnLeaf>
void octree_partition(std::span<const Vec3> positions, std::span<uint32_t> indices,
                      IsLeaf&& is_leaf, OnLeaf&& on_leaf, OpCounters& counters) {
  if (indices.empty()) return;
  Aabb b;
  for (uint32_t i : indices) b.extend(positions[i]);
  const float side = std::max(b.extent().maxCoeff(), 1e-30f) * 1.0001f;
  detail::partition_cell(positions, indices.data(), indices.data() + indices.size(), b.lo, side, 0,
                         is_leaf, on_leaf, counters);
}

}  // namespace pcrt
