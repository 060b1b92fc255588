#include "render/accuracy.hpp"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/rng.hpp"
#include "render/renderer.hpp"

namespace pcrt {
namespace {

// kSeeThrough, kEarly and kPhantom are false hits on rays the surface does hit; kMissPhantom is
// a hit on a ray that passes the surface by more than 2h.
enum class Verdict : uint8_t {
  kIgnored,
  kHole,
  kSeeThrough,
  kEarly,
  kPhantom,
  kMissPhantom,
  kGoodMiss,
  kGoodHit
};

enum class Feature : uint8_t { kOpen, kThin, kCrease };

struct RayOutcome {
  Verdict verdict = Verdict::kIgnored;
  Feature feature = Feature::kOpen;  // of the shape at the exact first hit
  bool phantom_near_crease = false;
  bool normal_judged = false;  // the surface is smooth within 2h of the exact hit
  float spread_deg = 0;        // normal spread within kFeatureReachH of the exact hit
  float distance_h = 0;
  float normal_deg = 0;         // to the true normal (judged only where smooth)
  float smooth_normal_deg = 0;  // to the smooth normal
  float floor_deg = 0;          // true normal to smooth normal at the exact hit
};

// Unsigned angle by atan2(|a x b|, |a . b|): acos of a float dot product cannot resolve angles
// below about 0.02 degrees.
float unsigned_angle_deg(const Vec3& a, const Vec3& b) {
  const Vec3d x = a.normalized().cast<double>(), y = b.normalized().cast<double>();
  return float(std::atan2(x.cross(y).norm(), std::abs(x.dot(y))) * 180.0 / M_PI);
}

// Why a method's hit more than 5h from the exact first hit is wrong: behind it (the front surface
// was missed), in front of it near the surface (fattened), or in empty space.
Verdict false_hit_cause(const Surface& truth, const Hit& hit, float t_true, float h) {
  if (hit.t > t_true) return Verdict::kSeeThrough;
  return std::abs(truth.signed_distance(hit.p)) <= 2.0f * h ? Verdict::kEarly : Verdict::kPhantom;
}

// Smallest |signed distance| along the ray inside the surface's bounds: sphere tracing never
// steps past the surface, and the minimum of the visited values bounds how close the ray passes.
float closest_approach(const Surface& truth, const Ray& ray, float scale) {
  Aabb box = truth.bounds();
  box.lo -= Vec3::Constant(0.1f * scale);
  box.hi += Vec3::Constant(0.1f * scale);
  float t0 = 0, t1 = 0;
  if (!box.intersect(ray, ray.d.cwiseInverse(), t0, t1)) return kInfinity;
  float best = kInfinity;
  float t = t0;
  for (int i = 0; i < 20000 && t <= t1; ++i) {
    const float d = std::abs(truth.signed_distance(ray.at(t)));
    best = std::min(best, d);
    t += std::max(0.5f * d, 1e-4f * scale);
  }
  return best;
}

// The shape at an exact hit p whose normal spread within kFeatureReachH is `spread_deg`: the
// wall's thickness is the distance to the back side along the inward normal (rays leaving p
// inward, like a shadow ray's exit).
Feature feature_at(const Surface& truth, const Vec3& p, float h, float spread_deg) {
  if (spread_deg > Surface::kSmoothAngleDeg) return Feature::kCrease;
  const Vec3 n_out = truth.normal(p);
  float t = 0;
  Vec3 n;
  const Ray inward{p, -n_out, 0.01f * h, FeatureSplit::kThinWallH * h};
  return truth.intersect(inward, t, n) ? Feature::kThin : Feature::kOpen;
}

// Judged at the phantom's nearest surface point (smooth_at centres its ball there): adding the
// phantom's distance to the reach, as before issue 30, called a splat standing 20 h off a face
// "near" every crease within 23.5 h of that face.
bool near_crease(const Surface& truth, const Vec3& phantom, float h) {
  return !truth.smooth_at(phantom, FeatureSplit::kFeatureReachH * h);
}

void count_feature(FeatureSplit& split, Feature f) {
  switch (f) {
    case Feature::kOpen:
      ++split.open;
      break;
    case Feature::kThin:
      ++split.thin;
      break;
    case Feature::kCrease:
      ++split.crease;
      break;
  }
}

}  // namespace

SpreadBands empty_spread_bands() {
  SpreadBands bands;
  for (size_t k = 0; k < bands.size(); ++k)
    bands[k].lo_deg = kSpreadEdgesDeg[k], bands[k].hi_deg = kSpreadEdgesDeg[k + 1];
  return bands;
}

std::vector<Ray> accuracy_rays(const Surface& truth, double h, size_t count, uint64_t seed) {
  const Aabb b = truth.bounds();
  const float radius = positive_or(0.5f * b.diagonal(), 1e-6f);
  std::vector<Ray> rays(count);
  for (size_t i = 0; i < count; ++i) {
    Rng rng(seed, i);
    Vec3 n;
    Vec3 target = truth.sample(rng, n);
    if (i % 2 == 1) target += float((2.0 * rng.uniform_double() - 1.0) * 10.0 * h) * n;
    Vec3 dir;
    do dir = Vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    while (dir.squaredNorm() > 1 || dir.squaredNorm() < 1e-3f);
    const Vec3 origin = b.center() + 3.0f * radius * dir.normalized();
    rays[i] = Ray{origin, (target - origin).normalized()};
  }
  return rays;
}

namespace {

// One ray judged against the exact surface: the method's closest hit compared with the exact
// first hit (or, on a ray that misses the surface by more than 2h, with none).
RayOutcome judge_ray(const SceneIntersector& scene, const Surface& truth, const Ray& ray, float hf,
                     float scale, OpCounters& counters) {
  Hit hit;
  const bool found = scene.closest_hit(ray, hit, counters);
  float t_true = 0;
  Vec3 n_true;
  RayOutcome o;
  if (!truth.intersect(ray, t_true, n_true)) {
    if (closest_approach(truth, ray, scale) <= 2.0f * hf) return o;  // near miss: not judged
    o.verdict = found ? Verdict::kMissPhantom : Verdict::kGoodMiss;
    if (found) o.phantom_near_crease = near_crease(truth, hit.p, hf);
    return o;
  }
  if (std::abs(n_true.dot(ray.d)) < 0.1f) return o;  // grazing: not judged
  const Vec3 p_true = ray.at(t_true);
  o.spread_deg = truth.normal_spread_deg(p_true, FeatureSplit::kFeatureReachH * hf);
  o.feature = feature_at(truth, p_true, hf, o.spread_deg);
  o.normal_judged = truth.smooth_at(p_true, 2.0f * hf);  // (for a false hit: smooth where missed?)
  if (!found) {
    o.verdict = Verdict::kHole;
  } else if ((hit.p - p_true).norm() > 5.0f * hf) {
    o.verdict = false_hit_cause(truth, hit, t_true, hf);
    if (o.verdict == Verdict::kPhantom) o.phantom_near_crease = near_crease(truth, hit.p, hf);
  } else {
    o.verdict = Verdict::kGoodHit;
    o.distance_h = std::abs(truth.signed_distance(hit.p)) / hf;
    o.normal_deg = unsigned_angle_deg(hit.n, truth.normal(hit.p));
    o.smooth_normal_deg = unsigned_angle_deg(hit.n, truth.smooth_normal(hit.p));
    o.floor_deg = unsigned_angle_deg(n_true, truth.smooth_normal(p_true));
  }
  return o;
}

// The per-hit values whose quantiles the report gives.
struct HitSamples {
  std::vector<float> distance, angle, smooth_angle, floor;
};

// A false hit on a ray the surface does hit still counts among the judged hits.
void count_false_hit(const RayOutcome& o, AccuracyReport& r) {
  ++r.judged_hits, ++r.false_hits;
  count_feature(r.judged_split, o.feature);
  if (o.verdict == Verdict::kSeeThrough) {
    ++r.see_through;
    r.see_through_smooth += o.normal_judged;
    count_feature(r.see_through_split, o.feature);
  } else if (o.verdict == Verdict::kEarly) {
    ++r.early;
  } else {
    ++r.phantom;
    r.phantom_near_crease += o.phantom_near_crease;
  }
}

// A ray with an exact hit, counted in the band of the normal spread there.
void count_band(const RayOutcome& o, AccuracyReport& r) {
  if (o.verdict == Verdict::kIgnored || o.verdict == Verdict::kGoodMiss ||
      o.verdict == Verdict::kMissPhantom)
    return;
  size_t k = 0;
  while (k + 1 < r.spread_bands.size() && o.spread_deg >= r.spread_bands[k].hi_deg) ++k;
  SpreadBand& b = r.spread_bands[k];
  ++b.judged_hits;
  b.holes += o.verdict == Verdict::kHole;
  b.see_through += o.verdict == Verdict::kSeeThrough;
  b.early += o.verdict == Verdict::kEarly;
  b.phantom += o.verdict == Verdict::kPhantom;
  if (o.feature != Feature::kThin) return;
  ++b.thin_hits;
  b.thin_failures += o.verdict == Verdict::kHole || o.verdict == Verdict::kSeeThrough ||
                     o.verdict == Verdict::kPhantom;
}

void count_outcome(const RayOutcome& o, AccuracyReport& r, HitSamples& samples) {
  count_band(o, r);
  switch (o.verdict) {
    case Verdict::kIgnored:
      return;
    case Verdict::kHole:
      ++r.judged_hits, ++r.holes;
      count_feature(r.hole_split, o.feature);
      count_feature(r.judged_split, o.feature);
      return;
    case Verdict::kGoodHit:
      ++r.judged_hits;
      count_feature(r.judged_split, o.feature);
      samples.distance.push_back(o.distance_h);
      samples.smooth_angle.push_back(o.smooth_normal_deg);
      if (o.normal_judged) {
        ++r.normal_judged;
        samples.angle.push_back(o.normal_deg);
        samples.floor.push_back(o.floor_deg);
      }
      return;
    case Verdict::kGoodMiss:
      ++r.judged_misses;
      return;
    case Verdict::kSeeThrough:
    case Verdict::kEarly:
    case Verdict::kPhantom:
      count_false_hit(o, r);
      return;
    case Verdict::kMissPhantom:
      ++r.judged_misses, ++r.false_hits, ++r.phantom;
      r.phantom_near_crease += o.phantom_near_crease;
      return;
  }
}

void summarise(const HitSamples& samples, AccuracyReport& r) {
  r.hole_rate = r.judged_hits ? double(r.holes) / double(r.judged_hits) : 0;
  const size_t judged = r.judged_hits + r.judged_misses;
  r.false_hit_rate = judged ? double(r.false_hits) / double(judged) : 0;
  r.distance_median_h = quantile(samples.distance, 0.5);
  r.distance_p95_h = quantile(samples.distance, 0.95);
  r.normal_median_deg = quantile(samples.angle, 0.5);
  r.normal_p95_deg = quantile(samples.angle, 0.95);
  r.smooth_normal_median_deg = quantile(samples.smooth_angle, 0.5);
  r.faceting_floor_deg = quantile(samples.floor, 0.5);
}

}  // namespace

AccuracyReport evaluate_accuracy(const SceneIntersector& scene, const Surface& truth, double h,
                                 const std::vector<Ray>& rays, OpCounters& counters) {
  const float scale = truth.bounds().diagonal();
  std::vector<RayOutcome> out(rays.size());
  tbb::combinable<OpCounters> per_thread;
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
    out[i] = judge_ray(scene, truth, rays[i], float(h), scale, per_thread.local());
  });
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });
  AccuracyReport r;
  r.rays = rays.size();
  r.mean_spacing = h;
  HitSamples samples;
  for (const RayOutcome& o : out) count_outcome(o, r, samples);
  summarise(samples, r);
  return r;
}

