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

namespace pcrt {

// Up to 16 shadow rays walked together (a packet): the tree is walked once for all of them, each
// node's boxes tested against every ray still active there, a child entered by the rays whose
// test hit it. Children are taken in the order walk_wide<true> takes them (higher slot first), so
// each ray visits the nodes and leaves its own walk would, in the same order, and stops at the
// same blocking leaf: the same answers and the same counts, ray by ray.
constexpr int kWidePacket = 16;

// A child a packet has yet to enter: the rays that enter it, and where their entry and exit t are
// (level -1: the ray's own span).
struct WidePacketTodo {
  uint32_t index, count;
  uint32_t active;
  int level, slot;
};

// Tests node n (at `level`) for each active ray, then pushes the children some ray enters in
// ascending slot order and returns the highest in `next` (next_children<true>'s order); false
// when no ray enters any.
template <auto kTest>
__attribute__((always_inline)) inline bool enter_children(
    const WideNode& n, int level, uint32_t active, const RaySlabs* slabs, const float* limit,
    float (*t0s)[kWideWidth], float (*t1s)[kWideWidth], WidePacketTodo* stack, int& top,
    WidePacketTodo& next) {
  uint32_t enters[kWideWidth] = {};
  for (; active; active &= active - 1) {
    const int i = __builtin_ctz(active);
    uint32_t mask = kTest(n, slabs[i], limit[i], t0s[i], t1s[i]);
    for (; mask; mask &= mask - 1) enters[__builtin_ctz(mask)] |= 1u << i;
  }
  int last = -1;
  for (int k = 0; k < kWideWidth; ++k) {
    if (enters[k] == 0 || (n.child[k] == 0 && n.count[k] == 0)) continue;
    if (last >= 0) stack[top++] = {n.child[last], n.count[last], enters[last], level, last};
    last = k;
  }
  if (last < 0) return false;
  next = {n.child[last], n.count[last], enters[last], level, last};
  return true;
}

template <auto kTest>
__attribute__((always_inline)) inline void walk_wide_occluded(const std::vector<WideNode>& wide,
                                                              const uint32_t* refs, const Ray* rays,
                                                              int n, const LeafIntersector& leaf,
                                                              char* blocked, OpCounters& counters) {
  for (int i = 0; i < n; ++i) blocked[i] = 0;
  if (wide.empty() || n <= 0 || n > kWidePacket) return;
  // Each ray's entry and exit t of the children of the node entered at each level, read when a
  // leaf child is visited (a stack entry holds its level and slot). 64 KB: per thread, not on
  // the stack.
  alignas(32) static thread_local float t0s[kWideWalkMaxDepth][kWidePacket][kWideWidth],
      t1s[kWideWalkMaxDepth][kWidePacket][kWideWidth];
  std::array<RaySlabs, kWidePacket> slabs;
  float limit[kWidePacket];
  uint32_t all = 0;  // the rays whose walk enters the root (walk_wide's first may_improve)
  for (int i = 0; i < n; ++i) {
    if (may_improve(rays[i].tmin, rays[i].tmax)) all |= 1u << i;
    slabs[size_t(i)] = RaySlabs(rays[i]);
    // walk_wide<true>'s limit, its hit.t being tmax
    limit[i] = std::min(rays[i].tmax * kWiden, rays[i].tmax * (1.0f + 1e-5f) + 1e-30f);
  }
  std::array<WidePacketTodo, (kWideWidth - 1) * kWideWalkMaxDepth + kWideWidth> stack;
  int top = 0;
  uint32_t done = 0;
  WidePacketTodo cur{0, 0, all, -1, 0};
  while (true) {
    uint32_t active = cur.active & ~done;
    if (active != 0) {
      counters.add(kNodesVisited, uint64_t(__builtin_popcount(active)));
      if (cur.count > 0) {
        counters.add(kLeavesVisited, uint64_t(__builtin_popcount(active)));
        counters.add(kItemsVisited, uint64_t(cur.count) * uint64_t(__builtin_popcount(active)));
        for (; active; active &= active - 1) {
          const int i = __builtin_ctz(active);
          const LeafVisit visit{{refs + cur.index, cur.count},
                                t0s[cur.level][i][cur.slot],
                                t1s[cur.level][i][cur.slot]};
          if (leaf.occluded_leaf(rays[i], visit, rays[i].tmax, counters)) {
            done |= 1u << i;
            blocked[i] = 1;
          }
        }
        if (done == all) return;
      } else if (enter_children<kTest>(wide[cur.index], cur.level + 1, active, slabs.data(), limit,
                                       t0s[cur.level + 1], t1s[cur.level + 1], stack.data(), top,
                                       cur)) {
        continue;
      }
    }
    if (top == 0) return;
    cur = stack[size_t(--top)];
  }
}

}  // namespace pcrt
