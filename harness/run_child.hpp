// A sweep runs each run in a child process (`pcrt _run SPEC PARENT_PID`): a crash or a time limit
// costs only that run.
#pragma once

#include "harness/run_spec.hpp"

namespace pcrt {

// Failures and timeouts come back as results with status failed or timeout and the error line;
// every result has the child's wall time (preparation and process included).
RunResult run_in_child(const RunSpec& spec, double time_limit_s);

}  // namespace pcrt
