#include "harness/run_executors.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "harness/crossover.hpp"
#include "harness/scene_file.hpp"
#include "harness/sweep_datasets.hpp"
#include "harness/workloads.hpp"
#include "reconstruction/reconstruction.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

namespace pcrt {
namespace {

// Every executor starts from the spec and fills in what it measured.
RunResult started(const RunSpec& spec) {
  RunResult r;
  r.spec = spec;
  return r;
}

PointCloud cloud_of(const RunSpec& spec, RunResult& r) {
  PointCloud cloud =
      run_cloud(spec.dataset_path.empty() ? spec.dataset : spec.dataset_path, spec.N, spec.seed);
  r.points = cloud.size();
  return cloud;
}

RenderSettings render_settings(const RunSpec& spec, const PointCloud& cloud) {
  RenderSettings rs;
  rs.width = rs.height = std::max(1, int(std::lround(std::sqrt(spec.M.value_or(64.0 * 64.0)))));
  rs.spp = int(spec.S.value_or(1.0));
  rs.bounces = int(spec.B.value_or(1.0));
  rs.threads = spec.threads;
  rs.seed = spec.seed;
  if (spec.camera_inside) {
    // At the centre of the cloud's bounds, looking along the default view, 90 degrees wide.
    const Aabb b = cloud.bounds();
    rs.camera = Camera(b.center(), b.center() - rs.view, rs.up, 90.0f, rs.width, rs.height);
  }
  return rs;
}

SceneOptions scene_options(const RunSpec& spec) {
  SceneOptions so;
  so.method = spec.method;
  so.structure = spec.structure;
  for (const auto& [k, v] : spec.set) so.set[k] = v;
  return so;
}

// A calibration workload: counters of the first pass (every pass counts the same).
RunResult execute_workload(const RunSpec& spec) {
  if (!spec.N) input_error("workload run '{}': no N", spec.workload);
  RunResult r = started(spec);
  OpCounters first;
  for (int i = 0; i < spec.warmup + spec.reps; ++i) {
    OpCounters c;
    const double s = run_workload(spec.workload, size_t(*spec.N), spec.seed, c);
    if (i >= spec.warmup) r.times_s.push_back(s);
    if (i == 0) first = c;
  }
  r.counters = first.to_map();
  return r;
}

// A mesh reconstruction: its element counts stand in for counters.
RunResult execute_reconstruct(const RunSpec& spec) {
  RunResult r = started(spec);
  const PointCloud cloud = cloud_of(spec, r);
  const auto& info = ReconstructionRegistry::instance().get(spec.reconstruction, "reconstruction");
  for (int i = 0; i < spec.warmup + spec.reps; ++i) {
    const ReconstructionReport rec = info.run(cloud);
    if (i >= spec.warmup) r.times_s.push_back(rec.seconds);
    r.counters.clear();
    const std::pair<const char*, std::optional<uint64_t>> counts[] = {
        {"cells", rec.cells},
        {"facets", rec.facets},
        {"triangles", rec.triangles},
        {"boundary_edges", rec.boundary_edges},
        {"predicates", rec.predicates}};
    for (const auto& [k, v] : counts)
      if (v) r.counters[k] = *v;
    r.counters["vertices"] = rec.vertices;
    r.measures.memory_bytes = rec.memory_bytes;
  }
  return r;
}

// A scene built per pass (warm-up passes first): preparation counters of the first pass, the
// scene's own measures of the last; `pass(scene, i)` returns the pass's time.
template <typename Pass>
RunResult execute_scene_passes(const RunSpec& spec, Pass&& pass) {
  RunResult r = started(spec);
  const PointCloud cloud = cloud_of(spec, r);
  const SceneOptions so = scene_options(spec);
  const RenderSettings rs = render_settings(spec, cloud);
  for (int i = 0; i < spec.warmup + spec.reps; ++i) {
    Timings t;
    OpCounters p;
    const PointScene scene(cloud, so, p, t);
    if (i == 0) r.prepare_counters = p.to_map();
    const double seconds = pass(scene, cloud, rs, t, i, r);
    if (i >= spec.warmup) r.times_s.push_back(seconds);
    r.measures.prepare_s = t["prepare"];
    r.measures.structure_bytes = scene.structure_bytes();
  }
  r.pixels = rs.width * rs.height;
  return r;
}

// Scene builds only: the build's time; no frame, so no render counters.
RunResult execute_build(const RunSpec& spec) {
  RunResult r =
      execute_scene_passes(spec, [](const PointScene&, const PointCloud&, const RenderSettings&,
                                    Timings& t, int, RunResult&) { return t["build"]; });
  r.counters = OpCounters().to_map();
  return r;
}

// Frames of a scene file whose swept objects trace the run's method on the run's cloud: the scene
// is loaded per pass like a method's scene; counters of the first pass, the swept structure's
// bytes.
RunResult execute_scene_file_render(const RunSpec& spec) {
  RunResult r = started(spec);
  const PointCloud cloud = cloud_of(spec, r);
  const SweptCloud swept{cloud, scene_options(spec)};
  RenderSettings rs = render_settings(spec, cloud);
  for (int i = 0; i < spec.warmup + spec.reps; ++i) {
    const auto file =
        load_scene_file(spec.scene_path.empty() ? spec.scene : spec.scene_path, &swept);
    apply_scene_camera(*file, rs);
    if (i == 0) r.prepare_counters = file->prepare.to_map();
    const RenderResult res = render(file->scene, rs);
    if (i == 0) r.counters = res.counters.to_map();
    if (i >= spec.warmup) r.times_s.push_back(res.seconds);
    r.measures.prepare_s = file->timings["prepare"];
    r.measures.build_s = file->timings["build"];
    r.measures.structure_bytes = file->swept->structure_bytes();
  }
  r.pixels = rs.width * rs.height;
  return r;
}

// Frames: a frame rendered per pass; render counters of the first pass.
RunResult execute_render(const RunSpec& spec) {
  if (!spec.scene.empty()) return execute_scene_file_render(spec);
  return execute_scene_passes(spec, [](const PointScene& scene, const PointCloud& cloud,
                                       const RenderSettings& rs, Timings& t, int i, RunResult& r) {
    const RenderResult res = render(scene, cloud, rs);
    if (i == 0) r.counters = res.counters.to_map();
    r.measures.build_s = t["build"];
    return res.seconds;
  });
}

// Direct tracing against reconstruct-then-trace; the time is the mesh path's setup and frame.
RunResult execute_crossover(const RunSpec& spec) {
  RunResult r = started(spec);
  const PointCloud cloud = cloud_of(spec, r);
  const CrossoverResult x = measure_crossover(cloud, scene_options(spec), spec.reconstruction,
                                              spec.engine, render_settings(spec, cloud), spec.reps);
  r.measures.crossover =
      CrossoverMeasures{x.direct_setup_s(), x.direct_frame_s, x.mesh_setup_s(),  x.mesh_frame_s,
                        x.reconstruct_s,    x.triangles,      x.crossover_frames};
  r.times_s.push_back(x.mesh_setup_s() + x.mesh_frame_s);
  return r;
}

}  // namespace

RunResult execute_run(const RunSpec& spec) {
  switch (spec.kind) {
    case RunKind::kRender:
      return execute_render(spec);
    case RunKind::kBuild:
      return execute_build(spec);
    case RunKind::kReconstruct:
      return execute_reconstruct(spec);
    case RunKind::kWorkload:
      return execute_workload(spec);
    case RunKind::kCrossover:
      return execute_crossover(spec);
  }
  input_error("run of an unknown kind");
}

}  // namespace pcrt
