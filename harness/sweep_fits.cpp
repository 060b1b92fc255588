#include "harness/sweep_fits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "harness/claims.hpp"
#include "harness/fit.hpp"
#include "harness/sweep_datasets.hpp"

namespace pcrt {

bool is_identity_column(const std::string& column) {
  static const std::array<const char*, 12> kIdentity = {
      "experiment", "kind",     "method", "structure", "dataset", "reconstruction",
      "engine",     "workload", "N",      "M",         "S",       "B"};
  return column.rfind("set_", 0) == 0 ||
         std::find(kIdentity.begin(), kIdentity.end(), column) != kIdentity.end();
}

namespace {

using Source = RunQuantity::Source;

bool contains(const std::vector<RunQuantity>& list, const RunQuantity& q) {
  return std::find(list.begin(), list.end(), q) != list.end();
}

// The terms a metric sums: "work" is the group's method's declared work (traversal nodes and
// items, and its own leaf counters, MethodInfo::work), so frame claims are judged on work, never
// on rays.
std::vector<RunQuantity> metric_terms(const std::vector<RunQuantity>& metric,
                                      const std::string& method) {
  std::vector<RunQuantity> terms;
  for (const RunQuantity& m : metric) {
    if (m.source != Source::kWork) {
      terms.push_back(m);
      continue;
    }
    for (RunQuantity& c : work_counters(method)) terms.push_back(std::move(c));
  }
  return terms;
}

std::string metric_description(const std::vector<RunQuantity>& terms,
                               const std::optional<RunQuantity>& per) {
  std::vector<std::string> names;
  for (const RunQuantity& t : terms) names.push_back(run_quantity_name(t));
  return fmt::format("{}{}", fmt::join(names, "+"), per ? " per " + run_quantity_name(*per) : "");
}

// The variables a run must hold while another is swept: K (held_k_of: the items per visited
// leaf), k and I as measured (I_run), and the hits per ray H of the methods that declare hits.
const std::array<RunQuantity, 4>& held_quantities() {
  static const std::array<RunQuantity, 4> kHeld = {
      RunQuantity::of(Variable::K), RunQuantity::of(Variable::k),
      RunQuantity::of(Source::kIterationsPerRun), RunQuantity::of(Variable::H)};
  return kHeld;
}

struct FitPoint {
  double x, y;
  std::array<double, 4> held;  // held_quantities() of the run; NaN where the run has none
};

// How a variable is held: I (the cap) by the iterations a run measured.
RunQuantity held_measure(Variable v) {
  return v == Variable::I ? RunQuantity::of(Source::kIterationsPerRun) : RunQuantity::of(v);
}

// Whether a held variable must stay put in this fit: not the one swept, a covariate or a free
// one; an I drift says nothing about a claim without I; and M, S and B touch neither the cloud
// nor the structure: K and k are held by construction there, and the measured items per visited
// leaf moves only with which leaves rays reach.
bool must_stay_put(const FitSpec& f, const Claim& claim, const RunQuantity& held) {
  const bool is_iterations = held.source == Source::kIterationsPerRun;
  if (f.variable && held_measure(*f.variable) == held) return false;
  if (f.covariate && RunQuantity::of(*f.covariate) == held) return false;
  if (contains(f.free, held)) return false;
  if (is_iterations && claim.complexity.find('I') == std::string::npos) return false;
  const bool renders_only =
      f.variable &&
      (*f.variable == Variable::M || *f.variable == Variable::S || *f.variable == Variable::B);
  return is_iterations || !renders_only;
}

// The spread of a held variable over (x, value) points, robust to one outlying run: with 4 or more
// runs the value farthest from the median is left out, but only where another run at its x
// remains (a replicate); with one run per x a value that jumps at one x is that x's only witness.
struct HeldRange {
  double lo, hi;
  bool left_out;
};
HeldRange robust_range(std::vector<std::pair<double, double>> runs) {
  std::vector<double> v;
  for (const auto& [x, value] : runs) v.push_back(value);
  std::sort(v.begin(), v.end());
  const double median = v[v.size() / 2];
  if (v.size() >= 4) {
    const double far = median - v.front() > v.back() - median ? v.front() : v.back();
    const auto at =
        std::find_if(runs.begin(), runs.end(), [&](auto& p) { return p.second == far; });
    const double x = at->first;
    if (std::count_if(runs.begin(), runs.end(), [&](auto& p) { return p.first == x; }) >= 2) {
      v.erase(far == v.front() ? v.begin() : v.end() - 1);
      return {v.front(), v.back(), true};
    }
  }
  return {v.front(), v.back(), false};
}

// Variables that the claim does not sweep must stay put: K (the measured items per visited leaf,
// else the method's K), k, I (the measured iterations per run) and H, unless free or a covariate.
std::string drift_of(const std::vector<FitPoint>& pts, const FitSpec& f, const Claim& claim) {
  for (size_t i = 0; i < held_quantities().size(); ++i) {
    const RunQuantity& held = held_quantities()[i];
    if (!must_stay_put(f, claim, held)) continue;
    std::vector<std::pair<double, double>> values;
    for (const FitPoint& p : pts)
      if (std::isfinite(p.held[i])) values.emplace_back(p.x, p.held[i]);
    if (values.size() < 2) continue;
    const auto [lo, hi, left_out] = robust_range(values);
    if (hi > 0 && lo < hi && (hi - lo) > 0.2 * lo)
      return fmt::format("{} moved from {:.3g} to {:.3g} (+{:.0f}%{}) while it should be fixed",
                         held.source == Source::kIterationsPerRun ? "I (iterations per run)"
                                                                  : run_quantity_name(held),
                         lo, hi, 100 * (hi - lo) / lo,
                         left_out ? ", the run farthest from the median left out" : "");
  }
  return {};
}

// "2 of its runs failed or timed out, 1 is missing from runs.jsonl": the runs a group lacks.
std::string lacking(const GroupFit& fit) {
  std::string out;
  if (fit.failed_runs > 0) out = fmt::format("{} of its runs failed or timed out", fit.failed_runs);
  if (fit.missing_runs > 0)
    out += fmt::format("{}{} of its runs {} missing from runs.jsonl", out.empty() ? "" : ", ",
                       fit.missing_runs, fit.missing_runs == 1 ? "is" : "are");
  return out;
}

ClaimVerdict fit_threshold(const FitSpec& f, const std::vector<FitPoint>& pts, GroupFit& fit) {
  ThresholdResult& result = fit.threshold.emplace();
  result.bound = f.max >= 0 ? fmt::format("<= {}", f.max) : fmt::format(">= {}", f.min);
  // A run without the measure (NaN: the run has no value) is missing data, never a pass.
  for (const FitPoint& p : pts)
    if (!std::isfinite(p.y)) {
      fit.error = fmt::format(
          "a run has no value for {} (null or not finite): no verdict without data", fit.metric);
      return ClaimVerdict::kError;
    }
  if (pts.empty() || fit.failed_runs + fit.missing_runs > 0) {
    fit.error = pts.empty() ? "no successful run"
                            : fmt::format("{}: no verdict without their data", lacking(fit));
    return ClaimVerdict::kError;
  }
  double worst = f.max >= 0 ? 0 : std::numeric_limits<double>::infinity();
  for (const FitPoint& p : pts) worst = f.max >= 0 ? std::max(worst, p.y) : std::min(worst, p.y);
  result.measured = worst;
  return (f.max >= 0 ? worst <= f.max : worst >= f.min) ? ClaimVerdict::kMeets
                                                        : ClaimVerdict::kMisses;
}

// Identical points (parameters that build the same structure, replicates of one and the same
// cloud) are one observation.
std::vector<FitPoint> distinct(std::vector<FitPoint> pts) {
  std::sort(pts.begin(), pts.end(), [](const FitPoint& a, const FitPoint& b) {
    return std::tie(a.x, a.y) < std::tie(b.x, b.y);
  });
  pts.erase(
      std::unique(pts.begin(), pts.end(),
                  [](const FitPoint& a, const FitPoint& b) { return a.x == b.x && a.y == b.y; }),
      pts.end());
  return pts;
}

// Fits one group into `fit.growth` (as far as it gets: an InputError leaves the rest out) and
// says why in `fit.reason`; returns its verdict.
ClaimVerdict fit_growth_group(const FitSpec& f, const Claim& claim, std::vector<FitPoint> pts,
                              GroupFit& fit) {
  // Before any sort: a NaN breaks the ordering distinct() relies on.
  for (const FitPoint& p : pts)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      input_error("{}: a run has no value for x or the metric (x = {}, y = {})", fit.claim, p.x,
                  p.y);
  pts = distinct(std::move(pts));
  const std::string variable = f.variable ? variable_name(*f.variable) : "";
  FitRules rules;
  rules.min_decades = min_decades(variable);
  rules.range_waiver = f.short_range;
  if (f.covariate) rules.covariate_name = "K (measured)";
  GrowthResult& growth = fit.growth.emplace();
  for (const FitPoint& p : pts) {
    growth.x.push_back(p.x), growth.y.push_back(p.y);
    if (f.covariate) rules.covariate.push_back(p.held[0]);
  }
  if (f.covariate) growth.covariate = rules.covariate;
  growth.short_range = f.short_range;
  growth.expected = expected_growth(claim.complexity, variable);
  GrowthFit g = fit_growth(growth.x, growth.y, *growth.expected, fit.claim, rules);
  if (g.verdict == ClaimVerdict::kHolds && fit.failed_runs + fit.missing_runs > 0) {
    g.verdict = ClaimVerdict::kInconclusive;  // not over missing data
    g.tightness = Tightness::kNotTested;
    g.reason = fmt::format("it would hold ({}), but {}", g.reason, lacking(fit));
  }
  fit.reason = g.reason;
  growth.fit = std::move(g);
  return growth.fit->verdict;
}

// Whether a dataset is a generator's uniform volume (no density ramp).
bool is_uniform_volume(const std::string& dataset) {
  if (!is_generator(dataset)) return false;
  const GeneratorInfo* info = nullptr;
  const ParamValues p = parse_generator_spec(dataset, &info);
  return info && (info->name == "ball" || info->name == "cube") && p.at("density") == 0;
}

// The group's points (ok runs only) and how many runs failed.
std::vector<FitPoint> fit_points(const FitSpec& f, const std::vector<RunQuantity>& terms,
                                 const std::vector<const RunResult*>& runs, size_t& failed) {
  std::vector<FitPoint> pts;
  for (const RunResult* r : runs) {
    if (!r->ok()) {
      ++failed;
      continue;
    }
    double y = 0;
    for (const RunQuantity& t : terms) y += run_value(*r, t);
    if (f.per) y /= run_value(*r, *f.per);
    std::array<double, 4> held{};
    for (size_t i = 0; i < held.size(); ++i) held[i] = run_value(*r, held_quantities()[i]);
    held[0] = held_k_of(*r).value_or(std::nan(""));  // K: as the leaves held it
    pts.push_back({f.x ? run_value(*r, *f.x) : 0.0, y, held});
  }
  return pts;
}

// The verdict of a group whose claim is known; fills in the fit's numbers.
ClaimVerdict judge_group(const FitSpec& f, const std::vector<FitPoint>& pts, GroupFit& fit) {
  const Claim& claim = find_claim(fit.claim);
  fit.claimed = &claim;
  if (claim.precondition == Precondition::kUniformVolume && !is_uniform_volume(fit.names.dataset)) {
    fit.reason = fmt::format("{}'s precondition is a uniformly distributed cloud; {} is not one",
                             claim.id, fit.names.dataset);
    return ClaimVerdict::kNotJudged;
  }
  if (f.is_threshold()) return fit_threshold(f, pts, fit);
  const std::string drift = drift_of(pts, f, claim);
  const ClaimVerdict verdict = fit_growth_group(f, claim, pts, fit);
  if (drift.empty() || verdict == ClaimVerdict::kLoopCheck) return verdict;
  fit.verdict_if_fixed = verdict;
  fit.reason = drift;
  return ClaimVerdict::kDrifted;
}

// A bound on I that every run's cap on its iterations already keeps: met by construction.
bool capped_by_construction(const FitSpec& f, const Claim& claim,
                            const std::vector<const RunResult*>& runs) {
  if (f.max < 0 || claim.complexity.rfind("I <=", 0) != 0) return false;
  return std::all_of(runs.begin(), runs.end(), [&](const RunResult* r) {
    const std::optional<double> cap = method_parameter(r->spec, "max_iterations");
    return cap && *cap <= f.max;
  });
}

GroupFit fit_group(const FitSpec& f, const GroupIdentity& group,
                   const std::vector<const RunResult*>& runs, size_t missing) {
  GroupFit fit;
  fit.missing_runs = missing;
  fit.names = group.names;
  fit.claim = fill_claim(f.claim, fit.names);
  fit.experiment = f.experiment;
  fit.variable = f.variable;
  fit.x = f.x;
  fit.group = group;
  const std::vector<RunQuantity> terms = metric_terms(f.metric, fit.names.method);
  fit.metric = metric_description(terms, f.per);
  const std::vector<FitPoint> pts = fit_points(f, terms, runs, fit.failed_runs);
  fit.runs = runs.size();
  if (runs.empty()) {  // every run of the group is missing
    fit.error = fmt::format("{}: no verdict without their data", lacking(fit));
    return fit;
  }
  try {
    fit.verdict = judge_group(f, pts, fit);
    if (fit.verdict == ClaimVerdict::kMeets && capped_by_construction(f, *fit.claimed, runs)) {
      fit.verdict = ClaimVerdict::kLoopCheck;
      fit.reason = fmt::format(
          "every run's max_iterations keeps I {}: met by construction (a check of the loops, "
          "not a test of the claim)",
          fit.threshold->bound);
    }
  } catch (const InputError& e) {
    fit.verdict = ClaimVerdict::kError;
    fit.error = e.what();
    if (fit.failed_runs + fit.missing_runs > 0) *fit.error += fmt::format(" ({})", lacking(fit));
  }
  return fit;
}

// Whether a group keeps an identity column: not x (x = K takes the K parameter along), nor what
// the experiment sweeps unless "by" keeps it.
bool group_keeps(const FitSpec& f, const RunQuantity& column) {
  if (f.x && *f.x == column) return false;
  if (f.x && *f.x == RunQuantity::of(Variable::K) && column == RunQuantity::parameter("K"))
    return false;
  return !contains(f.swept, column) || contains(f.by, column);
}

// N and M as loaded and rendered where the run has them (what fits.json shows), else the grid's.
std::optional<GridValue> grid_value(const RunResult& r, Variable v) {
  if (v == Variable::N && r.points) return GridValue{double(*r.points), true};
  if (v == Variable::M && r.pixels) return GridValue{double(*r.pixels), true};
  const double value = run_value(r, RunQuantity::of(v));
  return std::isnan(value) ? std::nullopt : std::optional<GridValue>(GridValue{value, false});
}

// The grid's own value, which a failed run has as well as an ok one.
std::optional<GridValue> spec_value(const RunSpec& s, Variable v) {
  const std::optional<double>& value = v == Variable::N   ? s.N
                                       : v == Variable::M ? s.M
                                       : v == Variable::S ? s.S
                                                          : s.B;
  return value ? std::optional<GridValue>(GridValue{*value, false}) : std::nullopt;
}

// With `measured`: the group as fits.json shows it (N and M as that run loaded and rendered
// them); without, the group as the config made it, which is what runs are grouped by: a run that
// failed has no N as loaded, and grouped by it would leave its group's fit without knowing of it.
GroupIdentity group_of(const FitSpec& f, const RunSpec& spec, const RunResult* measured) {
  GroupIdentity group;
  group.names = run_names(spec);
  for (Variable v : {Variable::N, Variable::M, Variable::S, Variable::B})
    if (group_keeps(f, RunQuantity::of(v)))
      group.grid[v] = measured ? grid_value(*measured, v) : spec_value(spec, v);
  for (const auto& [name, value] : spec.set)
    if (group_keeps(f, RunQuantity::parameter(name))) group.parameters[name] = value;
  return group;
}

struct RunGroup {
  GroupIdentity shown;
  bool shown_from_ok_run = false;
  std::vector<const RunResult*> runs;
  size_t missing = 0;
};

// The runs of one FitSpec by group, and the config's runs of each group runs.jsonl lacks.
std::map<std::string, RunGroup> groups_of(const FitSpec& f, const SweepConfig& config,
                                          const std::vector<RunResult>& results) {
  std::map<std::string, RunGroup> groups;  // by the group's JSON text: fits.json's order
  std::set<std::string> present;
  for (const RunResult& r : results) {
    if (r.spec.experiment != f.experiment) continue;
    present.insert(run_key(r));
    RunGroup& g = groups[group_json(group_of(f, r.spec, nullptr)).dump()];
    if (g.runs.empty() || (!g.shown_from_ok_run && r.ok()))
      g.shown = group_of(f, r.spec, &r), g.shown_from_ok_run = r.ok();
    g.runs.push_back(&r);
  }
  for (const RunSpec& s : config.runs)
    if (s.experiment == f.experiment && !present.count(run_key(s))) {
      const GroupIdentity group = group_of(f, s, nullptr);
      RunGroup& g = groups[group_json(group).dump()];
      if (g.runs.empty() && g.missing == 0) g.shown = group;
      ++g.missing;
    }
  return groups;
}

}  // namespace

std::vector<GroupFit> fit_runs(const SweepConfig& config, const std::vector<RunResult>& results) {
  std::vector<GroupFit> fits;
  for (const FitSpec& f : config.fits) {
    for (const auto& [text, g] : groups_of(f, config, results))
      fits.push_back(fit_group(f, g.shown, g.runs, g.missing));
  }
  return fits;
}

}  // namespace pcrt
