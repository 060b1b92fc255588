#include "harness/accuracy.hpp"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/rng.hpp"

namespace pcrt {
namespace {

enum class Verdict : uint8_t { kIgnored, kHole, kFalseHit, kGoodMiss, kGoodHit };

struct RayOutcome {
  Verdict verdict = Verdict::kIgnored;
  bool exact_hit = false;
  float distance_h = 0;
  float normal_deg = 0;
};

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

}  // namespace

std::vector<Ray> accuracy_rays(const Surface& truth, double h, size_t count, uint64_t seed) {
  const Aabb b = truth.bounds();
  const float radius = std::max(0.5f * b.diagonal(), 1e-6f);
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

AccuracyReport evaluate_accuracy(const SceneIntersector& scene, const Surface& truth, double h,
                                 const std::vector<Ray>& rays, OpCounters& counters) {
  const float scale = truth.bounds().diagonal();
  const auto hf = float(h);
  std::vector<RayOutcome> out(rays.size());
  tbb::combinable<OpCounters> per_thread;
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
    const Ray& ray = rays[i];
    Hit hit;
    const bool found = scene.closest_hit(ray, hit, per_thread.local());
    float t_true = 0;
    Vec3 n_true;
    RayOutcome& o = out[i];
    o.exact_hit = truth.intersect(ray, t_true, n_true);
    if (o.exact_hit) {
      if (std::abs(n_true.dot(ray.d)) < 0.1f) return;  // grazing: not judged
      if (!found) {
        o.verdict = Verdict::kHole;
        return;
      }
      if ((hit.p - ray.at(t_true)).norm() > 5.0f * hf) {
        o.verdict = Verdict::kFalseHit;
        return;
      }
      o.verdict = Verdict::kGoodHit;
      o.distance_h = std::abs(truth.signed_distance(hit.p)) / hf;
      // Unsigned angle by atan2(|a x b|, |a . b|): acos of a float dot product cannot resolve
      // angles below about 0.02 degrees.
      const Vec3d a = hit.n.normalized().cast<double>(), b = truth.normal(hit.p).cast<double>();
      o.normal_deg = float(std::atan2(a.cross(b).norm(), std::abs(a.dot(b))) * 180.0 / M_PI);
      return;
    }
    if (closest_approach(truth, ray, scale) <= 2.0f * hf) return;  // near miss: not judged
    o.verdict = found ? Verdict::kFalseHit : Verdict::kGoodMiss;
  });
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });

  AccuracyReport r;
  r.rays = rays.size();
  r.mean_spacing = h;
  std::vector<float> dist, angle;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayOutcome& o = out[i];
    switch (o.verdict) {
      case Verdict::kIgnored:
        continue;
      case Verdict::kHole:
        ++r.judged_hits, ++r.holes;
        break;
      case Verdict::kGoodHit:
        ++r.judged_hits;
        dist.push_back(o.distance_h);
        angle.push_back(o.normal_deg);
        break;
      case Verdict::kGoodMiss:
        ++r.judged_misses;
        break;
      case Verdict::kFalseHit:
        ++r.false_hits;
        // A false hit on a ray the surface does hit still counts among the judged hits.
        if (o.exact_hit)
          ++r.judged_hits;
        else
          ++r.judged_misses;
        break;
    }
  }
  auto quantile = [](std::vector<float> v, double q) {
    if (v.empty()) return std::nan("");
    const auto k = size_t(std::min<double>(double(v.size() - 1), q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return double(v[k]);
  };
  r.hole_rate = r.judged_hits ? double(r.holes) / double(r.judged_hits) : 0;
  r.false_hit_rate = (r.judged_hits + r.judged_misses)
                         ? double(r.false_hits) / double(r.judged_hits + r.judged_misses)
                         : 0;
  r.distance_median_h = quantile(dist, 0.5);
  r.distance_p95_h = quantile(dist, 0.95);
  r.normal_median_deg = quantile(angle, 0.5);
  r.normal_p95_deg = quantile(angle, 0.95);
  return r;
}

}  // namespace pcrt
