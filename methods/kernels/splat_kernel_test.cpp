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
  const std::vector<Vec3> centres{Vec3(-0.25f, 0, 0), Vec3(0.5f, 0, 0), Vec3(0, 0, -1)};
  const std::vector<Vec3> normals{na, nb, Vec3::UnitZ()};
  const std::vector<float> radii{1.0f, 1.0f, 1.0f};
  const std::vector<uint32_t> prims{7, 3, 9};
  const SplatSet splats = make_splat_set(centres, normals, radii, prims);
  const std::vector<uint32_t> items{0, 1, 2};
  // Read from the item-order set (a leaf of no bound structure), then from leaf-order blocks,
  // then gathered from the item arrays.
  SplatLeafBlocks unbound, leaf_order, item_order;
  leaf_order.bind(items, splats, DiscBlockLayout::kLeafOrder);
  item_order.bind(items, splats, DiscBlockLayout::kItemOrder);
  const int use_blocks = GENERATE(0, 1, 2);
  const SplatLeafBlocks& blocks = use_blocks == 0   ? unbound
                                  : use_blocks == 1 ? leaf_order
                                                    : item_order;
  INFO("blocks (0 unbound, 1 leaf order, 2 item order): " << use_blocks);
  const LeafVisit leaf{items, 0, kInfinity};
  const Ray down{Vec3(0, 0, 5), Vec3(0, 0, -1)};
  const SplatBlendSettings settings{0.2f, 1.0f, 0.0f};
  OpCounters counters;
  Hit hit;
  SECTION("the front group is blended with weights 1 - (d/r)^2") {
    REQUIRE(blend_splat_hits(down, leaf, blocks, splats, settings, hit, counters));
    // Splat 7's plane is crossed at t = 5.05, 0.065 squared from its centre (weight 0.935);
    // splat 3's at t = 5.1, 0.26 squared (weight 0.74); splat 9 (t = 6) is behind the window.
    REQUIRE(hit.t == Approx((0.935 * 5.05 + 0.74 * 5.1) / (0.935 + 0.74)).epsilon(1e-5));
    REQUIRE(hit.prim == 7);  // the larger weight: nearer its centre
    // The blended normal lies between the two and leans towards splat 7's.
    REQUIRE(hit.n.x() > 0);
    REQUIRE(hit.n.x() < na.x());
    REQUIRE(counters.get(kSplatTests) == 3);
  }
  SECTION("a normal field replaces the splat normals") {
    auto up = [](uint32_t, const PackedSplat&, const Vec3&) { return Vec3(Vec3::UnitZ()); };
    REQUIRE(blend_splat_hits(down, leaf, blocks, splats, settings, up, hit, counters));
    REQUIRE(hit.n.isApprox(Vec3::UnitZ()));
  }
  SECTION("rays outside every radius miss") {
    const Ray aside{Vec3(3, 0, 5), Vec3(0, 0, -1)};
    REQUIRE_FALSE(blend_splat_hits(aside, leaf, blocks, splats, settings, hit, counters));
  }
  SECTION("a nearer hit already found is kept") {
    hit.t = 2;
    REQUIRE_FALSE(blend_splat_hits(down, leaf, blocks, splats, settings, hit, counters));
  }
}
