// The slab of a leaf's discs along their mean normal (the octree's and the kd-tree's
// leaf_slabs): once the discs are wider than the cells their boxes fill the cells, but on a
// surface they stay nearly parallel, so a ray that crosses a cell above the surface misses the
// slab, and the walk need not hand it the leaf.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>

#include "core/geometry.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// Every point x of every disc of the leaf has lo <= v . x <= hi, with v the normal stored as
// 16-bit fixed point (v = n / 32767, |v| ~ 1; the build bounds the discs along the v the walk reads
// back, so the rounding of v costs nothing). lo > hi: no bound (a leaf whose discs face every way,
// or no disc).
struct LeafSlab {
  std::array<int16_t, 3> n{};
  float lo = 1, hi = 0;
  [[nodiscard]] Vec3 normal() const {
    constexpr float kInv = 1.0f / 32767.0f;
    return {float(n[0]) * kInv, float(n[1]) * kInv, float(n[2]) * kInv};
  }
  [[nodiscard]] bool bounded() const { return lo <= hi; }
  // Worth a test by the walk: thinner than half the cell's extent along the normal. A thicker
  // one culls few of the rays that cross the cell, and its test costs a load and a branch either
  // way (results/anchor/oct_slab).
  [[nodiscard]] bool thin(float cell_extent_along_normal) const {
    return bounded() && hi - lo < 0.5f * cell_extent_along_normal;
  }
};
static_assert(sizeof(LeafSlab) == 16);

// The slab of discs `refs` of `items` along their mean normal (each flipped to face the first's
// way): a disc (c, m, r) spans v . c +- r |v x m| / |m| along v (the cross product, not the
// cancelling |v|^2 - (v . m)^2 / |m|^2, since v and m are nearly parallel), padded as its box is
// (1e-4 r) and for the rounding of the dot products (1e-6 of |c|_1, their terms' sizes).
inline LeafSlab slab_of(const ItemSet& items, std::span<const uint32_t> refs) {
  LeafSlab slab;
  if (refs.empty()) return slab;
  const Vec3 n0 = items.disc_normals[refs[0]];
  Vec3 sum = Vec3::Zero();
  for (const uint32_t i : refs) {
    const Vec3& m = items.disc_normals[i];
    sum += m.dot(n0) < 0 ? Vec3(-m) : m;
  }
  const float length = sum.norm();
  if (!(length > 0) || !std::isfinite(length)) return slab;
  for (int a = 0; a < 3; ++a) slab.n[size_t(a)] = int16_t(std::lround(sum[a] / length * 32767));
  const Vec3 v = slab.normal();
  float lo = kInfinity, hi = -kInfinity;
  for (const uint32_t i : refs) {
    const Vec3& c = items.positions[i];
    const Vec3& m = items.disc_normals[i];  // not always of unit length (a file's normals)
    const float m_length = m.norm();
    if (!(m_length > 0) || !std::isfinite(m_length)) return LeafSlab{};
    const float r = items.radius(i), along = v.dot(c);
    const float reach = r * (v.cross(m).norm() / m_length + 1e-4f) + 1e-6f * c.cwiseAbs().sum();
    lo = std::min(lo, along - reach);
    hi = std::max(hi, along + reach);
  }
  slab.lo = lo, slab.hi = hi;
  return slab;
}

// Whether the ray over `interval` may meet the slab: false when v . (o + t d) lies below lo or
// above hi at both ends (it is linear in t), beyond a margin for the rounding of both dot
// products (1e-6 of their terms' sizes, as slab_of's). NaN (an infinite t times a zero rate)
// and infinities keep the leaf. Always inlined: the walks call it once per leaf, and the AVX2
// ones would otherwise call out of their encoding (3-7% of the octree's walk, c2ee3c5).
__attribute__((always_inline)) inline bool crosses_slab(const LeafSlab& slab, const Ray& ray,
                                                        std::pair<float, float> interval) {
  if (!slab.bounded()) return true;
  const auto [t0, t1] = interval;
  const Vec3 v = slab.normal();
  const float at_o = v.dot(ray.o), rate = v.dot(ray.d);
  const float s0 = at_o + t0 * rate, s1 = at_o + t1 * rate;
  const float pad = 1e-6f * (ray.o.cwiseAbs().sum() +
                             std::max(std::abs(t0), std::abs(t1)) * ray.d.cwiseAbs().sum());
  const bool below = s0 < slab.lo - pad && s1 < slab.lo - pad;
  const bool above = s0 > slab.hi + pad && s1 > slab.hi + pad;
  return !(below || above);
}

}  // namespace pcrt
