// The reporter of fits: a GroupFit as its fits.json entry (docs/verdicts.md has the keys). The
// JSON is what it has always been: report.py, findings.py, the gate's baselines read it.
#include <cmath>

#include "harness/sweep_fits.hpp"

namespace pcrt {

namespace {

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

void write_growth(const GrowthResult& growth, json& out) {
  out["x_values"] = growth.x;
  out["y_values"] = growth.y;
  if (growth.covariate) out["covariate_values"] = *growth.covariate;
  if (!growth.short_range.empty()) out["short_range"] = growth.short_range;
  if (growth.expected) out["expected_model"] = growth_name(*growth.expected);
  if (growth.fit) write_growth_fit(*growth.fit, out);
}

void write_threshold(const ThresholdResult& threshold, json& out) {
  out["threshold"] = threshold.bound;
  out["measured"] = threshold.measured ? json(*threshold.measured) : json(nullptr);
}

json names_json(const RunNames& n) {
  return {{"experiment", n.experiment}, {"kind", n.kind},
          {"method", n.method},         {"structure", n.structure},
          {"dataset", n.dataset},       {"reconstruction", n.reconstruction},
          {"engine", n.engine},         {"workload", n.workload}};
}

}  // namespace

json group_json(const GroupIdentity& group) {
  json out = names_json(group.names);
  for (const auto& [variable, v] : group.grid)
    out[variable_name(variable)] = !v            ? json(nullptr)
                                   : v->measured ? json(uint64_t(v->value))
                                                 : json(v->value);
  for (const auto& [name, value] : group.parameters) out["set_" + name] = value;
  return out;
}

json fit_json(const GroupFit& fit) {
  json out = {{"claim", fit.claim},
              {"experiment", fit.experiment},
              {"variable", fit.variable ? variable_name(*fit.variable) : ""},
              {"x", fit.x ? run_quantity_name(*fit.x) : std::string()},
              {"group", group_json(fit.group)},
              {"method", fit.names.method},
              {"structure", fit.names.structure},
              {"dataset", fit.names.dataset},
              {"reconstruction", fit.names.reconstruction},
              {"workload", fit.names.workload},
              {"metric", fit.metric},
              {"runs", fit.runs},
              {"failed_runs", fit.failed_runs},
              {"missing_runs", fit.missing_runs},
              {"verdict", verdict_name(fit.verdict)}};
  if (fit.claimed)
    out.update({{"claimed", fit.claimed->complexity},
                {"source", fit.claimed->source},
                {"about", claim_about_name(fit.claimed->about)}});
  if (fit.threshold) write_threshold(*fit.threshold, out);
  if (fit.growth) write_growth(*fit.growth, out);
  if (fit.verdict_if_fixed) out["verdict_if_fixed"] = verdict_name(*fit.verdict_if_fixed);
  if (fit.reason) out["reason"] = *fit.reason;
  if (fit.error) out["error"] = *fit.error;
  return out;
}

std::vector<json> fits_json(const std::vector<GroupFit>& fits) {
  std::vector<json> out;
  for (const GroupFit& f : fits) out.push_back(fit_json(f));
  return out;
}

}  // namespace pcrt
