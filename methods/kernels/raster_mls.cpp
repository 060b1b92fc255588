#include "methods/kernels/raster_mls.hpp"

#include <algorithm>
#include <cmath>

#include "methods/kernels/mls_method_params.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

// Each point drawn as a screen-space disc of its world footprint; the nearest point centre wins
// each pixel. O(N + pixels touched), sequential so that the buffer is the same for any thread
// count.
class ZBufferPass final : public PrimaryPass {
 public:
  ZBufferPass(const RasterMlsMethod& method, const Camera& camera, std::span<const Vec3> points,
              float footprint, OpCounters& counters)
      : method_(method), width_(camera.width()), height_(camera.height()) {
    depth_.assign(size_t(width_) * size_t(height_), kInfinity);
    index_.assign(depth_.size(), kNone);
    const float ppu = camera.pixels_per_unit();
    uint64_t pixels = 0;
    for (uint32_t i = 0; i < points.size(); ++i) {
      float px = 0, py = 0, z = 0;
      if (!camera.project(points[i], px, py, z)) continue;
      const float r = std::max(footprint * ppu / z, 0.5f);
      const int x0 = std::max(int(std::floor(px - r)), 0), x1 = std::min(int(px + r), width_ - 1);
      const int y0 = std::max(int(std::floor(py - r)), 0), y1 = std::min(int(py + r), height_ - 1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const float dx = float(x) + 0.5f - px, dy = float(y) + 0.5f - py;
          if (dx * dx + dy * dy > r * r) continue;
          ++pixels;
          const size_t p = size_t(y) * size_t(width_) + size_t(x);
          if (z < depth_[p]) depth_[p] = z, index_[p] = i;
        }
    }
    counters.add(kRasterPoints, points.size());
    counters.add(kRasterPixels, pixels);
  }

  bool closest_hit(const Ray& ray, float px, float py, Hit& hit,
                   OpCounters& counters) const override {
    const int x = std::clamp(int(px), 0, width_ - 1), y = std::clamp(int(py), 0, height_ - 1);
    const uint32_t i = index_[size_t(y) * size_t(width_) + size_t(x)];
    if (i == kNone) return false;
    if (method_.refine(ray, i, hit, counters)) return true;
    // The MLS run from the pixel's point can find no root where the surface bends within the
    // point's footprint (creases: the local polynomial curves away from the ray). The points
    // of the neighbouring pixels are starts the z-buffer already holds; the nearest root wins.
    bool found = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        const uint32_t j = index_[size_t(ny) * size_t(width_) + size_t(nx)];
        if (j != kNone && j != i) found |= method_.refine(ray, j, hit, counters);
      }
    if (!found) counters.add(kRasterMisses);
    return found;
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  const RasterMlsMethod& method_;
  int width_, height_;
  std::vector<float> depth_;
  std::vector<uint32_t> index_;
};

}  // namespace

std::vector<ParamSpec> RasterMlsMethod::params(double max_iterations, double tolerance) {
  auto p = mls_params(max_iterations, tolerance);
  p.push_back(
      {"raster_radius", 3.0, 0.1, 50, "world radius of each point's disc in the z-buffer, in h"});
  return p;
}

void RasterMlsMethod::prepare(const PointCloud& cloud, PrepareContext& ctx) {
  mls_.prepare(cloud, params_, ctx.counters, ctx.timings);
  footprint_ = float(params_.at("raster_radius")) * mls_.h;
}

std::unique_ptr<PrimaryPass> RasterMlsMethod::primary_pass(const Camera& camera,
                                                           OpCounters& counters) const {
  return std::make_unique<ZBufferPass>(*this, camera, mls_.positions, footprint_, counters);
}

bool RasterMlsMethod::refine(const Ray& ray, uint32_t i, Hit& hit, OpCounters& counters) const {
  // The z-buffer gives a depth: the guess is the ray's point nearest the rasterized point. Near
  // a silhouette the ray runs almost along the surface, so the crossing may lie far from the
  // guess: the root is searched along the whole ray, and kept only if it lies within a ball
  // radius of a sample (an MLS root far from every sample is extrapolation, not surface).
  const float guess = std::max((mls_.positions[i] - ray.o).dot(ray.d), ray.tmin);
  Vec3 n = Vec3::Zero();
  const float t = mls_.surface->intersect_ray(ray, ray.at(guess), ray.tmin, hit.t, n, counters);
  if (t == kInfinity) return false;
  uint32_t nearest = 0;
  float d2 = 0;
  if (mls_.knn->knn(ray.at(t), 1, &nearest, &d2, counters) == 0 || d2 > mls_.ball * mls_.ball)
    return false;
  record_hit(ray, t, i, n, mls_.ball, hit);
  return true;
}

}  // namespace pcrt
