#include "harness/compare.hpp"

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

}  // namespace

FrameComparison compare_frames(const RenderResult& truth, const RenderResult& method) {
  assert(truth.primary_t.size() == method.primary_t.size());
  FrameComparison c;
  c.pixels = truth.primary_t.size();
  double sq = 0;
  const auto& ti = truth.image.pixels();
  const auto& mi = method.image.pixels();
  for (size_t i = 0; i < c.pixels; ++i) {
    c.object_pixels += std::isfinite(truth.primary_t[i]);
    switch (judge(truth, method, i)) {
      case PixelVerdict::kMissing:
        ++c.missing;
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
