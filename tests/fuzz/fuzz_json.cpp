// JSON as sweep configs, baselines and a sweep's context.json are read; an accepted value is
// copied and written again, as a sweep does with its config.
#include "core/json_input.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] {
    const nlohmann::json value = parse_json_text(text, fuzz::kName);
    const nlohmann::json copy = value;
    (void)copy.dump(2);
  });
  return 0;
}
