// Accuracy of a method against an exact surface (the thesis's open "visual quality" question):
// rays from outside aimed at and around the surface; holes, false hits, hit-point distance to the
// true surface and normal error, in units of the mean spacing h.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/surfaces.hpp"
#include "render/scene.hpp"

namespace pcrt {

// Where failures happen, by the shape at the exact front hit: near a crease (two faces more than
// Surface::kSmoothAngleDeg = 15 degrees apart within the ball of radius kFeatureReachH around the
// hit), on a wall thinner than kThinWallH (measured along the inward normal to the back side), or
// on open smooth surface. The same split of every judged hit is
// the baseline: a cause is established when the failures crowd where the shape has that feature.
struct FeatureSplit {
  // Twice the widest kernel reach of the surveyed methods' defaults (3.5 h: Wald and Seidel's
  // support, the MLS start balls): a kernel centred on one side reaches the other.
  static constexpr float kThinWallH = 7.0f;
  static constexpr float kFeatureReachH = 3.5f;
  size_t thin = 0, crease = 0, open = 0;
  [[nodiscard]] size_t total() const { return thin + crease + open; }
};

// The judged hits and their failures by the normal spread at the exact first hit (the largest
// angle between face normals within kFeatureReachH, Surface::normal_spread_deg): one crease/open
// split cannot tell the faceting of smooth organic surface (15-30 degrees on coarse meshes) from
// a sharp edge, and failures rise steadily with the spread (issue 30). A band holds spreads in
// [lo_deg, hi_deg); the last one includes 180.
struct SpreadBand {
  float lo_deg = 0, hi_deg = 0;
  size_t judged_hits = 0, holes = 0, see_through = 0, early = 0, phantom = 0;
  // Of those, on a wall thinner than kThinWallH (only below the crease angle: a crease comes
  // first), which a kernel wider than the wall sees through at any spread.
  size_t thin_hits = 0, thin_failures = 0;
  // What the 1% bounds are about: holes, see-through and phantom hits.
  [[nodiscard]] size_t failures() const { return holes + see_through + phantom; }
  [[nodiscard]] double rate(size_t n) const {
    return judged_hits ? double(n) / double(judged_hits) : 0.0;
  }
};
inline constexpr std::array<float, 6> kSpreadEdgesDeg = {0, 5, 15, 30, 60, 180};
using SpreadBands = std::array<SpreadBand, kSpreadEdgesDeg.size() - 1>;
// The bands with their edges set and nothing counted.
SpreadBands empty_spread_bands();

struct AccuracyReport {
  size_t rays = 0;
  size_t judged_hits = 0;    // exact ray hits, not grazing (|cos| >= 0.1)
  size_t judged_misses = 0;  // exact ray passes the surface by more than 2h
  size_t holes = 0;          // judged hits the method misses
  size_t false_hits = 0;     // method hits on judged misses, or > 5h from the exact first hit
  // The false hits by cause: the front surface missed (the hit lands > 5h behind the exact first
  // hit), the surface fattened (> 5h in front of it but within 2h of the surface), or a hit in
  // empty space (more than 2h from any surface).
  size_t see_through = 0, early = 0, phantom = 0;
  // See-through hits whose missed front surface is smooth within 2h (the rest pass within 2h of a
  // crease or a feature thinner than the method's kernel).
  size_t see_through_smooth = 0;
  // Causes: judged hits, see-through hits and holes split by the shape at the exact first hit;
  // phantom hits with a crease within kFeatureReachH of their nearest surface point.
  FeatureSplit judged_split, see_through_split, hole_split;
  size_t phantom_near_crease = 0;
  // Rays with an exact hit by the normal spread there (phantoms on rays that miss the surface
  // have no exact hit and are in no band).
  SpreadBands spread_bands = empty_spread_bands();
  size_t normal_judged = 0;      // good hits where the surface is smooth within 2h (normals judged)
  double mean_spacing = 0;       // h
  double hole_rate = 0;          // holes / judged_hits
  double false_hit_rate = 0;     // false_hits / (judged_hits + judged_misses)
  double distance_median_h = 0;  // |signed distance| of reported hit points / h
  double distance_p95_h = 0;
  double normal_median_deg = 0;  // unsigned angle to the true normal, where it is smooth
  double normal_p95_deg = 0;
  // The same against the smooth normal (a mesh: its vertex normals interpolated), at every good
  // hit.
  double smooth_normal_median_deg = 0;
  // Median angle between the true and the smooth normal at the exact hits where normals are
  // judged: how far a faceted mesh's own normals are from the smooth surface its samples suggest.
  double faceting_floor_deg = 0;

