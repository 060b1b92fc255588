// Executing one run in this process: one executor per run kind. `pcrt _run` calls this in the
// child process a sweep starts per run (run_child.hpp).
#pragma once

#include "harness/run_spec.hpp"

namespace pcrt {

// The run's measurements; InputError for what the run cannot do (a missing file, say).
RunResult execute_run(const RunSpec& spec);

}  // namespace pcrt
