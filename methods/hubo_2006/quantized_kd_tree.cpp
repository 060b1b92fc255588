#include "methods/hubo_2006/quantized_kd_tree.hpp"

#include <sys/mman.h>
#include <tbb/parallel_invoke.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/offsets.hpp"
#include "core/point_cloud.hpp"

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

// The in-memory build partitions point indices (ids_ itself) and reads the cloud through them.
struct QuantizedKdTree::CloudInput {
  using Item = uint32_t;
  std::span<const Vec3> positions, normals;
  const uint32_t* base;  // the start of the order being partitioned
  uint64_t* records;

  [[nodiscard]] const Vec3& position(uint32_t i) const { return positions[i]; }
  void store(uint32_t* at, uint64_t position_bits) const {
    records[at - base] = position_bits | encode_normal(normals[*at]) << 36;
  }
};

// The streamed build partitions 16-byte records: 24 bits a coordinate on the grid of the cloud's
// bounds, the normal's 24 octahedral bits and the stream index. A leaf's encoding replaces the
// grid word with the tree's record (36 position bits, the normal's 24 above them) in place.
struct QuantizedKdTree::StreamInput {
  struct Item {
    uint64_t grid;  // x bits 0-23, y 24-47, z's low 16 at 48-63; then the tree's record
    uint64_t rest;  // z's high 8 at 0-7, the normal at 8-31, the stream index at 32-63
  };
  static constexpr uint32_t kGridMax = (1u << 24) - 1;
  Aabb bounds;
  Vec3 step;  // bounds extent / kGridMax
  const Item* base;

  [[nodiscard]] static uint32_t grid(const Item& e, int a) {
    if (a < 2) return uint32_t(e.grid >> (24 * a)) & kGridMax;
    return uint32_t(e.grid >> 48) | (uint32_t(e.rest) & 0xff) << 16;
  }
  [[nodiscard]] Vec3 position(const Item& e) const {
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = bounds.lo[a] + float(grid(e, a)) * step[a];
    return p;
  }
  void store(Item* at, uint64_t position_bits) const {
    at->grid = position_bits | ((at->rest >> 8) & 0xffffff) << 36;
  }
  [[nodiscard]] Item quantized(const Vec3& p, const Vec3& n, uint32_t id) const {
    uint32_t g[3];
    for (int a = 0; a < 3; ++a) {
      const double u = (double(p[a]) - bounds.lo[a]) / (double(bounds.hi[a]) - bounds.lo[a]);
      g[a] = bounds.hi[a] > bounds.lo[a]
                 ? uint32_t(std::clamp(std::round(u * kGridMax), 0.0, double(kGridMax)))
                 : 0;
    }
    return {uint64_t(g[0]) | uint64_t(g[1]) << 24 | uint64_t(g[2] & 0xffff) << 48,
            uint64_t(g[2] >> 16) | encode_normal(n) << 8 | uint64_t(id) << 32};
  }
};

void QuantizedKdTree::allocate_nodes(size_t n, size_t leaf_points) {
  const double want = std::max(1.0, double(n) / double(std::max<size_t>(leaf_points, 1)));
  const int depth = std::clamp(int(std::lround(std::log2(want))), 0, 30);
  const size_t leaves = size_t(1) << depth;
  first_leaf_ = uint32_t(leaves - 1);
  boxes_.assign(6 * (2 * leaves - 1), 0);
  planes_.assign(first_leaf_, 0);
  leaf_begin_.assign(leaves + 1, uint32_t(n));
}

