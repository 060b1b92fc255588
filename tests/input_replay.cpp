// pcrt_input_replay FILE...: every reader of user input on each hostile FILE, in-process, so a
// sanitizer build (scripts/test.sh) sees what the readers do with it. The reader is chosen by
// extension and name: mesh_*.ply/.off as a mesh (vertices and faces), other .ply/.off/.xyz/.pwn as
// a point cloud, .csv as rays, .spec as a dataset spec (the file's first line); config_*.json as
// a sweep config, plan_*.json as a cluster plan (against tests/fuzz/seeds/config/small.json),
// jobs_*.json as a cluster's jobs file (of a 3-shard plan), other .json as JSON; .jsonl as a
// sweep's runs file, then fitted as `pcrt fit` does. Every input must be rejected with an
// InputError whose message names it; exit status 1 otherwise. Point files (.ply, .xyz, .pwn) are
// also streamed (`render --stream`), which reads fewer fields: there an input may be accepted,
// but a refusal must name it and nothing else may go wrong.
#include <array>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/json_input.hpp"
#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "core/ray_io.hpp"
#include "harness/run_files.hpp"
#include "harness/shard_plan.hpp"
#include "harness/slurm.hpp"
#include "harness/sweep_config.hpp"
#include "harness/sweep_fits.hpp"

namespace {

using Triangles = std::vector<std::array<uint32_t, 3>>;

std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

bool starts_with(const std::string& path, const char* prefix) {
  return std::filesystem::path(path).filename().string().rfind(prefix, 0) == 0;
}

const pcrt::SweepConfig& small_sweep() {
  static const pcrt::SweepConfig config =
      pcrt::load_sweep_config(PCRT_SOURCE_DIR "/tests/fuzz/seeds/config/small.json");
  return config;
}

// The harness's files: configs, plans, jobs and runs files, each read as the command reads it.
std::vector<std::pair<std::string, std::function<void()>>> harness_readers_for(
    const std::string& path) {
  using namespace pcrt;
  if (std::filesystem::path(path).extension() == ".jsonl")
    return {{path, [=] { (void)fit_runs(small_sweep(), read_runs_file(path).runs); }}};
  if (starts_with(path, "config_")) return {{path, [=] { (void)load_sweep_config(path); }}};
  if (starts_with(path, "plan_"))
    return {{path, [=] {
               const json plan = read_json_file(path);
               for (size_t s = 0; s < read_plan(plan, path).size(); ++s)
                 (void)plan_shard(plan, small_sweep().runs, s, read_plan(plan, path).size(), path);
             }}};
  if (starts_with(path, "jobs_"))
    return {{path, [=] { (void)newest_jobs(read_json_file(path), 3, path); }}};
  return {{path, [=] { read_json_file(path); }}};
}

// The readers that take `path`, each with the name its message must contain.
std::vector<std::pair<std::string, std::function<void()>>> readers_for(const std::string& path) {
  using namespace pcrt;
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool mesh = std::filesystem::path(path).filename().string().rfind("mesh_", 0) == 0;
  if (mesh && ext == ".ply")
    return {{path, [=] {
               Triangles t;
               read_ply(path, &t);
             }}};
  if (mesh && ext == ".off")
    return {{path, [=] {
               Triangles t;
               read_off(path, &t);
             }}};
  if (ext == ".ply" || ext == ".off" || ext == ".xyz" || ext == ".pwn")
    return {{path, [=] { read_point_cloud(path); }}};
  if (ext == ".csv") return {{path, [=] { read_rays_csv(path); }}};
  if (ext == ".json" || ext == ".jsonl") return harness_readers_for(path);
  if (ext == ".spec") {
    const std::string spec = first_line(path);
    return {{spec, [=] { load_dataset(spec); }}};
  }
  return {};
}

// Whether `path` is a point file `render --stream` takes (not a mesh_ file).
bool streams(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return !starts_with(path, "mesh_") && (ext == ".ply" || ext == ".xyz" || ext == ".pwn");
}

// Opens the stream and reads every point (bounds() checks each).
std::function<void()> stream_all(const std::string& path) {
  return [=] { (void)pcrt::open_point_stream(path)->bounds(); };
}

// 0 when `read` rejects its input with one line naming it (or, if `may_accept`, accepts it).
int replay(const std::string& path, const std::string& name, const std::function<void()>& read,
           bool may_accept = false) {
  try {
    read();
    if (may_accept) {
      std::printf("ok   %s: streamed\n", path.c_str());
      return 0;
    }
  } catch (const pcrt::InputError& e) {
    const std::string what = e.what();
    // (The CLI prints it on one line whatever it quotes: tests/bad_inputs.sh cli.)
    if (what.find(name) == std::string::npos) {
      std::printf("FAIL %s: the error does not name it: %s\n", path.c_str(), what.c_str());
      return 1;
    }
    std::printf("ok   %s\n", what.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::printf("FAIL %s: not an InputError: %s\n", path.c_str(), e.what());
    return 1;
  }
  std::printf("FAIL %s: accepted\n", path.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  int failures = 0, inputs = 0;
  for (int i = 1; i < argc; ++i) {
    const auto readers = readers_for(argv[i]);
    if (readers.empty()) {
      std::printf("FAIL %s: no reader for this extension\n", argv[i]);
      ++failures;
    }
    for (const auto& [name, read] : readers) failures += replay(argv[i], name, read), ++inputs;
    if (streams(argv[i])) failures += replay(argv[i], argv[i], stream_all(argv[i]), true), ++inputs;
  }
  std::printf("%d reads of %d inputs, %d failures\n", inputs, argc - 1, failures);
  return failures == 0 ? 0 : 1;
}
