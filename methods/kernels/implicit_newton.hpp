// Algorithm 6 (Adams et al. 2005, Hubo et al. 2006/2007): Newton's method on the implicit
// function f(x) = n(x) . (x - p(x)) of a distance-weighted average plane (Eq. 3.22, 3.24). From a
// start t the ray meets the plane (p(x), n(x)) of the current point, which becomes the next
// point: t_{i+1} = t_i - f(r(t_i)) / (n . d), i.e. Eq. 3.24 simplified. O(IK) when each evaluation
// averages K points.
#pragma once

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

// The tolerance (in `unit`) and cap parameters of an iterative method; tolerance 0 runs exactly
// max_iterations, so that a sweep can hold I fixed.
inline std::vector<ParamSpec> iteration_params(double tolerance, double max_tolerance,
                                               const std::string& unit, double max_iterations) {
  return {{"tolerance", tolerance, 0, max_tolerance,
           "residual at convergence, in " + unit + " (0: always run max_iterations)"},
          {"max_iterations", max_iterations, 1, 100, "cap on the iterations I", true}};
}
// Those parameters with the tolerance scaled from `unit` to absolute length.
inline NewtonSettings newton_settings(const ParamValues& p, float unit) {
  return {float(p.at("tolerance")) * unit, int(p.at("max_iterations"))};
}

// Eval(x) returns the WeightedPlane at x. Returns the hit t in [t_lo, t_hi] (and the unit normal)
// or +inf: when no point reaches the current point, the plane is parallel to the ray, a step
// leaves the interval (Algorithm 6, lines 11-14), or the cap is reached before the tolerance.
template <typename Eval>
float newton_on_weighted_plane(const Ray& ray, float t, float t_lo, float t_hi, Eval&& eval,
                               const NewtonSettings& s, Vec3& normal, OpCounters& counters) {
  counters.add(kNewtonRuns);
  for (int i = 0; i < s.max_iterations; ++i) {
    counters.add(kNewtonSteps);
    const Vec3 x = ray.at(t);
    const WeightedPlane w = eval(x);
    const float len = w.n.norm();
    if (!(w.weight > 0) || !(len > 0)) return kInfinity;
    normal = w.n / len;
    const float f = normal.dot(x - w.p);
    if (s.tolerance > 0 && std::abs(f) <= s.tolerance) {
      counters.add(kNewtonConverged);
      return t;
    }
    const float slope = normal.dot(ray.d);
    if (std::abs(slope) < 1e-6f) return kInfinity;
    t -= f / slope;
    if (!(t >= t_lo && t <= t_hi)) return kInfinity;
  }
  counters.add(kNewtonCapped);
  return s.tolerance > 0 ? kInfinity : t;
}

}  // namespace pcrt
