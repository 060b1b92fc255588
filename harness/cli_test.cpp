#include "harness/cli.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "harness/command_options.hpp"

using namespace pcrt;
using Catch::Matchers::Contains;

namespace {

// The options a command line fills, or the InputError it raises.
AllOptions parsed(const std::vector<std::string>& args) {
  CommandLine line;
  REQUIRE(line.parse(args));
  return line.options();
}

std::string error_of(const std::vector<std::string>& args) {
  CommandLine line;
  try {
    line.parse(args);
  } catch (const InputError& e) {
    return line.command() + ": " + e.what();
  }
  return "no error";
}

const std::vector<std::string> kRender = {"render", "--method", "m", "--data", "d", "--out", "o"};

std::vector<std::string> render_with(std::vector<std::string> more) {
  std::vector<std::string> args = kRender;
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

TEST_CASE("the command line fills the command's options struct", "[cli]") {
  const AllOptions o = parsed(render_with({"--width", "64", "--set", "a=1", "--set=b=2",
                                           "--no-light", "--view", "1,0,0", "--depth", ""}));
  CHECK(o.render.scene.method == "m");
  CHECK(o.render.out == "o");
  CHECK(o.render.settings.width == 64);
  CHECK(o.render.scene.set == ParamValues{{"a", 1}, {"b", 2}});
  CHECK_FALSE(o.render.settings.point_light);
  CHECK(o.render.settings.view == Vec3(1, 0, 0));
  CHECK(o.render.depth == std::string());  // given, empty: the command refuses it by name
  CHECK_FALSE(o.render.normals.has_value());
  // Integers are decimal (CLI11 alone reads a leading 0 as octal).
  CHECK(parsed(render_with({"--spp", "010"})).render.settings.spp == 10);
  const AllOptions s = parsed({"sweep", "c.json", "--shard", "1/3", "--fit"});
  REQUIRE(s.sweep.shard.has_value());
  CHECK((s.sweep.shard->index == 1 && s.sweep.shard->count == 3 && s.sweep.fit));
  CHECK(parsed({"merge", "a", "b", "--out", "m"}).merge.dirs == std::vector<std::string>{"a", "b"});
  const AllOptions c = parsed({"cluster", "submit", "c.json", "--shards", "4", "--sbatch-arg",
                               "--qos=long", "--sbatch-arg=--x=1"});
  CHECK(c.cluster_submit.shards == size_t(4));
  CHECK(c.cluster_submit.sbatch_args == std::vector<std::string>{"--qos=long", "--x=1"});
  CHECK(parsed({"_run", "{\"a\": 1}", "42"}).run_one.parent_pid == std::string("42"));
}

TEST_CASE("defaults are the structs', written once: --help shows them", "[cli]") {
  const AllOptions o = parsed(kRender);
  CHECK(o.render.settings.width == RenderSettings{}.width);
  CHECK(o.render.settings.spp == RenderSettings{}.spp);
  CHECK(o.render.settings.point_light);
  CHECK(o.render.scene.threads == 0);
  CHECK(parsed({"compare", "--method", "m", "--out", "o"}).compare.width == 256);
  CommandLine line;
  REQUIRE_FALSE(line.parse({"render", "--help"}));
  CHECK(line.command() == "render");
  const std::string help = line.help();
  CHECK_THAT(help, Contains("usage: pcrt render") && Contains("--width W") &&
                       Contains("image width in pixels (default: 512)") &&
                       Contains("(default: 0.55,-0.75,0.4)") && Contains("(default: bvh)") &&
                       Contains("--out FILE.png") && Contains("(required)"));
  CommandLine compare;
  REQUIRE_FALSE(compare.parse({"compare", "--help"}));
  CHECK_THAT(compare.help(), Contains("image width (default: 256)"));
  CommandLine top;
  REQUIRE_FALSE(top.parse({"help"}));
  CHECK_THAT(top.help(), Contains("render") && Contains("cluster") && !Contains("_run"));
  // --help wins over a bad value given with it.
  CommandLine bad;
  CHECK_FALSE(bad.parse(render_with({"--width", "0", "--help"})));
}

TEST_CASE("ranges and numbers are enforced, naming option and value", "[cli]") {
  CHECK_THAT(error_of(render_with({"--width", "0"})),
             Contains("render: --width 0 is outside [1, 16384]"));
  CHECK_THAT(error_of(render_with({"--spp", "x"})), Contains("--spp 'x' is not an integer"));
  CHECK_THAT(error_of(render_with({"--spp", "1e3"})), Contains("--spp '1e3' is not an integer"));
  CHECK_THAT(error_of(render_with({"--ray-epsilon", "nan"})),
             Contains("--ray-epsilon: 'nan' is not finite"));
  CHECK_THAT(error_of(render_with({"--ray-epsilon", "-1"})),
             Contains("--ray-epsilon must be >= 0"));
  CHECK_THAT(error_of({"check", "--config", "c", "--baseline", "b", "--tolerance", "inf"}),
             Contains("--tolerance: 'inf' is not finite"));
  CHECK_THAT(error_of(render_with({"--view", "1,2"})), Contains("--view: '1,2' is not x,y,z"));
  CHECK_THAT(error_of(render_with({"--set", "a=1", "--set", "a=2"})),
             Contains("--set a given twice"));
  CHECK_THAT(error_of({"sweep", "c.json", "--shard", "2/2"}), Contains("--shard 2/2"));
  CHECK_THAT(error_of({"cluster", "submit", "c.json", "--shards", "0"}),
             Contains("cluster submit: --shards 0 is outside [1, 100000]"));
}

TEST_CASE("parse errors are our one-line messages", "[cli]") {
  CHECK_THAT(error_of({"info", "x", "--bogus"}),
             Contains("info: unknown option '--bogus' (see pcrt info --help)"));
  CHECK_THAT(error_of({"info", "x", "--bogus=3"}), Contains("unknown option '--bogus'"));
  // An unknown option is named before the other errors of the same line.
  CHECK_THAT(error_of({"render", "--widht", "0", "--spp", "x"}), Contains("'--widht'"));
  CHECK_THAT(error_of({"frobnicate"}), Contains(": unknown command 'frobnicate'"));
  CHECK_THAT(error_of({"render", "--method", "m", "--data", "d"}),
             Contains("--out is required: usage: pcrt render"));
  CHECK_THAT(error_of(render_with({"--out", "p"})), Contains("--out given twice"));
  CHECK_THAT(error_of(render_with({"--no-light", "--no-light"})),
             Contains("--no-light given twice"));
  CHECK_THAT(error_of(render_with({"--width"})), Contains("--width needs a value (W)"));
  CHECK_THAT(error_of({"info", "x", "--json=1"}), Contains("--json takes no value"));
  CHECK_THAT(error_of({"info", "x", "--help=1"}), Contains("--help takes no value"));
  CHECK_THAT(error_of({"info"}), Contains("expected 1 argument(s), got 0"));
  CHECK_THAT(error_of({"merge", "--out", "m"}), Contains("expected at least 1 argument(s), got 0"));
  CHECK_THAT(error_of({"info", "a", "b"}), Contains("unexpected argument 'b' (takes at most 1)"));
  CHECK_THAT(error_of({"list", "--json", "1"}),
             Contains("unexpected argument '1' (takes no arguments)"));
  CHECK_THAT(error_of({"info", "a", "fit"}), Contains("unexpected argument 'fit'"));
  CHECK_THAT(error_of({"cluster"}), Contains("cluster: usage: pcrt cluster submit"));
  CHECK_THAT(error_of({"cluster", "bogus"}), Contains("unknown subcommand 'bogus'"));
  CHECK_THAT(error_of({"cluster", "submit", "c.json", "--bogus"}),
             Contains("cluster submit: unknown option '--bogus' (see pcrt cluster submit --help)"));
}
