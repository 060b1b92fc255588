#include "preprocess/point_attributes.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/dataset.hpp"

using namespace pcrt;

namespace {
double degrees(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(double(a.dot(b)), -1.0, 1.0)) * 180.0 / 3.14159265358979;
}
}  // namespace

TEST_CASE("PCA normals on a noise-free sphere of 1e5 points: median error under 2 degrees, outward",
          "[normals]") {
  const Dataset d = load_dataset("sphere:n=100000,seed=1");
  const KnnIndex knn(d.cloud.positions);
  OpCounters c;
  const auto normals = estimate_normals(d.cloud.positions, knn, 16, c);
  std::vector<double> err;
  size_t outward = 0;
  for (size_t i = 0; i < normals.size(); ++i) {
    const Vec3 truth = d.cloud.positions[i].normalized();
    err.push_back(degrees(normals[i], truth) > 90 ? 180 - degrees(normals[i], truth)
                                                  : degrees(normals[i], truth));
    outward += normals[i].dot(truth) > 0;
  }
  std::nth_element(err.begin(), err.begin() + long(err.size() / 2), err.end());
  const double median = err[err.size() / 2];
  INFO("median angle " << median << " deg, outward " << outward);
  REQUIRE(median < 2.0);
  REQUIRE(outward == normals.size());  // MST orientation is consistent on a closed sphere
  REQUIRE(c.get(kNormalsEstimated) == 100000);
  REQUIRE(c.get(kKnnQueries) == 100000);
}

TEST_CASE("normal orientation is consistent on a torus", "[normals]") {
  const Dataset d = load_dataset("torus:n=20000,seed=2");
  const KnnIndex knn(d.cloud.positions);
  OpCounters c;
  const auto normals = estimate_normals(d.cloud.positions, knn, 16, c);
  size_t agree = 0;
  for (size_t i = 0; i < normals.size(); ++i) agree += normals[i].dot(d.cloud.normals[i]) > 0;
  REQUIRE(agree == normals.size());
}

TEST_CASE("radii and spacing follow neighbour distances", "[radii]") {
  // A regular grid with spacing 0.1: nearest neighbour 0.1, 4th 0.1, 8th 0.1*sqrt(2).
  std::vector<Vec3> pts;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) pts.emplace_back(0.1f * float(i), 0.1f * float(j), 0);
  const KnnIndex knn(pts);
  OpCounters c;
  REQUIRE(mean_spacing(pts, knn, c) == Approx(0.1).epsilon(1e-5));
  const auto r = estimate_radii(pts, knn, 8, 1.0f, c);
  REQUIRE(r[15 * 30 + 15] == Approx(0.1 * std::sqrt(2.0)).epsilon(1e-5));
  const auto r2 = estimate_radii(pts, knn, 4, 2.0f, c);
  REQUIRE(r2[15 * 30 + 15] == Approx(0.2).epsilon(1e-5));
}
