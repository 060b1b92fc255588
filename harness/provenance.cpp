#include "harness/provenance.hpp"

#include <cctype>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "harness/build_info.hpp"
#include "harness/subprocess.hpp"
#include "methods/kernels/disc_lanes.hpp"

namespace pcrt {
namespace {

// The value of the first "key: value" line of `file` that starts with `key` ("" if none).
std::string first_line_of(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const size_t colon = line.find(':');
      std::string v = colon == std::string::npos ? line : line.substr(colon + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      return v;
    }
  return std::string();
}

std::string read_all(const std::string& file) {
  std::ifstream in(file);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// git -C SOURCE_DIR ARGS... without a shell (no path needs quoting); nullopt when git is missing
// or fails.
std::optional<std::string> git(std::vector<std::string> args) {
  args.insert(args.begin(), {"git", "-C", build_info().source_dir});
  try {
    CommandOutput out = run_command(args);
    if (out.exit_code != 0) return std::nullopt;
    return out.out;
  } catch (const InputError&) {
    return std::nullopt;
  }
}

// The source tree's commit and whether tracked files differ from it (results made from a dirty
// tree cannot be reproduced from the commit alone); "unknown" without git.
std::pair<std::string, json> source_revision() {
  std::string commit = git({"rev-parse", "HEAD"}).value_or("");
  while (!commit.empty() && std::isspace(static_cast<unsigned char>(commit.back())))
    commit.pop_back();
  if (commit.empty()) return {"unknown", nullptr};
  const std::optional<std::string> status = git({"status", "--porcelain", "--untracked-files=no"});
  return {commit, status ? json(!status->empty()) : json(nullptr)};
}

}  // namespace

json source_context() {
  const auto [commit, dirty] = source_revision();
  return {{"git_commit", commit}, {"git_dirty", dirty}};
}

json machine_context(const json& config) {
  const auto [commit, dirty] = source_revision();
  return {{"machine",
           {{"cpu", first_line_of("/proc/cpuinfo", "model name")},
            {"cores", std::thread::hardware_concurrency()},
            {"memory", first_line_of("/proc/meminfo", "MemTotal")},
            {"governor", read_all("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor")}}},
          {"compiler", build_info().compiler},
          {"flags", build_info().flags},
          {"build_type", build_info().build_type},
          {"leaf_simd", disc_lanes_name()},
          {"dependencies", build_info().dependencies},
          {"git_commit", commit},
          {"git_dirty", dirty},
          {"build_commit", build_revision().commit},
          {"build_dirty", build_revision().dirty ? json(*build_revision().dirty) : json(nullptr)},
          {"config", config}};
}

}  // namespace pcrt
