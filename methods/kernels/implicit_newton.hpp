// Algorithm 6 (Adams et al. 2005, Hubo et al. 2006/2007): Newton's method on the implicit
// function f(x) = n(x) . (x - p(x)) of a distance-weighted average plane (Eq. 3.22, 3.24). From a
// start t the ray meets the plane (p(x), n(x)) of the current point, which becomes the next
// point: t_{i+1} = t_i - f(r(t_i)) / (n . d), i.e. Eq. 3.24 simplified. O(IK) when each evaluation
// averages K points.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "core/params.hpp"
#include "methods/kernels/weighted_plane.hpp"

namespace pcrt {

inline const Counter kNewtonRuns{"newton_runs", "Newton iterations started (Algorithm 6)"};
inline const Counter kNewtonSteps{"newton_steps", "Newton steps (one weighted average each)"};
inline const Counter kNewtonConverged{"newton_converged", "Newton runs that met the tolerance"};
inline const Counter kNewtonCapped{"newton_capped", "Newton runs stopped by the iteration cap"};

struct NewtonSettings {
  float tolerance = 0;  // |f| at convergence (absolute); 0: run exactly max_iterations
  int max_iterations = 10;
};

// The tolerance (in a method's own unit) and cap of an iterative method; tolerance 0 runs exactly
// max_iterations, so that a sweep can hold I fixed.
struct IterationParams {
  float tolerance = 0;
  int max_iterations = 10;
  // The declaration with the method's own defaults and unit.
  static ParamList<IterationParams> list(double tolerance, double max_tolerance,
                                         const std::string& unit, double max_iterations) {
    using P = IterationParams;
    return ParamList<P>()
        .add(&P::tolerance,
             {"tolerance", tolerance, 0, max_tolerance,
              "residual at convergence, in " + unit + " (0: always run max_iterations)"})
        .add(&P::max_iterations,
             {"max_iterations", max_iterations, 1, 100, "cap on the iterations I"});
  }
};
// Those parameters with the tolerance scaled from its unit to absolute length.
inline NewtonSettings newton_settings(const IterationParams& p, float unit) {
  return {p.tolerance * unit, p.max_iterations};
}

// The sign-change interval of f seen so far along the ray, once Newton has stood on both sides of
// the surface. The plane's slope n . d ignores how the weighted average p(x) moves with x, so on a
// tilted or curved surface every full step overshoots: a 2-cycle around the root (the cap then
// reports a hole and the ray goes on to the surface behind), or an oscillation that shrinks by
// only ~0.8 per step and misses the tolerance at the cap (1.2% of the noisy bunny's rays). Inside
// a sign change the step is therefore the bracket's secant (false position, Illinois variant:
// an end kept twice has its f halved, so neither end stalls), which measures the true slope.
class NewtonBracket {
 public:
  void add(float t, float f) {
    const bool positive = f > 0;
    if (bracketed() && positive == last_positive_) (positive ? f_neg_ : f_pos_) *= 0.5f;
    (positive ? pos_ : neg_) = t;
    (positive ? f_pos_ : f_neg_) = f;
    last_positive_ = positive;
  }
  [[nodiscard]] bool bracketed() const { return pos_ != kInfinity && neg_ != kInfinity; }
  // The Newton step `next` while there is no bracket, else the bracket's secant root.
  [[nodiscard]] float safeguard(float next) const {
    if (!bracketed()) return next;
    return pos_ + (neg_ - pos_) * f_pos_ / (f_pos_ - f_neg_);
  }

 private:
  float pos_ = kInfinity, neg_ = kInfinity, f_pos_ = 0, f_neg_ = 0;
  bool last_positive_ = false;
};

// Eval(x) returns the WeightedPlane at x. Returns the hit t in [t_lo, t_hi] (and the unit normal)
// or +inf: when no point reaches the start, the plane is parallel to the ray, a step leaves the
// interval from its bound (Algorithm 6, lines 11-14), or the cap is reached before the tolerance.
// Two safeguards keep a step that overshoots from ending the search (the plane's slope ignores
// how p(x) moves with x, so near grazing angles one step can jump over the surface): a step out
// of the interval stops at its bound first, and a step to where no point reaches (behind the
// surface, beyond the weights' support) is halved back toward the last point that had a plane.
// Inside a sign change, steps are held by NewtonBracket.
template <typename Eval>
float newton_on_weighted_plane(const Ray& ray, float t, float t_lo, float t_hi, Eval&& eval,
                               const NewtonSettings& s, Vec3& normal, OpCounters& counters) {
  counters.add(kNewtonRuns);
  NewtonBracket bracket;
  float t_valid = kInfinity;  // the last t where some point had weight
  for (int i = 0; i < s.max_iterations; ++i) {
    counters.add(kNewtonSteps);
    const Vec3 x = ray.at(t);
    const WeightedPlane w = eval(x);
    const float len = w.n.norm();
    if (!(w.weight > 0) || !(len > 0)) {
      if (t_valid == kInfinity) return kInfinity;
      t = 0.5f * (t_valid + t);
      continue;
    }
    t_valid = t;
    normal = w.n / len;
    const float f = normal.dot(x - w.p);
    if (s.tolerance > 0 && std::abs(f) <= s.tolerance) {
      counters.add(kNewtonConverged);
      return t;
    }
    const float slope = normal.dot(ray.d);
    if (std::abs(slope) < 1e-6f) return kInfinity;
    if (f != 0) bracket.add(t, f);
    const float next = bracket.safeguard(t - f / slope);
    if (next >= t_lo && next <= t_hi) {
      t = next;
      continue;
    }
    const float bound = next < t_lo ? t_lo : t_hi;
    if (t == bound || !(next == next)) return kInfinity;
    t = bound;
  }
  counters.add(kNewtonCapped);
  return s.tolerance > 0 ? kInfinity : t;
}

}  // namespace pcrt
