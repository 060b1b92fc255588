#include "harness/commands.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/exr_output.hpp"
#include "core/file_output.hpp"
#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "core/process_usage.hpp"
#include "core/ray_io.hpp"
#include "harness/catalogue.hpp"
#include "harness/claims.hpp"
#include "harness/command_helpers.hpp"
#include "harness/scene_file.hpp"
#include "preprocess/point_attributes.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/mesh_surface.hpp"
#include "reconstruction/reconstruction.hpp"
#include "render/accuracy.hpp"
#include "render/compare.hpp"
#include "render/furnace.hpp"
#include "render/mesh_truth.hpp"
#include "render/render_scene.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"
#include "render/surface_scene.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {
namespace {

// The point method a command traces: --method (required here), --structure and --set.
SceneOptions point_scene_options(const SceneArgs& a, const char* usage) {
  return {required(a.method, "--method", usage), a.structure, a.set};
}

json scene_json(const PointScene& scene, const PointCloud& cloud, const std::string& data) {
  json params = {{"method", scene.method_info().id},
                 {"structure", scene.structure_id()},
                 {"dataset", data},
                 {"N", cloud.size()}};
  if (!cloud.origin.isZero())  // positions are relative to it (kLocalOriginReach)
    params["origin"] = {cloud.origin.x(), cloud.origin.y(), cloud.origin.z()};
  for (const auto& [k, v] : scene.method_params()) params["method_params"][k] = v;
  for (const auto& [k, v] : scene.structure_params()) params["structure_params"][k] = v;
  return params;
}

// What render and trace run on: a point method over a dataset, or (--mesh) a triangle mesh on a
// triangle engine. Members are declared in the order they must outlive each other.
struct LoadedScene {
  Dataset data;
  TriangleMesh mesh;
  PointCloud mesh_vertices;  // the renderer's bounds and colours for a mesh
  OpCounters prepare;
  Timings timings;
  std::unique_ptr<PointScene> points;
  std::unique_ptr<MeshScene> triangles;
  std::unique_ptr<SurfaceScene> exact;  // the furnace's floor: data.truth itself
  std::unique_ptr<PointStream> stream;  // --stream: `points` was prepared from it, data is empty
  json params;

  [[nodiscard]] const SceneIntersector& scene() const {
    if (exact) return *exact;
    return points ? static_cast<const SceneIntersector&>(*points) : *triangles;
  }
  [[nodiscard]] const PointCloud& cloud() const {
    return points || exact ? data.cloud : mesh_vertices;
  }
  [[nodiscard]] size_t structure_bytes() const {
    return points ? points->structure_bytes() : triangles->memory_bytes();
  }
  [[nodiscard]] size_t point_count() const { return stream ? stream->size() : cloud().size(); }
  // The default frame of this scene (single_object_scene).
  [[nodiscard]] RenderResult render_frame(const RenderSettings& rs) const {
    if (!stream) return render(scene(), cloud(), rs);
    return render(single_object_scene(scene(), stream->bounds(), stream->name(), rs.view, rs.up,
                                      rs.point_light),
                  rs);
  }
  [[nodiscard]] std::string label() const {
    if (exact) return "exact surface";
    return points ? points->method_info().id + " on " + points->structure_id()
                  : "mesh on " + triangles->engine_id();
  }
};

// --mesh takes none of the point method's options, and --engine only goes with --mesh.
void check_scene_kind(const SceneArgs& a, const char* command) {
  if (a.mesh) {
    for (const auto& [given, option] :
         {std::pair{a.method.has_value(), "method"}, std::pair{a.data.has_value(), "data"},
          std::pair{!a.structure.empty(), "structure"}, std::pair{!a.set.empty(), "set"}})
      if (given) input_error("pcrt {}: --{} does not apply to --mesh", command, option);
  } else if (a.engine) {
    input_error("pcrt {}: --engine applies only to --mesh", command);
  }
}

std::unique_ptr<LoadedScene> load_scene(const SceneArgs& a, const char* command,
                                        const char* usage) {
  check_scene_kind(a, command);
  auto s = std::make_unique<LoadedScene>();
  if (a.mesh) {
    const std::string engine = a.engine.value_or(kDefaultMeshEngine);
    (void)MeshEngineRegistry::instance().get(engine, "mesh engine");  // names before work
    {
      ScopedTimer t(s->timings, "load");
      s->mesh = read_mesh(*a.mesh);
    }
    s->mesh_vertices.positions = s->mesh.vertices;
    s->mesh_vertices.origin = s->mesh.origin;
    s->triangles = std::make_unique<MeshScene>(s->mesh, engine, s->prepare, s->timings);
    s->params = {{"mesh", *a.mesh},
                 {"engine", engine},
                 {"triangles", s->mesh.triangles.size()},
                 {"N", s->mesh.vertices.size()}};
    return s;
  }
  const SceneOptions so = point_scene_options(a, usage);
  const std::string& data = required(a.data, "--data", usage);
  {
    ScopedTimer t(s->timings, "load");
    s->data = load_dataset(data);
  }
  s->points = std::make_unique<PointScene>(s->data.cloud, so, s->prepare, s->timings);
  s->params = scene_json(*s->points, s->data.cloud, data);
  return s;
}

// `pcrt render --stream`: a generator's points streamed into a method that prepares from a
// stream (MethodInfo::stream_bytes_per_point), never all in memory.
std::unique_ptr<LoadedScene> load_streamed_scene(const SceneArgs& a) {
  if (a.mesh) input_error("pcrt render: --stream does not apply to --mesh");
  const SceneOptions so = point_scene_options(a, RenderOptions::usage);
  const std::string& data = required(a.data, "--data", RenderOptions::usage);
  auto s = std::make_unique<LoadedScene>();
  s->stream = open_point_stream(data);
  s->points = std::make_unique<PointScene>(*s->stream, so, s->prepare, s->timings);
  s->params = scene_json(*s->points, s->data.cloud, data);
  s->params["N"] = s->stream->size();
  s->params["streamed"] = true;
  if (const Vec3d o = s->stream->origin(); !o.isZero()) s->params["origin"] = {o.x(), o.y(), o.z()};
  return s;
}

}  // namespace

