#include "harness/shard_plan.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

#include "core/error.hpp"
#include "harness/command_options.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

// What the method declares (MethodInfo::cost); a method this build does not know (a plan made
// elsewhere) is priced like the defaults.
MethodInfo::RunCost method_cost(const std::string& method) {
  for (const MethodInfo& m : MethodRegistry::instance().all())
    if (m.id == method) return m.cost;
  return {};
}

double n_log_n(double n) { return n * std::log2(std::max(2.0, n)); }

// Seconds of one CGAL reconstruction (results/thesis): Delaunay ~217 ns N log N on uniform
// points and ~90 ns N^2 on skew lines (its worst case), advancing front ~630 ns N log N.
double reconstruction_cost(const std::string& reconstruction, const std::string& dataset,
                           double n) {
  if (reconstruction == "afsr") return 630e-9 * n_log_n(n);
  if (dataset.rfind("skew_lines", 0) == 0) return 90e-9 * n * n;
  return 220e-9 * n_log_n(n);
}

double workload_cost(const std::string& workload, double n) {
  if (workload == "triple_loop") return 1e-9 * n * n * n;
  return 10e-9 * n_log_n(n);
}

double frame_cost(const RunSpec& spec, const MethodInfo::RunCost& c, double n) {
  const double rays = spec.M.value_or(4096.0) * spec.S.value_or(1.0) * (1 + spec.B.value_or(1.0));
  // The per-ray constants come from outside cameras, where most rays miss the cloud early. Inside
  // a closed surface every ray hits and works through its leaves: 17-30x as long on ci.json's
  // bounces_inside.
  const double hit_factor = spec.camera_inside ? 20.0 : 1.0;
  return hit_factor * c.ray_ns * 1e-9 * rays * std::log2(std::max(2.0, n));
}

}  // namespace

double model_run_cost(const RunSpec& spec) {
  // A child process, the registries and the cloud's generation come with every run (the shortest
  // runs of configs/ci.json take 4 ms).
  const double n = spec.N.value_or(1000.0);
  const double overhead = 0.004 + 200e-9 * n;
  const double passes = double(spec.warmup + spec.reps);
  const MethodInfo::RunCost c = method_cost(spec.method);
  const double prepare = c.prepare_ns * 1e-9 * n_log_n(n);
  switch (spec.kind) {
    case RunKind::kWorkload:
      return overhead + passes * workload_cost(spec.workload, n);
    case RunKind::kReconstruct:
      return overhead + passes * reconstruction_cost(spec.reconstruction, spec.dataset, n);
    case RunKind::kBuild:
      return overhead + passes * prepare;
    case RunKind::kCrossover:
      return overhead + reconstruction_cost(spec.reconstruction, "", n) + prepare +
             2 * passes * frame_cost(spec, c, n);
    case RunKind::kRender:
      break;
  }
  return overhead + passes * (prepare + frame_cost(spec, c, n));
}

std::vector<double> run_costs(const std::vector<RunSpec>& runs,
                              const std::vector<RunResult>& earlier) {
  std::unordered_map<std::string, double> measured;
  for (const RunResult& r : earlier)
    if (r.wall_s) measured[run_key(r)] = *r.wall_s;
  std::vector<double> model(runs.size()), ratios;
  for (size_t i = 0; i < runs.size(); ++i) {
    model[i] = model_run_cost(runs[i]);
    const auto it = measured.find(run_key(runs[i]));
    if (it != measured.end() && model[i] > 0) ratios.push_back(it->second / model[i]);
  }
  // The earlier machine may be faster or slower than the model's: scale the runs it did not do.
  double scale = 1;
  if (!ratios.empty()) {
    std::nth_element(ratios.begin(), ratios.begin() + long(ratios.size() / 2), ratios.end());
    scale = ratios[ratios.size() / 2];
  }
  std::vector<double> costs(runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    const auto it = measured.find(run_key(runs[i]));
    costs[i] = it != measured.end() ? it->second : model[i] * scale;
  }
  return costs;
}

ShardPlan plan_shards(const std::vector<double>& costs, size_t n) {
  std::vector<size_t> order(costs.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return costs[a] > costs[b]; });
  ShardPlan plan;
  plan.shards.resize(n);
  plan.cost.assign(n, 0.0);
  for (size_t run : order) {
    const size_t s =
        size_t(std::min_element(plan.cost.begin(), plan.cost.end()) - plan.cost.begin());
    plan.shards[s].push_back(run);
    plan.cost[s] += costs[run];
  }
  for (auto& s : plan.shards) std::sort(s.begin(), s.end());
  return plan;
}

