// Every structure pcrt ships, listed once (see core/registry.hpp).
#include "structures/structure.hpp"

namespace pcrt {

void register_brute_force(StructureRegistry& registry);
void register_bvh(StructureRegistry& registry);
void register_grid(StructureRegistry& registry);
void register_kd_tree(StructureRegistry& registry);
void register_octree(StructureRegistry& registry);
void register_sphere_tree(StructureRegistry& registry);

void register_builtins(StructureRegistry& registry) {
  register_brute_force(registry);
  register_bvh(registry);
  register_grid(registry);
  register_kd_tree(registry);
  register_octree(registry);
  register_sphere_tree(registry);
}

}  // namespace pcrt
