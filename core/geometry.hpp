// Rays and hits: the vocabulary every structure and method shares.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pcrt {

using Vec3 = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr uint32_t kNoPrim = ~uint32_t{0};

// r(t) = o + d t for t in [tmin, tmax]; d is unit length so t is a distance.
struct Ray {
  Vec3 o = Vec3::Zero();
  Vec3 d = Vec3::UnitZ();
  float tmin = 0.0f;
  float tmax = kInfinity;

  [[nodiscard]] Vec3 at(float t) const { return o + t * d; }
};

// The closest hit found so far. `prim` is the point that decided the hit (for colour lookup);
// methods that blend several points name the one nearest to the hit.
struct Hit {
  float t = kInfinity;
  Vec3 p = Vec3::Zero();
  Vec3 n = Vec3::UnitZ();
  uint32_t prim = kNoPrim;
  // Size of the surface element that produced the hit (a splat's radius, a leaf's point spacing).
  // The renderer lifts secondary rays off the surface by half of it: neighbouring splats of a
  // curved surface stand above the hit point by up to about radius^2 * curvature.
  float footprint = 0;

  [[nodiscard]] bool found() const { return prim != kNoPrim; }
};

// An orthonormal basis around a unit vector (Duff et al. 2017), for local frames and sampling.
inline void orthonormal_basis(const Vec3& n, Vec3& u, Vec3& v) {
  const float sign = n.z() >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z());
  const float b = n.x() * n.y() * a;
  u = Vec3(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  v = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

// The largest power of two not above `length` (1 for zero, NaN or inf): a unit a computation
// divides its lengths by, exactly, so that products of several lengths neither overflow nor
// underflow however large or small the cloud (and are the same floats, scaled, where they did not).
inline float length_unit(float length) {
  if (!(length > 0) || !std::isfinite(length)) return 1.0f;
  return std::ldexp(1.0f, std::ilogb(length));
}

// A size for what has none: `size` where positive, else `fallback` (a single point's bounds, which
// a camera frames and a ray lift needs a scale for). A floor would frame a small cloud as a speck.
inline float positive_or(float size, float fallback) { return size > 0 ? size : fallback; }

}  // namespace pcrt