void QuantizedKdTree::build(std::span<const Vec3> positions, std::span<const Vec3> normals,
                            size_t leaf_points, OpCounters& counters) {
  const size_t n = positions.size();
  offset32(n, "quantized_kd_tree");
  root_ = Aabb{};
  for (const Vec3& p : positions) root_.extend(p);
  allocate_nodes(n, leaf_points);
  records_.assign(n, 0);
  ids_.resize(n);
  for (uint32_t i = 0; i < n; ++i) ids_[i] = i;  // partitioned in place into leaf order
  build_node(0, root_, ids_.data(), ids_.data() + n,
             CloudInput{positions, normals, ids_.data(), records_.data()});
  counters.add(kBuildNodes, boxes_.size() / 6);
  counters.add(kBuildItemRefs, n);
  counters.add(kQkdBytes, memory_bytes());
}
namespace {

// Anonymous memory whose leading pages go back to the system while the rest is still in use, so
// that moving an array's items into smaller ones never holds both in full.
template <typename T>
class ReleasableArray {
 public:
  explicit ReleasableArray(size_t n, const std::string& what) : n_(n), bytes_(n * sizeof(T)) {
    void* p =
        bytes_ ? mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
               : nullptr;
    if (p == MAP_FAILED)
      input_error("out of memory: {} needs {:.2f} GiB of records it could not map", what,
                  double(bytes_) / double(1ull << 30));
    data_ = static_cast<T*>(p);
  }
  ReleasableArray(const ReleasableArray&) = delete;
  ReleasableArray& operator=(const ReleasableArray&) = delete;
  ~ReleasableArray() {
    if (data_) munmap(data_, bytes_);
  }
  T* data() { return data_; }
  [[nodiscard]] size_t size() const { return n_; }
  // Hands back the whole pages below item `end`.
  void release_before(size_t end) {
    const size_t page = size_t(sysconf(_SC_PAGESIZE));
    const size_t upto = end * sizeof(T) / page * page;
    if (upto > released_)
      madvise(reinterpret_cast<char*>(data_) + released_, upto - released_, MADV_DONTNEED);
    released_ = std::max(released_, upto);
  }

 private:
  T* data_ = nullptr;
  size_t n_, bytes_, released_ = 0;
};

}  // namespace

void QuantizedKdTree::build(const PointStream& stream, size_t leaf_points, OpCounters& counters) {
  const size_t n = stream.size();
  offset32(n, "quantized_kd_tree");
  if (n == 0) input_error("{}: no points", stream.name());
  root_ = stream.bounds();
  ReleasableArray<StreamInput::Item> items(n, stream.name());
  const StreamInput in{root_, root_.extent() / float(StreamInput::kGridMax), items.data()};
  stream.read([&](const PointChunk& c) {
    for (size_t i = 0; i < c.positions.size(); ++i)
      items.data()[c.first + i] = in.quantized(c.positions[i], c.normals[i], uint32_t(c.first + i));
  });
  allocate_nodes(n, leaf_points);
  build_node(0, root_, items.data(), items.data() + n, in);
  // Into the tree's arrays, their pages touched only as written, the records' handed back.
  records_ = {}, ids_ = {};
  records_.reserve(n), ids_.reserve(n);
  constexpr size_t kRelease = size_t(1) << 20;
  for (size_t i = 0; i < n; ++i) {
    records_.push_back(items.data()[i].grid);
    ids_.push_back(uint32_t(items.data()[i].rest >> 32));
    if ((i + 1) % kRelease == 0) items.release_before(i + 1);
  }
  counters.add(kBuildNodes, boxes_.size() / 6);
  counters.add(kBuildItemRefs, n);
  counters.add(kQkdBytes, memory_bytes());
}

// A node: its points' box quantized in its cell; an internal node's plane halfway between the two
// halves' nearest points at the median along the box's longest side, quantized in the box; a
// leaf's points quantized in the box.
template <typename In>
void QuantizedKdTree::build_node(uint32_t node, const Aabb& cell, typename In::Item* begin,
                                 typename In::Item* end, const In& in) {
  using Item = typename In::Item;
  Aabb pts;
  for (const Item* i = begin; i != end; ++i) pts.extend(in.position(*i));
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
    Item* mid = begin + (end - begin) / 2;
    auto coord = [&](const Item& i) { return in.position(i)[a]; };
    std::nth_element(begin, mid, end,
                     [&](const Item& x, const Item& y) { return coord(x) < coord(y); });
    float left_max = coord(*mid);
    for (const Item* i = begin; i != mid; ++i) left_max = std::max(left_max, coord(*i));
    q = quantize(0.5f * (left_max + coord(*mid)), box.lo[a], box.hi[a], kPlaneMax);
  }
  planes_[node] = uint16_t(uint32_t(a) << 14 | q);
  Aabb lcell = box.empty() ? cell : box, rcell = lcell;
  const float s = qkd_plane(lcell.lo[a], lcell.hi[a], q);
  lcell.hi[a] = rcell.lo[a] = s;
  Item* split = std::partition(begin, end, [&](const Item& i) { return in.position(i)[a] < s; });
  if (size_t(end - begin) >= kParallelPoints)
    tbb::parallel_invoke([&] { build_node(2 * node + 1, lcell, begin, split, in); },
                         [&] { build_node(2 * node + 2, rcell, split, end, in); });
  else
    build_node(2 * node + 1, lcell, begin, split, in),
        build_node(2 * node + 2, rcell, split, end, in);
}

