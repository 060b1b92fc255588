// plan.json as `pcrt sweep --shard i/n --plan FILE` and `pcrt cluster status` read it: every
// shard's run keys, then each shard's runs of the sweep it must belong to.
#include "core/json_input.hpp"
#include "harness/shard_plan.hpp"
#include "tests/fuzz/fuzz_small_sweep.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  const SweepConfig& config = fuzz::small_sweep();
  fuzz::expect_accepted_or_refused([&] {
    const json plan = parse_json_text(text, fuzz::kName);
    const size_t shards = read_plan(plan, fuzz::kName).size();
    for (size_t s = 0; s < shards && s < 64; ++s)
      (void)plan_shard(plan, config.runs, s, shards, fuzz::kName);
  });
  return 0;
}
