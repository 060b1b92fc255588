// The reconstruction side of the CLI: `pcrt reconstruct` (a global mesh from all N points) and
// `pcrt crossover` (reconstruct + build + trace against a direct method's prepare + build + trace:
// the frame count at which reconstruction pays off, thesis chapter 7).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "harness/command_helpers.hpp"
#include "harness/commands.hpp"
#include "harness/crossover.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

namespace pcrt {

int command_reconstruct(const ReconstructOptions& o) {
  auto limit = limit_threads(o.threads);
  const ReconstructionInfo& info =
      ReconstructionRegistry::instance().get(o.method, "reconstruction");
  if (o.out) check_outputs({{*o.out, "--out"}}, {{o.data, "--data"}});
  if (o.out) require_extension(*o.out, "--out", {".ply"});
  const Dataset d = load_dataset(o.data);
  const ReconstructionReport r = info.run(d.cloud);
  if (o.out) {
    if (r.mesh.triangles.empty())
      input_error("pcrt reconstruct: --out: '{}' makes no triangle mesh", info.id);
    TriangleMesh mesh = r.mesh;
    mesh.origin = d.cloud.origin;  // written back in the cloud's file coordinates
    write_mesh_ply(*o.out, mesh);
  }
  auto opt = [](const std::optional<uint64_t>& v) { return v ? json(*v) : json(nullptr); };
  const json j = {{"method", r.method},
                  {"dataset", o.data},
                  {"points", r.points},
                  {"vertices", r.vertices},
                  {"seconds", r.seconds},
                  {"memory_bytes", r.memory_bytes ? json(r.memory_bytes) : json(nullptr)},
                  {"cells", opt(r.cells)},
                  {"facets", opt(r.facets)},
                  {"triangles", opt(r.triangles)},
                  {"boundary_edges", opt(r.boundary_edges)}};
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s of %s: %zu points in %.3f s\n", r.method.c_str(), o.data.c_str(), r.points,
              r.seconds);
  for (const char* k : {"cells", "facets", "triangles", "boundary_edges", "memory_bytes"})
    if (!j[k].is_null()) std::printf("  %-16s %llu\n", k, (unsigned long long)j[k].get<uint64_t>());
  return 0;
}

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double frame_seconds(const SceneIntersector& scene, const PointCloud& cloud,
                     const RenderSettings& rs, int reps) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) t.push_back(render(scene, cloud, rs).seconds);
  return median(t);
}

}  // namespace

CrossoverResult measure_crossover(const PointCloud& cloud, const SceneOptions& direct_options,
                                  const std::string& reconstruction, const std::string& engine,
                                  RenderSettings rs, int reps) {
  CrossoverResult r;
  const auto& info = ReconstructionRegistry::instance().get(reconstruction, "reconstruction");
  (void)MeshEngineRegistry::instance().get(engine, "mesh engine");
  Timings direct_t;
  OpCounters direct_c;
  const PointScene direct(cloud, direct_options, direct_c, direct_t);
  r.method = direct.method_info().id;
  r.structure = direct.structure_id();
  r.direct_prepare_s = direct_t["prepare"];
  r.direct_build_s = direct_t["build"];
  rs.camera = Camera::framing(cloud.bounds(), rs.width, rs.height, rs.view, rs.up);
  r.direct_frame_s = frame_seconds(direct, cloud, rs, reps);
  const ReconstructionReport rec = info.run(cloud);
  if (rec.mesh.triangles.empty())
    input_error("crossover: reconstruction '{}' makes no triangle mesh", info.id);
  Timings mesh_t;
  OpCounters mesh_c;
  const MeshScene mesh(rec.mesh, engine, mesh_c, mesh_t);
  r.reconstruction = info.id;
  r.engine = engine;
  r.triangles = rec.mesh.triangles.size();
  r.reconstruct_s = rec.seconds;
  r.mesh_build_s = mesh_t["build"];
  r.mesh_frame_s = frame_seconds(mesh, cloud, rs, reps);
  // setup_r + F t_r < setup_d + F t_d once F exceeds this.
  if (r.mesh_frame_s < r.direct_frame_s)
    r.crossover_frames = std::max(0.0, std::ceil((r.mesh_setup_s() - r.direct_setup_s()) /
                                                 (r.direct_frame_s - r.mesh_frame_s)));
  return r;
}

namespace {

json crossover_json(const CrossoverResult& r, const std::string& data, size_t n,
                    const RenderSettings& rs, long long frames) {
  return {{"dataset", data},
          {"N", n},
          {"M", rs.width * rs.height},
          {"S", rs.spp},
          {"B", rs.bounces},
          {"direct",
           {{"method", r.method},
            {"structure", r.structure},
            {"prepare_s", r.direct_prepare_s},
            {"build_s", r.direct_build_s},
            {"frame_s", r.direct_frame_s},
            {"first_frame_s", r.direct_setup_s() + r.direct_frame_s},
            {"frames_s", r.direct_setup_s() + double(frames) * r.direct_frame_s}}},
          {"reconstruction",
           {{"method", r.reconstruction},
            {"engine", r.engine},
            {"triangles", r.triangles},
            {"reconstruct_s", r.reconstruct_s},
            {"build_s", r.mesh_build_s},
            {"frame_s", r.mesh_frame_s},
            {"first_frame_s", r.mesh_setup_s() + r.mesh_frame_s},
            {"frames_s", r.mesh_setup_s() + double(frames) * r.mesh_frame_s}}},
          {"frames", frames},
          {"crossover_frames", r.crossover_frames ? json(*r.crossover_frames) : json(nullptr)}};
}

void print_crossover(const CrossoverResult& r, const std::string& data, size_t n,
                     const RenderSettings& rs) {
  std::printf("%s, N = %zu, %dx%d, S=%d B=%d\n", data.c_str(), n, rs.width, rs.height, rs.spp,
              rs.bounces);
  std::printf("  direct %s on %s: setup %.3f s, frame %.4f s, first frame %.3f s\n",
              r.method.c_str(), r.structure.c_str(), r.direct_setup_s(), r.direct_frame_s,
              r.direct_setup_s() + r.direct_frame_s);
  std::printf("  %s + %s: setup %.3f s, frame %.4f s, first frame %.3f s\n",
              r.reconstruction.c_str(), r.engine.c_str(), r.mesh_setup_s(), r.mesh_frame_s,
              r.mesh_setup_s() + r.mesh_frame_s);
  if (!r.crossover_frames)
    std::printf("  reconstruction never pays off: its frames are not faster\n");
  else
    std::printf("  reconstruction pays off after %lld frames\n",
                json(*r.crossover_frames).get<long long>());
}

}  // namespace

int command_crossover(const CrossoverOptions& o) {
  auto limit = limit_threads(o.threads);
  RenderSettings rs = o.settings;
  rs.threads = o.threads;
  const Dataset d = load_dataset(o.data);
  const CrossoverResult r = measure_crossover(d.cloud, SceneOptions{o.method, o.structure, {}},
                                              o.reconstruction, o.engine, rs, o.reps);
  if (o.json)
    std::printf("%s\n", crossover_json(r, o.data, d.cloud.size(), rs, o.frames).dump(2).c_str());
  else
    print_crossover(r, o.data, d.cloud.size(), rs);
  return 0;
}

}  // namespace pcrt