std::string planned_run_key(const json& spec, const std::string& origin) {
  try {
    return run_key(spec.get<RunSpec>());
  } catch (const std::exception& e) {  // json's own exceptions or InputError
    input_error("{}: a planned run is not a run spec: {}", origin, e.what());
  }
}

json plan_json(const ShardPlan& plan, const std::vector<RunSpec>& runs, const std::string& source) {
  json shards = json::array();
  for (size_t s = 0; s < plan.shards.size(); ++s) {
    json specs = json::array();
    for (size_t i : plan.shards[s]) specs.push_back(json(runs[i]));
    shards.push_back({{"estimated_s", plan.cost[s]}, {"runs", specs}});
  }
  return {{"cost_source", source}, {"shards", shards}};
}

namespace {

// One shard of a plan file: its estimated seconds (if given) and its runs' keys.
std::vector<std::string> read_planned_shard(const json& shard, const std::string& where) {
  if (!shard.is_object() || !shard.contains("runs") || !shard["runs"].is_array())
    input_error("{}: not an object with a list of \"runs\"", where);
  if (shard.contains("estimated_s")) {
    const json& e = shard["estimated_s"];
    if (!e.is_number() || !(e.get<double>() >= 0 && std::isfinite(e.get<double>())))
      input_error("{}.estimated_s = {} is not a number of seconds", where, e.dump());
  }
  std::vector<std::string> keys;
  for (size_t r = 0; r < shard["runs"].size(); ++r)
    keys.push_back(planned_run_key(shard["runs"][r], fmt::format("{}.runs[{}]", where, r)));
  return keys;
}

}  // namespace

std::vector<std::vector<std::string>> read_plan(const json& plan, const std::string& origin) {
  if (!plan.is_object() || !plan.contains("shards"))
    input_error("{}: not a shard plan (written by pcrt cluster submit)", origin);
  const json& shards = plan["shards"];
  if (!shards.is_array() || shards.empty() || shards.size() > kMaxShards)
    input_error("{}: \"shards\" is not a list of 1 to {} shards", origin, kMaxShards);
  if (plan.contains("cost_source") && !plan["cost_source"].is_string())
    input_error("{}: \"cost_source\" = {} is not a string", origin, plan["cost_source"].dump());
  std::vector<std::vector<std::string>> keys;
  std::unordered_map<std::string, size_t> shard_of;
  for (size_t s = 0; s < shards.size(); ++s) {
    const std::string where = fmt::format("{}: shards[{}]", origin, s);
    keys.push_back(read_planned_shard(shards[s], where));
    for (size_t r = 0; r < keys.back().size(); ++r) {
      const auto [it, fresh] = shard_of.emplace(keys.back()[r], s);
      if (!fresh) input_error("{}.runs[{}]: also planned in shard {}", where, r, it->second);
    }
  }
  return keys;
}

std::vector<size_t> plan_shard(const json& plan, const std::vector<RunSpec>& runs, size_t shard,
                               size_t n, const std::string& origin) {
  const std::vector<std::vector<std::string>> keys = read_plan(plan, origin);
  if (keys.size() != n) input_error("{}: plans {} shards, not {}", origin, keys.size(), n);
  std::unordered_map<std::string, size_t> index;
  for (size_t i = 0; i < runs.size(); ++i) index[run_key(runs[i])] = i;
  // Every shard's runs must be the config's, and every run of the config planned (read_plan has
  // refused a run planned twice): a run no shard plans would never run anywhere.
  std::vector<size_t> mine;
  size_t planned = 0;
  for (size_t s = 0; s < keys.size(); ++s)
    for (const std::string& key : keys[s]) {
      const auto it = index.find(key);
      if (it == index.end())
        input_error(
            "{}: shard {} plans a run the config does not have; the plan belongs to "
            "another config",
            origin, s);
      if (s == shard) mine.push_back(it->second);
      ++planned;
    }
  if (planned != runs.size())
    input_error("{}: plans {} of the config's {} runs; the others would never run", origin, planned,
                runs.size());
  return mine;
}

}  // namespace pcrt