int command_info(const InfoOptions& o) {
  auto limit = limit_threads(o.threads);
  const Dataset d = load_dataset(o.data);
  const PointCloud& c = d.cloud;
  OpCounters counters;
  const double h = mean_spacing(c.positions, counters);
  const Aabb local = c.bounds();
  // In the file's coordinates, as every position pcrt writes out (kLocalOriginReach).
  const Vec3d lo = to_world(local.lo, c.origin), hi = to_world(local.hi, c.origin);
  json j = {{"name", c.name},
            {"points", c.size()},
            {"bounds", {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}}},
            {"origin", {c.origin.x(), c.origin.y(), c.origin.z()}},
            {"attributes", c.attributes()},
            {"mean_spacing", h},
            {"ground_truth", d.truth ? json(d.truth->describe()) : json(nullptr)}};
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf(
        "%s\n  points        %zu\n  bounds        (%.9g, %.9g, %.9g) - (%.9g, %.9g, %.9g)\n"
        "  attributes    %s\n  mean spacing  %g\n  ground truth  %s\n",
        c.name.c_str(), c.size(), lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(),
        fmt::format("{}", fmt::join(c.attributes(), ", ")).c_str(), h,
        d.truth ? d.truth->describe().c_str() : "none (file)");
  }
  return 0;
}

namespace {

// The frame, depth and normal images: PNG (8-bit; depth scaled to [0,1] over the image, normals
// as (n + 1) / 2) or, for a .exr name, 32-bit float (radiance as it is, depth as the primary
// hit's distance in scene units with +inf where nothing was hit, normals signed, 0 on a miss).
void stage_render_images(OutputFiles& outputs, const RenderResult& r, const std::string& out,
                         const std::string& depth, const std::string& normals) {
  const int w = r.image.width(), h = r.image.height();
  if (is_exr_path(out))
    outputs.stage(out, exr_writer(w, h, rgb_channels(r.image)), true);
  else
    outputs.stage(out, png_writer(r.image), true);
  if (is_exr_path(depth))
    outputs.stage(depth, exr_writer(w, h, {{"Z", r.primary_t}}), true);
  else if (!depth.empty())
    outputs.stage(depth, png_writer(r.depth, PngEncoding::kLinear), true);
  if (is_exr_path(normals)) {
    std::vector<FloatChannel> n = {{"R", {}}, {"G", {}}, {"B", {}}};
    for (const Vec3& v : r.primary_n)
      for (int k = 0; k < 3; ++k) n[size_t(k)].values.push_back(v[k]);
    outputs.stage(normals, exr_writer(w, h, std::move(n)), true);
  } else if (!normals.empty()) {
    outputs.stage(normals, png_writer(r.normals, PngEncoding::kLinear), true);
  }
}

// The camera's axes must span a plane.
void check_camera_axes(const Vec3& view, const Vec3& up, const char* command) {
  if (view.cross(up).norm() < 1e-6f * view.norm() * up.norm())
    input_error("pcrt {}: --view and --up must not be parallel", command);
}

// The frame's settings as --stats records them.
json frame_params(const RenderSettings& rs) {
  return {{"M", rs.width * rs.height}, {"width", rs.width}, {"height", rs.height},  {"S", rs.spp},
          {"B", rs.bounces},           {"seed", rs.seed},   {"threads", rs.threads}};
}

// The command line's frame settings on its threads, with camera axes that span a plane.
RenderSettings frame_settings(RenderSettings rs, int threads, const char* command) {
  rs.threads = threads;
  check_camera_axes(rs.view, rs.up, command);
  return rs;
}

// --stats: the settings, counters, timings and the process's cost.
json render_stats(const LoadedScene& loaded, const RenderSettings& rs, const RenderResult& r,
                  double setup_cpu) {
  json params = loaded.params;
  params.update(frame_params(rs));
  params["point_light"] = rs.point_light;
  return {{"params", params},
          {"counters", counters_json(r.counters)},
          {"prepare_counters", counters_json(loaded.prepare)},
          {"timings", loaded.timings},
          {"structure_bytes", loaded.structure_bytes()},
          {"frames_per_second", r.seconds > 0 ? 1.0 / r.seconds : 0.0},
          {"process",
           {{"setup_cpu_seconds", setup_cpu},
            {"peak_rss_bytes", peak_rss_bytes()},
            {"estimated_scene_bytes", loaded.points ? loaded.points->estimated_bytes() : 0}}}};
}

}  // namespace

