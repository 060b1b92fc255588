// Frame cost of the generic renderer with the O(N) oracle, reporting the operation counters as
// user counters so the harness can fit them against N.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "core/dataset.hpp"
#include "render/renderer.hpp"

namespace pcrt {
namespace {

void BM_RenderBruteForce(benchmark::State& state) {
  const Dataset d = load_dataset(fmt::format("sphere:n={}", state.range(0)));
  OpCounters prep;
  Timings t;
  const PointScene scene(d.cloud, SceneOptions{"reference_splat", "brute_force", {}}, prep, t);
  RenderSettings s;
  s.width = s.height = 32;
  s.bounces = 1;
  OpCounters last;
  for (auto _ : state) last = render(scene, d.cloud, s).counters;
  for (const auto& [name, value] : last.to_map()) state.counters[name] = double(value);
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_RenderBruteForce)
    ->RangeMultiplier(4)
    ->Range(256, 16384)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pcrt
