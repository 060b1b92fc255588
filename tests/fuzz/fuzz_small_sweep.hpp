// The sweep config the plan, runs and jobs targets read their files against
// (tests/fuzz/seeds/config/small.json, whose runs the seeds of those targets hold).
#pragma once

#include <string>

#include "core/json_input.hpp"
#include "harness/sweep_config.hpp"

namespace pcrt::fuzz {

inline const SweepConfig& small_sweep() {
  static const SweepConfig config =
      parse_sweep_config(read_json_file(PCRT_SOURCE_DIR "/tests/fuzz/seeds/config/small.json"),
                         "small.json", DatasetCheck::kNamesOnly);
  return config;
}

}  // namespace pcrt::fuzz