namespace {

// A scene file replaces the one method or mesh: none of their options apply.
void check_scene_file_args(const RenderOptions& o) {
  const SceneArgs& a = o.scene;
  for (const auto& [given, option] :
       {std::pair{a.method.has_value(), "method"}, std::pair{a.data.has_value(), "data"},
        std::pair{a.mesh.has_value(), "mesh"}, std::pair{a.engine.has_value(), "engine"},
        std::pair{!a.structure.empty(), "structure"}, std::pair{!a.set.empty(), "set"},
        std::pair{!o.settings.point_light, "no-light"}})
    if (given)
      input_error("pcrt render: --{} does not apply to --scene (the file says it)", option);
}

// The mean radiance per channel over the image: what analytic scenes are judged on.
json image_mean(const Image& image) {
  Vec3d sum = Vec3d::Zero();
  for (const Vec3& p : image.pixels()) sum += p.cast<double>();
  sum /= double(std::max<size_t>(image.pixels().size(), 1));
  return {sum.x(), sum.y(), sum.z()};
}

json scene_file_stats(const SceneFile& file, const RenderSettings& rs, const RenderResult& r) {
  json params = file.params;
  params.update(frame_params(rs));
  return {{"params", params},
          {"image_mean", image_mean(r.image)},
          {"counters", counters_json(r.counters)},
          {"prepare_counters", counters_json(file.prepare)},
          {"timings", file.timings}};
}

// `pcrt render --scene`: the file's objects, lights and camera at the command line's M, S, B.
// The outputs of a render, which none of its inputs may be.
std::vector<NamedPath> render_outputs(const RenderOptions& o) {
  std::vector<NamedPath> out{{o.out, "--out"}};
  for (const auto& [path, option] :
       {std::pair{&o.depth, "--depth"}, std::pair{&o.normals, "--normals"},
        std::pair{&o.stats, "--stats"}})
    if (*path) out.emplace_back(**path, option);
  return out;
}

// check_outputs of a frame's files, and the images named as what they are written as.
void check_render_outputs(const RenderOptions& o, const std::vector<NamedPath>& inputs) {
  check_outputs(render_outputs(o), inputs);
  const std::vector<std::string> images = {".png", ".exr"};
  require_extension(o.out, "--out", images);
  if (o.depth) require_extension(*o.depth, "--depth", images);
  if (o.normals) require_extension(*o.normals, "--normals", images);
}

int render_scene_file(const RenderOptions& o, RenderSettings rs) {
  check_scene_file_args(o);
  const auto file = load_scene_file(*o.scene_file);
  std::vector<NamedPath> read;  // the files the scene names, checked now that they are known
  for (const std::string& f : file->files) read.emplace_back(f, *o.scene_file);
  check_render_outputs(o, read);
  if (file->camera)  // the file's camera fixes the view, as it fixes the method
    for (const auto& [given, option] :
         {std::pair{o.view_given, "view"}, std::pair{o.up_given, "up"}})
      if (given)
        input_error("pcrt render: --{} does not apply to --scene {} (its camera says it)", option,
                    *o.scene_file);
  apply_scene_camera(*file, rs);
  RenderResult r = render(file->scene, rs);
  file->timings["render"] = r.seconds;
  if (r.csm_seconds > 0) file->timings["csm"] = r.csm_seconds;
  OutputFiles outputs;  // all or none
  stage_render_images(outputs, r, o.out, o.depth.value_or(""), o.normals.value_or(""));
  if (o.stats) outputs.stage(*o.stats, json_writer(scene_file_stats(*file, rs, r)));
  outputs.commit();
  std::printf("%s: %s, %zu objects, %dx%d, S=%d B=%d, render %.3f s\n", o.out.c_str(),
              o.scene_file->c_str(), file->scene.objects.size(), rs.width, rs.height, rs.spp,
              rs.bounces, r.seconds);
  for (const auto& [name, value] : r.counters.to_map())
    std::printf("  %-28s %llu\n", name.c_str(), (unsigned long long)value);
  return 0;
}

// The files a render or trace reads, which none of its outputs may be.
std::vector<NamedPath> scene_inputs(const SceneArgs& a) {
  return {{a.data.value_or(""), "--data"}, {a.mesh.value_or(""), "--mesh"}};
}

}  // namespace

