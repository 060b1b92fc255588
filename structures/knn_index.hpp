// k-nearest-neighbour queries over a cloud's positions through nanoflann (1.4 API). The positions
// stay the caller's; the index holds only its tree of indices.
#pragma once

#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"

namespace pcrt {

inline const Counter kKnnQueries{"knn_queries", "k-nearest-neighbour and radius queries"};
inline const Counter kKnnResults{"knn_results", "neighbours returned by k-NN queries"};

class KnnIndex {
 public:
  explicit KnnIndex(std::span<const Vec3> positions, size_t leaf_size = 10);
  ~KnnIndex();
  KnnIndex(const KnnIndex&) = delete;
  KnnIndex& operator=(const KnnIndex&) = delete;

  // The k points nearest to q (or fewer if the cloud is smaller), nearest first. indices and
  // dist2 must hold k entries. Returns how many were found.
  size_t knn(const Vec3& q, size_t k, uint32_t* indices, float* dist2, OpCounters& counters) const;
  // Every point within `radius` of q, nearest first, as (index, squared distance).
  size_t radius(const Vec3& q, float radius, std::vector<std::pair<uint32_t, float>>& out,
                OpCounters& counters) const;
  [[nodiscard]] size_t size() const { return positions_.size(); }
  [[nodiscard]] size_t memory_bytes() const;

 private:
  struct Tree;
  std::span<const Vec3> positions_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace pcrt
