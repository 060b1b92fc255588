// The three triangle engines on the same mesh and the same rays, in one run: rays per second
// (items_per_second in Google Benchmark's output).
#include <benchmark/benchmark.h>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"

namespace pcrt {
namespace {

const TriangleMesh& sphere_mesh() {
  static const TriangleMesh mesh = [] {
    const Dataset d = load_dataset("sphere:n=100000");
    return ReconstructionRegistry::instance().get("afsr", "reconstruction").run(d.cloud).mesh;
  }();
  return mesh;
}

std::vector<Ray> camera_rays(size_t n) {
  std::vector<Ray> rays(n);
  Rng rng(3, 9);
  for (Ray& r : rays) {
    r.o = Vec3(0, -4, 0.5f);
    const Vec3 target(1.6f * (rng.uniform() - 0.5f), 0, 1.6f * (rng.uniform() - 0.5f));
    r.d = (target - r.o).normalized();
  }
  return rays;
}

void BM_MeshEngine(benchmark::State& state, const char* engine) {
  const TriangleMesh& mesh = sphere_mesh();
  OpCounters counters;
  Timings timings;
  const MeshScene scene(mesh, engine, counters, timings);
  const std::vector<Ray> rays = camera_rays(1 << 14);
  for (auto _ : state) {
    for (const Ray& r : rays) {
      Hit h;
      benchmark::DoNotOptimize(scene.closest_hit(r, h, counters));
    }
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
  state.counters["triangles"] = double(mesh.triangles.size());
}

BENCHMARK_CAPTURE(BM_MeshEngine, bvh, "bvh")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MeshEngine, cgal_aabb, "cgal_aabb")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MeshEngine, embree, "embree")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pcrt
