#include "structures/knn_index.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

#include "core/dataset.hpp"

using namespace pcrt;

TEST_CASE("k-NN matches brute force", "[knn]") {
  const Dataset d = load_dataset("bumpy_sphere:n=3000,seed=3");
  const auto& pts = d.cloud.positions;
  const KnnIndex index(pts);
  OpCounters c;
  Rng rng(11);
  for (int q = 0; q < 200; ++q) {
    const Vec3 x(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    std::vector<std::pair<float, uint32_t>> all;
    for (uint32_t i = 0; i < pts.size(); ++i) all.push_back({(pts[i] - x).squaredNorm(), i});
    std::sort(all.begin(), all.end());
    uint32_t idx[12];
    float d2[12];
    REQUIRE(index.knn(x, 12, idx, d2, c) == 12);
    for (int k = 0; k < 12; ++k) REQUIRE(d2[k] == Approx(all[size_t(k)].first).margin(1e-6));
    std::vector<std::pair<uint32_t, float>> within;
    const float r = std::sqrt(all[20].first) * 1.0001f;
    index.radius(x, r, within, c);
    REQUIRE(within.size() == size_t(std::count_if(all.begin(), all.end(),
                                                  [&](auto& e) { return e.first <= r * r; })));
  }
  REQUIRE(c.get(kKnnQueries) == 400);
}
