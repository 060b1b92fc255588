#include "core/ray_io.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "tests/test_helpers.hpp"

using namespace pcrt;
using Catch::Matchers::Contains;
using pcrt::test::write_text;

TEST_CASE("rays CSV: origins Embree cannot take are refused naming the line", "[io][errors]") {
  // Embree 3 asserts |origin| <= 1.8e18 (issue 14: 2e18 aborted pcrt trace).
  REQUIRE_THROWS_WITH(read_rays_csv(write_text(
                          "far_rays.csv", "ox,oy,oz,dx,dy,dz\n0,0,5,0,0,-1\n2e18,0,5,0,0,-1\n")),
                      Contains("far_rays.csv: line 3: origin coordinate beyond"));
  REQUIRE_THROWS_WITH(
      read_rays_csv(write_text("nan_rays.csv", "ox,oy,oz,dx,dy,dz\n0,0,nan,0,0,1\n")),
      Contains("nan_rays.csv: line 2: non-finite value"));
  // A direction whose float norm overflows is still normalised.
  const auto rays =
      read_rays_csv(write_text("big_dir.csv", "ox,oy,oz,dx,dy,dz\n0,0,5,3e38,0,3e38\n"));
  REQUIRE(rays.size() == 1);
  REQUIRE(rays[0].d.norm() == Approx(1.0f));
}
