// A triangle mesh as an exact Surface: the ground truth of real shapes (CGAL's demo meshes, the
// bunny) for `pcrt accuracy --truth`. Distances are to the nearest point on the mesh (CGAL's
// AABB_tree), first hits come from a triangle engine (the ones `pcrt render --mesh` uses), samples
// are drawn by area. Implementing Surface lets the synthetic and the mesh truths share one
// evaluator (render/accuracy.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/surfaces.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/triangle_distance.hpp"
#include "reconstruction/triangle_mesh.hpp"

namespace pcrt {

class MeshSurface final : public Surface {
 public:
  // Orients the mesh outward (flips every triangle when its signed volume is negative) and builds
  // the distance tree and the `engine` (a MeshEngineRegistry id). Throws InputError naming `name`
  // for a mesh of zero area.
  MeshSurface(TriangleMesh mesh, std::string name, const std::string& engine);
  ~MeshSurface() override;

  [[nodiscard]] std::string describe() const override;
  // |distance| to the nearest mesh point; the sign is that of the nearest face's normal, so it is
  // reliable only off edges (the evaluator uses the magnitude).
  [[nodiscard]] float signed_distance(const Vec3& x) const override;
  // The normal of the nearest triangle.
  [[nodiscard]] Vec3 normal(const Vec3& x) const override;
  [[nodiscard]] Aabb bounds() const override { return bounds_; }
  Vec3 sample(Rng& rng, Vec3& normal) const override;
  bool intersect(const Ray& ray, float& t, Vec3& n) const override;
  [[nodiscard]] float normal_spread_deg(const Vec3& x, float radius) const override;
  [[nodiscard]] Vec3 smooth_normal(const Vec3& x) const override;
  [[nodiscard]] Vec3d origin() const override { return mesh_.origin; }

  [[nodiscard]] const TriangleMesh& mesh() const { return mesh_; }
  [[nodiscard]] double area() const { return cumulative_area_.back(); }

 private:
  [[nodiscard]] TriangleDistanceTree::Closest closest(const Vec3& x) const;

  TriangleMesh mesh_;
  std::string name_;
  Aabb bounds_;
  std::vector<double> cumulative_area_;
  std::vector<Vec3> vertex_normals_;  // area-weighted, for smooth_normal
  std::unique_ptr<TriangleDistanceTree> tree_;
  std::unique_ptr<MeshEngine> engine_;
};

}  // namespace pcrt
