// PLY of every format, as a point cloud (validated, duplicates dropped) and as a mesh.
#include "core/point_cloud_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] {
    PointCloud cloud = parse_ply(text, fuzz::kName, nullptr);
    cloud.validate();
    cloud.remove_duplicates();
  });
  fuzz::expect_accepted_or_refused([&] {
    std::vector<std::array<uint32_t, 3>> triangles;
    parse_ply(text, fuzz::kName, &triangles);
  });
  return 0;
}
