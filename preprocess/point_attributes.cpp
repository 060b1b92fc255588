#include "preprocess/point_attributes.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <queue>

namespace pcrt {

Vec3 pca_normal(std::span<const Vec3> positions, std::span<const uint32_t> nbrs) {
  Vec3d mean = Vec3d::Zero();
  for (uint32_t j : nbrs) mean += positions[j].cast<double>();
  mean /= double(nbrs.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (uint32_t j : nbrs) {
    const Vec3d d = positions[j].cast<double>() - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Vec3 n = eig.eigenvectors().col(0).cast<float>();  // eigenvalues ascending
  if (!n.allFinite() || n.squaredNorm() < 0.5f) n = Vec3::UnitZ();
  return n.normalized();
}

std::vector<Vec3> estimate_normals(std::span<const Vec3> positions, const KnnIndex& knn, size_t k,
                                   OpCounters& counters) {
  const size_t n = positions.size();
  k = std::max<size_t>(std::min(k, n), 1);
  std::vector<Vec3> normals(n, Vec3::UnitZ());
  std::vector<uint32_t> graph(n * k);
  std::vector<uint8_t> degree(n);
  for_each_point_knn(positions, knn, k, counters, [&](size_t i, auto nbrs, auto) {
    std::copy(nbrs.begin(), nbrs.end(), graph.begin() + long(i * k));
    degree[i] = static_cast<uint8_t>(std::min<size_t>(nbrs.size(), 255));
    if (nbrs.size() >= 3) normals[i] = pca_normal(positions, nbrs);
  });
  counters.add(kNormalsEstimated, n);

  // Prim's algorithm; ties broken by index so the result is deterministic.
  std::vector<uint32_t> by_height(n);
  for (uint32_t i = 0; i < n; ++i) by_height[i] = i;
  std::stable_sort(by_height.begin(), by_height.end(),
                   [&](uint32_t a, uint32_t b) { return positions[a].z() > positions[b].z(); });
  std::vector<uint8_t> done(n, 0);
  using Edge = std::pair<float, std::pair<uint32_t, uint32_t>>;  // weight, (child, parent)
  std::priority_queue<Edge, std::vector<Edge>, std::greater<>> queue;
  uint64_t flips = 0;
  auto push_neighbours = [&](uint32_t i) {
    for (size_t a = 0; a < degree[i]; ++a) {
      const uint32_t j = graph[i * k + a];
      if (!done[j]) queue.push({1.0f - std::abs(normals[i].dot(normals[j])), {j, i}});
    }
  };
  for (uint32_t root : by_height) {
    if (done[root]) continue;
    if (normals[root].z() < 0) normals[root] = -normals[root];
    done[root] = 1;
    push_neighbours(root);
    while (!queue.empty()) {
      const auto [child, parent] = queue.top().second;
      queue.pop();
      if (done[child]) continue;
      done[child] = 1;
      if (normals[child].dot(normals[parent]) < 0) {
        normals[child] = -normals[child];
        ++flips;
      }
      push_neighbours(child);
    }
  }
  counters.add(kOrientationFlips, flips);
  return normals;
}

std::vector<float> estimate_radii(std::span<const Vec3> positions, const KnnIndex& knn, size_t k,
                                  float scale, OpCounters& counters) {
  std::vector<float> radii(positions.size(), 0.0f);
  // Ask for k+1: the point itself comes back first at distance 0.
  for_each_point_knn(positions, knn, k + 1, counters, [&](size_t i, auto, auto d2) {
    radii[i] = d2.empty() ? 0.0f : scale * std::sqrt(d2.back());
  });
  return radii;
}

double mean_spacing(std::span<const Vec3> positions, const KnnIndex& knn, OpCounters& counters) {
  if (positions.size() < 2) return 0.0;
  std::vector<float> nearest(positions.size());
  for_each_point_knn(positions, knn, 2, counters,
                     [&](size_t i, auto, auto d2) { nearest[i] = std::sqrt(d2.back()); });
  double sum = 0;  // summed in index order: the same value for any thread count
  for (float d : nearest) sum += d;
  return sum / double(positions.size());
}

double mean_spacing(std::span<const Vec3> positions, OpCounters& counters) {
  const KnnIndex knn(positions);
  return mean_spacing(positions, knn, counters);
}

}  // namespace pcrt