  [[nodiscard]] double see_through_rate() const { return rate(see_through, judged_hits); }
  [[nodiscard]] double see_through_smooth_rate() const {
    return rate(see_through_smooth, judged_hits);
  }
  [[nodiscard]] double early_rate() const { return rate(early, judged_hits); }
  [[nodiscard]] double phantom_rate() const { return rate(phantom, judged_hits + judged_misses); }

 private:
  static double rate(size_t n, size_t of) { return of ? double(n) / double(of) : 0.0; }
};

// The accuracy bounds every method issue states.
struct AccuracyBounds {
  double max_hole_rate = 0.01, max_false_hit_rate = 0.01, max_distance_median_h = 0.1,
         max_distance_p95_h = 0.5, max_normal_median_deg = 3.0;
  [[nodiscard]] bool met_by(const AccuracyReport& r) const {
    return r.hole_rate <= max_hole_rate && r.false_hit_rate <= max_false_hit_rate &&
           r.distance_median_h <= max_distance_median_h && r.distance_p95_h <= max_distance_p95_h &&
           r.normal_median_deg <= max_normal_median_deg;
  }
};

// The q-quantile of v (the element of rank floor(q n), clamped to the last); NaN for none. What
// the accuracy report's medians and 95th percentiles are, and the anchor's frame differences.
double quantile(std::vector<float> v, double q);

// The rays: origins on a sphere three bounding radii around the surface; half aimed at points
// drawn on the surface, half at such points moved along their normal by up to +-10h.
std::vector<Ray> accuracy_rays(const Surface& truth, double h, size_t count, uint64_t seed);

AccuracyReport evaluate_accuracy(const SceneIntersector& scene, const Surface& truth, double h,
                                 const std::vector<Ray>& rays, OpCounters& counters);

// Secondary rays (shadow and bounce rays) against the truth, spawned as the renderer spawns them:
// a probe ray comes down the true normal onto a point drawn on the exact surface (from 4h out);
// where the method hits, the secondary ray leaves that hit in a cosine-distributed direction,
// half around the hit's normal facing the probe (a reflection) and half around the opposite one
// (a transmission), from spawn_point() with the renderer's default epsilon, 1e-3 of the truth's
// bounding diagonal. A *self-hit* is a method hit within 3h of the origin where the truth's first
// hit is farther than 5h beyond it (or absent): the ray hits the surface it leaves. A *missed
// occluder* is a truth hit the method passes (no hit, or a hit more than 5h beyond it). A *false
// occluder* is any other method hit more than 5h before the truth's. Rays whose exact hit is
// grazing (|cos| < 0.1) are not judged; points whose probe finds no method hit within 8h are
// counted as `unprobed` (holes; the accuracy rays judge those).
struct SecondaryReport {
  struct Side {
    size_t rays = 0, self_hits = 0, missed_occluders = 0, false_occluders = 0, unprobed = 0;
    [[nodiscard]] double rate(size_t n) const { return rays ? double(n) / double(rays) : 0.0; }
  };
  Side outward, inward;
};

SecondaryReport evaluate_secondary(const SceneIntersector& scene, const Surface& truth, double h,
                                   size_t count, uint64_t seed, OpCounters& counters);

}  // namespace pcrt
