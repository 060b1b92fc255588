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
  registry.add(MethodInfo{
      "tejada_2007",
      "E. Tejada, T. Schafhitzel and T. Ertl, Hardware-accelerated point-based rendering of "
      "surfaces and volumes, 2007",
      "[59]",
      "primary hits from a z-buffer of the points and one MLS step (no iteration); secondary rays "
      "through a uniform grid",
      "grid",
      {"positions only"},
      tejada_2007_params().specs(),
      {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
       {"frame", "O(MNK + SBNK)", {"M", "N", "K", "S", "B"}, "Table 6.1"}},
      create_from<RasterMlsMethod>(tejada_2007_params(), "tejada_2007"),
      {},
      {&kRasterPoints, &kRasterPixels, &kKnnResults, &kMlsNeighbours}});
}

}  // namespace pcrt
