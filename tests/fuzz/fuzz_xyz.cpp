// XYZ and PWN point files (3 or 6 columns), read whole and streamed (open_xyz_stream, from a
// file holding the input): where the whole read keeps normals, the stream must deliver the same
// positions, origin and normals; where it refuses, so must the stream.
#include "core/point_cloud_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

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
  const bool streams = fuzz::streamed(fuzz::input_file(text, ".xyz"), stream);
  if (whole && cloud.has_normals() && !(streams && fuzz::same_points(stream, cloud))) {
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
