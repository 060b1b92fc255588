// Rays CSV (trace --rays).
#include "core/ray_io.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] { parse_rays_csv(text, fuzz::kName); });
  return 0;
}
