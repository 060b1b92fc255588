#include "render/scene.hpp"

#include <fmt/ranges.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "render/memory_estimate.hpp"

namespace pcrt {

void PointScene::resolve(const SceneOptions& options) {
  method_info_ = &MethodRegistry::instance().get(options.method, "method");
  static const StructureInfo kOwn{"", "", "", "", {}, nullptr, nullptr};
  if (!method_info_->own_structure.empty()) {
    if (!options.structure.empty() && options.structure != method_info_->own_structure)
      input_error("method {} traces through its own {}; --structure {} does not apply",
                  method_info_->id, method_info_->own_structure, options.structure);
    structure_id_ = method_info_->own_structure;
  } else {
    structure_info_ = &StructureRegistry::instance().get(
        options.structure.empty() ? method_info_->structure : options.structure, "structure");
    structure_id_ = structure_info_->id;
  }
  const StructureInfo& sinfo = structure_info_ ? *structure_info_ : kOwn;
  ParamValues for_method, for_structure;
  for (const auto& [name, value] : options.set) {
    auto names = [&, &key = name](const std::vector<ParamSpec>& specs) {
      for (const auto& s : specs)
        if (s.name == key) return true;
      return false;
    };
    if (names(method_info_->params))
      for_method[name] = value;
    else if (names(sinfo.params))
      for_structure[name] = value;
    else {
      std::string known;
      for (const auto& s : method_info_->params) known += (known.empty() ? "" : ", ") + s.name;
      for (const auto& s : sinfo.params) known += (known.empty() ? "" : ", ") + s.name;
      input_error("{} {}: not a parameter of method '{}' or structure '{}' (known: {})",
                  options.set_source, name, method_info_->id, structure_id_,
                  known.empty() ? "none" : known);
    }
  }
  method_params_ = resolve_params(method_info_->params, for_method, "method " + method_info_->id);
  structure_params_ = resolve_params(sinfo.params, for_structure, "structure " + structure_id_);
}

PointScene::PointScene(const PointCloud& cloud, const SceneOptions& options, OpCounters& counters,
                       Timings& timings) {
  resolve(options);
  // Refused before any work if it cannot fit (the cloud is already in memory).
  estimated_bytes_ =
      estimate_scene_bytes(*method_info_, structure_id_, cloud, method_params_, structure_params_);
  require_memory(estimated_bytes_, fmt::format("{} with {} on {} points", cloud.name,
                                               method_info_->id, cloud.size()));
  prepare_and_build([&](PrepareContext& ctx) { method_->prepare(cloud, ctx); }, counters, timings);
}

PointScene::PointScene(const PointStream& stream, const SceneOptions& options, OpCounters& counters,
                       Timings& timings) {
  resolve(options);
  const auto& per_point = method_info_->stream_bytes_per_point;
  const size_t bytes = per_point ? per_point(method_params_) : 0;
  if (bytes == 0) {
    std::vector<std::string> streaming;
    for (const MethodInfo& m : MethodRegistry::instance().all())
      if (m.stream_bytes_per_point) streaming.push_back(m.id);
    input_error(
        "{}: method {} does not prepare from a stream with these parameters (methods "
        "that can, for some parameters: {})",
        stream.name(), method_info_->id, fmt::join(streaming, ", "));
  }
  // Refused before the first point is drawn if it cannot fit.
  estimated_bytes_ = bytes * stream.size();
  require_memory(estimated_bytes_, fmt::format("{} streamed into {} ({} points)", stream.name(),
                                               method_info_->id, stream.size()));
  prepare_and_build([&](PrepareContext& ctx) { method_->prepare_stream(stream, ctx); }, counters,
                    timings);
}

void PointScene::prepare_and_build(const std::function<void(PrepareContext&)>& prepare,
                                   OpCounters& counters, Timings& timings) {
  method_ = method_info_->create(method_params_);
  if (method_info_->caustic_map) caustic_map_ = method_info_->caustic_map(method_params_);
  {
    PrepareContext ctx{counters, timings};
    ScopedTimer t(timings, "prepare");
    prepare(ctx);
  }
  if (!structure_info_) return;  // the method built its own acceleration while preparing
  structure_ = structure_info_->create(structure_params_);
  ScopedTimer t(timings, "build");
  structure_->build(method_->items(), counters);
  method_->bind_leaf_references(structure_->leaf_references());
  for (const auto& [name, value] : structure_->resolved_params()) structure_params_[name] = value;
}

bool PointScene::closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const {
  counters.add(kRaysCast);
  const bool found = structure_ ? method_->closest_hit_through(*structure_, ray, hit, counters)
                                : method_->own_closest_hit(ray, hit, counters);
  if (found) counters.add(kRayHits);
  return found;
}

bool PointScene::any_hit(const Ray& ray, OpCounters& counters) const {
  counters.add(kRaysCast);
  counters.add(kAnyHitRays);
  const bool found = structure_ ? method_->any_hit_through(*structure_, ray, counters)
                                : method_->own_any_hit(ray, counters);
  if (found) counters.add(kRaysOccluded);
  return found;
}

void PointScene::any_hits(const Ray* rays, int n, char* blocked, OpCounters& counters) const {
  if (!structure_) return SceneIntersector::any_hits(rays, n, blocked, counters);
  counters.add(kRaysCast, uint64_t(n));
  counters.add(kAnyHitRays, uint64_t(n));
  method_->any_hits_through(*structure_, rays, n, blocked, counters);
  counters.add(kRaysOccluded, uint64_t(std::count(blocked, blocked + n, 1)));
}

OpCounters trace_rays(const SceneIntersector& scene, std::span<const Ray> rays, std::span<Hit> hits,
                      std::span<char> found) {
  tbb::combinable<OpCounters> per_thread;
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
    found[i] = scene.closest_hit(rays[i], hits[i], per_thread.local());
  });
  OpCounters counters;
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });
  return counters;
}

}  // namespace pcrt
