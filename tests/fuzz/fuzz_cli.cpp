// Whole command lines through pcrt's commands, in process: the input's lines are the arguments;
// an empty line ends a command, and up to three commands run in turn in one scratch directory, so
// that a later one reads what an earlier one wrote (convert, then info or render on its file).
// Every line is parsed by the real command line; a command runs when it stays small (clouds of
// at most kMaxPoints, frames of at most kMaxRays rays, files of this directory only), so that
// each input takes milliseconds. A command must succeed or refuse with an InputError; any other
// exception, a crash or a sanitizer report is a finding.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "harness/cli.hpp"
#include "harness/command_options.hpp"
#include "render/mesh_truth.hpp"

namespace {

namespace fs = std::filesystem;
using namespace pcrt;

constexpr double kMaxPoints = 300;
constexpr double kMaxRays = 4096;
constexpr double kMaxValue = 64;  // --set values, bounces, threads
constexpr size_t kMaxFileBytes = 1 << 16;

using Command = std::vector<std::string>;

std::vector<Command> commands_of(const uint8_t* data, size_t size) {
  std::vector<Command> commands(1);
  std::string token;
  for (size_t i = 0; i <= size; ++i) {
    if (i < size && data[i] != '\n') {
      token += char(data[i]);
    } else if (!token.empty()) {
      commands.back().push_back(token), token.clear();
    } else if (i < size && !commands.back().empty()) {
      if (commands.size() == 3) break;
      commands.emplace_back();
    }
  }
  return commands;
}

// Nothing outside the scratch directory: no path with a separator, no parent; and no NUL, which
// no argument of a real command line can hold.
bool stays_here(const Command& args) {
  return std::none_of(args.begin(), args.end(), [](const std::string& a) {
    return a.find('/') != std::string::npos || a.find('\0') != std::string::npos || a == "..";
  });
}

// A file of this directory that is small, or a generator spec of few points.
bool small_data(const std::string& data) {
  std::error_code ec;
  if (fs::exists(data, ec))
    return !fs::is_regular_file(data, ec) || fs::file_size(data, ec) <= kMaxFileBytes;
  try {
    return parse_generator_spec(data, nullptr).at("n") <= kMaxPoints;
  } catch (const InputError&) {
    return true;  // refused before anything is generated
  }
}

bool small_file(const std::optional<std::string>& file) { return !file || small_data(*file); }

bool small_scene(const SceneArgs& s) {
  return (!s.data || small_data(*s.data)) && small_file(s.mesh) && s.threads <= 2 &&
         std::all_of(s.set.begin(), s.set.end(),
                     [](const auto& p) { return std::abs(p.second) <= kMaxValue; });
}

bool small_frame(const RenderSettings& r) {
  return double(r.width) * r.height * r.spp * (r.bounces + 1) <= kMaxRays && r.threads <= 2;
}

bool small_truth(const TruthArgs& t) {
  if (!t.mesh) return true;
  if (!t.sample || !small_data(*t.mesh)) return false;  // the default samples 10^5 points
  try {
    return parse_mesh_sampling(*t.sample).n <= kMaxPoints;
  } catch (const InputError&) {
    return true;
  }
}

// Whether the parsed command runs here (the others are parsed only).
bool small_enough(const std::string& cmd, const AllOptions& o) {
  if (cmd == "list" || cmd == "fit" || cmd == "merge") return true;
  if (cmd == "info") return small_data(o.info.data) && o.info.threads <= 2;
  if (cmd == "convert") return small_data(o.convert.data);
  if (cmd == "render")
    return small_scene(o.render.scene) && small_frame(o.render.settings) &&
           small_file(o.render.scene_file);
  if (cmd == "trace") return small_scene(o.trace.scene) && small_data(o.trace.rays);
  if (cmd == "furnace")
    return small_scene(o.furnace.scene) && small_frame(o.furnace.settings) &&
           small_truth(o.furnace.truth);
  if (cmd == "accuracy")
    return small_scene(o.accuracy.scene) && o.accuracy.rays <= kMaxRays &&
           o.accuracy.secondary <= kMaxRays && small_truth(o.accuracy.truth);
  if (cmd == "compare")
    return small_scene(o.compare.scene) && small_truth(o.compare.truth) &&
           double(o.compare.width) * o.compare.height <= kMaxRays;
  return false;  // sweeps, clusters, CGAL, benchmarks and scripts: parsed only
}

void run_one(const Command& args) {
  CommandLine line;
  if (!line.parse(args)) return;  // help
  if (small_enough(line.command(), line.options())) (void)line.run();
}

// A fresh, empty directory of its own, made current, with stdout discarded.
void enter_scratch_directory() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("pcrt-fuzz-cli-" + std::to_string(getpid()));
    fs::create_directories(d);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    close(null);
    return d;
  }();
  fs::current_path(dir);
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) fs::remove_all(e.path());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<Command> commands = commands_of(data, size);
  if (!std::all_of(commands.begin(), commands.end(), stays_here)) return 0;
  enter_scratch_directory();
  for (const Command& args : commands) {
    if (args.empty()) continue;
    try {
      run_one(args);
    } catch (const InputError& e) {
      if (std::string(e.what()).empty()) {
        std::fprintf(stderr, "an InputError without a message\n");
        std::abort();
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "internal error (exit 3): %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
