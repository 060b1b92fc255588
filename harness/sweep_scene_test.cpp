// Scene files in sweeps: a run puts its method and cloud into the objects a scene marks "swept",
// the config names the scene beside its datasets, and what is wrong is refused before any run.
#include <catch2/catch.hpp>
#include <fstream>

#include "core/error.hpp"
#include "harness/run_executors.hpp"
#include "harness/scene_file.hpp"
#include "harness/sweep_config.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}

const char* kTwoMirrors = R"({
  "materials": {"mirror": {"type": "mirror"}},
  "objects": [
    {"points": "plane:n=300", "method": "reference_splat", "material": "mirror", "swept": true,
     "transform": {"translate": [0, 0, -1]}},
    {"points": "plane:n=300", "method": "reference_splat", "material": "mirror", "swept": true,
     "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 180}, "translate": [0, 0, 1]}},
    {"quad": {"size": 10}, "transform": {"translate": [0, 0, -3]}}
  ],
  "lights": [{"type": "sky"}],
  "camera": {"eye": [0, 0, 0.5], "target": [0.05, 0.02, -1], "up": [0, 1, 0], "fov": 10}
})";

std::string expect_input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("no InputError");
  return "";
}

}  // namespace

TEST_CASE("a sweep's run traces its own method and cloud in every swept object", "[sweep][scene]") {
  const std::string path = write_file("pcrt_two_mirrors.json", kTwoMirrors);
  PointCloud cloud = load_dataset("plane:n=500,seed=3").cloud;
  const SweptCloud run{cloud, SceneOptions{"goradia_2010", "", {}}};
  const auto file = load_scene_file(path, &run);
  REQUIRE(file->swept);
  REQUIRE(file->scene.objects.size() == 3);
  CHECK(file->scene.objects[0].geometry == file->swept);  // one structure for both mirrors
  CHECK(file->scene.objects[1].geometry == file->swept);
  CHECK(file->scene.objects[0].points == &cloud);
  CHECK(file->params["objects"][0]["method"] == "goradia_2010");
  CHECK(file->params["objects"][1]["N"] == 500);
  CHECK(file->clouds.empty());               // the file's own clouds are not even loaded
  const auto alone = load_scene_file(path);  // rendered alone, each traces its own
  CHECK_FALSE(alone->swept);
  CHECK(alone->params["objects"][0]["method"] == "reference_splat");
  CHECK(alone->scene.objects[0].geometry != alone->scene.objects[1].geometry);
}

TEST_CASE("a scene's render run bounces between its mirrors B times", "[sweep][scene]") {
  const std::string path = write_file("pcrt_two_mirrors_run.json", kTwoMirrors);
  RunSpec spec;
  spec.experiment = "mirrors";
  spec.dataset = "plane:size=6";
  spec.scene = path;
  spec.method = "reference_splat";
  spec.structure = "kd_tree";
  spec.N = 400, spec.M = 64, spec.B = 3;
  const RunResult r = execute_run(spec);
  REQUIRE(r.ok());
  CHECK(r.points == 400u);
  // Every camera ray meets a mirror and every bounce the other one: 4 hits per path.
  CHECK(r.counters.at("primary_rays") == 64);
  CHECK(r.counters.at("bounce_rays") == 3 * 64);
  CHECK(r.counters.at("ray_hits") == 4 * 64);
  CHECK(r.measures.structure_bytes);
  const json j = r;
  CHECK(j["scene"] == path);
}

TEST_CASE("scene files refuse what a sweep cannot use, naming file and key", "[sweep][scene]") {
  const std::string none = write_file(
      "pcrt_no_swept.json",
      R"({"objects": [{"points": "plane:n=100", "method": "reference_splat"}], "lights": [{"type": "sky"}]})");
  PointCloud cloud = load_dataset("plane:n=100").cloud;
  const SweptCloud run{cloud, SceneOptions{"reference_splat", "", {}}};
  CHECK_THAT(expect_input_error([&] { (void)load_scene_file(none, &run); }),
             Catch::Contains("pcrt_no_swept.json: objects mark no point cloud \"swept\": true"));
  CHECK_THAT(expect_input_error([&] { check_sweep_scene(none); }),
             Catch::Contains("pcrt_no_swept.json: objects mark no point cloud"));
  const std::string on_mesh = write_file(
      "pcrt_swept_mesh.json",
      R"({"objects": [{"quad": {"size": 1}, "swept": true}], "lights": [{"type": "sky"}]})");
  CHECK_THAT(expect_input_error([&] { (void)load_scene_file(on_mesh); }),
             Catch::Contains("objects[0].swept applies only to point clouds"));
  const std::string not_bool = write_file(
      "pcrt_swept_text.json",
      R"({"objects": [{"points": "plane:n=100", "method": "reference_splat", "swept": "yes"}], "lights": [{"type": "sky"}]})");
  CHECK_THAT(expect_input_error([&] { check_sweep_scene(not_bool); }),
             Catch::Contains("objects[0].swept must be true or false"));
}

TEST_CASE("sweep configs name scenes for render runs only, resolved beside the config",
          "[sweep][scene]") {
  const std::string scene = write_file("pcrt_cfg_mirrors.json", kTwoMirrors);
  const std::string folder = std::filesystem::path(scene).parent_path().string();
  auto config = [&](const std::string& extra) {
    return json::parse(R"({"dataset_dir": ")" + folder + R"(", "experiments": [{"name": "m",
      "kind": "render", "methods": ["reference_splat"], "datasets": ["plane"],
      "grid": {"N": [200], "M": [16], "B": [1, 2]})" +
                       extra + "}]}");
  };
  const SweepConfig c =
      parse_sweep_config(config(R"(, "scene": "pcrt_cfg_mirrors.json")"), "c.json");
  REQUIRE(c.runs.size() == 2);
  CHECK(c.runs[0].scene == "pcrt_cfg_mirrors.json");
  CHECK(c.runs[0].scene_path == scene);
  CHECK(json::parse(run_key(c.runs[0])).count("scene_path") ==
        0);  // where it lies is not what it is
  CHECK(json::parse(run_key(c.runs[0]))["scene"] == "pcrt_cfg_mirrors.json");
  CHECK_THAT(expect_input_error([&] {
               (void)parse_sweep_config(config(R"(, "scene": "missing.json")"), "c.json");
             }),
             Catch::Contains("c.json: experiments[0]: scene:"));
  CHECK_THAT(expect_input_error([&] {
               (void)parse_sweep_config(
                   config(R"(, "scene": "pcrt_cfg_mirrors.json", "camera": "inside")"), "c.json");
             }),
             Catch::Contains("a scene brings its own camera"));
  json build = config(R"(, "scene": "pcrt_cfg_mirrors.json")");
  build["experiments"][0]["kind"] = "build";
  CHECK_THAT(expect_input_error([&] { (void)parse_sweep_config(build, "c.json"); }),
             Catch::Contains("scene applies only to render runs"));
}
