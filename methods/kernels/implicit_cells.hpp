// The implicit-surface octree of Kashyap et al. 2010 [33] and Goradia et al. 2011 [25]: the cells
// of the finest octree level that lie within one cell of a point, with the implicit function
// f = n . (x - p) of the Gaussian-weighted average plane (Eq. 3.22, 3.24) and its normal
// precomputed at every cell corner; a ray marches k steps through a cell, interpolating f
// trilinearly, and takes the linear root of the first sign change (Algorithm 4). O(k) per cell.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.hpp"
#include "core/counters.hpp"
#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

inline const Counter kCornerEvaluations{"implicit_corner_evaluations",
                                        "implicit function values precomputed at cell corners"};
inline const Counter kImplicitCells{"implicit_cells", "cells of the implicit-surface octree"};
inline const Counter kMarchingSteps{"implicit_march_steps",
                                    "trilinear evaluations while marching cells (k per cell)"};
inline const Counter kCellsMarched{"implicit_cells_marched", "cells a ray marched through"};

// Normals as the splat methods make them, and the octree's cell size, Gaussian and marching.
struct ImplicitCellsParams {
  NormalParams normals;
  float cell_size = 2;  // in h
  double sigma = 1;     // in h
  size_t K = 16;
  int k = 4;
  static const ParamList<ImplicitCellsParams>& list();
};

class ImplicitCells {
 public:
  void prepare(const PointCloud& cloud, const ImplicitCellsParams& params, PrepareContext& ctx);

  // Cell items for a structure: centres and half-extents of the cells.
  [[nodiscard]] ItemSet items() const { return {centres_, radii_, half_extents_}; }
  // Algorithm 4 over every cell of the leaf the ray crosses before hit.t; the nearest root wins.
  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit, OpCounters& counters) const;

 private:
  struct Cell {
    uint32_t corner[8];  // indices into f_ / n_, corner c at offset (c & 1, c >> 1 & 1, c >> 2)
    uint32_t prim;       // a point of the cell's neighbourhood (for colour)
  };
  bool march(const Ray& ray, uint32_t cell, float t0, float t1, float& t_hit, Vec3& n_hit,
             OpCounters& counters) const;
  std::vector<uint32_t> evaluate_corners(const std::vector<uint64_t>& corners, const SplatSet& pts,
                                         const KnnIndex& knn, const ImplicitCellsParams& params,
                                         float h, PrepareContext& ctx);
  void link_cells(const std::vector<uint64_t>& keys, const std::vector<uint64_t>& corners,
                  const std::vector<uint32_t>& corner_prim);

  float size_ = 1;
  int steps_ = 4;
  Vec3 origin_ = Vec3::Zero();
  std::vector<Vec3> centres_, half_extents_;
  std::vector<float> radii_;
  std::vector<Cell> cells_;
  std::vector<float> f_;
  std::vector<Vec3> n_;
};

// The whole method (Kashyap et al. 2010 [33] and Goradia et al. 2011 [25] register it with their
// own citations).
class ImplicitCellsMethod final : public Method {
 public:
  explicit ImplicitCellsMethod(const ImplicitCellsParams& params) : params_(params) {}
  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    cells_.prepare(cloud, params_, ctx);
  }
  [[nodiscard]] ItemSet items() const override { return cells_.items(); }
  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return cells_.intersect_leaf(ray, leaf, hit, counters);
  }

 private:
  ImplicitCellsParams params_;
  ImplicitCells cells_;
};

}  // namespace pcrt
