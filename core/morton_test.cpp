#include "core/morton.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <numeric>
#include <random>

#include "core/dataset.hpp"

namespace pcrt {

TEST_CASE("morton_sort: the result depends on the points, not on their order") {
  PointCloud a = load_dataset_in_input_order("torus:n=5000,seed=3").cloud;
  a.radii.resize(a.size());
  for (size_t i = 0; i < a.size(); ++i) a.radii[i] = float(i);  // tags which point went where
  std::vector<uint32_t> shuffle(a.size());
  std::iota(shuffle.begin(), shuffle.end(), 0u);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(7));
  PointCloud b = a.subset(shuffle);
  const PointCloud original = a;
  morton_sort(a);
  morton_sort(b);
  CHECK(a.positions == b.positions);
  CHECK(a.normals == b.normals);
  CHECK(a.radii == b.radii);
  // Each point kept its own attributes.
  for (size_t k = 0; k < a.size(); ++k) {
    const auto i = size_t(a.radii[k]);
    REQUIRE(a.positions[k] == original.positions[i]);
    REQUIRE(a.normals[k] == original.normals[i]);
  }
  // Keys never decrease along the sorted cloud.
  const Aabb bounds = a.bounds();
  for (size_t k = 1; k < a.size(); ++k)
    REQUIRE(morton_key(a.positions[k - 1], bounds) <= morton_key(a.positions[k], bounds));
}

TEST_CASE("morton_key interleaves x, y, z from the lowest bit") {
  Aabb b;
  b.extend(Vec3(0, 0, 0));
  b.extend(Vec3(1, 1, 1));
  CHECK(morton_key(Vec3(0, 0, 0), b) == 0);
  CHECK(morton_key(Vec3(1, 0, 0), b) == 0x1249249249249249ull);
  CHECK(morton_key(Vec3(0, 1, 0), b) == 0x1249249249249249ull << 1);
  CHECK(morton_key(Vec3(0, 0, 1), b) == 0x1249249249249249ull << 2);
}

TEST_CASE("load_dataset returns the cloud in Morton order") {
  const PointCloud in_order = load_dataset_in_input_order("sphere:n=2000,seed=1").cloud;
  const PointCloud sorted = load_dataset("sphere:n=2000,seed=1").cloud;
  REQUIRE(sorted.size() == in_order.size());
  CHECK(sorted.positions != in_order.positions);
  PointCloud again = in_order;
  morton_sort(again);
  CHECK(again.positions == sorted.positions);
  CHECK(again.normals == sorted.normals);
}

TEST_CASE("morton_order of clouds 1e-38 across and of one repeated point is defined") {
  // The scale 2^21 / extent overflows to +inf for extents below about 1e-32: cells are clamped,
  // never converted from inf or NaN (UBSan's float-cast-overflow caught it before).
  const std::vector<Vec3> tiny = {Vec3(0, 0, 0), Vec3(1e-38f, 0, 0), Vec3(0, 2e-38f, 0),
                                  Vec3(3e-39f, 1e-38f, 1e-38f)};
  const std::vector<uint32_t> order = morton_order(tiny);
  REQUIRE(order.size() == tiny.size());
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted == std::vector<uint32_t>{0, 1, 2, 3});
  Aabb box;
  for (const Vec3& p : tiny) box.extend(p);
  CHECK(morton_key(tiny[3], box) <= morton_key(Vec3(1e-38f, 2e-38f, 1e-38f), box));
  const std::vector<Vec3> same(5, Vec3(1, 2, 3));
  CHECK(morton_order(same) == std::vector<uint32_t>{0, 1, 2, 3, 4});
}

}  // namespace pcrt
