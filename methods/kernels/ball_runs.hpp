// Iterations started from balls around points (Adamson and Alexa's MLS spheres, Adams et al.'s
// surfel spheres, Cai et al.'s splat spheres): every ball of the leaf that the ray crosses before
// the current hit starts a run on the ray's chord through it; the nearest result wins.
#pragma once

#include <cmath>
#include <span>

#include "core/geometry.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// The chord [t0, t1] of the ray through the ball (c, r) clipped to [ray.tmin, tmax]; false if
// the ray misses it.
inline bool ball_chord(const Ray& ray, const Vec3& c, float r, float tmax, float& t0, float& t1) {
  const Vec3 oc = c - ray.o;
  const float tc = oc.dot(ray.d);
  const float d2 = oc.squaredNorm() - tc * tc;
  if (d2 > r * r) return false;
  const float half = std::sqrt(r * r - d2);
  t0 = std::max(tc - half, ray.tmin);
  t1 = std::min(tc + half, tmax);
  return t0 <= t1;
}

// ball(k, centre, radius, prim) describes item k; run(k, t0, t1, normal) returns a hit t in
// [t0, t1] (and its normal) or +inf. Ties in t go to the lower prim (structures::closer).
template <typename Ball, typename Run>
bool nearest_ball_hit(const Ray& ray, std::span<const uint32_t> items, Ball&& ball, Run&& run,
                      Hit& hit) {
  bool found = false;
  for (uint32_t k : items) {
    Vec3 c;
    float r = 0;
    uint32_t prim = 0;
    ball(k, c, r, prim);
    float t0 = 0, t1 = 0;
    if (!ball_chord(ray, c, r, hit.t, t0, t1)) continue;
    Vec3 n = Vec3::Zero();
    const float t = run(k, t0, t1, n);
    if (t == kInfinity || !closer(t, prim, hit)) continue;
    record_hit(ray, t, prim, n, r, hit);
    found = true;
  }
  return found;
}

// The same over splats: each splat's bounding sphere is its ball, its cloud index the prim.
template <typename Run>
bool nearest_splat_ball_hit(const Ray& ray, std::span<const uint32_t> items,
                            std::span<const PackedSplat> splats, Run&& run, Hit& hit) {
  auto ball = [&](uint32_t k, Vec3& c, float& r, uint32_t& prim) {
    const PackedSplat& s = splats[k];
    c = s.c, r = s.r, prim = s.index;
  };
  return nearest_ball_hit(ray, items, ball, run, hit);
}

}  // namespace pcrt
