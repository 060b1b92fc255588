// fit_runs on crafted run results: what is judged and what is not (identities, drifted groups,
// duplicated points, too few distinct x), the work metric, and the typed names fits read.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.hpp"
#include "harness/sweep_config.hpp"
#include "harness/sweep_fits.hpp"

using namespace pcrt;

namespace {

SweepConfig config(const json& fit,
                   const json& n_grid = json{1000, 2000, 4000, 8000, 16000, 32000}) {
  const json raw = {{"name", "t"},
                    {"experiments",
                     {{{"name", "e"},
                       {"kind", "render"},
                       {"methods", {"hubo_2006"}},
                       {"datasets", {"sphere"}},
                       {"grid", {{"N", n_grid}, {"M", {64}}, {"B", {0}}}},
                       {"fits", {fit}}}}}};
  return parse_sweep_config(raw, "test");
}

// One ok result of hubo_2006 at N with the given counters (rounded: counts are whole numbers).
RunResult result(double n, const std::map<std::string, double>& counters) {
  RunResult r;
  r.spec = json({{"experiment", "e"},
                 {"kind", "render"},
                 {"method", "hubo_2006"},
                 {"structure", "kd_tree"},
                 {"dataset", "sphere"},
                 {"N", n},
                 {"M", 64},
                 {"B", 0}})
               .get<RunSpec>();
  for (const auto& [k, v] : counters) r.counters[k] = uint64_t(std::llround(v));
  return r;
}

// Frames whose items per leaf K grow by `factor` at each doubling of N, from 8.
std::vector<RunResult> drifting_k_runs(double factor) {
  std::vector<RunResult> runs;
  double k = 8;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000}) {
    runs.push_back(result(n, {{"nodes_visited", 100 * std::log(n)},
                              {"items_visited", 100 * k},
                              {"leaves_visited", 100},
                              {"weighted_plane_terms", 500 * k}}));
    k *= factor;
  }
  return runs;
}

}  // namespace

TEST_CASE("fit_runs: work includes the method's own leaf counters", "[sweep][fit]") {
  const SweepConfig c =
      config({{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "work"}});
  std::vector<RunResult> runs;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000})
    runs.push_back(result(n, {{"nodes_visited", 100 * std::log(n)},
                              {"items_visited", 800},
                              {"leaves_visited", 100},
                              {"weighted_plane_terms", 5000},
                              {"rays_cast", 64}}));
  const std::vector<json> fits = fits_json(fit_runs(c, runs));
  REQUIRE(fits.size() == 1);
  REQUIRE(fits[0]["metric"].get<std::string>().find("ops_weighted_plane_terms") !=
          std::string::npos);
  const double y0 = fits[0]["y_values"][0];
  REQUIRE(y0 == Approx(std::round(100 * std::log(1000.0)) + 800 + 5000));
  REQUIRE(fits[0]["verdict"] != "exceeds");
}

TEST_CASE("fit_runs: a fixed K that drifts is not judged", "[sweep][fit]") {
  const SweepConfig c =
      config({{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "work"}});
  const std::vector<RunResult> runs = drifting_k_runs(1.5);
  const json f = fits_json(fit_runs(c, runs))[0];
  REQUIRE(f["verdict"] == "drifted");
  REQUIRE(f["reason"].get<std::string>().find("K moved from 8 to") != std::string::npos);
  REQUIRE(f.contains("verdict_if_fixed"));
}

TEST_CASE("fit_runs: a drifting K declared a covariate is fitted, not held", "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/frame_reduced"},
                                {"variable", "N"},
                                {"metric", "work"},
                                {"covariate", "K"}});
  const std::vector<RunResult> runs = drifting_k_runs(1.5);
  const json f = fits_json(fit_runs(c, runs))[0];
  INFO(f.dump());
  REQUIRE(f["verdict"] != "drifted");
  REQUIRE(f["verdict"] != "exceeds");  // the K term carries the growth, not N
  REQUIRE(f["covariate_values"].size() == 6);
  // A K that does not move is no term of its own (it would be the intercept again): the faster
  // terms stay identifiable.
  const json fixed = fits_json(fit_runs(c, drifting_k_runs(1.0)))[0];
  INFO(fixed.dump());
  for (const json& t : fixed["faster_terms"]) REQUIRE(t["high95"].is_number());
}

TEST_CASE("fit_runs: a threshold without its measure is an error, never a pass", "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/iterations"}, {"metric", "I_run"}, {"max", 3}});
  std::vector<RunResult> runs;
  for (double n : {1000, 2000}) runs.push_back(result(n, {{"rays_cast", 64}}));  // no iterations
  const json f = fits_json(fit_runs(c, runs))[0];
  REQUIRE(f["verdict"] == "error");
  REQUIRE(f["error"].get<std::string>().find("no value") != std::string::npos);
}

