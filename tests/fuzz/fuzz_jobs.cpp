// jobs.json as `pcrt cluster status` and `cluster submit --resume` read it, against plans of
// 0 to 4 shards (the input's first byte picks how many).
#include "core/json_input.hpp"
#include "harness/slurm.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  if (size == 0) return 0;
  const size_t shards = data[0] % 5;
  const std::string text = fuzz::text_of(data + 1, size - 1);
  fuzz::expect_accepted_or_refused(
      [&] { (void)newest_jobs(parse_json_text(text, fuzz::kName), shards, fuzz::kName); });
  return 0;
}
