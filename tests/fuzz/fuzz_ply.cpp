// PLY of every format, as a point cloud (validated, duplicates dropped) and as a mesh; and
// streamed from a file holding the input (open_ply_stream, which reads the vertex element
// alone): where both the whole read and the stream accept it, the same positions, normals and
// origin.
#include "core/point_cloud_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  bool whole = false;
  PointCloud cloud;
  fuzz::expect_accepted_or_refused([&] {
    cloud = parse_ply(text, fuzz::kName, nullptr);
    whole = true;
  });
  PointCloud stream;
  if (fuzz::streamed(fuzz::input_file(text, ".ply"), stream) && whole && cloud.has_normals() &&
      !fuzz::same_points(stream, cloud)) {
    std::fprintf(stderr, "the stream differs from the whole read\n");
    std::abort();
  }
  fuzz::expect_accepted_or_refused([&] {
    if (!whole) return;
    cloud.validate();
    cloud.remove_duplicates();
  });
  fuzz::expect_accepted_or_refused([&] {
    std::vector<std::array<uint32_t, 3>> triangles;
    parse_ply(text, fuzz::kName, &triangles);
  });
  return 0;
}
