// Preprocessing cost (Table 5.3 preconditions) against N.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "core/dataset.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

void BM_EstimateNormals(benchmark::State& state) {
  const Dataset d = load_dataset(fmt::format("sphere:n={}", state.range(0)));
  const KnnIndex index(d.cloud.positions);
  OpCounters c;
  for (auto _ : state)
    benchmark::DoNotOptimize(estimate_normals(d.cloud.positions, index, 16, c).data());
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_EstimateNormals)
    ->RangeMultiplier(10)
    ->Range(1000, 1000000)
    ->Unit(benchmark::kMillisecond);

void BM_EstimateRadii(benchmark::State& state) {
  const Dataset d = load_dataset(fmt::format("sphere:n={}", state.range(0)));
  const KnnIndex index(d.cloud.positions);
  OpCounters c;
  for (auto _ : state)
    benchmark::DoNotOptimize(estimate_radii(d.cloud.positions, index, 8, 1.0f, c).data());
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_EstimateRadii)
    ->RangeMultiplier(10)
    ->Range(1000, 1000000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pcrt
