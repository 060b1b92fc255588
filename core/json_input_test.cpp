#include "core/json_input.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "core/error.hpp"

using namespace pcrt;
using Catch::Matchers::Contains;

TEST_CASE("JSON input: nesting is bounded, NUL and trailing bytes are errors", "[json][errors]") {
  const std::string deep = std::string(1000000, '[') + std::string(1000000, ']');
  REQUIRE_THROWS_WITH(parse_json_text(deep, "deep.json"),
                      Contains("deep.json: line 1: nested deeper than 64 levels"));
  const std::string at_limit = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  REQUIRE(parse_json_text(at_limit, "ok.json").is_array());
  // Brackets inside strings are not nesting.
  REQUIRE(parse_json_text("{\"a\": \"" + std::string(100, '[') + "\\\"\"}", "s.json").is_object());
  REQUIRE_THROWS_WITH(parse_json_text(std::string("{}\0", 3), "nul.json"),
                      Contains("nul.json: line 1: a NUL byte"));
  REQUIRE_THROWS_WITH(parse_json_text("{} {}", "two.json"),
                      Contains("two.json: not valid JSON: parse error at line 1, column 4"));
  REQUIRE_THROWS_AS(parse_json_text("{\n\"a\": [1,\n", "cut.json"), InputError);
}

TEST_CASE("JSON input: a number beyond double is an error naming the file", "[json][errors]") {
  // Found by fuzz_json: nlohmann throws out_of_range, not parse_error, for it.
  REQUIRE_THROWS_WITH(parse_json_text("{\"a\": 3e5353}", "big.json"),
                      Contains("big.json: not valid JSON: number overflow parsing '3e5353'"));
}

TEST_CASE("JSON input: a key twice in one object is an error naming it", "[json][errors]") {
  REQUIRE_THROWS_WITH(
      parse_json_text(R"({"grid": {"N": [100]}, "grid": {"N": [200]}})", "twice.json"),
      Contains("twice.json: key \"grid\" appears twice in one object"));
  REQUIRE_THROWS_WITH(parse_json_text(R"([{"a": 1}, {"b": {"c": 1, "c": 2}}])", "deep.json"),
                      Contains("key \"c\" appears twice"));
  // The same key in different objects, or nested under itself, is fine.
  REQUIRE(parse_json_text(R"([{"a": 1}, {"a": 2}, {"a": {"a": 3}}])", "ok.json").is_array());
}

TEST_CASE("JSON input: a long list of objects parses whole, duplicates still found",
          "[json][errors]") {
  // nlohmann's callback parser scanned the enclosing list at every object's end: a cluster plan
  // of 10^5 empty shards took 12 s (release) and 4 minutes under ASan to refuse; 4 10^5 would
  // take over three minutes here. Parsed in one linear pass now.
  std::string text = "[";
  for (int i = 0; i < 400000; ++i) text += R"({"runs": []},)";
  text.back() = ']';
  REQUIRE(parse_json_text(text, "long.json").size() == 400000);
  text.insert(text.size() - 1, R"(,{"a": 1, "b": 2, "a": 3})");
  REQUIRE_THROWS_WITH(parse_json_text(text, "long.json"), Contains("key \"a\" appears twice"));
}
