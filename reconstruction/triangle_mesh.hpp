// A triangle mesh: what a global reconstruction produces and what the triangle engines trace.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/geometry.hpp"

namespace pcrt {

// The unit normal e1 x e2 of a triangle with edges e1 and e2 from one vertex; +z if degenerate.
// In double: in float the cross product of edges of 5e9 squares to infinity (and of 1e-20 to
// zero), and the normal came out zero.
inline Vec3 triangle_normal(const Vec3& e1, const Vec3& e2) {
  const Vec3d n = e1.cast<double>().cross(e2.cast<double>());
  const double len = n.norm();
  return len > 0 && std::isfinite(len) ? Vec3((n / len).cast<float>()) : Vec3(Vec3::UnitZ());
}

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
  Vec3d origin = Vec3d::Zero();  // where the vertices' zero lies in the file's coordinates

  [[nodiscard]] Aabb bounds() const;
  // Edges used by exactly one triangle (the rims of holes and open borders).
  [[nodiscard]] size_t boundary_edges() const;
  // Unit normal of triangle i (right-handed in its vertex order); +z if degenerate.
  [[nodiscard]] Vec3 normal(uint32_t i) const;
};

// Flips every triangle when the mesh's signed volume is negative, so that a closed mesh's
// normals face outward (what sampled points and dielectrics need); true when it flipped.
bool orient_outward(TriangleMesh& mesh);

// .ply (a 'face' element with vertex_indices; polygons fanned) or .off. Throws InputError naming
// the file for anything malformed, and for a mesh without triangles.
TriangleMesh read_mesh(const std::string& path);
// Binary little-endian PLY, written to a temporary file and renamed; the vertices are written in
// the file's coordinates (vertices + origin, as double when the origin is not zero).
void write_mesh_ply(const std::string& path, const TriangleMesh& mesh);

}  // namespace pcrt
