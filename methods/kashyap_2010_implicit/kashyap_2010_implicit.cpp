// kashyap_2010_implicit: Kashyap, Goradia, Chaudhuri and Chandran, "Implicit surface octrees for
// ray tracing point models" (ICVGIP 2010), thesis [33]: Algorithm 4 on an implicit-surface octree
// (shared kernel
// methods/kernels/implicit_cells.{hpp,cpp}). See README.md.
#include "methods/kernels/implicit_cells.hpp"

namespace pcrt {

void register_kashyap_2010_implicit(MethodRegistry& registry) {
  registry.add(MethodInfo{
      "kashyap_2010_implicit",
      "S. Kashyap, R. Goradia, P. Chaudhuri and S. Chandran, Implicit surface octrees for ray "
      "tracing point models, ICVGIP 2010",
      "[33]",
      "implicit-surface octree: Gaussian-weighted plane values and normals precomputed at cell "
      "corners; k-step marching with trilinear interpolation and a linear root (Algorithm 4)",
      "octree",
      {"point normals", "implicit octree"},
      ImplicitCellsParams::list().specs(),
      {{"leaf intersection", "O(k)", {"k"}, "Table 5.5"},
       {"frame", "O(SMB(log N + k))", {"S", "M", "B", "N", "k"}, "Table 6.1"}},
      create_from<ImplicitCellsMethod>(ImplicitCellsParams::list(), "kashyap_2010_implicit"),
      {},
      {&kMarchingSteps}});
}

}  // namespace pcrt
