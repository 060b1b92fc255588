#include "render/compare.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace pcrt {
namespace {

enum class PixelVerdict : uint8_t { kEmpty, kMissing, kExtra, kNormalOff, kAgree };

PixelVerdict judge(const RenderResult& truth, const RenderResult& method, size_t i) {
  const bool t = std::isfinite(truth.primary_t[i]), m = std::isfinite(method.primary_t[i]);
  if (t && !m) return PixelVerdict::kMissing;
  if (!t && m) return PixelVerdict::kExtra;
  if (!t) return PixelVerdict::kEmpty;
  const Vec3 &a = truth.primary_n[i], &b = method.primary_n[i];
  const float deg = std::atan2(a.cross(b).norm(), a.dot(b)) * float(180.0 / M_PI);
  return deg > FrameComparison::kNormalOffDeg ? PixelVerdict::kNormalOff : PixelVerdict::kAgree;
}

// Whether the truth's pixel (x, y) has background or an occluding contour within kEdgeReachPx.
bool at_edge(const RenderResult& truth, int width, int height, int x, int y) {
  const float t = truth.primary_t[size_t(y) * size_t(width) + size_t(x)];
  constexpr int r = FrameComparison::kEdgeReachPx;
  for (int ny = std::max(y - r, 0); ny <= std::min(y + r, height - 1); ++ny)
    for (int nx = std::max(x - r, 0); nx <= std::min(x + r, width - 1); ++nx) {
      const float u = truth.primary_t[size_t(ny) * size_t(width) + size_t(nx)];
      if (!std::isfinite(u) || std::abs(u - t) > FrameComparison::kContourJump * t) return true;
    }
  return false;
}

float brightest_object_pixel(const RenderResult& truth) {
  float brightest = 0;
  for (size_t i = 0; i < truth.primary_t.size(); ++i)
    if (std::isfinite(truth.primary_t[i]))
      brightest = std::max(brightest, truth.image.pixels()[i].mean());
  return brightest;
}

// Lit in the truth's frame, and whether the method's agreeing hit is dark there (FrameComparison).
void count_shadow(const RenderResult& truth, const RenderResult& method, size_t i, float lit_from,
                  PixelVerdict v, FrameComparison& c) {
  const float t = truth.image.pixels()[i].mean();
  if (!std::isfinite(truth.primary_t[i]) || !(t >= lit_from) || t <= 0) return;
  ++c.lit_pixels;
  c.false_shadow += v == PixelVerdict::kAgree &&
                    method.image.pixels()[i].mean() < FrameComparison::kDarkFraction * t;
}

}  // namespace

FrameComparison compare_frames(const RenderResult& truth, const RenderResult& method) {
  assert(truth.primary_t.size() == method.primary_t.size());
  FrameComparison c;
  c.pixels = truth.primary_t.size();
  double sq = 0;
  const auto& ti = truth.image.pixels();
  const auto& mi = method.image.pixels();
  const int w = truth.image.width(), h = truth.image.height();
  const float lit_from = FrameComparison::kLitFraction * brightest_object_pixel(truth);
  for (size_t i = 0; i < c.pixels; ++i) {
    const bool object = std::isfinite(truth.primary_t[i]);
    const bool edge = object && at_edge(truth, w, h, int(i % size_t(w)), int(i / size_t(w)));
    c.object_pixels += object;
    c.edge_pixels += edge;
    const PixelVerdict v = judge(truth, method, i);
    count_shadow(truth, method, i, lit_from, v, c);
    switch (v) {
      case PixelVerdict::kMissing:
        ++c.missing;
        c.missing_at_edges += edge;
        break;
      case PixelVerdict::kExtra:
        ++c.extra;
        break;
      case PixelVerdict::kNormalOff:
        ++c.normal_off;
        break;
      case PixelVerdict::kEmpty:
      case PixelVerdict::kAgree:
        break;
    }
    sq += (ti[i] - mi[i]).squaredNorm() / 3.0;
  }
  c.rmse = c.pixels ? std::sqrt(sq / double(c.pixels)) : 0.0;
  return c;
}

Image difference_image(const RenderResult& truth, const RenderResult& method) {
  const int w = truth.image.width(), h = truth.image.height();
  Image out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      Vec3& o = out.at(x, y);
      switch (judge(truth, method, i)) {
        case PixelVerdict::kMissing:
          o = Vec3(1, 0, 0);
          break;
        case PixelVerdict::kExtra:
          o = Vec3(0, 0.3f, 1);
          break;
        case PixelVerdict::kNormalOff:
          o = Vec3(1, 0.9f, 0);
          break;
        case PixelVerdict::kEmpty:
        case PixelVerdict::kAgree:
          const float d = (truth.image.at(x, y) - method.image.at(x, y)).cwiseAbs().mean();
          o = Vec3::Constant(std::min(1.0f, 4.0f * d));
          break;
      }
    }
  return out;
}

}  // namespace pcrt
