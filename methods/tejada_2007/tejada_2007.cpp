// tejada_2007: Tejada, Schafhitzel and Ertl, "Hardware-accelerated point-based rendering of
// surfaces and volumes" (2007), thesis [59]: primary hits from a z-buffer of the
// points and a single MLS step from the rasterized point (no iteration), secondary rays through
// a uniform grid. The shared code is methods/kernels/raster_mls.{hpp,cpp}. See README.md.
#include "methods/kernels/raster_mls.hpp"

namespace pcrt {
namespace {

// One MLS step (no iteration).
const ParamList<RasterMlsParams>& tejada_2007_params() {
  static const auto l = RasterMlsParams::list(1, 0);
  return l;
}

}  // namespace

void register_tejada_2007(MethodRegistry& registry) {
  registry.add(
      MethodInfo{.id = "tejada_2007",
                 .paper = "E. Tejada, T. Schafhitzel and T. Ertl, Hardware-accelerated point-based "
                          "rendering of surfaces and volumes, 2007",
                 .thesis_ref = "[59]",
                 .description = "primary hits from a z-buffer of the points and one MLS step (no "
                                "iteration); secondary rays through a uniform grid",
                 .structure = "grid",
                 .needs = {"positions only"},
                 .params = tejada_2007_params().specs(),
                 .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                            {"frame", "O(MNK + SBNK)", {"M", "N", "K", "S", "B"}, "Table 6.1"}},
                 .create = create_from<RasterMlsMethod>(tejada_2007_params(), "tejada_2007"),
                 .work = {&kRasterPoints, &kRasterPixels, &kKnnResults, &kMlsNeighbours},
                 .real_time_claim = "Table 5.1",
                 .iterations = {&kMlsFits, &kMlsRuns},
                 .cost = {.prepare_ns = 47, .ray_ns = 620},
                 .other_claims = {{"iterations",
                                   "one MLS step, no iteration (I = 1)",
                                   "I <= 1",
                                   {},
                                   "Table 6.1 (no I in O(MNK + SBNK))"}},
                 .designs = {{.experiment = "leaf_K_mls",
                              .variable = "K",
                              .param = "K",
                              .values = {6, 8, 12, 16, 24, 32, 48, 64, 96, 128},
                              .metric = {&kMlsNeighbours},
                              .per = &kMlsRuns},
                             {.claim = "iterations",
                              .experiment = "tejada_2007_one_step",
                              .N = 20000,
                              .M = 4096,
                              .B = 1,
                              .metric = {&kMlsFits},
                              .per = &kMlsRuns,
                              .max = 1,
                              .replicates = 1,
                              .shapes = true}}});
}

}  // namespace pcrt
