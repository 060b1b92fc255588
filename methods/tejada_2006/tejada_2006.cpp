// tejada_2006: Tejada, Gois, Nonato, Castelo and Oliveira, "Hardware-accelerated extraction and
// rendering of point set surfaces" (EuroVis 2006), thesis [58]: primary hits by rasterizing the
// points into a z-buffer, refined by iterated MLS from the rasterized point; secondary rays by
// brute force (the paper had no structure for them). The shared code is
// methods/kernels/raster_mls.{hpp,cpp}. See README.md.
#include "methods/kernels/raster_mls.hpp"

namespace pcrt {
namespace {

// Iterated MLS: up to 10 iterations, stopping at 0.01 h.
const ParamList<RasterMlsParams>& tejada_2006_params() {
  static const auto l = RasterMlsParams::list(10, 0.01);
  return l;
}

}  // namespace

void register_tejada_2006(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "tejada_2006",
      .paper = "E. Tejada, J. Gois, L. Nonato, A. Castelo and T. Ertl, Hardware-accelerated "
               "extraction and rendering of point set surfaces, EuroVis 2006",
      .thesis_ref = "[58]",
      .description = "primary hits from a z-buffer of the points, refined by iterated MLS "
                     "(Algorithm 3); secondary rays by brute force",
      .structure = "brute_force",
      .needs = {"positions only"},
      .params = tejada_2006_params().specs(),
      .claims = {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(MNIK + SBNIK)", {"M", "N", "I", "K", "S", "B"}, "Table 6.1"}},
      .create = create_from<RasterMlsMethod>(tejada_2006_params(), "tejada_2006"),
      .work = {&kRasterPoints, &kRasterPixels, &kKnnResults, &kMlsNeighbours},
      .real_time_claim = "Table 5.1",
      .iterative_claim = "Table 5.1",
      .iterations = {&kMlsFits, &kMlsRuns},
      .cost = {.prepare_ns = 35, .ray_ns = 744},
      .designs = {{.experiment = "leaf_K_mls",
                   .variable = "K",
                   .param = "K",
                   .values = {6, 8, 12, 16, 24, 32, 48, 64, 96, 128},
                   .metric = {&kMlsNeighbours},
                   .per = &kMlsRuns},
                  {.experiment = "leaf_I_mls",
                   .variable = "I",
                   .param = "max_iterations",
                   .values = {1, 2, 3, 4, 6, 8, 12},
                   .metric = {&kMlsNeighbours},
                   .per = &kMlsRuns,
                   .x = "I_run",
                   .fixed = {{"tolerance", 0}},
                   .replicates = 1}},
      .real_time_designs = {{.experiment = "real_time_brute_force",
                             .repetitions = 1,
                             .why = "Tejada 2006 traces secondary rays through every point "
                                    "(about 90 s a frame here): one repetition"}}});
}

}  // namespace pcrt
