// Uniform grid (thesis section 5.4; Cai et al. 2015, Tejada et al. 2007 for secondary rays):
// G = N / c cells of equal size over the footprints' bounding box, items referenced in every cell
// their footprint box overlaps, stored as one index array per cell (CSR, built in two counting
// passes: O(N + references)). Traversal: 3D-DDA (Amanatides and Woo 1987), cell by cell along the
// ray, handing every non-empty cell over as a leaf.
//
// Note for the claims: the thesis's K = N/G per cell assumes points spread through the volume. A
// surface occupies about G^(2/3) of the cells, so per occupied cell K grows like N^(1/3) and a ray
// steps through up to G^(1/3) cells; the benchmarks report what is measured.
#include <algorithm>
#include <cmath>

#include "core/offsets.hpp"
#include "structures/build_buffer.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

struct GridParams {
  double points_per_cell = 2;
  double max_cells = 1 << 26;
  double max_refs_per_point = 32;
};
const ParamList<GridParams>& grid_params() {
  using P = GridParams;
  static const auto l =
      ParamList<P>()
          .add(&P::points_per_cell,
               {"points_per_cell", 2, 0.01, 1e6,
                "c in G = N/c: average points per cell if they filled the volume"})
          .add(&P::max_cells,
               {"max_cells", 1 << 26, 1, 1 << 30, "upper bound on G (memory: 4 bytes per cell)"})
          .add(&P::max_refs_per_point,
               {"max_refs_per_point", 32, 1, 1e4,
                "coarsen the grid (halving each axis) while footprints would need more cell "
                "references than this per point"});
  return l;
}

class Grid final : public Structure {
 public:
  explicit Grid(const GridParams& p)
      : per_cell_(p.points_per_cell), max_cells_(p.max_cells), max_refs_(p.max_refs_per_point) {}

  void build(const ItemSet& set, OpCounters& counters) override {
    items_ = set;
    bounds_ = items_.bounds();
    choose_resolution(double(items_.size()));
    // Footprints much larger than a cell (identical points, huge radii) would be referenced by
    // very many cells: coarsen until the references stay within max_refs_per_point * N.
    while (count_refs() > max_refs_ * double(std::max<size_t>(items_.size(), 1)) &&
           res_[0] * res_[1] * res_[2] > 1)
      coarsen();
    const size_t cells = size_t(res_[0]) * res_[1] * res_[2];
    // Pass 1: count references per cell (a cell holds at most N < 2^32) into start32_[c + 1];
    // their total decides the offsets' width; pass 2 fills.
    start32_.assign(cells + 1, 0);
    release(start64_);
    for (uint32_t i = 0; i < items_.size(); ++i)
      for_cells_of(i, [&](size_t c) { ++start32_[c + 1]; });
    uint64_t total = 0;
    for (uint32_t k : start32_) total += k;
    if (fits_narrow_offset(total)) {
      for (size_t c = 0; c < cells; ++c) start32_[c + 1] += start32_[c];
      fill(start32_);
    } else {
      start64_.assign(cells + 1, 0);
      for (size_t c = 0; c < cells; ++c) start64_[c + 1] = start64_[c] + start32_[c + 1];
      release(start32_);
      fill(start64_);
    }
    counters.add(kBuildNodes, cells);
    counters.add(kBuildItemRefs, refs_.size());
    counters.add(kBuildItemVisits, set.size() + refs_.size());
  }

  bool closest_hit(const Ray& ray, const LeafIntersector& leaf, Hit& hit,
                   OpCounters& counters) const override {
    return start64_.empty() ? walk<false>(start32_, ray, leaf, hit, counters)
                            : walk<false>(start64_, ray, leaf, hit, counters);
  }

  bool any_hit(const Ray& ray, const LeafIntersector& leaf, OpCounters& counters) const override {
    Hit hit;
    hit.t = ray.tmax;
    return start64_.empty() ? walk<true>(start32_, ray, leaf, hit, counters)
                            : walk<true>(start64_, ray, leaf, hit, counters);
  }

  // kAny: an occlusion query, ended by the first leaf that reports a hit. Offset: the width of
  // the CSR offsets (start32_ or start64_).
  template <bool kAny, class Offset>
  bool walk(const std::vector<Offset>& start, const Ray& ray, const LeafIntersector& leaf, Hit& hit,
            OpCounters& counters) const {
    if ((items_.size() == 0)) return false;
    const Vec3 inv = ray.d.cwiseInverse();
    float t0 = 0, t1 = 0;
    if (!bounds_.intersect(ray, inv, t0, t1)) return false;
    const Vec3 p = ray.at(t0);
    int cell[3], step[3];
    float t_next[3], delta[3];
    for (int a = 0; a < 3; ++a) {
      cell[a] = std::clamp(int(std::floor((p[a] - bounds_.lo[a]) / size_[a])), 0, res_[a] - 1);
      if (ray.d[a] > 0) {
        step[a] = 1;
        t_next[a] = (bounds_.lo[a] + float(cell[a] + 1) * size_[a] - ray.o[a]) * inv[a];
        delta[a] = size_[a] * inv[a];
      } else if (ray.d[a] < 0) {
        step[a] = -1;
        t_next[a] = (bounds_.lo[a] + float(cell[a]) * size_[a] - ray.o[a]) * inv[a];
        delta[a] = -size_[a] * inv[a];
      } else {
        step[a] = 0;
        t_next[a] = kInfinity;
        delta[a] = kInfinity;
      }
    }
    bool found = false;
    float t_enter = t0;
    while (true) {
      int ax = 0;
      if (t_next[1] < t_next[ax]) ax = 1;
      if (t_next[2] < t_next[ax]) ax = 2;
      const float t_exit = std::min(t_next[ax], t1);
      counters.add(kNodesVisited);
      const size_t c = (size_t(cell[2]) * res_[1] + size_t(cell[1])) * res_[0] + size_t(cell[0]);
      const auto count = uint32_t(start[c + 1] - start[c]);
      if (count > 0) {
        counters.add(kLeavesVisited);
        counters.add(kItemsVisited, count);
        const LeafVisit visit{{refs_.data() + start[c], count}, t_enter, t_exit};
        if constexpr (kAny) {
          if (leaf.occluded_leaf(ray, visit, hit.t, counters)) return true;
        } else {
          found |= leaf.intersect_leaf(ray, visit, hit, counters);
        }
      }
      if (!may_improve(t_exit, hit.t) || t_next[ax] >= t1) break;
      cell[ax] += step[ax];
      if (cell[ax] < 0 || cell[ax] >= res_[ax]) break;
      t_enter = t_exit;
      t_next[ax] += delta[ax];
    }
    return found;
  }

