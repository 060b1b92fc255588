// Sampling routines the BSDFs, lights and integrator share: warps of the unit square to
// directions with their densities, and the power heuristic of multiple importance sampling.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/geometry.hpp"
#include "core/rng.hpp"

namespace pcrt {

using Vec2 = Eigen::Vector2f;

inline constexpr float kPi = 3.14159265358979f;
inline constexpr float kInvPi = 0.318309886183791f;

// Two uniform numbers in the order drawn (a constructor's arguments have no evaluation order).
inline Vec2 uniform2(Rng& rng) {
  const float a = rng.uniform();
  const float b = rng.uniform();
  return {a, b};
}

// Cosine-weighted direction about +z (Malley's method on a concentric disk would also do; the
// polar map keeps the renderer's random-number use and its images unchanged). pdf = cos / pi.
inline Vec3 cosine_hemisphere(const Vec2& u) {
  const float r = std::sqrt(u.x());
  const float phi = 2.0f * kPi * u.y();
  return Vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x())));
}

// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
inline Vec3 uniform_sphere(const Vec2& u) {
  const float z = 1.0f - 2.0f * u.x();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y();
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Uniform direction in the cone of half-angle acos(cos_max) about +z; pdf = 1 / (2 pi (1 -
// cos_max)).
inline Vec3 uniform_cone(const Vec2& u, float cos_max) {
  const float cos_t = 1.0f - u.x() * (1.0f - cos_max);
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  const float phi = 2.0f * kPi * u.y();
  return Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}

// Veach's power heuristic (beta = 2) for one sample from each of two strategies.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0 ? a / (a + b) : 0.0f;
}

// The local shading frame about a unit normal: to_local and to_world are each other's inverse.
struct Frame3 {
  Vec3 s, t, n;
  explicit Frame3(const Vec3& normal) : n(normal) { orthonormal_basis(n, s, t); }
  [[nodiscard]] Vec3 to_local(const Vec3& v) const { return Vec3(v.dot(s), v.dot(t), v.dot(n)); }
  [[nodiscard]] Vec3 to_world(const Vec3& v) const { return v.x() * s + v.y() * t + v.z() * n; }
};

}  // namespace pcrt
