#include "methods/kernels/implicit_cells.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "methods/kernels/splat_set.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

constexpr size_t kMaxK = 64;
constexpr int64_t kBias = 1 << 20;  // cell coordinates are packed as 21-bit unsigned fields

uint64_t pack(int64_t x, int64_t y, int64_t z) {
  return uint64_t(x + kBias) | uint64_t(y + kBias) << 21 | uint64_t(z + kBias) << 42;
}
void unpack(uint64_t key, int64_t& x, int64_t& y, int64_t& z) {
  x = int64_t(key & 0x1fffff) - kBias;
  y = int64_t(key >> 21 & 0x1fffff) - kBias;
  z = int64_t(key >> 42 & 0x1fffff) - kBias;
}

// The cells within one cell of a point's cell, sorted, each once.
std::vector<uint64_t> occupied_cells(std::span<const Vec3> points, const Vec3& origin, float size) {
  std::vector<uint64_t> keys;
  keys.reserve(points.size() * 27);
  for (const Vec3& p : points) {
    const Vec3 q = (p - origin) / size;
    const int64_t x = int64_t(q.x()), y = int64_t(q.y()), z = int64_t(q.z());
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) keys.push_back(pack(x + dx, y + dy, z + dz));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// The corners of those cells, sorted, each once.
std::vector<uint64_t> cell_corners(const std::vector<uint64_t>& keys) {
  std::vector<uint64_t> corners;
  corners.reserve(keys.size() * 8);
  for (uint64_t key : keys) {
    int64_t x, y, z;
    unpack(key, x, y, z);
    for (int c = 0; c < 8; ++c)
      corners.push_back(pack(x + (c & 1), y + (c >> 1 & 1), z + (c >> 2)));
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  return corners;
}

}  // namespace

const ParamList<ImplicitCellsParams>& ImplicitCellsParams::list() {
  using P = ImplicitCellsParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::cell_size,
               {"cell_size", 2.0, 0.25, 100, "edge of the finest octree cells, in h"})
          .add(&P::sigma, {"sigma", 1.0, 0.1, 50, "Gaussian weight standard deviation, in h"})
          .add(&P::K, {"K", 16, 1, double(kMaxK), "points averaged at each corner"})
          .add(&P::k, {"k", 4, 1, 1000, "marching steps per cell"});
  return l;
}

void ImplicitCells::prepare(const PointCloud& cloud, const ImplicitCellsParams& params,
                            PrepareContext& ctx) {
  // Normals only; the radius is unused.
  const SplatSet pts = prepare_splats(cloud, SplatParams{params.normals}, ctx, 1.0f);
  KnnIndex knn(pts.centres);
  const float h = std::max(float(mean_spacing(pts.centres, knn, ctx.counters)), 1e-30f);
  size_ = params.cell_size * h;
  steps_ = params.k;
  Aabb b;
  for (const Vec3& p : pts.centres) b.extend(p);
  origin_ = b.lo - Vec3::Constant(2 * size_);
  if ((b.extent() / size_).maxCoeff() > float(kBias)) {
    throw InputError(
        "implicit octree: cell_size too small for the cloud's extent (more than 2^20 "
        "cells per axis)");
  }
  ScopedTimer timer(ctx.timings, "prepare/implicit_octree");
  const std::vector<uint64_t> keys = occupied_cells(pts.centres, origin_, size_);
  const std::vector<uint64_t> corners = cell_corners(keys);
  const std::vector<uint32_t> corner_prim = evaluate_corners(corners, pts, knn, params, h, ctx);
  ctx.counters.add(kImplicitCells, keys.size());
  link_cells(keys, corners, corner_prim);
}

// Corner values: the Gaussian-weighted average plane of the K nearest points. Returns the nearest
// point of each corner (for the cells' colours).
std::vector<uint32_t> ImplicitCells::evaluate_corners(const std::vector<uint64_t>& corners,
                                                      const SplatSet& pts, const KnnIndex& knn,
                                                      const ImplicitCellsParams& params, float h,
                                                      PrepareContext& ctx) {
  const size_t k = std::min(params.K, kMaxK);
  const double inv_two_sigma2 = 0.5 / std::pow(params.sigma * h, 2);
  f_.resize(corners.size());
  n_.resize(corners.size());
  std::vector<uint32_t> corner_prim(corners.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, corners.size(), 1024), [&](const auto& r) {
    OpCounters local;
    std::array<uint32_t, kMaxK> idx;
    std::array<float, kMaxK> d2;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      int64_t x, y, z;
      unpack(corners[i], x, y, z);
      const Vec3 at = origin_ + size_ * Vec3(float(x), float(y), float(z));
      const size_t found = knn.knn(at, k, idx.data(), d2.data(), local);
      Vec3d p = Vec3d::Zero(), n = Vec3d::Zero();
      double wsum = 0;
      for (size_t j = 0; j < found; ++j) {  // weights relative to the nearest: no underflow
        const double w = std::exp(-(double(d2[j]) - double(d2[0])) * inv_two_sigma2);
        wsum += w;
        p += w * pts.centres[idx[j]].cast<double>();
        n += w * pts.normals[idx[j]].cast<double>();
      }
      const Vec3d nn = n.norm() > 0 ? Vec3d(n.normalized()) : Vec3d::UnitZ();
      f_[i] = float(nn.dot(at.cast<double>() - p / wsum));
      n_[i] = nn.cast<float>();
      corner_prim[i] = found > 0 ? pts.point_of(idx[0]) : 0;
    }
  });
  ctx.counters.add(kKnnQueries, corners.size());
  ctx.counters.add(kKnnResults, corners.size() * std::min(k, pts.size()));
  ctx.counters.add(kCornerEvaluations, corners.size());
  return corner_prim;
}

