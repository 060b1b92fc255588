// Point projection onto a ray (thesis section 5.5.2, "point projection based intersection"): the
// leaf's points are projected onto the ray through their tangent planes, and the front-most group
// is blended into one hit. Shared by Schaufler and Jensen 2000 (ray cylinder, linear weights) and
// Wand and Strasser 2003 (ray cone, Gaussian weights); the weight function is what differs.
#pragma once

#include <cmath>
#include <span>

#include "core/counters.hpp"
#include "methods/kernels/splat_kernel.hpp"
#include "structures/structure.hpp"

namespace pcrt {

inline const Counter kProjectionTests{
    "projection_tests", "points projected onto a ray (2 per leaf item and group tried)"};
inline const Counter kProjectionCandidates{"projection_candidates",
                                           "points inside the ray's cylinder or cone"};

struct ProjectionSettings {
  float depth = 0;         // blend the candidates within this distance behind the front-most
  float min_weight = 0;    // the blended weight must reach this (coverage), or the leaf misses
  float early_margin = 0;  // a blend may land this far before the leaf (rounding at its wall)
  float footprint = 0;     // reported as Hit::footprint
};

// Records the blended hit at t_hit (normal: the weighted normal sum, else the best splat's) if it
// is this leaf's and nearer than hit. The cell rule: a hit belongs to the leaf whose span holds
// it; later leaves blend their own.
inline bool record_blend(const Ray& ray, const LeafVisit& leaf, const ProjectionSettings& s,
                         float t_hit, const Vec3& nsum, const PackedSplat& best, Hit& hit) {
  if (t_hit > leaf.t_exit || t_hit < leaf.t_enter - s.early_margin || t_hit < ray.tmin ||
      !closer(t_hit, best.index, hit))
    return false;
  hit.t = t_hit;
  hit.prim = best.index;
  hit.p = ray.at(t_hit);
  hit.n = nsum.norm() > 0 ? Vec3(nsum.normalized()) : best.n;
  hit.footprint = s.footprint;
  return true;
}

// Weight(ray, splat, t, lateral) returns the weight of a point whose tangent plane the ray crosses
// at t, with `lateral` its offset from the ray axis, and 0 if it is no candidate. ForEachSplat(f)
// calls f(k, splat) for the leaf's items in leaf order (k the item index; it may skip items whose
// weight would be 0). NormalAt(k, splat, x) is item k's normal at the crossing x (its own normal,
// or a normal field's value there). Allocation-free, two passes over the leaf per group tried:
// O(K) per group.
template <typename ForEachSplat, typename Weight, typename NormalAt>
bool blend_projected(const Ray& ray, const LeafVisit& leaf, ForEachSplat&& for_each_splat,
                     const ProjectionSettings& s, Weight&& weight, NormalAt&& normal_at, Hit& hit,
                     OpCounters& counters) {
  auto project = [&](const PackedSplat& p, float& t, float& w) {
    const Vec3 v = p.c - ray.o;
    const Vec3 lateral = v - v.dot(ray.d) * ray.d;
    const float denom = p.n.dot(ray.d);
    if (denom == 0) return false;
    t = p.n.dot(v) / denom;
    if (t < ray.tmin) return false;
    w = weight(ray, p, t, lateral);
    return w > 0;
  };
  // Groups front to back: the front-most candidate starts a group of the candidates within
  // `depth` behind it. A group below the coverage threshold is no surface (a stray tangent plane
  // crossing the ray early); the next group is tried rather than the leaf giving up, since the
  // surface behind the stray crossing may then lie before the next leaf's reach and be lost.
  float floor_t = -kInfinity, wsum = 0, tsum = 0;
  Vec3 nsum = Vec3::Zero();
  PackedSplat best{};
  bool has_best = false;
  uint64_t candidates = 0;
  bool first_pass = true;
  while (true) {
    counters.add(kProjectionTests, leaf.items.size());
    float front = kInfinity;
    for_each_splat([&](uint32_t, const PackedSplat& p) {
      float t = 0, w = 0;
      if (project(p, t, w) && t > floor_t) candidates += first_pass, front = std::min(front, t);
    });
    first_pass = false;
    if (front == kInfinity) break;
    counters.add(kProjectionTests, leaf.items.size());
    wsum = 0, tsum = 0, nsum = Vec3::Zero(), has_best = false;
    float best_w = -1;
    for_each_splat([&](uint32_t k, const PackedSplat& p) {
      float t = 0, w = 0;
      if (!project(p, t, w) || t < front || t > front + s.depth) return;
      wsum += w;
      tsum += w * t;
      nsum += w * normal_at(k, p, ray.at(t));
      if (w > best_w || (w == best_w && p.index < best.index)) best_w = w, best = p;
      has_best = true;
    });
    if (wsum > 0 && wsum >= s.min_weight) break;
    floor_t = front + s.depth;
  }
  counters.add(kProjectionCandidates, candidates);
  if (!has_best || !(wsum > 0) || wsum < s.min_weight) return false;
  return record_blend(ray, leaf, s, tsum / wsum, nsum, best, hit);
}

// The same over item-order records, each point with its own normal.
template <typename Weight>
bool blend_projected_points(const Ray& ray, const LeafVisit& leaf,
                            std::span<const PackedSplat> splats, const ProjectionSettings& s,
                            Weight&& weight, Hit& hit, OpCounters& counters) {
  auto each = [&](auto&& f) {
    for (uint32_t k : leaf.items) f(k, splats[k]);
  };
  auto own_normal = [](uint32_t, const PackedSplat& p, const Vec3&) { return p.n; };
  return blend_projected(ray, leaf, each, s, weight, own_normal, hit, counters);
}

}  // namespace pcrt
