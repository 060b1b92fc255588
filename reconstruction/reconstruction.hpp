// Global reconstruction, the thesis's baseline (sections 5.1.1, 6, 7): a mesh is built from all
// N points first, then traced as triangles. Each reconstruction registers itself; CGAL lives in
// one translation unit (cgal_backend.cpp) and in no header.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "core/counters.hpp"
#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "core/registry.hpp"
#include "reconstruction/triangle_mesh.hpp"

namespace pcrt {

struct ReconstructionReport {
  std::string method;
  size_t points = 0;    // N given
  size_t vertices = 0;  // distinct points the reconstruction kept
  double seconds = 0;
  size_t memory_bytes = 0;  // of the triangulation (estimated from its element counts)
  std::optional<uint64_t> cells, facets, triangles, boundary_edges;  // null where not applicable
  std::optional<uint64_t> predicates;  // Delaunay: orientation and in-sphere tests evaluated
  TriangleMesh mesh;                   // empty for delaunay
};

struct ReconstructionInfo {
  std::string id;
  std::string description;
  std::string claim;  // the thesis's complexity for it
  // Throws InputError naming the reconstruction for input it cannot handle.
  std::function<ReconstructionReport(const PointCloud&)> run;
};

using ReconstructionRegistry = Registry<ReconstructionInfo>;

// The reconstructions pcrt ships (reconstruction/builtin_reconstruction.cpp, the one list).
void register_builtins(ReconstructionRegistry& registry);

}  // namespace pcrt
