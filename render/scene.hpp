// A method on a structure over a cloud: what the renderer and `pcrt trace` ask for closest hits.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/counters.hpp"
#include "core/point_cloud.hpp"
#include "methods/method.hpp"
#include "structures/structure.hpp"

namespace pcrt {

// Anything that answers closest-hit queries: a point method on a structure, later a mesh engine.
class SceneIntersector {
 public:
  virtual ~SceneIntersector() = default;
  virtual bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const = 0;
  // Whether anything blocks the ray within [ray.tmin, ray.tmax) (shadow rays). This default asks
  // for a closest hit; scenes with a cheaper occlusion query override it.
  virtual bool any_hit(const Ray& ray, OpCounters& counters) const {
    Hit h;
    h.t = ray.tmax;
    return closest_hit(ray, h, counters);
  }
  // n <= 16 occlusion queries traced together (a tile's shadow rays): blocked[i] as
  // any_hit(rays[i]) answers, with the same counts. This default asks ray by ray.
  virtual void any_hits(const Ray* rays, int n, char* blocked, OpCounters& counters) const {
    for (int i = 0; i < n; ++i) blocked[i] = char(any_hit(rays[i], counters));
  }
  // A primary pass replacing camera-ray tracing for this frame, or nullptr (Method::primary_pass).
  [[nodiscard]] virtual std::unique_ptr<PrimaryPass> primary_pass(const Camera& /*camera*/,
                                                                  OpCounters& /*counters*/) const {
    return nullptr;
  }
  // The caustic sample map a frame holding this object builds (MethodInfo::caustic_map), or null.
  [[nodiscard]] virtual const CausticMapSpec* caustic_map() const { return nullptr; }
};

struct SceneOptions {
  std::string method;
  std::string structure;  // empty: the method's paper's structure
  ParamValues set;        // --set values; each name must belong to the method or the structure
  // How a user gave `set`, for the error naming an unknown one ("--set", "keyword").
  std::string set_source = "--set";
};

class PointScene final : public SceneIntersector {
 public:
  // Prepares the method and builds the structure, counting into `counters` and timing
  // "prepare/..." and "build" into `timings`. Throws InputError for unknown ids or parameters.
  PointScene(const PointCloud& cloud, const SceneOptions& options, OpCounters& counters,
             Timings& timings);
  // The same from a stream (core/point_stream.hpp) for methods that prepare from one
  // (MethodInfo::stream_bytes_per_point); InputError naming the method for the others.
  PointScene(const PointStream& stream, const SceneOptions& options, OpCounters& counters,
             Timings& timings);

  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override;
  bool any_hit(const Ray& ray, OpCounters& counters) const override;
  void any_hits(const Ray* rays, int n, char* blocked, OpCounters& counters) const override;
  [[nodiscard]] std::unique_ptr<PrimaryPass> primary_pass(const Camera& camera,
                                                          OpCounters& counters) const override {
    return method_->primary_pass(camera, counters);
  }
  [[nodiscard]] const CausticMapSpec* caustic_map() const override {
    return caustic_map_ ? &*caustic_map_ : nullptr;
  }

  [[nodiscard]] const MethodInfo& method_info() const { return *method_info_; }
  // The structure's id, or the method's own acceleration (e.g. "embree_bvh").
  [[nodiscard]] const std::string& structure_id() const { return structure_id_; }
  [[nodiscard]] const ParamValues& method_params() const { return method_params_; }
  // As given, with what the build chose where a value was left to it (Structure::resolved_params).
  [[nodiscard]] const ParamValues& structure_params() const { return structure_params_; }
  [[nodiscard]] size_t structure_bytes() const {
    return structure_ ? structure_->memory_bytes() : 0;
  }
  // What the method and structure were estimated to add to the cloud (render/memory_estimate).
  [[nodiscard]] size_t estimated_bytes() const { return estimated_bytes_; }

 private:
  // Looks up the method and structure and splits --set between them.
  void resolve(const SceneOptions& options);
  // Creates the method, runs `prepare` on it and builds the structure over its items.
  void prepare_and_build(const std::function<void(PrepareContext&)>& prepare, OpCounters& counters,
                         Timings& timings);

  const MethodInfo* method_info_;
  const StructureInfo* structure_info_ = nullptr;  // null when the method traces on its own
  std::string structure_id_;
  ParamValues method_params_, structure_params_;
  std::unique_ptr<Method> method_;
  std::unique_ptr<Structure> structure_;
  size_t estimated_bytes_ = 0;
  std::optional<CausticMapSpec> caustic_map_;
};

// Closest hits of `rays` on all threads TBB may use (a tbb::global_control bounds them);
// found[i] says whether rays[i] hit. Counters are kept per thread and summed, so they do not
// depend on the thread count. What `pcrt trace` and the Python module's Scene.trace run.
OpCounters trace_rays(const SceneIntersector& scene, std::span<const Ray> rays, std::span<Hit> hits,
                      std::span<char> found);

}  // namespace pcrt
