// Point projection onto a ray (thesis section 5.5.2, "point projection based intersection"): the
// leaf's points are projected onto the ray through their tangent planes, and the front-most group
// is blended into one hit. Shared by Schaufler and Jensen 2000 (ray cylinder, linear weights) and
// Wand and Strasser 2003 (ray cone, Gaussian weights); the weight function is what differs. Their
// leaves are read through an 8-wide prefilter (projection_lanes.hpp) and projected exactly only
// where it lets a point through, once per leaf; the splat blend (splat_blend.hpp) reuses the
// grouping with the disc lanes as its prefilter.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

#include "core/counters.hpp"
#include "methods/kernels/projection_lanes.hpp"
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

// The weight of p's crossing of the ray at t (t its tangent plane's crossing): false if t is
// before tmin or Weight(ray, p, t, lateral) is 0 (lateral: the point's offset from the ray axis).
template <typename Weight>
inline bool weigh_crossing(const Ray& ray, const PackedSplat& p, float t, Weight&& weight,
                           float& w) {
  if (t < ray.tmin) return false;
  const Vec3 v = p.c - ray.o;
  w = weight(ray, p, t, Vec3(v - v.dot(ray.d) * ray.d));
  return w > 0;
}

// Where the ray crosses p's tangent plane (t), false if it runs parallel to it. The dots sum
// x + (y + z), as the disc lanes' num and den (disc_t, splat_blocks.hpp): their t is this one.
inline bool plane_crossing(const Ray& ray, const PackedSplat& p, float& t) {
  const float denom = p.n.dot(ray.d);
  if (denom == 0) return false;
  t = p.n.dot(Vec3(p.c - ray.o)) / denom;
  return true;
}

// Projects point p onto the ray through its tangent plane: false if the ray is parallel to the
// plane or weigh_crossing refuses the crossing; else the crossing t and the weight w.
template <typename Weight>
inline bool project_point(const Ray& ray, const PackedSplat& p, Weight&& weight, float& t,
                          float& w) {
  return plane_crossing(ray, p, t) && weigh_crossing(ray, p, t, weight, w);
}

