// Nearest points on a triangle mesh, and the triangles near a point: CGAL's AABB tree, compiled in
// cgal_backend.cpp with the rest of CGAL (each CGAL translation unit costs a minute to build).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "reconstruction/triangle_mesh.hpp"

namespace pcrt {

class TriangleDistanceTree {
 public:
  // Copies the triangles; builds the tree and its distance accelerator at once (CGAL builds the
  // accelerator lazily otherwise, which would race between threads).
  explicit TriangleDistanceTree(const TriangleMesh& mesh);
  ~TriangleDistanceTree();
  TriangleDistanceTree(const TriangleDistanceTree&) = delete;
  TriangleDistanceTree& operator=(const TriangleDistanceTree&) = delete;

  struct Closest {
    Vec3 point;
    uint32_t triangle;
  };
  [[nodiscard]] Closest closest(const Vec3& x) const;
  // Appends the triangles within distance `r` of x (a closed ball: point-to-triangle distance).
  void triangles_near(const Vec3& x, float r, std::vector<uint32_t>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcrt
