#include "structures/knn_index.hpp"

#include <nanoflann.hpp>

namespace pcrt {
namespace {

// nanoflann's dataset adaptor: reads the caller's positions in place.
struct PositionsAdaptor {
  std::span<const Vec3> pts;
  [[nodiscard]] size_t kdtree_get_point_count() const { return pts.size(); }
  [[nodiscard]] float kdtree_get_pt(size_t i, size_t dim) const {
    return pts[i][static_cast<Eigen::Index>(dim)];
  }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using TreeType =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PositionsAdaptor>,
                                        PositionsAdaptor, 3, uint32_t>;

}  // namespace

struct KnnIndex::Tree {
  PositionsAdaptor adaptor;
  TreeType tree;
  Tree(std::span<const Vec3> p, size_t leaf)
      : adaptor{p}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(leaf)) {}
};

KnnIndex::KnnIndex(std::span<const Vec3> positions, size_t leaf_size)
    : positions_(positions), tree_(std::make_unique<Tree>(positions, leaf_size)) {}

KnnIndex::~KnnIndex() = default;

size_t KnnIndex::knn(const Vec3& q, size_t k, uint32_t* indices, float* dist2,
                     OpCounters& counters) const {
  const size_t found = tree_->tree.knnSearch(q.data(), k, indices, dist2);
  counters.add(kKnnQueries);
  counters.add(kKnnResults, found);
  return found;
}

size_t KnnIndex::radius(const Vec3& q, float r, std::vector<std::pair<uint32_t, float>>& out,
                        OpCounters& counters) const {
  // nanoflann's L2 adaptors take the squared radius.
#if NANOFLANN_VERSION >= 0x150
  // 1.5 returns ResultItems (and 1.7 numbers versions 0x01MMPP, still above 0x150): converted
  // through a buffer each thread keeps, so no allocation once it has grown.
  thread_local std::vector<nanoflann::ResultItem<uint32_t, float>> items;
  const size_t found =
      tree_->tree.radiusSearch(q.data(), r * r, items, nanoflann::SearchParameters(0.0f, true));
  out.resize(items.size());
  for (size_t i = 0; i < items.size(); ++i) out[i] = {items[i].first, items[i].second};
#else
  const size_t found =
      tree_->tree.radiusSearch(q.data(), r * r, out, nanoflann::SearchParams(32, 0.0f, true));
#endif
  counters.add(kKnnQueries);
  counters.add(kKnnResults, found);
  return found;
}

size_t KnnIndex::memory_bytes() const { return tree_->tree.usedMemory(tree_->tree); }

}  // namespace pcrt
