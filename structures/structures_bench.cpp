// Build time and closest-hit cost of every structure against N (10^3 to 10^7 points on the unit
// sphere), with the traversal counters per query as user counters so the harness can fit them.
// Families register themselves for every structure in the registry.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <mutex>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "methods/method.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

// A sphere cloud with its splats, generated once per N for all families.
struct Scene {
  PointCloud cloud;
  std::unique_ptr<Method> method;
  std::vector<Ray> rays;
};

const Scene& scene(int64_t n) {
  static std::map<int64_t, std::unique_ptr<Scene>> cache;
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  auto& slot = cache[n];
  if (!slot) {
    slot = std::make_unique<Scene>();
    slot->cloud = load_dataset(fmt::format("sphere:n={},seed=1", n)).cloud;
    // Radius about 2.4 mean spacings (mean nearest-neighbour distance ~ 0.5 sqrt(4 pi / N)):
    // fixed analytically so that 10^7-point clouds need no k-NN pass.
    slot->cloud.radii.assign(size_t(n), 1.2f * std::sqrt(4.0f * 3.14159265f / float(n)));
    const MethodInfo& info = MethodRegistry::instance().get("reference_splat", "method");
    slot->method = info.create(resolve_params(info.params, {}, "bench"));
    OpCounters c;
    Timings t;
    PrepareContext ctx{c, t};
    slot->method->prepare(slot->cloud, ctx);
    // Camera-like rays from outside aimed at points of the sphere: they all hit a surface.
    Rng rng(7);
    const Vec3 eye(1.5f, -2.5f, 1.5f);
    for (int i = 0; i < 4096; ++i) {
      const Vec3 target = slot->cloud.positions[rng.below(uint32_t(n))];
      slot->rays.push_back(Ray{eye, (target - eye).normalized()});
    }
  }
  return *slot;
}

std::unique_ptr<Structure> make(const StructureInfo& info, const Scene& s, OpCounters& c) {
  auto st = info.create(resolve_params(info.params, {}, info.id));
  st->build(s.method->items(), c);
  return st;
}

void build_bench(benchmark::State& state, const StructureInfo* info) {
  const Scene& s = scene(state.range(0));
  size_t bytes = 0;
  OpCounters c;
  for (auto _ : state) bytes = make(*info, s, c)->memory_bytes();
  state.SetComplexityN(state.range(0));
  state.counters["bytes_per_point"] = double(bytes) / double(state.range(0));
  state.counters["refs_per_point"] =
      double(c.get(kBuildItemRefs)) / double(state.iterations()) / double(state.range(0));
}

void query_bench(benchmark::State& state, const StructureInfo* info) {
  const Scene& s = scene(state.range(0));
  OpCounters build;
  const auto st = make(*info, s, build);
  OpCounters c;
  size_t i = 0, hits = 0;
  for (auto _ : state) {
    Hit hit;
    hits += st->closest_hit(s.rays[i++ % s.rays.size()], *s.method, hit, c);
  }
  const double q = double(state.iterations());
  state.SetComplexityN(state.range(0));
  state.counters["nodes_per_query"] = double(c.get(kNodesVisited)) / q;
  state.counters["leaves_per_query"] = double(c.get(kLeavesVisited)) / q;
  state.counters["items_per_query"] = double(c.get(kItemsVisited)) / q;
  state.counters["hit_fraction"] = double(hits) / q;
}

const bool kRegistered = [] {
  for (const StructureInfo& info : StructureRegistry::instance().all()) {
    const bool brute = info.id == "brute_force";
    auto* b = benchmark::RegisterBenchmark(("BM_Build/" + info.id).c_str(), build_bench, &info);
    b->RangeMultiplier(10)->Range(1000, brute ? 100000 : 10000000)->Unit(benchmark::kMillisecond);
    auto* q =
        benchmark::RegisterBenchmark(("BM_ClosestHit/" + info.id).c_str(), query_bench, &info);
    q->RangeMultiplier(10)->Range(1000, brute ? 100000 : 10000000);
  }
  return true;
}();

}  // namespace
}  // namespace pcrt
