#include "methods/kernels/raster_mls.hpp"

#include <algorithm>
#include <cmath>

#include "methods/kernels/ball_runs.hpp"
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
    // Runs searching the chord of the start's ball first, then the whole ray (silhouettes: the
    // ray runs along the surface and may cross it outside every ball it was rasterized from).
    // Each from the pixel's point, then from the points of the 8 neighbouring pixels: starts the
    // z-buffer already holds, for where the surface bends within a footprint and the run from
    // one point finds no root. The nearest root wins.
    for (Reach reach : {Reach::kBall, Reach::kWholeRay}) {
      if (method_.refine(ray, i, reach, hit, counters)) return true;
      if (refine_from_neighbours(ray, x, y, i, reach, hit, counters)) return true;
    }
    counters.add(kRasterMisses);
    return false;
  }

 private:
  using Reach = RasterMlsMethod::Reach;
  static constexpr uint32_t kNone = 0xffffffffu;

  bool refine_from_neighbours(const Ray& ray, int x, int y, uint32_t own, Reach reach, Hit& hit,
                              OpCounters& counters) const {
    bool found = false;
    for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, height_ - 1); ++ny)
      for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, width_ - 1); ++nx) {
        const uint32_t j = index_[size_t(ny) * size_t(width_) + size_t(nx)];
        if (j != kNone && j != own) found |= method_.refine(ray, j, reach, hit, counters);
      }
    return found;
  }

  const RasterMlsMethod& method_;
  int width_, height_;
  std::vector<float> depth_;
  std::vector<uint32_t> index_;
};

}  // namespace

ParamList<RasterMlsParams> RasterMlsParams::list(double max_iterations, double tolerance) {
  using P = RasterMlsParams;
  return ParamList<P>()
      .add(&P::mls, MlsParams::list(max_iterations, tolerance))
      .add(&P::raster_radius, {"raster_radius", 3.0, 0.1, 50,
                               "world radius of each point's disc in the z-buffer, in h"});
}

void RasterMlsMethod::prepare(const PointCloud& cloud, PrepareContext& ctx) {
  mls_.prepare(cloud, params_.mls, ctx.counters, ctx.timings);
  footprint_ = params_.raster_radius * mls_.h;
}

std::unique_ptr<PrimaryPass> RasterMlsMethod::primary_pass(const Camera& camera,
                                                           OpCounters& counters) const {
  return std::make_unique<ZBufferPass>(*this, camera, mls_.positions, footprint_, counters);
}

bool RasterMlsMethod::refine(const Ray& ray, uint32_t i, Reach reach, Hit& hit,
                             OpCounters& counters) const {
  // The z-buffer gives a depth: the guess is the ray's point nearest the rasterized point. The
  // search stays on the chord of the point's ball, as a traced ray's run does: over the whole
  // ray, the local polynomial's other root (far along the ray) can be taken, and the next fit
  // there finds nothing. kWholeRay is for silhouettes (see ZBufferPass). A root is kept only if
  // it lies within a ball radius of a sample (far from every sample is extrapolation).
  float t0 = ray.tmin, t1 = hit.t;
  if (reach == Reach::kBall && !ball_chord(ray, mls_.positions[i], mls_.ball, hit.t, t0, t1))
    return false;
  const float guess = std::clamp((mls_.positions[i] - ray.o).dot(ray.d), t0, t1);
  Vec3 n = Vec3::Zero();
  const float t = mls_.surface->intersect_ray(ray, ray.at(guess), t0, t1, n, counters);
  if (t == kInfinity) return false;
  uint32_t nearest = 0;
  float d2 = 0;
  if (mls_.knn->knn(ray.at(t), 1, &nearest, &d2, counters) == 0 || d2 > mls_.ball * mls_.ball)
    return false;
  record_hit(ray, t, i, n, mls_.ball, hit);
  return true;
}

}  // namespace pcrt
