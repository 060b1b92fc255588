// Splitting a sweep into shards that take about the same time (`pcrt sweep --shard i/n`, `pcrt
// cluster submit`). Runs differ by orders of magnitude (a Delaunay run on skew lines against a
// 64-pixel frame), so every n-th run would leave one shard running long after the others: each run
// gets a cost estimate, and the runs are dealt longest first to the least loaded shard.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/run_spec.hpp"

namespace pcrt {

using nlohmann::json;

// Estimated seconds of one run on one core-ish machine, from its kind, N, M, S, B, repetitions
// and method. Only the ratios between runs matter for balance; the scale is rough.
double model_run_cost(const RunSpec& spec);

// Per-run costs: the earlier sweep's measured wall time where it ran the same run, else the
// model scaled by the median ratio of measured to modelled time over the runs both know.
// `earlier` may be empty (model only).
std::vector<double> run_costs(const std::vector<RunSpec>& runs,
                              const std::vector<RunResult>& earlier);

struct ShardPlan {
  std::vector<std::vector<size_t>> shards;  // indices into the runs, in run order
  std::vector<double> cost;                 // estimated seconds per shard
};

// Longest-processing-time-first: deterministic for given costs, so every shard of one sweep
// computes the same plan on its own.
ShardPlan plan_shards(const std::vector<double>& costs, size_t n);

// The plan as JSON (each shard's run specs and estimated seconds) and back: a plan file fixes the
// split of a cluster sweep, so resubmitting a shard never moves runs between shards.
json plan_json(const ShardPlan& plan, const std::vector<RunSpec>& runs, const std::string& source);
// The key (run_key) of a run spec in a plan file; InputError naming the plan if it is not one.
std::string planned_run_key(const json& spec, const std::string& origin);
// Each shard's run keys, every field of the plan checked where it is read: InputError naming
// `origin` and the field ("shards[2].runs[0]: ...") if it is not a plan pcrt wrote, among them a
// run planned in two shards.
std::vector<std::vector<std::string>> read_plan(const json& plan, const std::string& origin);
// The shard's run indices in `runs`; InputError if the plan does not belong to these runs.
std::vector<size_t> plan_shard(const json& plan, const std::vector<RunSpec>& runs, size_t shard,
                               size_t n, const std::string& origin);

}  // namespace pcrt
