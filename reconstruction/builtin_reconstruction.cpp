// Every reconstruction and mesh engine pcrt ships, listed once (see core/registry.hpp).
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"

namespace pcrt {

void register_cgal_backend_reconstructions(ReconstructionRegistry& registry);
void register_cgal_backend_engine(MeshEngineRegistry& registry);
void register_embree_triangles(MeshEngineRegistry& registry);
void register_triangle_bvh(MeshEngineRegistry& registry);

void register_builtins(ReconstructionRegistry& registry) {
  register_cgal_backend_reconstructions(registry);
}

void register_builtins(MeshEngineRegistry& registry) {
  register_triangle_bvh(registry);
  register_cgal_backend_engine(registry);
  register_embree_triangles(registry);
}

}  // namespace pcrt
