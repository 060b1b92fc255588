// 3D Gaussian particles (3D Gaussian Splatting, Kerbl et al. 2023) as a point attribute set: per
// point a scale along each of three rotated axes, a rotation and a peak opacity; the point's
// position is the mean and its colour the zeroth spherical-harmonic band. Stored activated (the
// files hold log scales, opacity logits and unnormalised quaternions), so every reader and
// method sees one meaning.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "core/geometry.hpp"

namespace pcrt {

using Vec4 = Eigen::Vector4f;
using Mat3 = Eigen::Matrix3f;

struct GaussianParticles {
  std::vector<Vec3> scales;      // standard deviations along the particle's axes, > 0
  std::vector<Vec4> rotations;   // unit quaternions (w, x, y, z): the axes are its matrix's columns
  std::vector<float> opacities;  // peak opacity in [0, 1]

  [[nodiscard]] size_t size() const { return scales.size(); }
  [[nodiscard]] bool empty() const { return scales.empty(); }
  void clear() {
    scales.clear();
    rotations.clear();
    opacities.clear();
  }
};

// The 3D Gaussian Splatting file layout's activations and their inverses.
inline float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }
inline float logit(float p) { return std::log(p / (1.0f - p)); }
// The zeroth band's constant, 1 / (2 sqrt(pi)): colour = 0.5 + kShC0 * f_dc.
inline constexpr float kShC0 = 0.28209479177387814f;

// The rotation of a unit quaternion (w, x, y, z).
inline Mat3 rotation_matrix(const Vec4& q) {
  return Eigen::Quaternionf(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

// The axis of a particle's smallest scale: the normal of the surface a flat particle lies in.
inline Vec3 shortest_axis(const Vec3& scale, const Vec4& rotation) {
  int axis = 0;
  scale.minCoeff(&axis);
  return rotation_matrix(rotation).col(axis).normalized();
}

}  // namespace pcrt
