// Fits (`pcrt fit`, `pcrt sweep --fit`): each FitSpec groups its experiment's runs by explicit
// identity columns, fits the metric against x per group, and gives each group a verdict. The fits
// read typed runs (run_quantity.hpp) and fill a typed GroupFit; fits.json is written from it by
// one reporter, fit_json (JSON only at the edges).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/claims.hpp"
#include "harness/fit.hpp"
#include "harness/run_quantity.hpp"
#include "harness/run_spec.hpp"
#include "harness/sweep_config.hpp"

namespace pcrt {

using nlohmann::json;

// A grid variable's value in a group: N as loaded and M as rendered are measured counts (JSON
// integers in fits.json, as in runs.jsonl); the grid's own are doubles.
struct GridValue {
  double value = 0;
  bool measured = false;
  bool operator==(const GridValue&) const = default;
};

// What makes runs one group: what they are (their names), and the grid variables and parameters
// that neither x nor the experiment's sweep removes (none: the run has no value for it).
struct GroupIdentity {
  RunNames names;
  std::map<Variable, std::optional<GridValue>> grid;  // of N, M, S, B
  std::map<std::string, double> parameters;           // set_*
};

// A threshold claim's verdict: the bound and the worst run.
struct ThresholdResult {
  std::string bound;               // "<= 3", ">= 1"
  std::optional<double> measured;  // none: no verdict without data
};

// A growth fit's points and its numbers: filled as far as the fit got (an InputError, fewer
// than 5 distinct x say, leaves `fit` empty).
struct GrowthResult {
  std::vector<double> x, y;
  std::optional<std::vector<double>> covariate;  // the measured K per point, when fitted
  std::string short_range;                       // the config's waiver, if any
  std::optional<Growth> expected;
  std::optional<GrowthFit> fit;
};

// One fits.json entry: a FitSpec's verdict on one group of runs.
struct GroupFit {
  std::string claim, experiment;  // the claim id, its template filled from the group's runs
  std::optional<Variable> variable;
  std::optional<RunQuantity> x;
  GroupIdentity group;
  RunNames names;      // of the group's first run
  std::string metric;  // the columns summed, e.g. "ops_nodes_visited+ops_items_visited per ..."
  size_t runs = 0, failed_runs = 0;
  // Runs the config expands to for this group that runs.jsonl does not hold (a partial merge, a
  // shard): missing data, as a failed run is.
  size_t missing_runs = 0;
  const Claim* claimed = nullptr;  // none: the claim is unknown (an error)
  ClaimVerdict verdict = ClaimVerdict::kError;
  std::optional<ClaimVerdict> verdict_if_fixed;  // a drifted group's verdict had it held still
  std::optional<std::string> reason, error;
  std::optional<ThresholdResult> threshold;
  std::optional<GrowthResult> growth;
};

// One per FitSpec and group, in the order fits.json has always had.
std::vector<GroupFit> fit_runs(const SweepConfig& config, const std::vector<RunResult>& results);

// The reporter: a fit as its fits.json entry, and a whole fits.json.
json fit_json(const GroupFit& fit);
json group_json(const GroupIdentity& group);
std::vector<json> fits_json(const std::vector<GroupFit>& fits);

// The columns that identify a group of runs before a fit removes x and what the experiment sweeps:
// what the run is (experiment, kind, method, ..., N, M, S, B) and its parameters (set_*). The
// measurements (ops_*, time_*, K, k, I, I_run, the kind's own columns) never split groups.
bool is_identity_column(const std::string& column);

}  // namespace pcrt