int command_render(const RenderOptions& o) {
  auto limit = limit_threads(o.scene.threads);
  const RenderSettings rs = frame_settings(o.settings, o.scene.threads, "render");
  auto inputs = scene_inputs(o.scene);
  inputs.emplace_back(o.scene_file.value_or(""), "--scene");
  check_outputs(render_outputs(o), inputs);
  if (o.scene_file) {
    if (o.stream) input_error("pcrt render: --stream does not apply to --scene");
    return render_scene_file(o, rs);  // its outputs checked again with the files it reads
  }
  check_render_outputs(o, inputs);
  const auto loaded =
      o.stream ? load_streamed_scene(o.scene) : load_scene(o.scene, "render", RenderOptions::usage);
  const double setup_cpu = process_cpu_seconds();  // load, prepare and build, every thread
  Timings& timings = loaded->timings;
  RenderResult r = loaded->render_frame(rs);
  timings["render"] = r.seconds;
  OutputFiles outputs;  // all or none
  stage_render_images(outputs, r, o.out, o.depth.value_or(""), o.normals.value_or(""));
  if (o.stats) outputs.stage(*o.stats, json_writer(render_stats(*loaded, rs, r, setup_cpu)));
  outputs.commit();
  std::printf("%s: %s, %zu points%s, %dx%d, S=%d B=%d\n", o.out.c_str(), loaded->label().c_str(),
              loaded->point_count(), loaded->stream ? " (streamed)" : "", rs.width, rs.height,
              rs.spp, rs.bounces);
  std::printf("  prepare %.3f s, build %.3f s, render %.3f s (%.2f frames/s)\n", timings["prepare"],
              timings["build"], r.seconds, r.seconds > 0 ? 1.0 / r.seconds : 0.0);
  for (const auto& [name, value] : r.counters.to_map())
    std::printf("  %-28s %llu\n", name.c_str(), (unsigned long long)value);
  return 0;
}

namespace {

// One line per ray; hit positions in the file's coordinates (local + origin, in double).
void write_hits_csv(std::ostream& csv, const std::vector<Hit>& hits, const std::vector<char>& found,
                    const Vec3d& origin) {
  csv << "ray,hit,t,px,py,pz,nx,ny,nz\n";
  // Nine significant digits hold a float; a georeferenced position needs its double's.
  const bool local = origin.isZero();
  for (size_t i = 0; i < hits.size(); ++i) {
    const Hit& h = hits[i];
    if (!found[i]) {
      csv << i << ",0,,,,,,,\n";
      continue;
    }
    const Vec3d p = to_world(h.p, origin);
    if (local)
      csv << fmt::format("{},1,{:.9g},{:.9g},{:.9g},{:.9g},", i, h.t, p.x(), p.y(), p.z());
    else
      csv << fmt::format("{},1,{:.9g},{:.17g},{:.17g},{:.17g},", i, h.t, p.x(), p.y(), p.z());
    csv << fmt::format("{:.9g},{:.9g},{:.9g}\n", h.n.x(), h.n.y(), h.n.z());
  }
}

}  // namespace

int command_trace(const TraceOptions& o) {
  auto limit = limit_threads(o.scene.threads);
  auto inputs = scene_inputs(o.scene);
  inputs.emplace_back(o.rays, "--rays");
  std::vector<NamedPath> written{{o.out, "--out"}};
  if (o.stats) written.emplace_back(*o.stats, "--stats");
  check_outputs(written, inputs);
  std::vector<Ray> rays = read_rays_csv(o.rays);  // checked before the load
  const auto loaded = load_scene(o.scene, "trace", TraceOptions::usage);
  const Vec3d& origin = loaded->cloud().origin;
  if (!origin.isZero()) rays = read_rays_csv(o.rays, origin);  // in the cloud's local frame
  Timings& timings = loaded->timings;
  const SceneIntersector& scene = loaded->scene();
  std::vector<Hit> hits(rays.size());
  std::vector<char> found(rays.size(), 0);
  OpCounters counters;
  {
    ScopedTimer t(timings, "trace");
    counters = trace_rays(scene, rays, hits, found);
  }
  OutputFiles outputs;  // all or none
  outputs.stage(o.out, [&](std::ostream& csv) { write_hits_csv(csv, hits, found, origin); });
  if (o.stats) {
    json params = loaded->params;
    params["rays"] = rays.size();
    outputs.stage(*o.stats, json_writer({{"params", params},
                                         {"counters", counters_json(counters)},
                                         {"prepare_counters", counters_json(loaded->prepare)},
                                         {"timings", timings},
                                         {"structure_bytes", loaded->structure_bytes()}}));
  }
  outputs.commit();
  size_t n_hit = 0;
  for (char f : found) n_hit += size_t(f);
  std::printf("%s: %zu rays, %zu hits (%s, %zu points)\n", o.out.c_str(), rays.size(), n_hit,
              loaded->label().c_str(), loaded->cloud().size());
  return 0;
}