namespace {

enum class SecondaryVerdict : uint8_t {
  kIgnored,
  kUnprobed,
  kRight,
  kSelfHit,
  kMissedOccluder,
  kFalse
};

SecondaryVerdict judge_secondary(const Ray& ray, bool found, const Hit& hit, const Surface& truth,
                                 float h) {
  float t_true = kInfinity;
  Vec3 n_true;
  const bool exact = truth.intersect(ray, t_true, n_true);
  if (exact && std::abs(n_true.dot(ray.d)) < 0.1f) return SecondaryVerdict::kIgnored;
  if (!exact) t_true = kInfinity;
  if (!found) return exact ? SecondaryVerdict::kMissedOccluder : SecondaryVerdict::kRight;
  if (hit.t > t_true + 5.0f * h) return SecondaryVerdict::kMissedOccluder;
  if (hit.t >= t_true - 5.0f * h) return SecondaryVerdict::kRight;
  return hit.t < 3.0f * h ? SecondaryVerdict::kSelfHit : SecondaryVerdict::kFalse;
}

// One secondary ray, spawned from the method's own hit of a probe onto a true surface point.
SecondaryVerdict secondary_ray(const SceneIntersector& scene, const Surface& truth, float h,
                               float epsilon, bool outward, Rng& rng, OpCounters& counters) {
  Vec3 n;
  const Vec3 p = truth.sample(rng, n);
  const Ray probe{p + 4.0f * h * n, -n, 0.0f, 8.0f * h};
  Hit surface;
  const bool probed = scene.closest_hit(probe, surface, counters);
  const Vec3 facing = surface.n.dot(probe.d) > 0 ? Vec3(-surface.n) : surface.n;
  const Vec3 d = cosine_direction(outward ? facing : Vec3(-facing), rng);
  if (!probed) return SecondaryVerdict::kUnprobed;
  const Ray ray{spawn_point(surface, facing, d, epsilon), d, 0.0f, kInfinity};
  Hit hit;
  const bool found = scene.closest_hit(ray, hit, counters);
  return judge_secondary(ray, found, hit, truth, h);
}

void count_secondary(SecondaryVerdict v, SecondaryReport::Side& side) {
  switch (v) {
    case SecondaryVerdict::kIgnored:
      return;
    case SecondaryVerdict::kUnprobed:
      ++side.unprobed;
      return;
    case SecondaryVerdict::kRight:
      break;
    case SecondaryVerdict::kSelfHit:
      ++side.self_hits;
      break;
    case SecondaryVerdict::kMissedOccluder:
      ++side.missed_occluders;
      break;
    case SecondaryVerdict::kFalse:
      ++side.false_occluders;
      break;
  }
  ++side.rays;
}

}  // namespace

SecondaryReport evaluate_secondary(const SceneIntersector& scene, const Surface& truth, double h,
                                   size_t count, uint64_t seed, OpCounters& counters) {
  const auto hf = float(h);
  const float epsilon =
      1e-3f * positive_or(truth.bounds().diagonal(), 1e-6f);  // render()'s default
  std::vector<SecondaryVerdict> out(count);
  tbb::combinable<OpCounters> per_thread;
  tbb::parallel_for(size_t(0), count, [&](size_t i) {
    Rng rng(seed ^ 0x5ec0d, i);
    out[i] = secondary_ray(scene, truth, hf, epsilon, i % 2 == 0, rng, per_thread.local());
  });
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });
  SecondaryReport r;
  for (size_t i = 0; i < count; ++i) count_secondary(out[i], i % 2 == 0 ? r.outward : r.inward);
  return r;
}

double quantile(std::vector<float> v, double q) {
  if (v.empty()) return std::nan("");
  const auto k = size_t(std::min<double>(double(v.size() - 1), q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return double(v[k]);
}

}  // namespace pcrt
