// kashyap_2010_implicit: Kashyap, Goradia, Chaudhuri and Chandran, "Implicit surface octrees for
// ray tracing point models" (ICVGIP 2010), thesis [33]: Algorithm 4 on an implicit-surface octree
// (shared kernel
// methods/kernels/implicit_cells.{hpp,cpp}). See README.md.
#include "methods/kernels/implicit_cells.hpp"

namespace pcrt {

void register_kashyap_2010_implicit(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "kashyap_2010_implicit",
      .paper = "S. Kashyap, R. Goradia, P. Chaudhuri and S. Chandran, Implicit surface octrees for "
               "ray tracing point models, ICVGIP 2010",
      .thesis_ref = "[33]",
      .description =
          "implicit-surface octree: Gaussian-weighted plane values and normals precomputed at cell "
          "corners; k-step marching with trilinear interpolation and a linear root (Algorithm 4)",
      .structure = "octree",
      .needs = {"point normals", "implicit octree"},
      .params = ImplicitCellsParams::list().specs(),
      .claims = {{"leaf intersection", "O(k)", {"k"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + k))", {"S", "M", "B", "N", "k"}, "Table 6.1"}},
      .create =
          create_from<ImplicitCellsMethod>(ImplicitCellsParams::list(), "kashyap_2010_implicit"),
      .work = {&kMarchingSteps},
      .real_time_claim = "Table 5.1",
      .own_items = true,
      .cost = {.prepare_ns = 747, .ray_ns = 96},
      .designs = {{.experiment = "leaf_k_implicit",
                   .variable = "k",
                   .param = "k",
                   .values = {1, 2, 4, 8, 16, 32, 64},
                   .metric = {&kMarchingSteps},
                   .per = &kCellsMarched}}});
}

}  // namespace pcrt