template <typename In>
void QuantizedKdTree::encode_points(const Aabb& box, typename In::Item* begin,
                                    typename In::Item* end, const In& in) {
  for (auto* i = begin; i != end; ++i) {
    const Vec3 p = in.position(*i);
    uint64_t r = 0;
    for (int a = 0; a < 3; ++a)
      r |= uint64_t(quantize(p[a], box.lo[a], box.hi[a], kPosMax)) << (12 * a);
    in.store(i, r);
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

Aabb QuantizedKdTree::leaf_box(uint32_t leaf) const {
  uint32_t path[32];
  int depth = 0;
  for (uint32_t node = first_leaf_ + leaf; node > 0; node = (node - 1) / 2) path[depth++] = node;
  Node n{0, point_box(0, root_)};
  while (depth > 0) {
    Node left{}, right{};
    children(n, left, right);
    n = path[--depth] == left.index ? left : right;
  }
  return n.box;
}

Vec3 QuantizedKdTree::decoded_position(size_t k, const Aabb& leaf) const {
  Vec3 p;
  for (int a = 0; a < 3; ++a)
    p[a] = position(leaf.lo[a], leaf.hi[a], uint32_t(records_[k] >> (12 * a)) & kPosMax);
  return p;
}

double QuantizedKdTree::nearest_other(size_t k, const Aabb& leaf, const Vec3& p,
                                      OpCounters& counters) const {
  // Grown until the nearest point found lies within the searched box's inscribed ball.
  float w = std::max(leaf.extent().maxCoeff(), 1e-6f * root_.diagonal());
  std::vector<PackedSplat> near;
  for (;;) {
    near.clear();
    gather(Aabb{p - Vec3::Constant(w), p + Vec3::Constant(w)}, near, counters);
    float best = kInfinity;
    for (const PackedSplat& s : near)
      if (s.index != ids_[k]) best = std::min(best, (s.c - p).norm());
    if (best <= w) return best;
    if (w > 2 * root_.diagonal()) return 0;  // a single point: no neighbour
    w *= 2;
  }
}

double QuantizedKdTree::sampled_mean_spacing(size_t samples, OpCounters& counters) const {
  const size_t n = records_.size();
  if (n < 2) return 0;
  samples = std::clamp<size_t>(samples, 1, n);
  double sum = 0;
  Vec3 previous = Vec3::Constant(kInfinity);
  for (size_t j = 0; j < samples; ++j) {
    const size_t k = j * n / samples;
    const auto leaf = uint32_t(std::upper_bound(leaf_begin_.begin(), leaf_begin_.end(), k) -
                               leaf_begin_.begin() - 1);
    const Aabb box = leaf_box(leaf);
    const Vec3 p = decoded_position(k, box);
    // Two samples decoded at one place are each other's nearest point, at 0: found without a
    // gather, which in a run of identical points (a stream keeps duplicates) decodes them all.
    if (p != previous) sum += nearest_other(k, box, p, counters);
    previous = p;
  }
  return sum / double(samples);
}

size_t QuantizedKdTree::memory_bytes() const {
  return boxes_.size() + planes_.size() * sizeof(uint16_t) + leaf_begin_.size() * sizeof(uint32_t) +
         records_.size() * sizeof(uint64_t) + ids_.size() * sizeof(uint32_t);
}

}  // namespace pcrt