namespace {

// The truth an accuracy run judges against and the cloud a method is built on: a generator's
// exact surface and its points, or a mesh and points sampled on it.
struct AccuracyInput {
  Dataset data;
  std::shared_ptr<const Surface> truth;
  double h = 0;  // the spacing tolerances are in
  json describe;
};

AccuracyInput accuracy_input(const std::optional<std::string>& data, const TruthArgs& t,
                             const char* usage, OpCounters& prep) {
  AccuracyInput in;
  if (!t.mesh) {
    if (t.sample || t.engine) input_error("--sample and --truth-engine apply only to --truth");
    const std::string& spec = required(data, "--data", usage);
    in.data = load_dataset(spec);
    if (!in.data.truth)
      input_error(
          "--data {}: no exact surface (a file, or a generator without one); accuracy needs a "
          "generator with an exact surface or --truth MESH",
          spec);
    in.truth = in.data.truth;
    in.h = mean_spacing(in.data.cloud.positions, prep);
    in.describe = {{"dataset", spec}};
    return in;
  }
  if (data) input_error("give --data or --truth, not both");
  const std::string& path = *t.mesh;
  const MeshSampling sampling = parse_mesh_sampling(t.sample.value_or(""));
  const std::string engine = t.engine.value_or(kDefaultMeshEngine);
  (void)MeshEngineRegistry::instance().get(engine, "mesh engine");  // names before work
  auto truth = std::make_shared<MeshSurface>(read_mesh(path), path, engine);
  SampledCloud sampled = sample_cloud(*truth, sampling, path, prep);
  in.data.cloud = std::move(sampled.cloud);
  in.h = sampled.spacing;
  in.describe = {{"truth", path},
                 {"truth_engine", engine},
                 {"triangles", truth->mesh().triangles.size()},
                 {"sample", describe(sampling)},
                 {"dataset", path + " sampled " + describe(sampling)}};
  in.truth = std::move(truth);
  return in;
}

json split_json(const FeatureSplit& s) {
  return {{"thin", s.thin}, {"crease", s.crease}, {"open", s.open}};
}

// The failures by the shape where they happen, beside the same split of all judged hits.
json causes_json(const AccuracyReport& r) {
  return {{"thin_wall_h", FeatureSplit::kThinWallH},
          {"feature_reach_h", FeatureSplit::kFeatureReachH},
          {"crease_angle_deg", Surface::kSmoothAngleDeg},
          {"judged_hits", split_json(r.judged_split)},
          {"see_through", split_json(r.see_through_split)},
          {"holes", split_json(r.hole_split)},
          {"phantom_near_crease", r.phantom_near_crease}};
}

// The judged hits and failure rates by the normal spread at the exact hit (SpreadBand).
json spread_json(const SpreadBands& bands) {
  json out = json::array();
  for (const SpreadBand& b : bands)
    out.push_back({{"lo_deg", b.lo_deg},
                   {"hi_deg", b.hi_deg},
                   {"judged_hits", b.judged_hits},
                   {"holes", b.holes},
                   {"see_through", b.see_through},
                   {"early", b.early},
                   {"phantom", b.phantom},
                   {"thin_hits", b.thin_hits},
                   {"thin_failures", b.thin_failures},
                   {"hole_rate", b.rate(b.holes)},
                   {"see_through_rate", b.rate(b.see_through)},
                   {"early_rate", b.rate(b.early)},
                   {"phantom_rate", b.rate(b.phantom)},
                   {"failure_rate", b.rate(b.failures())}});
  return {{"reach_h", FeatureSplit::kFeatureReachH}, {"bands", out}};
}

json accuracy_json(const AccuracyReport& r) {
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return {{"rays", r.rays},
          {"judged_hits", r.judged_hits},
          {"judged_misses", r.judged_misses},
          {"holes", r.holes},
          {"false_hits", r.false_hits},
          {"see_through", r.see_through},
          {"early", r.early},
          {"phantom", r.phantom},
          {"hole_rate", r.hole_rate},
          {"false_hit_rate", r.false_hit_rate},
          {"see_through_rate", r.see_through_rate()},
          {"see_through_smooth", r.see_through_smooth},
          {"see_through_smooth_rate", r.see_through_smooth_rate()},
          {"early_rate", r.early_rate()},
          {"causes", causes_json(r)},
          {"normal_spread", spread_json(r.spread_bands)},
          {"phantom_rate", r.phantom_rate()},
          {"distance_median_h", num(r.distance_median_h)},
          {"distance_p95_h", num(r.distance_p95_h)},
          {"normal_judged", r.normal_judged},
          {"normal_median_deg", num(r.normal_median_deg)},
          {"normal_p95_deg", num(r.normal_p95_deg)},
          {"smooth_normal_median_deg", num(r.smooth_normal_median_deg)},
          {"faceting_floor_deg", num(r.faceting_floor_deg)},
          {"meets_bounds", AccuracyBounds{}.met_by(r)}};
}

json secondary_json(const SecondaryReport& r) {
  auto side = [](const SecondaryReport::Side& s) {
    return json{{"rays", s.rays},
                {"self_hits", s.self_hits},
                {"missed_occluders", s.missed_occluders},
                {"false_occluders", s.false_occluders},
                {"unprobed", s.unprobed},
                {"self_hit_rate", s.rate(s.self_hits)},
                {"missed_occluder_rate", s.rate(s.missed_occluders)},
                {"false_occluder_rate", s.rate(s.false_occluders)}};
  };
  return {{"outward", side(r.outward)}, {"inward", side(r.inward)}};
}

void print_secondary(const SecondaryReport& r) {
  for (const auto& [name, s] : {std::pair{"outward", &r.outward}, std::pair{"inward", &r.inward}})
    std::printf(
        "  secondary %-8s %zu rays: self-hits %.3f%%  missed occluders %.3f%%  false occluders "
        "%.3f%%  (%zu points unprobed)\n",
        name, s->rays, 100 * s->rate(s->self_hits), 100 * s->rate(s->missed_occluders),
        100 * s->rate(s->false_occluders), s->unprobed);
}

void print_accuracy(const std::string& label, const std::string& data, double h,
                    const AccuracyReport& r) {
  std::printf("%s, %s (h = %.4g): %zu judged hits, %zu judged misses\n", label.c_str(),
              data.c_str(), h, r.judged_hits, r.judged_misses);
  std::printf(
      "  holes %.3f%%  false hits %.3f%% (see-through %.3f%% of which %.3f%% on smooth surface, "
      "early %.3f%%, phantom %.3f%%)\n"
      "  distance median %.4f h, p95 %.4f h  normal median %.3f deg (%zu smooth hits; faceting "
      "floor %.3f deg)  -> %s\n",
      100 * r.hole_rate, 100 * r.false_hit_rate, 100 * r.see_through_rate(),
      100 * r.see_through_smooth_rate(), 100 * r.early_rate(), 100 * r.phantom_rate(),
      r.distance_median_h, r.distance_p95_h, r.normal_median_deg, r.normal_judged,
      r.faceting_floor_deg, AccuracyBounds{}.met_by(r) ? "meets the bounds" : "MISSES the bounds");
  std::printf("  holes + see-through + phantom by normal spread within %.1f h:",
              double(FeatureSplit::kFeatureReachH));
  for (const SpreadBand& b : r.spread_bands)
    std::printf(" %g-%g deg %.3f%% of %zu%s", double(b.lo_deg), double(b.hi_deg),
                100 * b.rate(b.failures()), b.judged_hits,
                &b == &r.spread_bands.back() ? "\n" : ",");
}

void check_accuracy_options(const AccuracyOptions& o) {
  if (o.scene.mesh)
    input_error("pcrt accuracy: --mesh has no exact surface; use --truth or --reconstruction");
  if (o.reconstruction && o.scene.method)
    input_error("pcrt accuracy: give --method or --reconstruction, not both");
  if (!o.reconstruction && o.scene.engine)
    input_error("pcrt accuracy: --engine applies only to --reconstruction");
}

// What accuracy judges: a point method's scene, or a reconstructed mesh on a triangle engine.
struct JudgedScene {
  TriangleMesh mesh;  // a reconstruction's (the scene refers to it, so it is destroyed later)
  std::unique_ptr<SceneIntersector> scene;
  std::string method, structure;
};

std::unique_ptr<JudgedScene> judged_scene(const AccuracyOptions& o, const PointCloud& cloud,
                                          OpCounters& prep, Timings& timings) {
  auto j = std::make_unique<JudgedScene>();
  if (!o.reconstruction) {
    auto ps = std::make_unique<PointScene>(
        cloud, point_scene_options(o.scene, AccuracyOptions::usage), prep, timings);
    j->method = ps->method_info().id;
    j->structure = ps->structure_id();
    j->scene = std::move(ps);
    return j;
  }
  const auto& info = ReconstructionRegistry::instance().get(*o.reconstruction, "reconstruction");
  ReconstructionReport rec = info.run(cloud);
  if (rec.mesh.triangles.empty())
    input_error("pcrt accuracy: reconstruction '{}' makes no triangle mesh", info.id);
  timings["reconstruct"] = rec.seconds;
  j->mesh = std::move(rec.mesh);
  j->structure = o.scene.engine.value_or(kDefaultMeshEngine);
  j->method = "reconstruction:" + info.id;
  j->scene = std::make_unique<MeshScene>(j->mesh, j->structure, prep, timings);
  return j;
}

}  // namespace