// A bound on I that the method's own cap on its iterations keeps cannot fail: it is tallied as
// a check of the loops, not as a claim met.
TEST_CASE("fit_runs: a bound on I that max_iterations keeps is a loop check", "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/iterations"}, {"metric", "I_run"}, {"max", 3}});
  std::vector<RunResult> runs;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000})
    runs.push_back(result(n, {{"newton_runs", 100}, {"newton_steps", 250}}));
  REQUIRE(fits_json(fit_runs(c, runs))[0]["verdict"] == "meets");  // the cap is hubo_2006's own
  for (RunResult& r : runs) r.spec.set["max_iterations"] = 3;
  const json capped = fits_json(fit_runs(c, runs))[0];
  REQUIRE(capped["verdict"] == "loop_check");
  REQUIRE(capped["reason"].get<std::string>().find("by construction") != std::string::npos);
}

TEST_CASE("fit_runs: y proportional to x by construction is a loop check", "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/leaf"},
                                {"variable", "I"},
                                {"x", "I_run"},
                                {"metric", "ops_newton_steps"},
                                {"per", "ops_newton_runs"}});
  std::vector<RunResult> runs;
  int i = 1;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000})
    runs.push_back(result(n, {{"newton_steps", 100 * i++}, {"newton_runs", 100}}));
  const json f = fits_json(fit_runs(c, runs))[0];
  INFO(f.dump());
  REQUIRE(f["verdict"] == "loop_check");
}

TEST_CASE("fit_runs: identical points are merged, and fewer than 5 distinct x is an error",
          "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/leaf"},
                                {"variable", "I"},
                                {"x", "I_run"},
                                {"metric", "ops_weighted_plane_terms"},
                                {"per", "ops_newton_runs"}});
  std::vector<RunResult> runs;
  int i = 0;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000}) {
    const int steps = std::min(++i, 3);  // the last four runs are one and the same point
    runs.push_back(result(n, {{"newton_steps", 100 * steps},
                              {"newton_runs", 100},
                              {"weighted_plane_terms", 1000 * steps + 7}}));
  }
  const json f = fits_json(fit_runs(c, runs))[0];
  REQUIRE(f["verdict"] == "error");
  REQUIRE(f["x_values"].size() == 3);
  REQUIRE(f["error"].get<std::string>().find("5 distinct x") != std::string::npos);
}

TEST_CASE("run_value: what a fit reads from a run", "[sweep][fit]") {
  RunResult r = result(1000, {{"nodes_visited", 10},
                              {"items_visited", 20},
                              {"weighted_plane_terms", 5},
                              {"leaves_visited", 4}});
  r.times_s = {0.5, 0.25, 1.0};
  r.points = 999;  // N as loaded replaces the grid's
  auto value = [&](const std::string& name) { return run_value(r, *run_quantity_from_name(name)); };
  REQUIRE(value("N") == 999);
  REQUIRE(value("M") == 64);
  REQUIRE(std::isnan(value("S")));          // not in the grid: missing, never zero
  REQUIRE(value("K") == 5);                 // the measured items per visited leaf
  REQUIRE(value("ops_newton_steps") == 0);  // a counter never touched
  REQUIRE(value("time") == 0.5);
  REQUIRE(value("fps") == 2);
  REQUIRE(value("work") == 10 + 20 + 5);  // with hubo_2006's own leaf counter
  REQUIRE(std::isnan(value("build_s")));
  REQUIRE(std::isnan(value("set_K")));
  const RunResult failed = failed_run(r.spec, RunStatus::kFailed, "crashed");
  REQUIRE(std::isnan(run_value(failed, *run_quantity_from_name("time"))));
  REQUIRE(std::isnan(run_value(failed, *run_quantity_from_name("fps"))));
}

