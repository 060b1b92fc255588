#include "harness/sweep_fits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.hpp"
#include "harness/claims.hpp"
#include "harness/fit.hpp"
#include "harness/run_files.hpp"
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
  if (name == "time") return row.value("time_median_s", 0.0);
  if (name == "fps") {
    const double t = row.value("time_median_s", 0.0);
    return t > 0 ? 1.0 / t : 0.0;
  }
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

// Variables that the claim does not sweep must stay put: K (the method's K or the measured
// items per leaf), k, and I (the measured iterations per run).
std::string drift_of(const std::vector<FitPoint>& pts, const FitSpec& f) {
  for (size_t i = 0; i < kHeldColumns.size(); ++i) {
    const std::string v = kHeldColumns[i];
    if (f.variable == v || (f.variable == "I" && v == "I_run")) continue;
    if (std::find(f.free.begin(), f.free.end(), v) != f.free.end()) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const FitPoint& p : pts)
      if (std::isfinite(p.held[i])) lo = std::min(lo, p.held[i]), hi = std::max(hi, p.held[i]);
    if (hi > 0 && lo < hi && (hi - lo) > 0.2 * lo)
      return fmt::format("{} moved from {:.3g} to {:.3g} (+{:.0f}%) while it should be fixed",
                         v == "I_run" ? "I (iterations per run)" : v, lo, hi, 100 * (hi - lo) / lo);
  }
  return {};
}

// y / x the same at every x: the metric counts x by construction (a loop over K items adds K).
bool is_identity(const std::vector<FitPoint>& pts) {
  const double r0 = pts.front().y / pts.front().x;
  return std::all_of(pts.begin(), pts.end(),
                     [&](const FitPoint& p) { return std::abs(p.y / p.x - r0) <= 1e-9 * r0; });
}

ClaimVerdict fit_threshold(const FitSpec& f, const std::vector<FitPoint>& pts, json& out) {
  double worst = f.max >= 0 ? 0 : std::numeric_limits<double>::infinity();
  for (const FitPoint& p : pts) worst = f.max >= 0 ? std::max(worst, p.y) : std::min(worst, p.y);
  out["measured"] = pts.empty() ? json(nullptr) : json(worst);
  out["threshold"] = f.max >= 0 ? fmt::format("<= {}", f.max) : fmt::format(">= {}", f.min);
  const bool met = f.max >= 0 ? worst <= f.max : worst >= f.min;
  return pts.empty() ? ClaimVerdict::kError : met ? ClaimVerdict::kMeets : ClaimVerdict::kMisses;
}

// Identical points (parameters that build the same structure) are one observation.
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

void write_growth_fit(const GrowthFit& g, json& out) {
  json weights = json::object();
  for (size_t m = 0; m < kModels; ++m) weights[growth_name(kAllGrowths[m])] = g.weight[m];
  out.update({{"points", g.points},
              {"exponent", g.exponent},
              {"ci_low", g.ci_low},
              {"ci_high", g.ci_high},
              {"detectable_exponent", g.detectable_exponent},
              {"best_model", growth_name(g.best)},
              {"r2", g.r2},
              {"noise", g.noise},
              {"akaike_weights", weights},
              {"weight_faster", g.weight_faster},
              {"weight_slower", g.weight_slower},
              {"delta_aicc_expected", g.delta_aicc_expected}});
}

// A judged verdict and why.
struct Judgement {
  ClaimVerdict verdict;
  std::string reason;
};

// What this design could detect at the noise it shows (floor 0.5%): a violation one class up,
// and how often an exactly true claim would be called `exceeds`. "Within" is a claim about what
// was not seen: it needs a design that would have seen a violation one class up at this noise at
// least 90% of the time.
Judgement check_power(const GrowthFit& g, Growth expected, const std::vector<double>& xs,
                      json& out) {
  const double noise = std::max(g.noise, 0.005);
  if (next_growth(expected) != expected)
    out["power_one_up"] =
        simulate_verdicts(xs, next_growth(expected), expected, noise, 0, 200, 7).exceeds;
  out["false_exceeds"] = simulate_verdicts(xs, expected, expected, noise, 0, 200, 8).exceeds;
  const double power = out.value("power_one_up", 1.0);
  if (g.verdict != ClaimVerdict::kWithin || power >= 0.9) return {g.verdict, g.reason};
  return {ClaimVerdict::kInconclusive,
          fmt::format("no faster model is preferred, but at this noise ({:.1f}%) the design would "
                      "catch {} only {:.0f}% of the time",
                      100 * g.noise, growth_name(next_growth(expected)), 100 * power)};
}

// Fits one group and writes its numbers and reason into `out`; returns its verdict.
ClaimVerdict fit_growth_group(const FitSpec& f, const Claim& claim, std::vector<FitPoint> pts,
                              json& out) {
  pts = distinct(std::move(pts));
  std::vector<double> xs, ys;
  for (const FitPoint& p : pts) xs.push_back(p.x), ys.push_back(p.y);
  out["x_values"] = xs;
  out["y_values"] = ys;
  const Growth expected = expected_growth(claim.complexity, f.variable);
  out["expected_model"] = growth_name(expected);
  const GrowthFit g = fit_growth(xs, ys, expected, out["claim"].get<std::string>());
  write_growth_fit(g, out);
  Judgement j = check_power(g, expected, xs, out);
  if (is_identity(pts))
    j = {ClaimVerdict::kIdentity,
         fmt::format("y / x = {:.6g} at every x: the metric counts x by construction "
                     "(a loop-structure check, not a test of the claim)",
                     pts.front().y / pts.front().x)};
  out["reason"] = j.reason;
  return j.verdict;
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
  if (f.is_threshold()) return fit_threshold(f, pts, out);
  const std::string drift = drift_of(pts, f);
  const ClaimVerdict verdict = fit_growth_group(f, claim, pts, out);
  if (drift.empty() || verdict == ClaimVerdict::kIdentity) return verdict;
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