void ImplicitCells::link_cells(const std::vector<uint64_t>& keys,
                               const std::vector<uint64_t>& corners,
                               const std::vector<uint32_t>& corner_prim) {
  cells_.resize(keys.size());
  centres_.resize(keys.size());
  half_extents_.assign(keys.size(), Vec3::Constant(0.5f * size_ * 1.0001f));
  radii_.assign(keys.size(), 0.5f * size_ * std::sqrt(3.0f));
  for (size_t i = 0; i < keys.size(); ++i) {
    int64_t x, y, z;
    unpack(keys[i], x, y, z);
    centres_[i] = origin_ + size_ * (Vec3(float(x), float(y), float(z)) + Vec3::Constant(0.5f));
    for (int c = 0; c < 8; ++c) {
      const uint64_t ck = pack(x + (c & 1), y + (c >> 1 & 1), z + (c >> 2));
      cells_[i].corner[c] =
          uint32_t(std::lower_bound(corners.begin(), corners.end(), ck) - corners.begin());
    }
    cells_[i].prim = corner_prim[cells_[i].corner[0]];
  }
}

bool ImplicitCells::march(const Ray& ray, uint32_t cell, float t0, float t1, float& t_hit,
                          Vec3& n_hit, OpCounters& counters) const {
  const Cell& c = cells_[cell];
  const Vec3 lo = centres_[cell] - Vec3::Constant(0.5f * size_);
  auto weights = [&](const Vec3& x, std::array<float, 8>& w) {
    const Vec3 u = ((x - lo) / size_).cwiseMax(0.0f).cwiseMin(1.0f);
    for (int i = 0; i < 8; ++i)
      w[size_t(i)] = ((i & 1) ? u.x() : 1 - u.x()) * ((i >> 1 & 1) ? u.y() : 1 - u.y()) *
                     ((i >> 2) ? u.z() : 1 - u.z());
  };
  auto value = [&](float t) {  // triLerp of f (Algorithm 4, lines 3 and 7)
    std::array<float, 8> w;
    weights(ray.at(t), w);
    float f = 0;
    for (int i = 0; i < 8; ++i) f += w[size_t(i)] * f_[c.corner[i]];
    return f;
  };
  counters.add(kCellsMarched);
  // A root on the cell's face (a flat face of the shape on a grid plane: the grid starts at the
  // cloud's bounds) sits between this cell's exit value and the next cell's entry value, which
  // rounding can give the same sign on both sides: values within the rounding of the sample
  // position count as zero, so that the face's root is found from either side.
  const float round_off =
      8 * std::numeric_limits<float>::epsilon() * (ray.o.cwiseAbs().maxCoeff() + t1 + size_);
  auto snapped = [&](float t) {
    const float f = value(t);
    return std::abs(f) <= round_off ? 0.0f : f;
  };
  const float step = (t1 - t0) / float(steps_);
  float t_prev = t0, f_prev = snapped(t0);
  for (int i = 1; i <= steps_; ++i) {
    const float t = i == steps_ ? t1 : t0 + step * float(i);
    const float f = snapped(t);
    if (f * f_prev <= 0 && !(f == 0 && f_prev == 0)) {
      t_hit = f_prev == f ? t_prev : t_prev + (t - t_prev) * f_prev / (f_prev - f);  // Lerp
      std::array<float, 8> w;
      weights(ray.at(t_hit), w);
      Vec3 n = Vec3::Zero();
      for (int j = 0; j < 8; ++j) n += w[size_t(j)] * n_[c.corner[j]];
      n_hit = n.norm() > 0 ? Vec3(n.normalized()) : n_[c.corner[0]];
      counters.add(kMarchingSteps, uint64_t(i + 1));
      return true;
    }
    t_prev = t, f_prev = f;
  }
  counters.add(kMarchingSteps, uint64_t(steps_ + 1));
  return false;
}

bool ImplicitCells::intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                                   OpCounters& counters) const {
  bool found = false;
  const Vec3 inv = ray.d.cwiseInverse();
  for (uint32_t k : leaf.items) {
    const Vec3 lo = centres_[k] - Vec3::Constant(0.5f * size_);
    const Vec3 a = (lo - ray.o).cwiseProduct(inv);
    const Vec3 b = (lo + Vec3::Constant(size_) - ray.o).cwiseProduct(inv);
    const float t0 = std::max(a.cwiseMin(b).maxCoeff(), ray.tmin);
    const float t1 = std::min(a.cwiseMax(b).minCoeff(), hit.t);
    if (!(t0 <= t1)) continue;
    float t = 0;
    Vec3 n = Vec3::Zero();
    if (!march(ray, k, t0, t1, t, n, counters) || !closer(t, cells_[k].prim, hit)) continue;
    record_hit(ray, t, cells_[k].prim, n, 0.5f * size_, hit);
    found = true;
  }
  return found;
}

}  // namespace pcrt