// H is the declared hits counter per ray cast (grt_2024: proxy hits), missing for a method
// without one; as a held variable, an H that moves in an N sweep is not judged unless free.
TEST_CASE("H: hits per ray, measured and held", "[sweep][fit]") {
  RunResult hubo = result(1000, {{"rays_cast", 64}});
  REQUIRE(std::isnan(run_value(hubo, *run_quantity_from_name("H"))));
  auto grt_runs = [](double growth) {
    std::vector<RunResult> runs;
    double hits = 10;
    for (double n : {1000, 2000, 4000, 8000, 16000, 32000}) {
      RunResult r = result(n, {{"nodes_visited", 64 * 30 * std::log(n)},
                               {"gaussian_proxy_tests", 64 * 40.0},
                               {"gaussian_proxy_hits", 64 * hits},
                               {"rays_cast", 64}});
      r.spec.method = "grt_2024";
      r.spec.structure = "bvh";
      runs.push_back(r);
      hits *= growth;
    }
    return runs;
  };
  REQUIRE(run_value(grt_runs(1)[0], *run_quantity_from_name("H")) == 10);
  const json traversal = {{"claim", "grt_2024/in_N_traversal"},
                          {"variable", "N"},
                          {"metric", {"ops_nodes_visited", "ops_gaussian_proxy_tests"}},
                          {"per", "ops_rays_cast"}};
  const json held = fits_json(fit_runs(config(traversal), grt_runs(1)))[0];
  INFO(held.dump());
  REQUIRE(held["verdict"] != "drifted");
  const json drifted = fits_json(fit_runs(config(traversal), grt_runs(1.5)))[0];
  REQUIRE(drifted["verdict"] == "drifted");
  REQUIRE(drifted["reason"].get<std::string>().find("H moved from 10 to") != std::string::npos);
  json free = traversal;
  free["free"] = {"H"};
  REQUIRE(fits_json(fit_runs(config(free), grt_runs(1.5)))[0]["verdict"] != "drifted");
}

