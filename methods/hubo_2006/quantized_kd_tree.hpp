// The quantized kd-tree of Hubo, Mertens, Haber and Bekaert 2006 ("The quantized kd-tree:
// efficient ray tracing of compressed point clouds", thesis [28]), as built here: a kd-tree whose
// split planes are stored quantized relative to the cell they cut, whose leaves keep a quantized
// bounding box relative to their cell, and whose points keep their position quantized relative to
// that leaf box and their normal quantized on the octahedron. Nothing is decompressed ahead: a
// ray walk decodes the split planes it crosses, and a neighbourhood gather decodes the planes and
// point records of the cells it reaches (random access). See README.md for the layout and bytes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.hpp"
#include "core/counters.hpp"
#include "core/point_stream.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// The decompression work, counted where it happens.
inline const Counter kQkdNodesDecoded{
    "qkd_nodes_decoded",
    "quantized kd-tree nodes decoded (point box, and plane if internal) by walks and gathers"};
inline const Counter kQkdPointsDecoded{
    "qkd_points_decoded", "quantized point records decoded (position and normal) by gathers"};
inline const Counter kQkdGathers{"qkd_gathers",
                                 "neighbourhood gathers in the quantized kd-tree (random access)"};
inline const Counter kQkdBytes{
    "qkd_bytes",
    "bytes the quantized kd-tree holds: planes, leaf offsets and boxes, point records "
    "and point ids (a size, not work)"};

class QuantizedKdTree {
 public:
  // Builds over the points (positions and unit normals, item i is cloud point i): a complete tree
  // of depth round(log2(N / leaf_points)), so leaves hold leaf_points points on average (within a
  // factor sqrt 2).
  void build(std::span<const Vec3> positions, std::span<const Vec3> normals, size_t leaf_points,
             OpCounters& counters);
  // The same tree over a stream's points (item i is stream point i), read twice and never held
  // in float: the first read takes the bounds, the second quantizes every point to 24 bits a
  // coordinate in them (16 bytes a point with its normal and index), the build partitions those
  // records in place and encodes each leaf's into its own, and they are moved into the tree's
  // arrays as their memory is handed back. Peak: about 16 bytes a point plus the nodes.
  void build(const PointStream& stream, size_t leaf_points, OpCounters& counters);
  // The mean distance from a point to its nearest other point, over `samples` points spread
  // evenly through the tree's order (all of them when samples >= N), found among the decoded
  // points: what the streamed build has in place of the whole cloud's mean spacing.
  [[nodiscard]] double sampled_mean_spacing(size_t samples, OpCounters& counters) const;

  // Every array the tree holds, in bytes.
  [[nodiscard]] size_t memory_bytes() const;
  [[nodiscard]] const Aabb& bounds() const { return root_; }

  // Walks the nodes whose point boxes, grown by `reach`, the ray crosses, nearer child first, and
  // calls leaf(t_enter, t_exit) -> void with the ray's interval in each leaf's grown point box:
  // every point within reach of the ray has its leaf called with an interval holding the point's
  // nearest approach. Nodes entered beyond *t_stop (which the callback may lower) are skipped.
  // Counts the nodes it decodes.
  template <typename Leaf>
  void walk(const Ray& ray, float reach, const float* t_stop, Leaf&& leaf,
            OpCounters& counters) const;

  // Appends to `out` the decoded points (centre, normal, cloud index; r = 0) lying in `box`.
  void gather(const Aabb& box, std::vector<PackedSplat>& out, OpCounters& counters) const;

