#include "core/file_output.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "tests/test_helpers.hpp"

using namespace pcrt;
using Catch::Matchers::Contains;

namespace {
std::string contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST_CASE("outputs are committed all or none", "[io][errors]") {
  const auto dir = pcrt::test::scratch_dir() / "outputs";
  std::filesystem::create_directories(dir);
  const std::string a = pcrt::test::write_text("outputs/a.txt", "precious a");
  const std::string b = pcrt::test::write_text("outputs/b.txt", "precious b");
  auto writes = [](const char* text) { return [text](std::ostream& o) { o << text; }; };
  SECTION("a failure after the first file is staged leaves both targets as they were") {
    {
      OutputFiles outputs;
      outputs.stage(a, writes("new a"));
      REQUIRE_THROWS_AS(outputs.stage(b, [](std::ostream&) { input_error("render failed"); }),
                        InputError);
    }
    REQUIRE(contents(a) == "precious a");
    REQUIRE(contents(b) == "precious b");
    REQUIRE(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()) == 2);  // no temporaries
  }
  SECTION("commit renames every staged file") {
    OutputFiles outputs;
    outputs.stage(a, writes("new a"));
    outputs.stage(b, writes("new b"));
    REQUIRE(contents(a) == "precious a");
    outputs.commit();
    REQUIRE(contents(a) == "new a");
    REQUIRE(contents(b) == "new b");
  }
  SECTION("output paths are checked before any work, naming the option") {
    REQUIRE_THROWS_WITH(check_output_path("", "--depth"), Contains("--depth: an empty file name"));
    REQUIRE_THROWS_WITH(check_output_path(dir.string(), "--stats"),
                        Contains("--stats " + dir.string() + ": is a directory"));
    REQUIRE_THROWS_WITH(check_output_path((dir / "none" / "x.png").string(), "--out"),
                        Contains("does not exist"));
    REQUIRE_NOTHROW(check_output_path(a, "--out"));
    REQUIRE_NOTHROW(check_output_path("relative.png", "--out"));
  }
}
