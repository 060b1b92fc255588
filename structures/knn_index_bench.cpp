// k-NN index build and query cost against N (nanoflann).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "core/dataset.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {
namespace {

void BM_KnnBuild(benchmark::State& state) {
  const Dataset d = load_dataset(fmt::format("sphere:n={}", state.range(0)));
  for (auto _ : state) {
    KnnIndex index(d.cloud.positions);
    benchmark::DoNotOptimize(index.memory_bytes());
  }
  state.SetComplexityN(state.range(0));
  const KnnIndex index(d.cloud.positions);
  state.counters["bytes_per_point"] = double(index.memory_bytes()) / double(state.range(0));
}
BENCHMARK(BM_KnnBuild)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond);

void BM_KnnQuery16(benchmark::State& state) {
  const Dataset d = load_dataset(fmt::format("sphere:n={}", state.range(0)));
  const KnnIndex index(d.cloud.positions);
  OpCounters c;
  uint32_t idx[16];
  float d2[16];
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(index.knn(d.cloud.positions[i++ % d.cloud.size()], 16, idx, d2, c));
  }
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_KnnQuery16)->RangeMultiplier(10)->Range(1000, 1000000);

}  // namespace
}  // namespace pcrt
