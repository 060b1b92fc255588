// A pinhole camera over a width x height virtual screen (M = width * height pixels).
#pragma once

#include <cmath>

#include "core/aabb.hpp"
#include "core/geometry.hpp"

namespace pcrt {

class Camera {
 public:
  Camera(const Vec3& eye, const Vec3& target, const Vec3& up, float vfov_degrees, int width,
         int height)
      : eye_(eye), width_(width), height_(height) {
    forward_ = (target - eye).normalized();
    right_ = forward_.cross(up).normalized();
    if (!right_.allFinite()) right_ = forward_.cross(Vec3::UnitX()).normalized();
    up_ = right_.cross(forward_);
    tan_half_ = std::tan(0.5f * vfov_degrees * 3.14159265358979f / 180.0f);
    aspect_ = static_cast<float>(width) / static_cast<float>(height);
  }

  // Looks at the centre of `bounds` from direction `view_dir`, far enough that the bounding
  // sphere fills the frame.
  static Camera framing(const Aabb& bounds, int width, int height,
                        const Vec3& view_dir = Vec3(0.55f, -0.75f, 0.4f),
                        const Vec3& up = Vec3::UnitZ(), float vfov = 35.0f) {
    const Vec3 c = bounds.center();
    const float r = positive_or(0.5f * bounds.diagonal(), 1e-6f);
    const float dist = 1.05f * r / std::sin(0.5f * vfov * 3.14159265358979f / 180.0f);
    return Camera(c + dist * view_dir.normalized(), c, up, vfov, width, height);
  }

  // Ray through the film position (px, py) in pixels, (0,0) top left.
  [[nodiscard]] Ray ray(float px, float py) const {
    const float sx = (2.0f * px / static_cast<float>(width_) - 1.0f) * tan_half_ * aspect_;
    const float sy = (1.0f - 2.0f * py / static_cast<float>(height_)) * tan_half_;
    Ray r;
    r.o = eye_;
    r.d = (forward_ + sx * right_ + sy * up_).normalized();
    return r;
  }
  // The inverse of ray(): film position and distance along the view axis of the point x; false
  // if x is not in front of the camera.
  bool project(const Vec3& x, float& px, float& py, float& depth) const {
    const Vec3 d = x - eye_;
    depth = d.dot(forward_);
    if (!(depth > 0)) return false;
    const float sx = d.dot(right_) / depth, sy = d.dot(up_) / depth;
    px = (sx / (tan_half_ * aspect_) + 1.0f) * 0.5f * static_cast<float>(width_);
    py = (1.0f - sy / tan_half_) * 0.5f * static_cast<float>(height_);
    return true;
  }
  // Pixels per unit length at distance 1 along the view axis.
  [[nodiscard]] float pixels_per_unit() const {
    return 0.5f * static_cast<float>(height_) / tan_half_;
  }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] const Vec3& eye() const { return eye_; }

 private:
  Vec3 eye_, forward_, right_, up_;
  float tan_half_ = 1.0f, aspect_ = 1.0f;
  int width_, height_;
};

}  // namespace pcrt
