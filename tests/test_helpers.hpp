// Small helpers shared by the Catch2 tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pcrt::test {

// A fresh scratch directory per test binary run, removed when the process exits (ctest runs each
// case in a process of its own: without the removal every run left its files, tens of MB, in the
// temporary directory).
inline std::filesystem::path scratch_dir() {
  struct Scratch {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("pcrt_test_" + std::to_string(::getpid()));
    Scratch() { std::filesystem::create_directories(path); }
    ~Scratch() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Scratch dir;
  return dir.path;
}

inline std::string write_text(const std::string& name, const std::string& content) {
  const auto p = scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}

}  // namespace pcrt::test
