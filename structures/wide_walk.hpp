// The walk of a tree of 8-wide nodes whose leaves are pieces of one reference array: the bvh's,
// and the loose octree's (octree loose=1), which differ only in how they build. Children are
// tested at once when their node is visited (kTest: node_test_avx2 or node_test_sse), walked
// nearest first, and a waiting one is dropped once its entry lies beyond the hit so far (boxes
// overlap, so the walk cannot stop at the first hit).
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "structures/structure.hpp"
#include "structures/wide_node.hpp"

namespace pcrt {

// The deepest tree the walk's stack holds: at most seven siblings wait per level.
constexpr int kWideWalkMaxDepth = 64;

// kAny: an occlusion query, ended by the first leaf that reports a hit. `refs`: the items of
// leaf child (first, count) are refs[first, first + count).
template <bool kAny, auto kTest>
__attribute__((always_inline)) inline bool walk_wide(const std::vector<WideNode>& wide,
                                                     const uint32_t* refs, const Ray& ray,
                                                     const LeafIntersector& leaf, Hit& hit,
                                                     OpCounters& counters) {
  if (wide.empty()) return false;
  const RaySlabs slabs(ray);
  std::array<WideTodo, (kWideWidth - 1) * kWideWalkMaxDepth + kWideWidth> stack;
  int top = 0;
  WideTodo cur{0, 0, ray.tmin, ray.tmax};  // the next node, kept out of the stack
  bool found = false;
  while (true) {
    if (may_improve(cur.t0, hit.t)) {
      counters.add(kNodesVisited);
      if (cur.count > 0) {
        counters.add(kLeavesVisited);
        counters.add(kItemsVisited, cur.count);
        const LeafVisit visit{{refs + cur.index, cur.count}, cur.t0, cur.t1};
        if constexpr (kAny) {
          if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
        } else {
          found |= leaf.intersect_leaf(ray, visit, hit, counters);
        }
      } else {
        const WideNode& n = wide[cur.index];
        const float limit = std::min(ray.tmax * kWiden, hit.t * (1.0f + 1e-5f) + 1e-30f);
        alignas(32) float t0s[kWideWidth], t1s[kWideWidth];
        const uint32_t mask = kTest(n, slabs, limit, t0s, t1s);
        if (next_children<kAny>(n, mask, t0s, t1s, stack.data(), top, cur)) continue;
      }
    }
    if (top == 0) break;
    cur = stack[size_t(--top)];
  }
  return found;
}

}  // namespace pcrt