namespace {

// The furnace's object: a method on --data, a mesh, a method on points sampled on --truth, or
// (--exact) the exact surface of a generator. `data.truth` holds the exact surface where the
// object samples one (generators and --truth), for the split of the dark pixels by cause.
std::unique_ptr<LoadedScene> furnace_scene(const FurnaceOptions& o) {
  if (o.exact) {
    if (o.scene.method || o.scene.mesh || o.truth.mesh)
      input_error("pcrt furnace: --exact traces a generator's own surface: give --data only");
    auto s = std::make_unique<LoadedScene>();
    s->data = load_dataset(required(o.scene.data, "--data", FurnaceOptions::usage));
    if (!s->data.truth)
      input_error(
          "--data {}: no exact surface (a file, or a generator without one); --exact "
          "needs a generator with an exact surface",
          *o.scene.data);
    s->exact = std::make_unique<SurfaceScene>(*s->data.truth);
    s->params = {{"dataset", *o.scene.data}, {"N", s->data.cloud.size()}};
    return s;
  }
  if (!o.truth.mesh) {
    if (o.truth.sample || o.truth.engine)
      input_error("--sample and --truth-engine apply only to --truth");
    return load_scene(o.scene, "furnace", FurnaceOptions::usage);
  }
  if (o.scene.data || o.scene.mesh) input_error("pcrt furnace: give --data, --mesh or --truth");
  auto s = std::make_unique<LoadedScene>();
  AccuracyInput in = accuracy_input(std::nullopt, o.truth, FurnaceOptions::usage, s->prepare);
  s->data = std::move(in.data);
  s->data.truth = in.truth;
  s->points = std::make_unique<PointScene>(
      s->data.cloud, point_scene_options(o.scene, FurnaceOptions::usage), s->prepare, s->timings);
  s->params = scene_json(*s->points, s->data.cloud, in.describe["dataset"].get<std::string>());
  return s;
}

// The furnace's numbers, and where its dark pixels lost their light when there is a truth.
json furnace_json(const FurnaceResult& f, const json& params) {
  json j = {{"params", params},
            {"object_pixels", f.object_pixels},
            {"mean", f.mean},
            {"dark_pixels", f.dark_pixels},
            {"dark_share", f.object_pixels ? double(f.dark_pixels) / double(f.object_pixels) : 0.0},
            {"dark_primary", nullptr},
            {"dark_secondary", nullptr},
            {"counters", counters_json(f.frame.counters)}};
  if (f.causes) j["dark_primary"] = f.causes->primary, j["dark_secondary"] = f.causes->secondary;
  return j;
}

void print_furnace(const std::string& label, const FurnaceResult& f, const json& j,
                   const RenderSettings& rs) {
  std::printf("%s: furnace mean %.5f over %zu object pixels, %zu dark (%.2f%%), S=%d B=%d\n",
              label.c_str(), f.mean, f.object_pixels, f.dark_pixels,
              100.0 * j["dark_share"].get<double>(), rs.spp, rs.bounces);
  if (f.causes)
    std::printf("  by centre sample: %zu with a false camera-ray hit, %zu lost after a true one\n",
                f.causes->primary, f.causes->secondary);
}

}  // namespace

