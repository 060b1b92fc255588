// Small helpers shared by the Catch2 tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pcrt::test {

// A fresh scratch directory per test binary run.
inline std::filesystem::path scratch_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("pcrt_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string write_text(const std::string& name, const std::string& content) {
  const auto p = scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}

}  // namespace pcrt::test
