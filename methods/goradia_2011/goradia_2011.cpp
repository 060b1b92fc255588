// goradia_2011: Goradia, Kashyap, Chaudhuri and Chandran, "Tracing specular light paths in
// point-based scenes" (The Visual Computer 2011), thesis [25]: the implicit-surface octree
// intersection of [33] (shared kernel
// methods/kernels/implicit_cells.{hpp,cpp}). See README.md.
#include "methods/kernels/implicit_cells.hpp"

namespace pcrt {

void register_goradia_2011(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "goradia_2011",
      .paper = "R. Goradia, S. Kashyap, P. Chaudhuri and S. Chandran, Tracing specular light paths "
               "in point-based scenes, The Visual Computer 27.12 (2011)",
      .thesis_ref = "[25]",
      .description = "the implicit-surface octree intersection of Kashyap et al. 2010 (Algorithm "
                     "4); the caustic sample map prepass is not implemented",
      .structure = "octree",
      .needs = {"point normals", "implicit octree"},
      .params = ImplicitCellsParams::list().specs(),
      .claims = {{"leaf intersection", "O(k)", {"k"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + k))", {"S", "M", "B", "N", "k"}, "Table 6.1"}},
      .create = create_from<ImplicitCellsMethod>(ImplicitCellsParams::list(), "goradia_2011"),
      .work = {&kMarchingSteps},
      .real_time_claim = "Table 5.1",
      .own_items = true,
      .cost = {.prepare_ns = 771, .ray_ns = 101},
      .designs = {{.experiment = "leaf_k_implicit",
                   .variable = "k",
                   .param = "k",
                   .values = {1, 2, 4, 8, 16, 32, 64},
                   .metric = {&kMarchingSteps},
                   .per = &kCellsMarched}},
      .real_time_designs = {MethodInfo::RealTimeDesign{},
                            {.experiment = "real_time_paper_N",
                             .N = 5000000,
                             .repetitions = 1,
                             .why = "Goradia 2011 at its paper's own 5 x 10^6 points and 512x512 "
                                    "(about 80 s of preparation here): one repetition"}}});
}

}  // namespace pcrt
