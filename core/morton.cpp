#include "core/morton.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include "core/error.hpp"

namespace pcrt {
namespace {

// Spreads the low 21 bits of x to every third bit.
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

Vec3 key_scale(const Aabb& b) {
  return (b.extent().array() > 0)
      .select(Vec3::Constant(2097151.0f).cwiseQuotient(b.extent()), 0.0f);
}

// A cell index in [0, 2^21): a cloud a few 1e-38 across makes the scale infinite, so q may be
// inf (or NaN, 0 x inf), which no integer conversion may see.
uint64_t cell(float q) {
  if (!(q > 0)) return 0;
  return q < 2097151.0f ? uint64_t(q) : 2097151u;
}

uint64_t key_of(const Vec3& p, const Aabb& b, const Vec3& scale) {
  const Vec3 q = (p - b.lo).cwiseProduct(scale);
  return spread_bits(cell(q.x())) | spread_bits(cell(q.y())) << 1 | spread_bits(cell(q.z())) << 2;
}

struct Keyed {
  uint64_t key;
  uint32_t index;
};

template <typename T>
void permute(std::vector<T>& v, const std::vector<uint32_t>& order) {
  if (v.empty()) return;
  std::vector<T> sorted(v.size());
  tbb::parallel_for(size_t(0), order.size(), [&](size_t k) { sorted[k] = v[order[k]]; });
  v.swap(sorted);
}

}  // namespace

uint64_t morton_key(const Vec3& p, const Aabb& bounds) {
  return key_of(p, bounds, key_scale(bounds));
}

std::vector<uint32_t> morton_order(std::span<const Vec3> positions) {
  if (positions.size() > size_t(UINT32_MAX))
    input_error("{} points: more than 2^32 - 1, the most pcrt indexes", positions.size());
  Aabb b;
  for (const Vec3& p : positions) b.extend(p);
  const Vec3 scale = key_scale(b);
  std::vector<Keyed> keyed(positions.size());
  tbb::parallel_for(size_t(0), positions.size(), [&](size_t i) {
    keyed[i] = {key_of(positions[i], b, scale), uint32_t(i)};
  });
  // A strict total order (the index breaks every tie), so the parallel sort's result is unique.
  tbb::parallel_sort(keyed.begin(), keyed.end(), [&](const Keyed& a, const Keyed& c) {
    if (a.key != c.key) return a.key < c.key;
    const Vec3& p = positions[a.index];
    const Vec3& q = positions[c.index];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a.index < c.index;
  });
  std::vector<uint32_t> order(keyed.size());
  for (size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].index;
  return order;
}

size_t morton_sort_bytes(size_t n) {
  return n * std::max(sizeof(Keyed) + sizeof(uint32_t), 2 * sizeof(uint32_t) + sizeof(Vec3));
}

std::vector<uint32_t> morton_sort(PointCloud& cloud) {
  std::vector<uint32_t> order = morton_order(cloud.positions);
  permute(cloud.positions, order);
  permute(cloud.normals, order);
  permute(cloud.radii, order);
  permute(cloud.colours, order);
  permute(cloud.gaussians.scales, order);
  permute(cloud.gaussians.rotations, order);
  permute(cloud.gaussians.opacities, order);
  return order;
}

}  // namespace pcrt
