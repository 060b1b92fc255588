// A method's frame against the truth's frame (a mesh rendered with the same camera, seeds and
// light, B = 0): the image-space accuracy of `pcrt compare`, through the renderer's own code path,
// so a method's primary pass (Tejada's z-buffer) is judged like any traced ray.
#pragma once

#include <cstddef>

#include "core/image.hpp"
#include "render/renderer.hpp"

namespace pcrt {

struct FrameComparison {
  size_t pixels = 0;
  size_t object_pixels = 0;  // pixels where the truth has a primary hit
  size_t missing = 0;        // object pixels the method leaves empty
  size_t extra = 0;          // pixels the method covers where the truth has none
  size_t normal_off = 0;     // pixels both hit with normals more than kNormalOffDeg apart
  // Object pixels at an edge of the truth's frame (background, or a depth jump of more than
  // kContourJump of the pixel's depth, within kEdgeReachPx pixels: silhouettes and occluding
  // contours), and the missing pixels among them: where a frame loses its pixels.
  size_t edge_pixels = 0, missing_at_edges = 0;
  double rmse = 0;  // root mean square radiance error over all pixels (per channel)
  // Lit pixels: object pixels where the truth's radiance is at least kLitFraction of its brightest
  // object pixel's. False shadows among them: the method hits too, with a normal within
  // kNormalOffDeg, but returns less than kDarkFraction of the truth's radiance, so its shadow ray
  // was stopped where the mesh's was not (the shading itself agrees).
  size_t lit_pixels = 0, false_shadow = 0;

  static constexpr float kNormalOffDeg = 30.0f;
  static constexpr int kEdgeReachPx = 2;
  static constexpr float kContourJump = 0.02f;
  static constexpr float kLitFraction = 0.1f;
  static constexpr float kDarkFraction = 0.25f;
  [[nodiscard]] double missing_rate() const { return rate(missing, object_pixels); }
  [[nodiscard]] double extra_rate() const { return rate(extra, object_pixels); }
  [[nodiscard]] double normal_off_rate() const { return rate(normal_off, object_pixels); }
  [[nodiscard]] double false_shadow_rate() const { return rate(false_shadow, lit_pixels); }

 private:
  static double rate(size_t n, size_t of) { return of ? double(n) / double(of) : 0.0; }
};

// Both frames must have the same size (same camera).
FrameComparison compare_frames(const RenderResult& truth, const RenderResult& method);

// The difference picture: missing pixels red, extra pixels blue, normals off yellow, elsewhere
// the absolute radiance difference in grey (amplified 4x so that shading errors show).
Image difference_image(const RenderResult& truth, const RenderResult& method);

}  // namespace pcrt
