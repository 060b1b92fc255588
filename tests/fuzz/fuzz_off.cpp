// OFF files, as points and as meshes.
#include "core/point_cloud_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] {
    PointCloud cloud = parse_off(text, fuzz::kName, nullptr);
    cloud.validate();
    cloud.remove_duplicates();
  });
  fuzz::expect_accepted_or_refused([&] {
    std::vector<std::array<uint32_t, 3>> triangles;
    parse_off(text, fuzz::kName, &triangles);
  });
  return 0;
}
