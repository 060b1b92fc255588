#include "reconstruction/triangle_mesh.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/point_cloud.hpp"
#include "core/point_cloud_io.hpp"

namespace pcrt {

bool orient_outward(TriangleMesh& mesh) {
  double volume6 = 0;  // six times the signed volume enclosed
  for (const auto& t : mesh.triangles) {
    const Vec3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                c = mesh.vertices[t[2]].cast<double>();
    volume6 += a.dot(b.cross(c));
  }
  if (volume6 >= 0) return false;
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return true;
}

Aabb TriangleMesh::bounds() const {
  Aabb b;
  for (const Vec3& v : vertices) b.extend(v);
  return b;
}

size_t TriangleMesh::boundary_edges() const {
  std::vector<uint64_t> edges;
  edges.reserve(triangles.size() * 3);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      edges.push_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  size_t once = 0;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    once += (j - i == 1);
    i = j;
  }
  return once;
}

Vec3 TriangleMesh::normal(uint32_t i) const {
  const auto& t = triangles[i];
  return triangle_normal(vertices[t[1]] - vertices[t[0]], vertices[t[2]] - vertices[t[0]]);
}

TriangleMesh read_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  TriangleMesh mesh;
  PointCloud cloud;
  if (ext == ".ply")
    cloud = read_ply(path, &mesh.triangles);
  else if (ext == ".off")
    cloud = read_off(path, &mesh.triangles);
  else
    input_error("{}: a mesh must be .ply or .off", path);
  if (mesh.triangles.empty()) input_error("{}: the mesh has no faces", path);
  require_extent(cloud.bounds(), path, "mesh");
  mesh.vertices = std::move(cloud.positions);
  mesh.origin = cloud.origin;
  return mesh;
}

void write_mesh_ply(const std::string& path, const TriangleMesh& mesh) {
  static_assert(std::endian::native == std::endian::little, "raw little-endian writes");
  write_file_atomically(path, [&](std::ostream& o) {
    o << "ply\nformat binary_little_endian 1.0\ncomment written by pcrt\n"
      << "element vertex " << mesh.vertices.size() << "\n"
      << fmt::format("property {0} x\nproperty {0} y\nproperty {0} z\n",
                     mesh.origin.isZero() ? "float" : "double")
      << "element face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& v : mesh.vertices) {
      if (mesh.origin.isZero()) {
        o.write(reinterpret_cast<const char*>(v.data()), 12);
      } else {
        const Vec3d w = to_world(v, mesh.origin);
        o.write(reinterpret_cast<const char*>(w.data()), 24);
      }
    }
    for (const auto& t : mesh.triangles) {
      const char three = 3;
      o.write(&three, 1);
      const int32_t idx[3] = {int32_t(t[0]), int32_t(t[1]), int32_t(t[2])};
      o.write(reinterpret_cast<const char*>(idx), sizeof(idx));
    }
  });
}

}  // namespace pcrt
