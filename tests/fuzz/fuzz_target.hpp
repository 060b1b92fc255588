// What every fuzz target checks: the input is either accepted or refused with an InputError
// naming it on one line; any other exception, a crash, a hang or a sanitizer report is a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/point_cloud.hpp"
#include "core/point_stream.hpp"

namespace pcrt::fuzz {

inline constexpr const char* kName = "fuzz-input";

template <typename Read>
void expect_accepted_or_refused(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    if (std::string(e.what()).find(kName) == std::string::npos) {
      std::fprintf(stderr, "the error does not name the input: %s\n", e.what());
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "not an InputError: %s\n", e.what());
    std::abort();
  }
}

inline std::string text_of(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// The input as a file whose path names it (fuzz-input.EXT in a directory of this process's own),
// for the readers that take a path (the streams).
inline std::string input_file(const std::string& text, const std::string& ext) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("pcrt_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string path = (dir / (std::string(kName) + ext)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  return path;
}

// The stream of the file at `path` read whole into `out`, or false where it refuses it (an
// InputError naming it).
inline bool streamed(const std::string& path, PointCloud& out) {
  bool ok = false;
  expect_accepted_or_refused([&] {
    const auto stream = open_point_stream(path);
    out.origin = stream->origin();
    stream->read([&](const PointChunk& c) {
      out.positions.insert(out.positions.end(), c.positions.begin(), c.positions.end());
      out.normals.insert(out.normals.end(), c.normals.begin(), c.normals.end());
    });
    ok = true;
  });
  return ok;
}

// Whether the stream delivered the whole read's positions, normals and origin.
inline bool same_points(const PointCloud& a, const PointCloud& b) {
  return a.positions == b.positions && a.normals == b.normals && a.origin == b.origin;
}

}  // namespace pcrt::fuzz
