#include "harness/cli_args.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"

using namespace pcrt;
using Catch::Matchers::Contains;

TEST_CASE("strict command-line options", "[cli]") {
  auto make = [] {
    return CliArgs(
        "t", "pcrt t",
        {{"out", "FILE", "output"}, {"json", "", "flag"}, {"set", "N=V", "repeat", true}}, 0, 1);
  };
  CliArgs a = make();
  REQUIRE(a.parse({"x", "--out", "f.png", "--json", "--set", "a=1", "--set=b=2"}));
  REQUIRE(a.get("out") == "f.png");
  REQUIRE(a.has("json"));
  REQUIRE(a.all("set") == std::vector<std::string>{"a=1", "b=2"});
  REQUIRE(a.positional() == std::vector<std::string>{"x"});
  REQUIRE_THROWS_WITH(make().parse({"--bogus"}), Contains("unknown option '--bogus'"));
  REQUIRE_THROWS_WITH(make().parse({"--out"}), Contains("needs a value"));
  REQUIRE_THROWS_WITH(make().parse({"--out", "a", "--out", "b"}), Contains("twice"));
  // Issue 14: the stray argument is named, and --help=1 is not an unknown option.
  REQUIRE_THROWS_WITH(make().parse({"a", "b"}),
                      Contains("unexpected argument 'b' (takes at most 1)"));
  REQUIRE_THROWS_WITH(CliArgs("t", "pcrt t", {{"json", "", "flag"}}, 0, 0).parse({"--json", "1"}),
                      Contains("unexpected argument '1' (takes no arguments)"));
  REQUIRE_THROWS_WITH(make().parse({"--help=1"}), Contains("--help takes no value"));
  REQUIRE_THROWS_WITH(CliArgs("t", "pcrt t", {}, 1, 1).parse({}), Contains("expected 1 argument"));
  REQUIRE_THROWS_WITH(make().parse({"--json=1"}), Contains("takes no value"));
  CliArgs n("t", "pcrt t", {integer_option("width", "W", "w", 1, 1, 10)}, 0, 0);
  REQUIRE(n.parse({"--width", "abc"}));
  REQUIRE_THROWS_WITH(n.integer("width"), Contains("not an integer"));
  CliArgs m("t", "pcrt t", {integer_option("width", "W", "w", 1, 1, 10)}, 0, 0);
  REQUIRE(m.parse({"--width", "0"}));
  REQUIRE_THROWS_WITH(m.integer("width"), Contains("outside"));
}

TEST_CASE("an option's default is declared once: help shows it, reads return it", "[cli]") {
  CliArgs a("t", "pcrt t",
            {integer_option("width", "W", "image width", 512, 1, 16384),
             {"engine", "ID", "triangle engine", false, "bvh"},
             {"out", "FILE", "output"}},
            0, 0);
  REQUIRE(a.parse({}));
  CHECK(a.integer("width") == 512);
  CHECK(a.get("engine") == "bvh");
  CHECK(a.get("out").empty());
  CHECK_FALSE(a.has("width"));  // has(): given on the command line, not defaulted
  CHECK_THAT(a.help(), Contains("image width (default 512)") && Contains("(default bvh)"));
  CliArgs b("t", "pcrt t", {integer_option("width", "W", "image width", 512, 1, 16384)}, 0, 0);
  REQUIRE(b.parse({"--width", "64"}));
  CHECK(b.integer("width") == 64);
}
