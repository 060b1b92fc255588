// XYZ and PWN point files (3 or 6 columns), read whole and streamed (open_xyz_stream, from a
// file holding the input): where the whole read keeps normals, the stream must deliver the same
// positions, origin and normals; where it refuses, so must the stream.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "tests/fuzz/fuzz_target.hpp"

namespace {

// The input as a file whose path names it (fuzz-input.xyz in a directory of this process's own).
std::string input_file(const std::string& text) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("pcrt_fuzz_xyz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string path = (dir / (std::string(pcrt::fuzz::kName) + ".xyz")).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  return path;
}

// The stream's points, or false where it refuses the input (an InputError naming it).
bool streamed(const std::string& path, pcrt::PointCloud& out) {
  bool ok = false;
  pcrt::fuzz::expect_accepted_or_refused([&] {
    const auto stream = pcrt::open_point_stream(path);
    out.origin = stream->origin();
    stream->read([&](const pcrt::PointChunk& c) {
      out.positions.insert(out.positions.end(), c.positions.begin(), c.positions.end());
      out.normals.insert(out.normals.end(), c.normals.begin(), c.normals.end());
    });
    ok = true;
  });
  return ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  bool whole = false;
  PointCloud cloud;
  fuzz::expect_accepted_or_refused([&] {
    cloud = parse_xyz(text, fuzz::kName);
    whole = true;
  });
  PointCloud stream;
  const bool streams = streamed(input_file(text), stream);
  if (whole && cloud.has_normals() &&
      (!streams || stream.positions != cloud.positions || stream.normals != cloud.normals ||
       stream.origin != cloud.origin)) {
    std::fprintf(stderr, "the stream differs from the whole read\n");
    std::abort();
  }
  if (!whole && streams) {
    std::fprintf(stderr, "the stream accepts what the whole read refuses\n");
    std::abort();
  }
  fuzz::expect_accepted_or_refused([&] {
    if (!whole) return;
    cloud.validate();
    cloud.remove_duplicates();
  });
  return 0;
}
