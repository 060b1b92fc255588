// Sweep configs into the pipeline a sweep runs before its first run: parsed and validated as a
// whole, expanded into runs, each run's cost modelled, the size check's numbers, the runs dealt
// into shards and the plan written and read back, as `pcrt sweep` and `pcrt cluster submit` do.
// Dataset files are not opened (a fuzzed path could name anything on this machine).
#include <algorithm>

#include "core/json_input.hpp"
#include "harness/shard_plan.hpp"
#include "harness/sweep_config.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string text = fuzz::text_of(data, size);
  fuzz::expect_accepted_or_refused([&] {
    const json raw = parse_json_text(text, fuzz::kName);
    const SweepConfig config = parse_sweep_config(raw, fuzz::kName, DatasetCheck::kNamesOnly);
    const std::vector<double> costs = run_costs(config.runs, {});
    // Planning keys every run as JSON: on the few-run configs mutation makes, so that each input
    // stays well under the 10 s hang limit (the thesis config's 3584 runs take 8 s here).
    if (config.runs.size() > 500) return;
    const size_t shards = std::clamp<size_t>(config.runs.size() / 3, 1, 8);
    const json plan = plan_json(plan_shards(costs, shards), config.runs, "model");
    (void)plan_shard(plan, config.runs, shards - 1, shards, fuzz::kName);
  });
  return 0;
}