  [[nodiscard]] std::span<const uint32_t> leaf_references() const override { return refs_; }
  [[nodiscard]] size_t memory_bytes() const override {
    return start32_.capacity() * sizeof(uint32_t) + start64_.capacity() * sizeof(uint64_t) +
           refs_.capacity() * sizeof(uint32_t);
  }

 private:
  // The references in cell order, from the CSR offsets.
  template <class Offset>
  void fill(const std::vector<Offset>& start) {
    refs_.assign(size_t(start.back()), 0);
    std::vector<Offset> cursor(start.begin(), start.end() - 1);
    for (uint32_t i = 0; i < items_.size(); ++i)
      for_cells_of(i, [&](size_t c) { refs_[size_t(cursor[c]++)] = i; });
  }

  // Cubic cells, about N / c of them; axes thinner than one cell get a single cell and the cell
  // size is solved again over the others (a plane gets a 2D grid, a line a 1D one).
  void choose_resolution(double n) {
    const Vec3 ext = bounds_.empty() ? Vec3::Zero() : bounds_.extent();
    const double target = std::clamp(n / per_cell_, 1.0, max_cells_);
    bool thin[3] = {!(ext[0] > 0), !(ext[1] > 0), !(ext[2] > 0)};
    double side = 0;
    for (int iter = 0; iter < 3; ++iter) {
      double prod = 1;
      int k = 0;
      for (int a = 0; a < 3; ++a)
        if (!thin[a]) prod *= ext[a], ++k;
      side = k == 0 ? 1.0 : std::pow(prod / target, 1.0 / k);
      bool changed = false;
      for (int a = 0; a < 3; ++a)
        if (!thin[a] && ext[a] < side) thin[a] = changed = true;
      if (!changed) break;
    }
    for (int a = 0; a < 3; ++a) {
      res_[a] = thin[a] ? 1 : std::clamp(int(std::lround(ext[a] / side)), 1, 1 << 20);
      size_[a] = ext[a] > 0 ? ext[a] / float(res_[a]) : 1.0f;
    }
    while (double(res_[0]) * res_[1] * res_[2] > max_cells_) {  // rounding overshoot on huge N
      const int a = res_[0] >= res_[1] && res_[0] >= res_[2] ? 0 : (res_[1] >= res_[2] ? 1 : 2);
      res_[a] = std::max(1, res_[a] / 2);
      size_[a] = ext[a] > 0 ? ext[a] / float(res_[a]) : 1.0f;
    }
  }

  // References the current resolution would store, without storing them: O(N).
  [[nodiscard]] double count_refs() const {
    double total = 0;
    for (uint32_t i = 0; i < items_.size(); ++i) {
      int lo[3], hi[3];
      cell_range(i, lo, hi);
      total += double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
    }
    return total;
  }

  void coarsen() {
    const Vec3 ext = bounds_.extent();
    for (int a = 0; a < 3; ++a) {
      res_[a] = std::max(1, res_[a] / 2);
      size_[a] = ext[a] > 0 ? ext[a] / float(res_[a]) : 1.0f;
    }
  }

  void cell_range(uint32_t i, int lo[3], int hi[3]) const {
    const Aabb b = items_.box(i);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp(int(std::floor((b.lo[a] - bounds_.lo[a]) / size_[a])), 0, res_[a] - 1);
      hi[a] = std::clamp(int(std::floor((b.hi[a] - bounds_.lo[a]) / size_[a])), 0, res_[a] - 1);
    }
  }

  template <typename F>
  void for_cells_of(uint32_t i, F&& f) const {
    int lo[3], hi[3];
    cell_range(i, lo, hi);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
          f((size_t(z) * res_[1] + size_t(y)) * res_[0] + size_t(x));
  }

  double per_cell_, max_cells_, max_refs_;
  ItemSet items_;
  Aabb bounds_;
  int res_[3] = {1, 1, 1};
  float size_[3] = {1, 1, 1};
  std::vector<uint32_t> start32_;  // CSR offsets, one per cell + 1, while the references fit
  std::vector<uint64_t> start64_;  // otherwise
  std::vector<uint32_t> refs_;
};

}  // namespace

void register_grid(StructureRegistry& registry) {
  registry.add(StructureInfo{
      .id = "grid",
      .description = "uniform grid of about N/c cubic cells, 3D-DDA traversal",
      .build_claim = "O(N)",
      .query_claim = "O(1)",
      .params = grid_params().specs(),
      .create = structure_from<Grid>(grid_params(), "grid"),
      .footprint =
          fixed_footprint({.item_order = 20, .leaf_order = 72, .references_per_item = 1.9}),
  });
}

}  // namespace pcrt
