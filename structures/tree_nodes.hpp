// The node layouts of the kd-tree and the octree, here so that tests can check their 64-bit leaf
// offsets with values no test could build (core/offsets.hpp says when each is used).
#pragma once

#include <cstdint>

namespace pcrt {

// 16 bytes. Inner: the split plane, axis 0..2 and the index of the right child (the left one
// follows its parent). Leaf: axis 3 (4: a leaf whose walk tests its slab, kd_tree.cpp
// leaf_slabs), the count of its references and the first one as 64 bits, the low half in `a` and
// the high half where an inner node keeps its plane, so 64-bit offsets cost no byte.
struct KdNode {
  static constexpr uint32_t kLeaf = 3;
  static constexpr uint32_t kLeafSlab = 4;
  union {
    float split = 0;
    uint32_t first_hi;
  };
  uint32_t axis = kLeaf;
  uint32_t a = 0;
  uint32_t b = 0;

  static KdNode inner(float split, int axis) {
    KdNode n;
    n.split = split;
    n.axis = uint32_t(axis);
    return n;
  }
  static KdNode leaf(uint64_t first, uint32_t count) {
    KdNode n;
    n.first_hi = uint32_t(first >> 32);
    n.a = uint32_t(first);
    n.b = count;
    return n;
  }
  [[nodiscard]] bool is_leaf() const { return axis >= kLeaf; }
  [[nodiscard]] bool tests_slab() const { return axis == kLeafSlab; }
  [[nodiscard]] uint64_t first() const { return uint64_t(first_hi) << 32 | a; }
  [[nodiscard]] uint32_t count() const { return b; }
  // The node with its indices moved by a subtree's place in its parent's arrays.
  [[nodiscard]] KdNode shifted(uint32_t node_base, uint64_t ref_base) const {
    if (is_leaf()) {
      KdNode n = leaf(first() + ref_base, b);
      n.axis = axis;
      return n;
    }
    KdNode n = *this;
    n.a += node_base;
    return n;
  }
};
static_assert(sizeof(KdNode) == 16);

// Octree nodes. Inner: `count` is kOctInner with the mask of its stored children in the low
// eight bits (oct_inner(mask)); only those children are stored, consecutive from first() in child
// order (an octree over a surface leaves most of a cell's children empty).
// Leaf: its references from first(), and kOctCompact set in `count` when they are 16-bit offsets
// from a base item (octree.cpp) rather than 32-bit items, and kOctSlab when the walk tests its
// slab (octree.cpp, leaf_slabs). OctNode32 (8 bytes) while the references
// fit 32-bit offsets, OctNode64 (12 bytes) beyond.
inline constexpr uint32_t kOctInner = uint32_t{1} << 31;
inline constexpr uint32_t kOctCompact = uint32_t{1} << 30;
inline constexpr uint32_t kOctSlab = uint32_t{1} << 29;
inline constexpr uint32_t oct_inner(uint32_t child_mask) { return kOctInner | child_mask; }

struct OctNode32 {
  uint32_t first_ = 0;
  uint32_t count = 0;

  static constexpr bool kWide = false;
  static OctNode32 make(uint64_t first, uint32_t count) { return {uint32_t(first), count}; }
  [[nodiscard]] uint64_t first() const { return first_; }
  [[nodiscard]] bool leaf() const { return (count & kOctInner) == 0; }
  [[nodiscard]] uint32_t child_mask() const { return leaf() ? 0 : count & 0xFFu; }
  [[nodiscard]] bool compact() const { return (count & (kOctInner | kOctCompact)) == kOctCompact; }
  [[nodiscard]] bool has_slab() const { return (count & (kOctInner | kOctSlab)) == kOctSlab; }
  [[nodiscard]] uint32_t leaf_count() const { return count & (kOctSlab - 1); }
};
static_assert(sizeof(OctNode32) == 8);

struct OctNode64 {
  uint32_t first_lo = 0;
  uint32_t count = 0;
  uint32_t first_hi = 0;

  static constexpr bool kWide = true;
  static OctNode64 make(uint64_t first, uint32_t count) {
    return {uint32_t(first), count, uint32_t(first >> 32)};
  }
  [[nodiscard]] uint64_t first() const { return uint64_t(first_hi) << 32 | first_lo; }
  [[nodiscard]] bool leaf() const { return (count & kOctInner) == 0; }
  [[nodiscard]] uint32_t child_mask() const { return leaf() ? 0 : count & 0xFFu; }
  [[nodiscard]] bool compact() const { return (count & (kOctInner | kOctCompact)) == kOctCompact; }
  [[nodiscard]] bool has_slab() const { return (count & (kOctInner | kOctSlab)) == kOctSlab; }
  [[nodiscard]] uint32_t leaf_count() const { return count & (kOctSlab - 1); }
};
static_assert(sizeof(OctNode64) == 12);

}  // namespace pcrt