// The blend over a leaf's projected points. ForEachProjected(g) calls g(k, p, t, w) for each
// point of the leaf that project_point accepts, in leaf order (k the item index). Groups front to
// back: the front-most point starts a group of the points within `depth` behind it. A group below
// the coverage threshold is no surface (a stray tangent plane crossing the ray early); the next
// group is tried rather than the leaf giving up, since the surface behind the stray crossing may
// then lie before the next leaf's reach and be lost. Work counts as the thesis algorithm's: every
// leaf item projected twice per group tried.
template <typename ForEachProjected, typename NormalAt>
bool blend_groups(const Ray& ray, const LeafVisit& leaf, ForEachProjected&& for_each_projected,
                  const ProjectionSettings& s, NormalAt&& normal_at, Hit& hit,
                  OpCounters& counters) {
  float floor_t = -kInfinity, wsum = 0, tsum = 0;
  Vec3 nsum = Vec3::Zero();
  PackedSplat best{};
  bool has_best = false;
  uint64_t candidates = 0;
  bool first_pass = true;
  while (true) {
    counters.add(kProjectionTests, leaf.items.size());
    float front = kInfinity;
    for_each_projected([&](uint32_t, const PackedSplat&, float t, float) {
      if (t > floor_t) candidates += first_pass, front = std::min(front, t);
    });
    first_pass = false;
    if (front == kInfinity) break;
    counters.add(kProjectionTests, leaf.items.size());
    wsum = 0, tsum = 0, nsum = Vec3::Zero(), has_best = false;
    float best_w = -1;
    for_each_projected([&](uint32_t k, const PackedSplat& p, float t, float w) {
      if (t < front || t > front + s.depth) return;
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

// The points a leaf's blend keeps, with their crossing and weight: projected once per leaf, not
// twice per group tried. A leaf that keeps more than kCapacity points is blended from the
// projection itself (projecting again per pass: the same floats, so the same hit).
struct ProjectedPoints {
  static constexpr uint32_t kCapacity = 64;
  struct Entry {
    PackedSplat p;
    uint32_t k;
    float t, w;
  };
  Entry entry[kCapacity];
  uint32_t size = 0;
  bool overflow = false;
  void add(uint32_t k, const PackedSplat& p, float t, float w) {
    if (size == kCapacity) overflow = true;
    if (!overflow) entry[size++] = Entry{p, k, t, w};
  }
  template <typename G>
  void for_each(G&& g) const {
    for (uint32_t i = 0; i < size; ++i) g(entry[i].k, entry[i].p, entry[i].t, entry[i].w);
  }
};

// The blend over a leaf's crossings: ForEachCrossing(g) calls g(k, splat, t) for the leaf's items
// whose plane the ray crosses, in leaf order, t as plane_crossing computes it (the disc lanes'
// candidates carry it: one division per candidate, not two); it may skip items whose weight
// would be 0. Weight and NormalAt as in blend_projected.
template <typename ForEachCrossing, typename Weight, typename NormalAt>
bool blend_crossings(const Ray& ray, const LeafVisit& leaf, ForEachCrossing&& for_each_crossing,
                     const ProjectionSettings& s, Weight&& weight, NormalAt&& normal_at, Hit& hit,
                     OpCounters& counters) {
  auto projected = [&](auto&& g) {
    for_each_crossing([&](uint32_t k, const PackedSplat& p, float t) {
      float w = 0;
      if (weigh_crossing(ray, p, t, weight, w)) g(k, p, t, w);
    });
  };
  ProjectedPoints kept;
  projected([&](uint32_t k, const PackedSplat& p, float t, float w) { kept.add(k, p, t, w); });
  if (kept.overflow) return blend_groups(ray, leaf, projected, s, normal_at, hit, counters);
  auto each_kept = [&](auto&& g) { kept.for_each(g); };
  return blend_groups(ray, leaf, each_kept, s, normal_at, hit, counters);
}

// Weight(ray, splat, t, lateral) as in project_point. ForEachSplat(f) calls f(k, splat) for the
// leaf's items in leaf order (k the item index; it may skip items whose weight would be 0).
// NormalAt(k, splat, x) is item k's normal at the crossing x (its own normal, or a normal field's
// value there). Allocation-free; O(K) per leaf, plus O(candidates) per group tried.
template <typename ForEachSplat, typename Weight, typename NormalAt>
bool blend_projected(const Ray& ray, const LeafVisit& leaf, ForEachSplat&& for_each_splat,
                     const ProjectionSettings& s, Weight&& weight, NormalAt&& normal_at, Hit& hit,
                     OpCounters& counters) {
  auto crossings = [&](auto&& g) {
    for_each_splat([&](uint32_t k, const PackedSplat& p) {
      float t = 0;
      if (plane_crossing(ray, p, t)) g(k, p, t);
    });
  };
  return blend_crossings(ray, leaf, crossings, s, weight, normal_at, hit, counters);
}

// The prefilter's query: crossings from ray.tmin widened by 1e-5 relative (the exact t = num / den
// is rounded once more than the lanes' comparison), r^2 widened by 10% (5% on the radius). The
// lanes compute num and den as the exact projection does (projection_lanes.hpp); their |x - c|^2
// and the exact one then differ by a few roundings of the coordinates of o, c and x = o + t d
// (about 6e-8 of |o| + |c| + |t| each), whatever the angle between ray and plane: a few 0.1% of
// the radius where it is 1e-4 of the scene's and the camera's scale, less above. The methods'
// radii are 3 (schaufler_jensen_2000) and 6 (wand_strasser_2003) mean spacings by default.
// Checked by ray_projection_test.cpp, which fails with r^2 scaled by 0.999 (it passes at 1.0).
inline ProjectionQuery projection_query(const Ray& ray) {
  return {{ray.o.x(), ray.o.y(), ray.o.z()},
          {ray.d.x(), ray.d.y(), ray.d.z()},
          ray.tmin - 1e-5f * std::abs(ray.tmin) - 1e-30f,
          1.1f};
}

static_assert(sizeof(PackedSplat) == kRecordFloats * sizeof(float) && alignof(PackedSplat) == 32,
              "projection lanes read PackedSplat records as 8 aligned floats");
static_assert(offsetof(PackedSplat, r) == kR * sizeof(float) &&
                  offsetof(PackedSplat, n) == kNx * sizeof(float),
              "projection lanes read c, r, n at these fields");

// Calls f(k, record) for the items of the leaf whose records the lanes let through (a superset
// of those project_point accepts, given a Weight that is 0 where |x - c| >= r), in leaf order,
// 64 items at a time.
template <typename F>
void for_each_projection_candidate(std::span<const PackedSplat> splats,
                                   std::span<const uint32_t> items, ProjectionKernel kernel,
                                   const ProjectionQuery& q, F&& f) {
  const float* records = reinterpret_cast<const float*>(splats.data());
  for (uint32_t c = 0; c < items.size(); c += 64) {
    const uint32_t n = std::min<uint32_t>(64, uint32_t(items.size()) - c);
    uint64_t bits = 0;
    kernel(records, items.data() + c, n, q, &bits);
    for (; bits; bits &= bits - 1) {
      const uint32_t k = items[c + uint32_t(__builtin_ctzll(bits))];
      f(k, splats[k]);
    }
  }
}

// The blend over item-order records, each point with its own normal, read through the lanes
// (kernel: best_projection_kernel(), chosen once by the caller). Weight must be 0 where the
// crossing lies r or more from the point (|ray.at(t) - p.c| >= p.r, up to a few roundings of r):
// the lanes drop those points unprojected.
template <typename Weight>
bool blend_projected_points(const Ray& ray, const LeafVisit& leaf,
                            std::span<const PackedSplat> splats, ProjectionKernel kernel,
                            const ProjectionSettings& s, Weight&& weight, Hit& hit,
                            OpCounters& counters) {
  const ProjectionQuery q = projection_query(ray);
  auto each = [&](auto&& f) { for_each_projection_candidate(splats, leaf.items, kernel, q, f); };
  auto own_normal = [](uint32_t, const PackedSplat& p, const Vec3&) { return p.n; };
  return blend_projected(ray, leaf, each, s, weight, own_normal, hit, counters);
}

}  // namespace pcrt
