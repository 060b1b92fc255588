// goradia_2011: Goradia, Kashyap, Chaudhuri and Chandran, "Tracing specular light paths in
// point-based scenes" (The Visual Computer 2011), thesis [25]: the implicit-surface octree
// intersection of [33] (shared kernel
// methods/kernels/implicit_cells.{hpp,cpp}) and the paper's caustic sample map (CSM), which the
// renderer builds before a frame holding this method (render/caustic_map.{hpp,cpp}) from the
// csm_* parameters declared here. See README.md.
#include "methods/kernels/implicit_cells.hpp"
#include "render/caustic_map.hpp"

namespace pcrt {
namespace {

// The shared kernel's parameters and the caustic sample map's.
struct GoradiaParams {
  ImplicitCellsParams cells;
  int csm_photons = 4000000;
  int csm_k = 64;
  float csm_radius = 0.01f;

  static const ParamList<GoradiaParams>& list() {
    using P = GoradiaParams;
    static const auto l =
        ParamList<P>()
            .add(&P::cells, ImplicitCellsParams::list())
            .add(&P::csm_photons,
                 {"csm_photons", 4000000, 0, 1e8,
                  "photons the CSM prepass emits over the point and sphere lights"})
            .add(&P::csm_k, {"csm_k", 64, 1, double(CausticMap::kMaxK),
                             "nearest CSM entries in each density estimate"})
            .add(&P::csm_radius, {"csm_radius", 0.01, 1e-5, 1,
                                  "bound on the density estimate's radius, in scene diagonals"});
    return l;
  }
};

// The sweep harness fits N, M, S, B, K, k and I on generated datasets; the photons P and the
// map's entries E are neither, and the map needs a specular scene.
constexpr const char* kCsmNotSwept =
    "P (photons) and E (CSM entries) are not sweep variables; measured by scripts/csm_cost.sh "
    "on scenes/caustic_bunny.json into results/caustics/csm_cost.md";

std::unique_ptr<Method> create(const ParamValues& given) {
  return std::make_unique<ImplicitCellsMethod>(
      GoradiaParams::list().read(given, "goradia_2011").cells);
}

CausticMapSpec caustic_map(const ParamValues& given) {
  const GoradiaParams p = GoradiaParams::list().read(given, "goradia_2011");
  return CausticMapSpec{p.csm_photons, p.csm_k, p.csm_radius};
}

}  // namespace

void register_goradia_2011(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "goradia_2011",
      .paper = "R. Goradia, S. Kashyap, P. Chaudhuri and S. Chandran, Tracing specular light paths "
               "in point-based scenes, The Visual Computer 27.12 (2011)",
      .thesis_ref = "[25]",
      .description = "the implicit-surface octree intersection of Kashyap et al. 2010 (Algorithm "
                     "4) and the caustic sample map: photons through specular surfaces, stored in "
                     "an octree and looked up at diffuse hits for caustics",
      .structure = "octree",
      .needs = {"point normals", "implicit octree"},
      .params = GoradiaParams::list().specs(),
      .claims = {{"leaf intersection", "O(k)", {"k"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + k))", {"S", "M", "B", "N", "k"}, "Table 6.1"}},
      .create = create,
      .work = {&kMarchingSteps, &kCsmNodesVisited, &kCsmEntriesVisited},
      .real_time_claim = "Table 5.1",
      .own_items = true,
      .caustic_map = caustic_map,
      .cost = {.prepare_ns = 771, .ray_ns = 101},
      .other_claims = {{"csm_prepass",
                        "the CSM prepass: P photons, each a few rays of O(log N) ray-object work "
                        "through the scene, and the CSM octree over their entries",
                        "O(P log N)",
                        {"P", "N"},
                        "Table 5.4 (CSM octree)",
                        kCsmNotSwept},
                       {"csm_lookup",
                        "a CSM lookup: the k nearest of the map's E entries through the CSM octree",
                        "O(log E + k)",
                        {"E", "k"},
                        "Goradia et al. 2011",
                        kCsmNotSwept}},
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
