// Fits (`pcrt fit`, `pcrt sweep --fit`): each FitSpec groups its experiment's runs by explicit
// identity columns, fits the metric against x per group, and gives each group a verdict.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "harness/run_spec.hpp"
#include "harness/sweep_config.hpp"

namespace pcrt {

using nlohmann::json;

// fits.json entries, one per FitSpec and group.
std::vector<json> fit_runs(const SweepConfig& config, const std::vector<RunResult>& results);

// The columns that identify a group of runs before a fit removes x and what the experiment sweeps:
// what the run is (experiment, kind, method, ..., N, M, S, B) and its parameters (set_*). The
// measurements (ops_*, time_*, K, k, I, I_run, the kind's own columns) never split groups.
bool is_identity_column(const std::string& column);

}  // namespace pcrt
