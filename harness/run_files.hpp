// A sweep directory's run files: DIR/runs.jsonl (one result per line, appended as runs finish)
// and DIR/runs.csv (one flat row per run, rewritten from runs.jsonl).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/run_spec.hpp"

namespace pcrt {

using nlohmann::json;

// Every result in the file; InputError naming the file and line if one is not a result. A sweep
// killed mid-write leaves at most a truncated last line: it is skipped (that run is redone).
std::vector<RunResult> read_runs_jsonl(const std::string& path);

// The same, saying whether the last line was torn: not ended by a newline, or not valid JSON (and
// then skipped). A resume redoes such a line; a merge must not take it for a finished shard.
struct RunsFile {
  std::vector<RunResult> runs;
  bool torn_tail = false;
};
RunsFile read_runs_file(const std::string& path);
void write_runs_jsonl(const std::string& path, const std::vector<RunResult>& results);
void append_run(const std::string& path, const RunResult& result);

// One flat row per run: the variables, K, k, I, parameters (set_*), counters (ops_*, ops_prep_*),
// times and the kind's own measurements. Fits read the same rows.
json run_row(const RunResult& result);
void write_runs_csv(const std::string& path, const std::vector<RunResult>& results);

}  // namespace pcrt
