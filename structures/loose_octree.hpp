// The octree's two placements of an item (the parameter `loose`): in every cell its footprint
// reaches (octree.cpp, the papers' rule) or in the one cell holding its centre (loose_octree.cpp).
#pragma once

#include <cstddef>
#include <memory>

#include "core/aabb.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// The root cell of both: a cube around the bounds, a little larger and not centred on them, so
// that the mid-planes of the first levels do not fall exactly on the symmetry planes of symmetric
// data (a line or plane through the centre would straddle them at every level). Empty bounds give
// a zero-size cube at the origin.
struct OctreeCube {
  Vec3 lo = Vec3::Zero();
  float side = 0;
};
inline OctreeCube octree_root_cube(const Aabb& b) {
  if (b.empty()) return {};
  const float side = 1.0137f * b.extent().maxCoeff();
  return {Vec3(b.lo - Vec3::Constant(0.0049f * side)), side};
}

// A loose octree: cells split at their centres while they hold over leaf_size item centres (to
// max_depth), each item referenced once, in the leaf whose cell holds its centre; each child's box
// is its items' whole footprints, so sibling boxes overlap. Walked as the bvh's wide nodes
// (wide_walk.hpp), a cell's stored children being one node's children.
std::unique_ptr<Structure> make_loose_octree(size_t leaf_size, int max_depth);

}  // namespace pcrt
