#include "methods/kernels/splat_kernel.hpp"

#include <catch2/catch.hpp>
#include <vector>

#include "methods/kernels/splat_blend.hpp"

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

TEST_CASE("weighted splat blend", "[kernels]") {
  // Two coplanar splats at z = 0 tilted normals, one further splat at z = -1 behind them.
  const Vec3 na = Vec3(0.2f, 0, 1).normalized(), nb = Vec3(-0.2f, 0, 1).normalized();
  const std::vector<PackedSplat> splats{{Vec3(-0.25f, 0, 0), 1.0f, na, 7},
                                        {Vec3(0.5f, 0, 0), 1.0f, nb, 3},
                                        {Vec3(0, 0, -1), 1.0f, Vec3::UnitZ(), 9}};
  const std::vector<uint32_t> items{0, 1, 2};
  const LeafVisit leaf{items, 0, kInfinity};
  const Ray down{Vec3(0, 0, 5), Vec3(0, 0, -1)};
  OpCounters counters;
  Hit hit;
  SECTION("the front group is blended with weights 1 - (d/r)^2") {
    REQUIRE(blend_splat_hits(down, leaf, splats, {0.2f, 1.0f, 0.0f}, hit, counters));
    // Splat 0's plane is crossed at t = 5.05, 0.065 squared from its centre (weight 0.935);
    // splat 1's at t = 5.1, 0.26 squared (weight 0.74); splat 2 (t = 6) is behind the window.
    REQUIRE(hit.t == Approx((0.935 * 5.05 + 0.74 * 5.1) / (0.935 + 0.74)).epsilon(1e-5));
    REQUIRE(hit.prim == 7);  // the larger weight: nearer its centre
    // The blended normal lies between the two and leans towards splat 0's.
    REQUIRE(hit.n.x() > 0);
    REQUIRE(hit.n.x() < na.x());
    REQUIRE(counters.get(kSplatTests) == 3);
  }
  SECTION("a normal field replaces the splat normals") {
    auto up = [](uint32_t, const Vec3&) { return Vec3(Vec3::UnitZ()); };
    REQUIRE(blend_splat_hits(down, leaf, splats, {0.2f, 1.0f, 0.0f}, up, hit, counters));
    REQUIRE(hit.n.isApprox(Vec3::UnitZ()));
  }
  SECTION("rays outside every radius miss") {
    const Ray aside{Vec3(3, 0, 5), Vec3(0, 0, -1)};
    REQUIRE_FALSE(blend_splat_hits(aside, leaf, splats, {0.2f, 1.0f, 0.0f}, hit, counters));
  }
  SECTION("a nearer hit already found is kept") {
    hit.t = 2;
    REQUIRE_FALSE(blend_splat_hits(down, leaf, splats, {0.2f, 1.0f, 0.0f}, hit, counters));
  }
}
