#include "core/params.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"

namespace pcrt {
namespace {

struct Inner {
  size_t k = 0;
  static const ParamList<Inner>& list() {
    static const auto l = ParamList<Inner>().add(&Inner::k, {"k", 4, 1, 10, "count", false});
    return l;
  }
};

struct Outer {
  Inner inner;
  float depth = 0;
  bool flag = false;
  static const ParamList<Outer>& list() {
    static const auto l = ParamList<Outer>()
                              .add(&Outer::inner, Inner::list())
                              .add(&Outer::depth, {"depth", 0.5, 0, 2, "window", true})
                              .add(&Outer::flag, {"flag", 1, 0, 1, "switch"});
    return l;
  }
};

TEST_CASE("a typed parameter list declares once and reads into its struct", "[params]") {
  const auto& specs = Outer::list().specs();
  REQUIRE(specs.size() == 3);
  CHECK(specs[0].name == "k");
  // Integer or not follows the member's type, not what the spec literal said.
  CHECK(specs[0].integer);
  CHECK_FALSE(specs[1].integer);
  CHECK(specs[2].integer);

  const Outer defaults = Outer::list().read({}, "test");
  CHECK(defaults.inner.k == 4);
  CHECK(defaults.depth == 0.5f);
  CHECK(defaults.flag);

  const Outer set = Outer::list().read({{"k", 7}, {"depth", 1.25}, {"flag", 0}}, "test");
  CHECK(set.inner.k == 7);
  CHECK(set.depth == 1.25f);
  CHECK_FALSE(set.flag);
}

TEST_CASE("a typed parameter list refuses unknown names, fractions and out-of-range values",
          "[params]") {
  CHECK_THROWS_WITH(Outer::list().read({{"dpeth", 1}}, "m"),
                    "m: unknown parameter 'dpeth' (known: k, depth, flag)");
  CHECK_THROWS_WITH(Outer::list().read({{"k", 2.5}}, "m"), "m: k must be an integer, not 2.5");
  CHECK_THROWS_AS(Outer::list().read({{"depth", 3}}, "m"), InputError);
}

}  // namespace
}  // namespace pcrt
