// XYZ and PWN point files (3 or 6 columns).
#include "core/point_cloud_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] {
    PointCloud cloud = parse_xyz(text, fuzz::kName);
    cloud.validate();
    cloud.remove_duplicates();
  });
  return 0;
}