TEST_CASE("fit names are typed where the config is read", "[sweep][fit]") {
  const SweepConfig c = config({{"claim", "{method}/leaf"},
                                {"variable", "I"},
                                {"x", "I_run"},
                                {"metric", {"ops_newton_steps", "work"}},
                                {"per", "ops_newton_runs"},
                                {"free", {"K"}}});
  const FitSpec& f = c.fits.at(0);
  REQUIRE(f.variable == Variable::I);
  REQUIRE(f.x == RunQuantity::of(RunQuantity::Source::kIterationsPerRun));
  REQUIRE(f.metric.at(0) == RunQuantity::counter("newton_steps"));
  REQUIRE(f.metric.at(1) == RunQuantity::of(RunQuantity::Source::kWork));
  REQUIRE(f.per == RunQuantity::counter("newton_runs"));
  REQUIRE(f.free.at(0) == RunQuantity::of(Variable::K));
  REQUIRE(f.swept.at(0) == RunQuantity::of(Variable::N));  // the grid's N has six values
  auto error_of = [](const json& fit) {
    try {
      (void)config(fit);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const json base = {{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "work"}};
  json bad = base;
  bad["metric"] = "tme";
  REQUIRE_THAT(error_of(bad), Catch::Contains("fits[0].metric: 'tme' is not a run column"));
  bad = base;
  bad["by"] = {"method"};
  REQUIRE_THAT(error_of(bad), Catch::Contains("fits[0].by: 'method' is not one of N M S B"));
  bad = base;
  bad["variable"] = "NK";
  REQUIRE_THAT(error_of(bad), Catch::Contains("variable 'NK' is not one of S M B N K k I H"));
}

TEST_CASE("an optional key of the wrong type is an InputError naming it", "[sweep][config]") {
  // nlohmann's value() throws its own type_error for these; the fuzzer found "per": {} first.
  const json fit = {{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "work"}};
  const json experiment = {{"name", "e"},
                           {"kind", "render"},
                           {"methods", {"hubo_2006"}},
                           {"datasets", {"sphere"}},
                           {"grid", {{"N", {1000, 2000}}, {"M", {64}}, {"B", {0}}}},
                           {"fits", {fit}}};
  const json good = {{"name", "t"}, {"experiments", {experiment}}};
  REQUIRE_NOTHROW(parse_sweep_config(good, "test"));
  auto message = [](const json& raw) {
    try {
      (void)parse_sweep_config(raw, "test");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  for (const char* key : {"name", "measure", "time_limit_s", "threads", "dataset_dir"}) {
    json bad = good;
    bad[key] = json::object();
    REQUIRE_THAT(message(bad), Catch::StartsWith("test:") && Catch::Contains(key));
  }
  for (const char* key : {"name", "kind", "camera", "repetitions", "replicates"}) {
    json bad = good;
    bad["experiments"][0][key] = json::object();
    REQUIRE_THAT(message(bad), Catch::Contains("experiments[0]") && Catch::Contains(key));
  }
  for (const char* key : {"per", "variable", "x", "covariate", "short_range", "max", "min"}) {
    json bad = good;
    bad["experiments"][0]["fits"][0][key] = json::object();
    REQUIRE_THAT(message(bad), Catch::Contains("fits[0]") && Catch::Contains(key));
  }
}

namespace {

// Results for every run the config expands to, in its own specs, N as loaded where given:
// frames whose node visits grow as log N, at 8 items per leaf.
std::vector<RunResult> runs_of(const SweepConfig& c, bool loaded_n) {
  std::vector<RunResult> runs;
  for (const RunSpec& s : c.runs) {
    const double n = *s.N;
    RunResult r;
    r.spec = s;
    if (loaded_n) r.points = uint64_t(n), r.pixels = int64_t(*s.M);
    r.counters = {{"nodes_visited", uint64_t(std::llround(1000 * std::log(n)))},
                  {"items_visited", 800},
                  {"leaves_visited", 100}};
    runs.push_back(r);
  }
  return runs;
}

}  // namespace

// A run that failed has no N as loaded: grouped by it, it once formed a group of its own and its
// group's fit held without it.
TEST_CASE("fit_runs: a failed or missing run keeps its group from holding", "[sweep][fit]") {
  const SweepConfig c = config(
      {{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "ops_nodes_visited"}},
      {1000, 3000, 9000, 27000, 81000, 243000, 729000});
  std::vector<RunResult> runs = runs_of(c, true);
  const json all = fits_json(fit_runs(c, runs));
  REQUIRE(all.size() == 1);
  REQUIRE(all[0]["missing_runs"] == 0);
  REQUIRE(all[0]["failed_runs"] == 0);
  INFO(all[0].dump());
  REQUIRE(all[0]["verdict"] == "holds");

  std::vector<RunResult> with_failed = runs;
  with_failed.back() = failed_run(runs.back().spec, RunStatus::kTimeout, "timed out");
  const json failed = fits_json(fit_runs(c, with_failed));
  REQUIRE(failed.size() == 1);
  REQUIRE(failed[0]["failed_runs"] == 1);
  REQUIRE(failed[0]["verdict"] == "inconclusive");

  std::vector<RunResult> with_missing = runs;
  with_missing.pop_back();
  const json missing = fits_json(fit_runs(c, with_missing));
  REQUIRE(missing.size() == 1);
  INFO(missing[0].dump());
  REQUIRE(missing[0]["missing_runs"] == 1);
  REQUIRE(missing[0]["verdict"] == "inconclusive");
  REQUIRE(missing[0]["reason"].get<std::string>().find("1 of its runs is missing") !=
          std::string::npos);

  const json none = fits_json(fit_runs(c, {}));
  REQUIRE(none.size() == 1);
  REQUIRE(none[0]["verdict"] == "error");
  REQUIRE(none[0]["missing_runs"] == 7);
}

// With one run per x the run farthest from the median is that x's only witness: leaving it out
// once hid a K that jumped at the largest N.
TEST_CASE("fit_runs: a held K that jumps at one x without replicates is drifted", "[sweep][fit]") {
  const SweepConfig c =
      config({{"claim", "{method}/frame_reduced"}, {"variable", "N"}, {"metric", "work"}});
  std::vector<RunResult> runs;
  for (double n : {1000, 2000, 4000, 8000, 16000, 32000}) {
    const double k = n == 32000 ? 20 : 8;
    runs.push_back(result(n, {{"nodes_visited", 100 * std::log(n)},
                              {"items_visited", 100 * k},
                              {"leaves_visited", 100}}));
  }
  const json f = fits_json(fit_runs(c, runs))[0];
  INFO(f.dump());
  REQUIRE(f["verdict"] == "drifted");
  REQUIRE(f["reason"].get<std::string>().find("K moved from 8 to 20 (+150%)") != std::string::npos);
}

TEST_CASE("a config's M is a square and its name a plain folder name", "[sweep][config]") {
  const auto parse = [](const json& name, const json& m) {
    json raw = {{"experiments",
                 {{{"kind", "render"},
                   {"methods", {"reference_splat"}},
                   {"datasets", {"sphere"}},
                   {"grid", {{"N", {100}}, {"M", m}, {"B", {1}}}}}}}};
    if (!name.is_null()) raw["name"] = name;
    return parse_sweep_config(raw, "c.json");
  };
  REQUIRE(parse(nullptr, {16, 1024}).name == "c");
  REQUIRE_THROWS_WITH(
      parse(nullptr, {17}),
      Catch::Contains("M = 17 is not a square number of pixels") && Catch::Contains("16 or 25"));
  for (const char* bad : {"", ".", "..", "../victim", "a/b"})
    REQUIRE_THROWS_WITH(parse(bad, {16}), Catch::Contains("must be a plain folder name"));
}
