// Sweep configs (`pcrt sweep CONFIG.json`): a JSON config names experiments (datasets, methods,
// structures, reconstructions or workloads, and values for N, M, S, B and any parameter), is
// validated as a whole before anything runs, and expands into typed runs and fits.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/run_quantity.hpp"
#include "harness/run_spec.hpp"

namespace pcrt {

using nlohmann::json;

// A fit as the config asks for it, its names already typed (run_quantity.hpp).
struct FitSpec {
  std::string experiment;
  std::string claim;                 // claim id, may use {method}, {structure}, {reconstruction},
                                     // {workload}
  std::optional<Variable> variable;  // the thesis variable the claim is judged in (none: a
                                     // threshold over the runs)
  std::optional<RunQuantity> x;      // the run column used as x (default: the variable)
  std::vector<RunQuantity> metric;   // summed ("time" = median seconds, "fps", "work")
  std::optional<RunQuantity> per;    // a counter the metric is divided by
  double max = -1, min = -1;         // threshold claims instead of a growth fit
  // What the experiment sweeps (N, M, S, B, set_*): the x axis, not groups, unless listed in
  // "by".
  std::vector<RunQuantity> swept;
  std::vector<RunQuantity> by;
  // Of K, k and I_run, which may move (the metric itself, say); the others must stay within 20%.
  std::vector<RunQuantity> free;
  // A held variable the claim adds linearly (K in O(SMB(log N + K))), fitted as a term of its
  // own instead of being held: the claim in x is then judged at fixed covariate. Only K.
  std::optional<Variable> covariate;
  // Why x cannot span its variable's minimum range here (waives the rule; shown in the verdict).
  std::string short_range;

  [[nodiscard]] bool is_threshold() const { return max >= 0 || min >= 0; }
};

// The most runs a config may expand to, refused before they are made (`pcrt sweep` refuses more
// than SweepOptions::kMaxSweepRuns unless told --no-limit; this bound no option lifts: a million
// runs of a second each are twelve days).
inline constexpr size_t kMaxConfigRuns = 1'000'000;

struct SweepConfig {
  json raw;  // as read (context.json and a cluster's config.json keep it)
  std::string name;
  double time_limit_s = 300;
  std::vector<RunSpec> runs;  // expanded, in execution order
  std::vector<FitSpec> fits;
};

// Reads and validates the whole config; every problem is an InputError naming the key.
SweepConfig load_sweep_config(const std::string& path);
// Whether dataset files are opened to check that they hold the grid's largest N: a results folder
// is fitted from its runs alone, without the scans it was made from.
enum class DatasetCheck { kOpenFiles, kNamesOnly };
SweepConfig parse_sweep_config(const json& raw, const std::string& origin,
                               DatasetCheck datasets = DatasetCheck::kOpenFiles);

// A claim template ({method}, {structure}, {reconstruction}, {workload}) filled from a run's names
// (empty where its kind has none).
std::string fill_claim(std::string claim, const RunNames& run);

}  // namespace pcrt