int command_furnace(const FurnaceOptions& o) {
  auto limit = limit_threads(o.scene.threads);
  const RenderSettings rs = frame_settings(o.settings, o.scene.threads, "furnace");
  if (o.out)
    check_outputs({{*o.out, "--out"}}, {{o.scene.data.value_or(""), "--data"},
                                        {o.scene.mesh.value_or(""), "--mesh"},
                                        {o.truth.mesh.value_or(""), "--truth"}});
  if (o.out) require_extension(*o.out, "--out", {".png", ".exr"});
  const auto loaded = furnace_scene(o);
  std::optional<FurnaceTruth> truth;
  if (loaded->data.truth) {
    OpCounters spacing;  // not the frame's work
    truth.emplace(
        FurnaceTruth{*loaded->data.truth, mean_spacing(loaded->cloud().positions, spacing)});
  }
  const FurnaceResult f = white_furnace(loaded->scene(), loaded->cloud(), rs, truth);
  if (o.out) {
    OutputFiles outputs;
    stage_render_images(outputs, f.frame, *o.out, "", "");
    outputs.commit();
  }
  json params = loaded->params;
  params.update({{"M", rs.width * rs.height}, {"S", rs.spp}, {"B", rs.bounces}, {"seed", rs.seed}});
  if (truth) params["mean_spacing"] = truth->h;
  const json j = furnace_json(f, params);
  if (o.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_furnace(loaded->label(), f, j, rs);
  return 0;
}

int command_accuracy(const AccuracyOptions& o) {
  auto limit = limit_threads(o.scene.threads);
  check_accuracy_options(o);
  Timings timings;
  OpCounters prep, counters;
  const AccuracyInput in = accuracy_input(o.scene.data, o.truth, AccuracyOptions::usage, prep);
  const PointCloud& cloud = in.data.cloud;
  const auto judged = judged_scene(o, cloud, prep, timings);
  const SceneIntersector& scene = *judged->scene;
  const std::string& method = judged->method;
  const std::string& structure = judged->structure;
  const auto rays = accuracy_rays(*in.truth, in.h, o.rays, o.seed);
  AccuracyReport r;
  {
    ScopedTimer t(timings, "trace");
    r = evaluate_accuracy(scene, *in.truth, in.h, rays, counters);
  }
  SecondaryReport sec;
  if (o.secondary > 0) {
    ScopedTimer t(timings, "secondary");
    sec = evaluate_secondary(scene, *in.truth, in.h, o.secondary, o.seed, counters);
  }
  json j = {{"method", method},
            {"structure", structure},
            {"N", cloud.size()},
            {"mean_spacing", in.h},
            {"counters", counters_json(counters)},
            {"timings", timings}};
  j.update(in.describe);
  j.update(accuracy_json(r));
  if (o.secondary > 0) j["secondary"] = secondary_json(sec);
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  print_accuracy(method + " on " + structure, j["dataset"].get<std::string>(), in.h, r);
  if (o.secondary > 0) print_secondary(sec);
  return 0;
}

namespace {

json comparison_json(const FrameComparison& c) {
  return {{"pixels", c.pixels},
          {"object_pixels", c.object_pixels},
          {"missing", c.missing},
          {"extra", c.extra},
          {"normal_off", c.normal_off},
          {"edge_pixels", c.edge_pixels},
          {"missing_at_edges", c.missing_at_edges},
          {"edge_reach_px", FrameComparison::kEdgeReachPx},
          {"missing_rate", c.missing_rate()},
          {"extra_rate", c.extra_rate()},
          {"normal_off_rate", c.normal_off_rate()},
          {"normal_off_deg", FrameComparison::kNormalOffDeg},
          {"lit_pixels", c.lit_pixels},
          {"false_shadow", c.false_shadow},
          {"false_shadow_rate", c.false_shadow_rate()},
          {"rmse", c.rmse}};
}

// The options compare refuses, and its outputs checked before any work.
void check_compare_options(const CompareOptions& o) {
  if (!o.truth.mesh) input_error("pcrt compare: --truth MESH is required");
  for (const auto& [given, option] :
       {std::pair{o.scene.data.has_value(), "data"}, std::pair{o.scene.mesh.has_value(), "mesh"},
        std::pair{o.scene.engine.has_value(), "engine"}})
    if (given)
      input_error("pcrt compare: --{} does not apply (the cloud comes from --truth)", option);
  std::vector<NamedPath> outputs{{o.out, "--out"}};
  if (o.images)
    for (const char* side : {".method.png", ".truth.png"})
      outputs.emplace_back(*o.images + side, "--images");
  check_outputs(outputs, {{*o.truth.mesh, "--truth"}});
  require_extension(o.out, "--out", {".png"});
}

RenderSettings compare_settings(const CompareOptions& o) {
  RenderSettings rs;
  rs.width = o.width;
  rs.height = o.height;
  rs.seed = o.seed;
  rs.threads = o.scene.threads;
  rs.spp = 1;
  rs.bounces = 0;  // direct light only: no sampling noise between the two frames
  rs.view = o.view;
  rs.up = o.up;
  check_camera_axes(rs.view, rs.up, "compare");
  return rs;
}

void print_comparison(const std::string& out, const json& j, const RenderSettings& rs,
                      const FrameComparison& c) {
  std::printf("%s: %s on %s vs %s, %dx%d, %zu object pixels\n", out.c_str(),
              j["method"].get<std::string>().c_str(), j["structure"].get<std::string>().c_str(),
              j["truth"].get<std::string>().c_str(), rs.width, rs.height, c.object_pixels);
  std::printf(
      "  missing %.3f%% (%zu of %zu at silhouettes and contours, which hold %.1f%% of the object)  "
      "extra %.3f%%  normal > %.0f deg %.3f%%  false shadows %.3f%% of %zu lit  RMSE %.4f\n",
      100 * c.missing_rate(), c.missing_at_edges, c.missing,
      c.object_pixels ? 100.0 * double(c.edge_pixels) / double(c.object_pixels) : 0.0,
      100 * c.extra_rate(), FrameComparison::kNormalOffDeg, 100 * c.normal_off_rate(),
      100 * c.false_shadow_rate(), c.lit_pixels, c.rmse);
}

}  // namespace

int command_compare(const CompareOptions& o) {
  auto limit = limit_threads(o.scene.threads);
  check_compare_options(o);
  RenderSettings rs = compare_settings(o);
  OpCounters prep;
  Timings timings;
  const AccuracyInput in = accuracy_input(std::nullopt, o.truth, CompareOptions::usage, prep);
  const auto& truth = static_cast<const MeshSurface&>(*in.truth);
  PointScene method(in.data.cloud, point_scene_options(o.scene, CompareOptions::usage), prep,
                    timings);
  const MeshScene mesh(truth.mesh(), o.truth.engine.value_or(kDefaultMeshEngine), prep, timings);
  // One camera and one light for both frames: both framed on the mesh's vertices.
  PointCloud frame;
  frame.positions = truth.mesh().vertices;
  rs.camera = Camera::framing(frame.bounds(), rs.width, rs.height, rs.view, rs.up);
  const RenderResult t = render(mesh, frame, rs);
  const RenderResult m = render(method, frame, rs);
  const FrameComparison c = compare_frames(t, m);
  const Image difference = difference_image(t, m);
  OutputFiles outputs;  // all or none
  outputs.stage(o.out, png_writer(difference), true);
  if (o.images) {
    outputs.stage(*o.images + ".method.png", png_writer(m.image), true);
    outputs.stage(*o.images + ".truth.png", png_writer(t.image), true);
  }
  outputs.commit();
  json j = {{"method", method.method_info().id},
            {"structure", method.structure_id()},
            {"width", rs.width},
            {"height", rs.height},
            {"N", in.data.cloud.size()},
            {"counters", counters_json(m.counters)}};
  j.update(in.describe);
  j.update(comparison_json(c));
  if (o.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_comparison(o.out, j, rs, c);
  return 0;
}

namespace {

void print_catalogue(const json& j) {
  std::printf("methods:\n");
  for (const auto& m : j["methods"])
    std::printf("  %-24s %-14s %s\n", m["id"].get<std::string>().c_str(),
                m["structure"].get<std::string>().c_str(),
                m["description"].get<std::string>().c_str());
  for (const auto& [title, key] : {std::pair{"structures", "structures"},
                                   {"reconstructions", "reconstructions"},
                                   {"mesh engines", "mesh_engines"},
                                   {"generators", "generators"}}) {
    std::printf("%s:\n", title);
    for (const auto& e : j[key])
      std::printf("  %-24s %s\n", e["id"].get<std::string>().c_str(),
                  e["description"].get<std::string>().c_str());
  }
}

}  // namespace

int command_list(const ListOptions& o) {
  const json j = catalogue_json();
  if (o.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_catalogue(j);
  return 0;
}

int command_convert(const ConvertOptions& o) {
  check_outputs({{o.out, "--out"}}, {{o.data, "DATA"}});
  require_extension(o.out, "--out", {".ply"});
  const Dataset d = load_dataset_in_input_order(o.data);  // a file keeps its order
  write_ply(o.out, d.cloud, o.ascii ? PlyFormat::kAscii : PlyFormat::kBinaryLittleEndian);
  std::printf("%s: %zu points (%s)\n", o.out.c_str(), d.cloud.size(),
              fmt::format("{}", fmt::join(d.cloud.attributes(), ", ")).c_str());
  return 0;
}

}  // namespace pcrt
