#include "harness/sweep_fits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "harness/claims.hpp"
#include "harness/fit.hpp"
#include "harness/run_files.hpp"
#include "harness/sweep_datasets.hpp"
#include "methods/method.hpp"

namespace pcrt {

bool is_identity_column(const std::string& column) {
  static const std::array<const char*, 12> kIdentity = {
      "experiment", "kind",     "method", "structure", "dataset", "reconstruction",
      "engine",     "workload", "N",      "M",         "S",       "B"};
  return column.rfind("set_", 0) == 0 ||
         std::find(kIdentity.begin(), kIdentity.end(), column) != kIdentity.end();
}

namespace {

double column(const json& row, const std::string& name) {
  constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();
  // A run without a time (measured in operations only) has no time: missing, never zero.
  const json t = row.value("time_median_s", json(nullptr));
  if (name == "time") return t.is_number() ? t.get<double>() : kMissing;
  if (name == "fps") return t.is_number() && t.get<double>() > 0 ? 1.0 / t.get<double>() : kMissing;
  const json v = row.value(name, json(nullptr));
  if (v.is_number()) return v.get<double>();
  // A counter a run never touched is zero (a method that does no rasterization, say).
  return name.rfind("ops_", 0) == 0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
}

// The columns a metric names: "work" is a method's declared work (traversal nodes and items, and
// its own leaf counters, MethodInfo::work), so frame claims are judged on work, never on rays.
std::vector<std::string> metric_columns(const std::vector<std::string>& metric, const json& row) {
  std::vector<std::string> cols;
  for (const std::string& m : metric) {
    if (m != "work") {
      cols.push_back(m);
      continue;
    }
    cols.push_back("ops_nodes_visited");
    cols.push_back("ops_items_visited");
    const std::string method = row.value("method", "");
    if (MethodRegistry::instance().contains(method))
      for (const Counter* c : MethodRegistry::instance().get(method, "method").work)
        cols.push_back("ops_" + registered_counters()[c->id()].name);
  }
  return cols;
}

// The variables a run must hold while another is swept, as run columns.
constexpr std::array<const char*, 3> kHeldColumns = {"K", "k", "I_run"};

struct FitPoint {
  double x, y;
  std::array<double, 3> held;  // kHeldColumns of the run; NaN where the run has none
};

// The run columns of the variables a fit holds (kHeldColumns) and whether the claim's
// complexity names them: an I drift says nothing about a claim without I.
bool claim_names(const Claim& claim, const std::string& column) {
  return column != "I_run" || claim.complexity.find('I') != std::string::npos;
}

// The spread of a held variable, robust to one outlier: the value farthest from the median is
// left out before the range is taken.
std::pair<double, double> robust_range(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const double median = v[v.size() / 2];
  if (v.size() >= 4) {
    const bool low_is_farther = median - v.front() > v.back() - median;
    v.erase(low_is_farther ? v.begin() : v.end() - 1);
  }
  return {v.front(), v.back()};
}

// Variables that the claim does not sweep must stay put: K (the method's K or the measured
// items per leaf), k, and I (the measured iterations per run), unless free or a covariate.
std::string drift_of(const std::vector<FitPoint>& pts, const FitSpec& f, const Claim& claim) {
  for (size_t i = 0; i < kHeldColumns.size(); ++i) {
    const std::string v = kHeldColumns[i];
    if (f.variable == v || (f.variable == "I" && v == "I_run") || f.covariate == v) continue;
    if (std::find(f.free.begin(), f.free.end(), v) != f.free.end()) continue;
    if (!claim_names(claim, v)) continue;
    // M, S and B touch neither the cloud nor the structure: K and k are held by construction
    // there, and the measured items per visited leaf moves only with which leaves rays reach.
    if (v != "I_run" && (f.variable == "M" || f.variable == "S" || f.variable == "B")) continue;
    std::vector<double> values;
    for (const FitPoint& p : pts)
      if (std::isfinite(p.held[i])) values.push_back(p.held[i]);
    if (values.size() < 2) continue;
    const auto [lo, hi] = robust_range(values);
    if (hi > 0 && lo < hi && (hi - lo) > 0.2 * lo)
      return fmt::format("{} moved from {:.3g} to {:.3g} (+{:.0f}%{}) while it should be fixed",
                         v == "I_run" ? "I (iterations per run)" : v, lo, hi, 100 * (hi - lo) / lo,
                         values.size() >= 4 ? ", the run farthest from the median left out" : "");
  }
  return {};
}

ClaimVerdict fit_threshold(const FitSpec& f, const std::vector<FitPoint>& pts, json& out) {
  out["threshold"] = f.max >= 0 ? fmt::format("<= {}", f.max) : fmt::format(">= {}", f.min);
  // A run without the measure (NaN: the column is null) is missing data, never a pass.
  for (const FitPoint& p : pts)
    if (!std::isfinite(p.y)) {
      out["error"] = fmt::format(
          "a run has no value for {} (null or not finite): no verdict "
          "without data",
          out.value("metric", std::string("the metric")));
      out["measured"] = nullptr;
      return ClaimVerdict::kError;
    }
  if (pts.empty() || out.value("failed_runs", 0) > 0) {
    out["error"] = pts.empty() ? "no successful run"
                               : fmt::format(
                                     "{} of its runs failed or timed out: no verdict "
                                     "without their data",
                                     out.value("failed_runs", 0));
    out["measured"] = nullptr;
    return ClaimVerdict::kError;
  }
  double worst = f.max >= 0 ? 0 : std::numeric_limits<double>::infinity();
  for (const FitPoint& p : pts) worst = f.max >= 0 ? std::max(worst, p.y) : std::min(worst, p.y);
  out["measured"] = worst;
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

json share_json(const FasterTerm& t) {
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return {{"model", t.model},
          {"share", num(t.share)},
          {"low95", num(t.low95)},
          {"high95", num(t.high95)},
          {"low99", num(t.low99)}};
}

void write_growth_fit(const GrowthFit& g, json& out) {
  json weights = json::object();
  for (size_t m = 0; m < kModels; ++m) weights[growth_name(kAllGrowths[m])] = g.weight[m];
  json faster = json::array();
  for (const FasterTerm& t : g.faster) faster.push_back(share_json(t));
  out.update({{"points", g.points},
              {"distinct_x", g.distinct_x},
              {"decades", g.decades},
              {"exponent", g.exponent},
              {"ci_low", g.ci_low},
              {"ci_high", g.ci_high},
              {"claimed_exponent", g.claimed_exponent},
              {"best_model", growth_name(g.best)},
              {"r2", g.r2},
              {"noise", g.noise},
              {"akaike_weights", weights},
              {"weight_faster", g.weight_faster},
              {"faster_terms", faster},
              {"tolerance", kHoldsTolerance},
              {"lower_term", g.lower ? json(growth_name(*g.lower)) : json(nullptr)},
              {"tightness", tightness_name(g.tightness)}});
  if (g.verdict == ClaimVerdict::kHolds) out["hidden_at_most"] = g.hidden;
  if (g.tightness != Tightness::kNotTested) out["claimed_share"] = share_json(g.claimed_term);
  if (g.lof_tested)
    out.update({{"lack_of_fit_f", g.lof_f},
                {"lack_of_fit_critical", g.lof_critical},
                {"pure_noise", g.pure_noise}});
  if (!g.flip.empty()) out["leave_one_out"] = g.flip;
}

// Fits one group and writes its numbers and reason into `out`; returns its verdict.
ClaimVerdict fit_growth_group(const FitSpec& f, const Claim& claim, std::vector<FitPoint> pts,
                              json& out) {
  // Before any sort: a NaN breaks the ordering distinct() relies on.
  for (const FitPoint& p : pts)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      input_error("{}: a run has no value for x or the metric (x = {}, y = {})",
                  out["claim"].get<std::string>(), p.x, p.y);
  pts = distinct(std::move(pts));
  std::vector<double> xs, ys;
  FitRules rules;
  rules.min_decades = min_decades(f.variable);
  rules.range_waiver = f.short_range;
  if (!f.covariate.empty()) rules.covariate_name = "K (measured)";
  for (const FitPoint& p : pts) {
    xs.push_back(p.x), ys.push_back(p.y);
    if (!f.covariate.empty()) rules.covariate.push_back(p.held[0]);
  }
  out["x_values"] = xs;
  out["y_values"] = ys;
  if (!f.covariate.empty()) out["covariate_values"] = rules.covariate;
  if (!f.short_range.empty()) out["short_range"] = f.short_range;
  const Growth expected = expected_growth(claim.complexity, f.variable);
  out["expected_model"] = growth_name(expected);
  GrowthFit g = fit_growth(xs, ys, expected, out["claim"].get<std::string>(), rules);
  const size_t failed = out.value("failed_runs", size_t(0));
  if (g.verdict == ClaimVerdict::kHolds && failed > 0) {  // a bound cannot hold over missing data
    g.verdict = ClaimVerdict::kInconclusive;
    g.tightness = Tightness::kNotTested;
    g.reason =
        fmt::format("it would hold ({}), but {} of its runs failed or timed out", g.reason, failed);
  }
  write_growth_fit(g, out);
  out["reason"] = g.reason;
  return g.verdict;
}

// Whether a dataset is a generator's uniform volume (no density ramp).
bool is_uniform_volume(const std::string& dataset) {
  if (!is_generator(dataset)) return false;
  const GeneratorInfo* info = nullptr;
  const ParamValues p = parse_generator_spec(dataset, &info);
  return info && (info->name == "ball" || info->name == "cube") && p.at("density") == 0;
}

// The group's points (ok runs only) and how many runs failed.
std::vector<FitPoint> fit_points(const FitSpec& f, const std::vector<std::string>& cols,
                                 const std::vector<json>& rows, size_t& failed) {
  std::vector<FitPoint> pts;
  for (const json& row : rows) {
    if (row.value("status", "") != run_status_name(RunStatus::kOk)) {
      ++failed;
      continue;
    }
    double y = 0;
    for (const std::string& m : cols) y += column(row, m);
    if (!f.per.empty()) y /= column(row, f.per);
    std::array<double, 3> held{};
    for (size_t i = 0; i < kHeldColumns.size(); ++i) {
      const json v = row.value(kHeldColumns[i], json(nullptr));
      held[i] = v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
    }
    pts.push_back({f.x.empty() ? 0.0 : column(row, f.x), y, held});
  }
  return pts;
}

// The verdict of a group whose claim is known; writes the fit's numbers into `out`.
ClaimVerdict judge_group(const FitSpec& f, const std::vector<FitPoint>& pts, json& out) {
  const Claim& claim = find_claim(out["claim"].get<std::string>());
  out["claimed"] = claim.complexity;
  out["source"] = claim.source;
  out["about"] = claim_about_name(claim.about);
  if (claim.precondition == Precondition::kUniformVolume &&
      !is_uniform_volume(out.value("dataset", std::string()))) {
    out["reason"] = fmt::format("{}'s precondition is a uniformly distributed cloud; {} is not one",
                                claim.id, out.value("dataset", std::string()));
    return ClaimVerdict::kNotJudged;
  }
  if (f.is_threshold()) return fit_threshold(f, pts, out);
  const std::string drift = drift_of(pts, f, claim);
  const ClaimVerdict verdict = fit_growth_group(f, claim, pts, out);
  if (drift.empty() || verdict == ClaimVerdict::kLoopCheck) return verdict;
  out["verdict_if_fixed"] = verdict_name(verdict);
  out["reason"] = drift;
  return ClaimVerdict::kDrifted;
}

json fit_group(const FitSpec& f, const json& group, const std::vector<json>& rows) {
  const json& first = rows.front();
  json out = {{"claim", fill_claim(f.claim, first)},
              {"experiment", f.experiment},
              {"variable", f.variable},
              {"x", f.x},
              {"group", group}};
  for (const char* k : {"method", "structure", "dataset", "reconstruction", "workload"})
    out[k] = first.value(k, "");
  const std::vector<std::string> cols = metric_columns(f.metric, first);
  out["metric"] = fmt::format("{}{}", fmt::join(cols, "+"), f.per.empty() ? "" : " per " + f.per);
  size_t failed = 0;
  const std::vector<FitPoint> pts = fit_points(f, cols, rows, failed);
  out["runs"] = rows.size();
  out["failed_runs"] = failed;
  try {
    out["verdict"] = verdict_name(judge_group(f, pts, out));
  } catch (const InputError& e) {
    out["verdict"] = verdict_name(ClaimVerdict::kError);
    out["error"] = e.what();
  }
  return out;
}

// A run's group: its identity columns but x and what the experiment sweeps (unless "by" keeps it).
json group_of(const FitSpec& f, const json& row) {
  json group = json::object();
  for (const auto& [k, v] : row.items()) {
    if (!is_identity_column(k) || k == f.x || (f.x == "K" && k == "set_K")) continue;
    const bool swept = std::find(f.swept.begin(), f.swept.end(), k) != f.swept.end();
    if (swept && std::find(f.by.begin(), f.by.end(), k) == f.by.end()) continue;
    group[k] = v;
  }
  return group;
}

}  // namespace

std::vector<json> fit_runs(const SweepConfig& config, const std::vector<RunResult>& results) {
  std::vector<json> fits;
  for (const FitSpec& f : config.fits) {
    std::map<std::string, std::pair<json, std::vector<json>>> groups;  // by the group's JSON
    for (const RunResult& r : results)
      if (r.spec.experiment == f.experiment) {
        const json row = run_row(r);
        const json group = group_of(f, row);
        auto& [key, rows] = groups[group.dump()];
        key = group;
        rows.push_back(row);
      }
    for (const auto& [dump, group] : groups)
      fits.push_back(fit_group(f, group.first, group.second));
  }
  return fits;
}

}  // namespace pcrt
