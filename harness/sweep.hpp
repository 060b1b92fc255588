// Sweeps (`pcrt sweep`): a JSON config names experiments (datasets, methods, structures,
// reconstructions or workloads, and values for N, M, S, B and any parameter), is validated as a
// whole before anything runs, and expands into runs. Each run executes in a child process (so a
// crash or a time limit costs only that run) and is appended to DIR/runs.jsonl at once;
// DIR/runs.csv and DIR/context.json are rewritten from it. Fits (`pcrt fit`) read the runs back.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pcrt {

using nlohmann::json;

struct FitSpec {
  std::string experiment;
  std::string claim;     // claim id, may use {method}, {structure}, {reconstruction}, {workload}
  std::string variable;  // the thesis variable the claim is judged in (N, M, S, B, K, k, I)
  std::string x;         // the run column used as x (default: the variable)
  std::vector<std::string> metric;  // run columns summed ("time" = median seconds, "fps")
  std::string per;                  // optional column the metric is divided by
  double max = -1, min = -1;        // threshold claims instead of a growth fit
  // Run columns the experiment sweeps (N, M, S, B, set_*): they form the x axis, not groups,
  // unless listed in "by".
  std::vector<std::string> swept;
  std::vector<std::string> by;
  // Of K, k and I_run, which may move (the metric itself, say); the others must stay within 20%.
  std::vector<std::string> free;
};

struct SweepConfig {
  json raw;
  std::string name;
  double time_limit_s = 300;
  std::vector<json> runs;  // expanded run specs, in execution order
  std::vector<FitSpec> fits;
};

// Reads and validates the whole config; every problem is an InputError naming the key.
SweepConfig load_sweep_config(const std::string& path);
SweepConfig parse_sweep_config(const json& raw, const std::string& origin);

// The identity of a run (its spec, canonically serialised): what --resume and merges compare.
std::string run_key(const json& spec);
// Executes one run in this process and returns its result (spec + measurements).
json execute_run(const json& spec);
// Executes one run in a child process (`pcrt _run`), with a time limit; failures and timeouts
// come back as results with "status" "failed" or "timeout" and the error line.
json run_in_child(const json& spec, double time_limit_s);

// One flat row per run: the variables, parameters, ops_* counters and times.
json run_row(const json& result);
void write_runs_csv(const std::string& path, const std::vector<json>& results);
std::vector<json> read_runs_jsonl(const std::string& path);  // skips nothing; InputError if bad
json machine_context(const json& config);

// Fits of every FitSpec over the runs: fits.json entries.
std::vector<json> fit_runs(const SweepConfig& config, const std::vector<json>& results);

}  // namespace pcrt
