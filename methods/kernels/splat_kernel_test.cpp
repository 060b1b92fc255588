#include "methods/kernels/splat_kernel.hpp"

#include <catch2/catch.hpp>

using namespace pcrt;

TEST_CASE("ray-splat kernel", "[kernels]") {
  const Ray down{Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1)};
  REQUIRE(intersect_splat(down, Vec3::Zero(), Vec3::UnitZ(), 0.5f, 0, kInfinity) == Approx(5));
  // Two-sided.
  REQUIRE(intersect_splat(down, Vec3::Zero(), -Vec3::UnitZ(), 0.5f, 0, kInfinity) == Approx(5));
  // Outside the radius, behind the origin, beyond tmax, parallel.
  REQUIRE(intersect_splat(down, Vec3::Zero(), Vec3::UnitZ(), 0.2f, 0, kInfinity) == kInfinity);
  REQUIRE(intersect_splat(down, Vec3(0, 0, 6), Vec3::UnitZ(), 0.5f, 0, kInfinity) == kInfinity);
  REQUIRE(intersect_splat(down, Vec3::Zero(), Vec3::UnitZ(), 0.5f, 0, 4.0f) == kInfinity);
  REQUIRE(intersect_splat(down, Vec3::Zero(), Vec3::UnitX(), 0.5f, 0, kInfinity) == kInfinity);
  // Tilted disc: hit where the ray crosses its plane.
  const Vec3 n = Vec3(0, 1, 1).normalized();
  REQUIRE(intersect_splat(down, Vec3::Zero(), n, 1.0f, 0, kInfinity) == Approx(5.2f));
}
