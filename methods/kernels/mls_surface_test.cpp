#include "methods/kernels/mls_surface.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "methods/kernels/weighted_plane.hpp"

using namespace pcrt;

namespace {

// A grid of points on the height field z = 0.3 x^2 - 0.2 xy + 0.1 y^2 + 0.05 x (spacing 0.05).
std::vector<Vec3> paraboloid_points() {
  std::vector<Vec3> p;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      const float x = 0.05f * float(i), y = 0.05f * float(j);
      p.emplace_back(x, y, 0.3f * x * x - 0.2f * x * y + 0.1f * y * y + 0.05f * x);
    }
  return p;
}

float height(float x, float y) { return 0.3f * x * x - 0.2f * x * y + 0.1f * y * y + 0.05f * x; }

}  // namespace

TEST_CASE("MLS fit reproduces a quadratic height field and the ray root is exact", "[kernels]") {
  const std::vector<Vec3> pts = paraboloid_points();
  const KnnIndex knn(pts);
  MlsSettings s;
  s.k = 30;
  s.weight_radius = 0.1f;
  s.tolerance = 1e-6f;
  s.max_iterations = 10;
  const MlsSurface surface(pts, knn, s);
  OpCounters counters;
  // An oblique ray from above aimed at (0.1, -0.05) on the surface.
  const Vec3 target(0.1f, -0.05f, height(0.1f, -0.05f));
  const Vec3 dir = Vec3(0.3f, 0.2f, -1).normalized();
  const Ray ray{target - 2 * dir, dir};
  Vec3 n = Vec3::Zero();
  const float t = surface.intersect_ray(ray, pts[0], 0, 10, n, counters);
  REQUIRE(t == Approx(2.0f).margin(1e-4));
  // The height field's gradient at the target: (0.6x - 0.2y + 0.05, -0.2x + 0.2y).
  const Vec3 truth =
      Vec3(-(0.6f * 0.1f + 0.2f * 0.05f + 0.05f), -(-0.2f * 0.1f - 0.2f * 0.05f), 1).normalized();
  REQUIRE(std::abs(n.dot(truth)) == Approx(1.0f).margin(1e-4));
  REQUIRE(counters.get(kMlsConverged) == 1);
  REQUIRE(counters.get(kMlsFits) >= 2);
  REQUIRE(counters.get(kMlsNeighbours) == 30 * counters.get(kMlsFits));
}

TEST_CASE("MLS iteration cap and misses", "[kernels]") {
  const std::vector<Vec3> pts = paraboloid_points();
  const KnnIndex knn(pts);
  MlsSettings s;
  s.k = 20;
  s.weight_radius = 0.1f;
  s.tolerance = 0;  // always run the cap
  s.max_iterations = 4;
  const MlsSurface surface(pts, knn, s);
  OpCounters counters;
  Vec3 n = Vec3::Zero();
  const Ray down{Vec3(0, 0, 1), Vec3(0, 0, -1)};
  REQUIRE(surface.intersect_ray(down, pts[220], 0, 5, n, counters) == Approx(1.0f).margin(1e-4));
  REQUIRE(counters.get(kMlsFits) == 4);
  REQUIRE(counters.get(kMlsCapped) == 1);
  // A ray parallel to the surface far above it has no root.
  const Ray above{Vec3(-1, 0, 1), Vec3(1, 0, 0)};
  REQUIRE(surface.intersect_ray(above, pts[220], 0, 5, n, counters) == kInfinity);
  REQUIRE(counters.get(kMlsNoRoot) == 1);
}

TEST_CASE("ball chord", "[kernels]") {
  const Ray r{Vec3(0, 0, 0), Vec3(1, 0, 0)};
  float t0 = 0, t1 = 0;
  REQUIRE(ball_chord(r, Vec3(5, 1, 0), 2, kInfinity, t0, t1));
  REQUIRE(t0 == Approx(5 - std::sqrt(3.0f)));
  REQUIRE(t1 == Approx(5 + std::sqrt(3.0f)));
  REQUIRE_FALSE(ball_chord(r, Vec3(5, 3, 0), 2, kInfinity, t0, t1));
  REQUIRE_FALSE(ball_chord(r, Vec3(5, 1, 0), 2, 3.0f, t0, t1));  // beyond tmax
}

TEST_CASE("weighted plane: average, implicit distance and height difference", "[kernels]") {
  const std::vector<PackedSplat> pts{{Vec3(0, 0, 0), 1, Vec3::UnitZ(), 0},
                                     {Vec3(1, 0, 0.2f), 1, Vec3::UnitZ(), 1},
                                     {Vec3(9, 9, 9), 1, Vec3::UnitX(), 2}};
  const std::vector<uint32_t> items{0, 1, 2};
  OpCounters counters;
  auto theta = [](float d2, const PackedSplat&) { return d2 < 4.0f ? 1.0f : 0.0f; };
  const WeightedPlane w = weighted_plane(Vec3(0.5f, 0, 1), items, pts, theta, counters);
  REQUIRE(w.weight == Approx(2));  // the far point has no weight
  REQUIRE(w.p.isApprox(Vec3(0.5f, 0, 0.1f)));
  REQUIRE(w.implicit(Vec3(0.5f, 0, 1)) == Approx(0.9f));
  REQUIRE(w.height == Approx(0.9f));
  REQUIRE(counters.get(kWeightedPointTerms) == 3);
}