 private:
  // A node as decoding sees it: its index (heap order) and its points' box.
  struct Node {
    uint32_t index;
    Aabb box;
  };
  [[nodiscard]] bool internal(uint32_t node) const { return node < first_leaf_; }
  // A node's point box, decoded from its 6 bytes inside its cell (empty for an empty node).
  [[nodiscard]] Aabb point_box(uint32_t node, const Aabb& cell) const;
  // The two children of an internal node, their boxes decoded (its plane cuts its point box).
  void children(const Node& n, Node& left, Node& right) const;
  struct CloudInput;
  struct StreamInput;
  // Sizes the node arrays for n points, leaf_points a leaf on average.
  void allocate_nodes(size_t n, size_t leaf_points);
  // Builds node's subtree over the items [begin, end) of `in` (CloudInput or StreamInput in the
  // .cpp), partitioning them in place.
  template <typename In>
  void build_node(uint32_t node, const Aabb& cell, typename In::Item* begin, typename In::Item* end,
                  const In& in);
  template <typename In>
  void encode_points(const Aabb& box, typename In::Item* begin, typename In::Item* end,
                     const In& in);
  // The point box of a leaf, decoded from the root down.
  [[nodiscard]] Aabb leaf_box(uint32_t leaf) const;
  // Record k's decoded position in its leaf's point box.
  [[nodiscard]] Vec3 decoded_position(size_t k, const Aabb& leaf) const;
  // The distance from record k, decoded at p in its leaf's point box, to the nearest other
  // decoded point.
  [[nodiscard]] double nearest_other(size_t k, const Aabb& leaf, const Vec3& p,
                                     OpCounters& counters) const;

  Aabb root_;
  uint32_t first_leaf_ = 0;           // 2^depth - 1: nodes below are internal (heap order)
  std::vector<uint8_t> boxes_;        // per node: 6 bytes, its points' box in its cell
  std::vector<uint16_t> planes_;      // per internal node: axis (2 bits), plane (14 bits)
  std::vector<uint32_t> leaf_begin_;  // per leaf (and one past): its points in records_
  std::vector<uint64_t> records_;     // per point: 3 x 12 bits position, 2 x 12 bits normal
  std::vector<uint32_t> ids_;         // per point: its index in the cloud (the hit's prim)
};

// The plane coordinate q/16383 of the way through [lo, hi]: the one formula build and decoding
// share, so both cut a box at bit-identical coordinates.
inline float qkd_plane(float lo, float hi, uint32_t q) {
  return lo + (hi - lo) * (float(q) * (1.0f / 16383.0f));
}

template <typename Leaf>
void QuantizedKdTree::walk(const Ray& ray, float reach, const float* t_stop, Leaf&& leaf,
                           OpCounters& counters) const {
  if (records_.empty()) return;
  const Vec3 inv_d = ray.d.cwiseInverse();
  const Vec3 grow = Vec3::Constant(reach);
  auto enter = [&](const Aabb& box, float& t0, float& t1) {
    return !box.empty() && Aabb{box.lo - grow, box.hi + grow}.intersect(ray, inv_d, t0, t1) &&
           may_improve(t0, *t_stop);
  };
  struct Entry {
    Node node;
    float t0, t1;
  };
  Entry stack[64];
  int top = 0;
  Entry root{{0, point_box(0, root_)}, 0, 0};
  counters.add(kQkdNodesDecoded);
  if (enter(root.node.box, root.t0, root.t1)) stack[top++] = root;
  while (top > 0) {
    const Entry e = stack[--top];
    if (!may_improve(e.t0, *t_stop)) continue;  // a hit found since it was pushed
    if (!internal(e.node.index)) {
      counters.add(kLeavesVisited);
      leaf(e.t0, e.t1);
      continue;
    }
    Entry l{}, r{};
    children(e.node, l.node, r.node);
    counters.add(kQkdNodesDecoded, 2);
    const bool hit_l = enter(l.node.box, l.t0, l.t1), hit_r = enter(r.node.box, r.t0, r.t1);
    if (hit_l && hit_r && l.t0 <= r.t0)
      stack[top++] = r, stack[top++] = l;
    else if (hit_l && hit_r)
      stack[top++] = l, stack[top++] = r;
    else if (hit_l || hit_r)
      stack[top++] = hit_l ? l : r;
  }
}

}  // namespace pcrt
