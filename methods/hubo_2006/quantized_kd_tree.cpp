#include "methods/hubo_2006/quantized_kd_tree.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/offsets.hpp"

namespace pcrt {
namespace {

constexpr uint32_t kPlaneMax = 16383;  // 14 bits
constexpr uint32_t kBoxMax = 255;      // 8 bits per leaf box side
constexpr uint32_t kPosMax = 4095;     // 12 bits per position coordinate
constexpr uint32_t kNormalMax = 4095;  // 12 bits per octahedral coordinate
constexpr size_t kParallelPoints = 1 << 15;

float box_side(float lo, float hi, uint32_t k) {
  return lo + (hi - lo) * (float(k) * (1.0f / float(kBoxMax)));
}
float position(float lo, float hi, uint32_t k) {
  return lo + (hi - lo) * (float(k) * (1.0f / float(kPosMax)));
}

uint32_t quantize(float x, float lo, float hi, uint32_t max) {
  if (!(hi > lo)) return 0;
  const float u = std::round((x - lo) / (hi - lo) * float(max));
  return uint32_t(std::clamp(u, 0.0f, float(max)));
}

// The 8-bit sides of a leaf's box inside its cell, rounded outward so the decoded box holds every
// point (checked against the decoding itself, so rounding cannot leave a point outside).
uint32_t side_below(float x, float lo, float hi) {
  if (!(hi > lo)) return 0;
  auto k =
      uint32_t(std::clamp(std::floor((x - lo) / (hi - lo) * float(kBoxMax)), 0.0f, float(kBoxMax)));
  while (k > 0 && box_side(lo, hi, k) > x) --k;
  return k;
}
uint32_t side_above(float x, float lo, float hi) {
  if (!(hi > lo)) return 0;
  auto k =
      uint32_t(std::clamp(std::ceil((x - lo) / (hi - lo) * float(kBoxMax)), 0.0f, float(kBoxMax)));
  while (k < kBoxMax && box_side(lo, hi, k) < x) ++k;
  return k;
}

float sign_of(float v) { return v < 0 ? -1.0f : 1.0f; }

// Octahedral normal encoding (a unit vector folded onto the octahedron, then its square).
uint64_t encode_normal(const Vec3& n) {
  const float l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
  float u = l1 > 0 ? n.x() / l1 : 0, v = l1 > 0 ? n.y() / l1 : 0;
  if (n.z() < 0) {
    const float fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
    u = fu, v = fv;
  }
  return uint64_t(quantize(u, -1, 1, kNormalMax)) | uint64_t(quantize(v, -1, 1, kNormalMax)) << 12;
}
Vec3 decode_normal(uint32_t bits) {
  float u = float(bits & kNormalMax) * (2.0f / float(kNormalMax)) - 1.0f;
  float v = float((bits >> 12) & kNormalMax) * (2.0f / float(kNormalMax)) - 1.0f;
  const float z = 1.0f - std::abs(u) - std::abs(v);
  if (z < 0) {
    const float fu = (1 - std::abs(v)) * sign_of(u), fv = (1 - std::abs(u)) * sign_of(v);
    u = fu, v = fv;
  }
  return Vec3(u, v, z).normalized();
}

bool overlaps(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

}  // namespace

void QuantizedKdTree::build(std::span<const Vec3> positions, std::span<const Vec3> normals,
                            size_t leaf_points, OpCounters& counters) {
  const size_t n = positions.size();
  offset32(n, "quantized_kd_tree");
  root_ = Aabb{};
  for (const Vec3& p : positions) root_.extend(p);
  const double want = std::max(1.0, double(n) / double(std::max<size_t>(leaf_points, 1)));
  const int depth = std::clamp(int(std::lround(std::log2(want))), 0, 30);
  const size_t leaves = size_t(1) << depth;
  first_leaf_ = uint32_t(leaves - 1);
  boxes_.assign(6 * (2 * leaves - 1), 0);
  planes_.assign(first_leaf_, 0);
  leaf_begin_.assign(leaves + 1, uint32_t(n));
  records_.assign(n, 0);
  ids_.resize(n);
  for (uint32_t i = 0; i < n; ++i) ids_[i] = i;  // partitioned in place into leaf order
  build_node(0, root_, ids_.data(), ids_.data() + n, Input{positions, normals, ids_.data()});
  counters.add(kBuildNodes, 2 * leaves - 1);
  counters.add(kBuildItemRefs, n);
  counters.add(kQkdBytes, memory_bytes());
}

// A node: its points' box quantized in its cell; an internal node's plane halfway between the two
// halves' nearest points at the median along the box's longest side, quantized in the box; a
// leaf's points quantized in the box.
void QuantizedKdTree::build_node(uint32_t node, const Aabb& cell, uint32_t* begin, uint32_t* end,
                                 const Input& in) {
  Aabb pts;
  for (const uint32_t* i = begin; i != end; ++i) pts.extend(in.positions[*i]);
  uint8_t* side = &boxes_[6 * size_t(node)];
  if (begin == end) {
    side[0] = uint8_t(kBoxMax);  // marks the node empty (lo above hi)
  } else {
    for (int a = 0; a < 3; ++a) {
      side[a] = uint8_t(side_below(pts.lo[a], cell.lo[a], cell.hi[a]));
      side[3 + a] = uint8_t(side_above(pts.hi[a], cell.lo[a], cell.hi[a]));
    }
  }
  const Aabb box = point_box(node, cell);
  if (!internal(node)) {
    leaf_begin_[node - first_leaf_] = uint32_t(begin - in.base);
    return encode_points(box, begin, end, in);
  }
  int a = 0;
  uint32_t q = kPlaneMax / 2;
  if (begin != end) {
    const Vec3 e = pts.extent();
    a = e.x() >= e.y() && e.x() >= e.z() ? 0 : (e.y() >= e.z() ? 1 : 2);
    uint32_t* mid = begin + (end - begin) / 2;
    auto coord = [&](uint32_t i) { return in.positions[i][a]; };
    std::nth_element(begin, mid, end, [&](uint32_t x, uint32_t y) { return coord(x) < coord(y); });
    float left_max = coord(*mid);
    for (const uint32_t* i = begin; i != mid; ++i) left_max = std::max(left_max, coord(*i));
    q = quantize(0.5f * (left_max + coord(*mid)), box.lo[a], box.hi[a], kPlaneMax);
  }
  planes_[node] = uint16_t(uint32_t(a) << 14 | q);
  Aabb lcell = box.empty() ? cell : box, rcell = lcell;
  const float s = qkd_plane(lcell.lo[a], lcell.hi[a], q);
  lcell.hi[a] = rcell.lo[a] = s;
  uint32_t* split = std::partition(begin, end, [&](uint32_t i) { return in.positions[i][a] < s; });
  if (size_t(end - begin) >= kParallelPoints)
    tbb::parallel_invoke([&] { build_node(2 * node + 1, lcell, begin, split, in); },
                         [&] { build_node(2 * node + 2, rcell, split, end, in); });
  else
    build_node(2 * node + 1, lcell, begin, split, in),
        build_node(2 * node + 2, rcell, split, end, in);
}

void QuantizedKdTree::encode_points(const Aabb& box, const uint32_t* begin, const uint32_t* end,
                                    const Input& in) {
  for (const uint32_t* i = begin; i != end; ++i) {
    const Vec3& p = in.positions[*i];
    uint64_t r = 0;
    for (int a = 0; a < 3; ++a)
      r |= uint64_t(quantize(p[a], box.lo[a], box.hi[a], kPosMax)) << (12 * a);
    r |= encode_normal(in.normals[*i]) << 36;
    records_[size_t(i - in.base)] = r;
  }
}

Aabb QuantizedKdTree::point_box(uint32_t node, const Aabb& cell) const {
  const uint8_t* side = &boxes_[6 * size_t(node)];
  if (side[0] > side[3]) return Aabb{};  // empty
  Aabb b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = box_side(cell.lo[a], cell.hi[a], side[a]);
    b.hi[a] = box_side(cell.lo[a], cell.hi[a], side[3 + a]);
  }
  return b;
}

void QuantizedKdTree::children(const Node& n, Node& left, Node& right) const {
  const uint16_t bits = planes_[n.index];
  const int a = bits >> 14;
  Aabb lcell = n.box, rcell = n.box;
  lcell.hi[a] = rcell.lo[a] = qkd_plane(n.box.lo[a], n.box.hi[a], bits & kPlaneMax);
  left = {2 * n.index + 1, point_box(2 * n.index + 1, lcell)};
  right = {2 * n.index + 2, point_box(2 * n.index + 2, rcell)};
}

void QuantizedKdTree::gather(const Aabb& box, std::vector<PackedSplat>& out,
                             OpCounters& counters) const {
  if (records_.empty()) return;
  counters.add(kQkdGathers);
  Node stack[64];
  int top = 0;
  stack[top++] = {0, point_box(0, root_)};
  size_t nodes = 1, decoded = 0;
  while (top > 0) {
    const Node n = stack[--top];
    if (n.box.empty() || !overlaps(n.box, box)) continue;
    if (internal(n.index)) {
      children(n, stack[top], stack[top + 1]);
      top += 2;
      nodes += 2;
      continue;
    }
    const uint32_t leaf = n.index - first_leaf_;
    const uint32_t b = leaf_begin_[leaf], e = leaf_begin_[leaf + 1];
    decoded += e - b;
    for (uint32_t i = b; i < e; ++i) {
      const uint64_t r = records_[i];
      Vec3 p;
      for (int a = 0; a < 3; ++a)
        p[a] = position(n.box.lo[a], n.box.hi[a], uint32_t(r >> (12 * a)) & kPosMax);
      if (!overlaps(Aabb{p, p}, box)) continue;
      out.push_back(PackedSplat{p, 0.0f, decode_normal(uint32_t(r >> 36)), ids_[i]});
    }
  }
  counters.add(kQkdNodesDecoded, nodes);
  counters.add(kQkdPointsDecoded, decoded);
}

size_t QuantizedKdTree::memory_bytes() const {
  return boxes_.size() + planes_.size() * sizeof(uint16_t) + leaf_begin_.size() * sizeof(uint32_t) +
         records_.size() * sizeof(uint64_t) + ids_.size() * sizeof(uint32_t);
}

}  // namespace pcrt
