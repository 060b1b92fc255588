// The fitter on exact and noisy synthetic growth (no timing here: the timed and counted
// calibration workloads run through `pcrt calibrate`), and the power of its verdicts on every
// growth design of configs/thesis.json.
#include "harness/fit.hpp"

#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

namespace {
double model(Growth m, double x) {
  switch (m) {
    case Growth::kConstant:
      return 5;
    case Growth::kLog:
      return 5 + 3 * std::log(x);
    case Growth::kSqrt:
      return 10 + 4 * std::sqrt(x);
    case Growth::kLinear:
      return 40 + 2 * x;
    case Growth::kLinearLog:
      return 40 + 2 * x * std::log2(x);
    case Growth::kQuadratic:
      return 100 + 0.5 * x * x;
    case Growth::kCubic:
      return 100 + 0.01 * x * x * x;
  }
  return 0;
}

std::vector<double> powers_of_two(int from, int to, int replicates = 1) {
  std::vector<double> x;
  for (int e = from; e <= to; ++e)
    for (int r = 0; r < replicates; ++r) x.push_back(std::pow(2.0, e));
  return x;
}
}  // namespace

TEST_CASE("fit_growth picks the generating model, and a true bound holds", "[fit]") {
  Rng rng(11, 2);
  for (Growth truth : kAllGrowths) {
    for (double noise : {0.0, 0.02}) {
      const std::vector<double> x = powers_of_two(6, 18, 3);
      std::vector<double> y;
      for (double v : x)
        y.push_back(model(truth, v) * (1 + noise * (2 * rng.uniform_double() - 1)));
      const GrowthFit f = fit_growth(x, y, truth, "synthetic");
      INFO(growth_name(truth) << " noise " << noise << " -> " << growth_name(f.best) << ": "
                              << verdict_name(f.verdict) << ", " << f.reason);
      REQUIRE(f.best == truth);
      REQUIRE(f.verdict == ClaimVerdict::kHolds);
      REQUIRE(f.hidden < kHoldsTolerance);
      REQUIRE(f.faster.size() == 3);
    }
  }
}

TEST_CASE("verdicts against an upper bound: exceeds, holds (loose), holds (tight)", "[fit]") {
  const std::vector<double> x = powers_of_two(6, 16);
  std::vector<double> y;
  for (double v : x) y.push_back(model(Growth::kQuadratic, v));
  const GrowthFit over = fit_growth(x, y, Growth::kLinear, "q");
  INFO(over.reason);
  REQUIRE(over.verdict == ClaimVerdict::kExceeds);
  REQUIRE(over.faster[2].low99 > 0);  // x^2, two classes up
  const GrowthFit loose = fit_growth(x, y, Growth::kCubic, "q");
  INFO(loose.reason);
  REQUIRE(loose.verdict == ClaimVerdict::kHolds);
  REQUIRE(loose.tightness == Tightness::kLoose);
  const GrowthFit f = fit_growth(x, y, Growth::kQuadratic, "q");
  REQUIRE(f.verdict == ClaimVerdict::kHolds);
  REQUIRE(f.tightness == Tightness::kTight);
  REQUIRE(f.exponent == Approx(2.0).margin(0.05));
  REQUIRE(f.reason.find("at most") != std::string::npos);
}

TEST_CASE("verdicts: a faster term the data cannot exclude is inconclusive", "[fit]") {
  // Five points over a factor 4 of x at 10% noise: x and x log x cannot be told apart.
  Rng rng(3, 1);
  int inconclusive = 0;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> x, y;
    for (double v : {1000.0, 1400.0, 2000.0, 2800.0, 4000.0})
      x.push_back(v), y.push_back(v * std::log(v) * (1 + 0.1 * (2 * rng.uniform_double() - 1)));
    const GrowthFit f = fit_growth(x, y, Growth::kLinear, "x");
    inconclusive += f.verdict == ClaimVerdict::kInconclusive;
  }
  REQUIRE(inconclusive >= 45);
}

TEST_CASE("design rules: range, leave-one-out, lack of fit, loop checks", "[fit]") {
  Rng rng(5, 3);
  auto noisy = [&](double scatter) { return 1 + scatter * (2 * rng.uniform_double() - 1); };
  SECTION("a true claim over too short a range is inconclusive, unless waived") {
    std::vector<double> x, y;
    for (int i = 0; i < 8; ++i) x.push_back(1000 * std::pow(1.5, i));
    for (double v : x) y.push_back(v * std::log(v) * noisy(0.01));
    FitRules rules;
    rules.min_decades = 2;
    const GrowthFit f = fit_growth(x, y, Growth::kLinearLog, "short", rules);
    REQUIRE(f.verdict == ClaimVerdict::kInconclusive);
    REQUIRE(f.reason.find("decades") != std::string::npos);
    rules.range_waiver = "the scan has no more points";
    REQUIRE(fit_growth(x, y, Growth::kLinearLog, "short", rules).verdict !=
            ClaimVerdict::kInconclusive);
  }
  SECTION("one point carrying the whole departure does not make a verdict") {
    std::vector<double> x = powers_of_two(10, 17), y;
    for (double v : x) y.push_back(std::log(v) * (v == x.back() ? 1.8 : 1.0));
    const GrowthFit f = fit_growth(x, y, Growth::kLog, "upturn");
    INFO(f.reason);
    REQUIRE(f.verdict == ClaimVerdict::kInconclusive);
  }
  SECTION("replicates: a claimed model that misfits them is no basis for holds") {
    // (log x)^1.3 against a claimed log x, 0.1% replicate scatter: the misfit is far above the
    // pure error, and the class below (a constant) is already in the model.
    std::vector<double> x = powers_of_two(10, 18, 3), y;
    for (double v : x) y.push_back(std::pow(std::log(v), 1.3) * noisy(0.001));
    const GrowthFit f = fit_growth(x, y, Growth::kLog, "lof");
    REQUIRE(f.lof_tested);
    REQUIRE(f.verdict != ClaimVerdict::kHolds);
  }
  SECTION("a lower-order term the replicates show is taken into the claimed model") {
    std::vector<double> x = powers_of_two(11, 19, 3), y;
    for (double v : x) y.push_back(v * (std::log(v) - 2) * noisy(0.002));
    const GrowthFit f = fit_growth(x, y, Growth::kLinearLog, "n log(n/k)");
    REQUIRE(f.verdict != ClaimVerdict::kExceeds);
  }
  SECTION("work per sample flat over 32x is a loop check") {
    std::vector<double> x = {1, 2, 4, 8, 16, 32}, y;
    for (double v : x) y.push_back(v * (100 + 2 * std::log(v)));
    REQUIRE(fit_growth(x, y, Growth::kLinear, "S").verdict == ClaimVerdict::kLoopCheck);
  }
  SECTION("replicates scattering about the same work per sample are still a loop check") {
    // Three clouds (seeds) whose work per sample differs by up to 15%, each exactly linear: the
    // scatter is between clouds, not a movement of y / x with x (judged point by point it was a
    // "holds").
    std::vector<double> x, y;
    for (double v : {1, 2, 4, 8, 16, 32})
      for (double per_sample : {100.0, 108.0, 115.0}) x.push_back(v), y.push_back(v * per_sample);
    REQUIRE(fit_growth(x, y, Growth::kLinear, "S").verdict == ClaimVerdict::kLoopCheck);
  }
  SECTION("y / x that moves beyond the flatness is judged, not a loop check") {
    std::vector<double> x = {1, 2, 4, 8, 16, 32}, y;
    for (double v : x) y.push_back(v * (100 + 10 * std::log(v)));
    REQUIRE(fit_growth(x, y, Growth::kLinear, "S").verdict != ClaimVerdict::kLoopCheck);
  }
}

namespace {

// The growth designs of configs/thesis.json: the grid values of each fit's variable, repeated
// for the experiment's replicates, and whether the fit is in time (noisier).
struct Design {
  std::string name;
  std::vector<double> x;
  Growth claimed;
  bool timed;
  double min_decades;
};

std::string fill(std::string claim, const nlohmann::json& e, const std::string& tag,
                 const std::string& list, const std::string& dflt) {
  const size_t at = claim.find(tag);
  if (at == std::string::npos) return claim;
  std::string v = e.contains(list) ? std::string(e[list][0]) : dflt;
  if (v == "surveyed") v = dflt;
  return claim.replace(at, tag.size(), v);
}

// Times: "time", or seconds columns ("direct_setup_s").
bool timed(const nlohmann::json& metric) {
  for (const std::string m : metric.is_array() ? metric : nlohmann::json::array({metric}))
    if (m == "time" || (m.size() > 2 && m.compare(m.size() - 2, 2, "_s") == 0)) return true;
  return false;
}

std::vector<Design> thesis_designs() {
  std::ifstream in(pcrt::test::source_dir() / "configs/thesis.json");
  REQUIRE(in);
  const nlohmann::json config = nlohmann::json::parse(in);
  std::vector<Design> out;
  for (const auto& e : config["experiments"])
    for (const auto& fit : e.value("fits", nlohmann::json::array())) {
      if (!fit.contains("variable") || fit.contains("x")) continue;  // thresholds; measured x
      const std::string var = fit["variable"];
      const std::string key = var == "K" || var == "k" ? "set." + var : var;
      if (!e["grid"].contains(key)) continue;  // x measured (points per leaf): no design
      std::string claim = fill(fit["claim"], e, "{method}", "methods", "hubo_2006");
      claim = fill(claim, e, "{structure}", "structures", "kd_tree");
      Design d{fmt::format("{} {} in {}", e["name"].get<std::string>(), claim, var),
               {},
               expected_growth(find_claim(claim).complexity, var),
               timed(fit["metric"]),
               min_decades(var)};
      for (double v : e["grid"][key].get<std::vector<double>>())
        for (int r = 0; r < e.value("replicates", 1); ++r) d.x.push_back(v);
      out.push_back(d);
    }
  return out;
}

// A class's pure form, 1 at the design's largest x.
std::function<double(double)> unit(const std::vector<double>& x,
                                   const std::function<double(double, double)>& h) {
  const double xmin = *std::min_element(x.begin(), x.end());
  const double xmax = *std::max_element(x.begin(), x.end());
  return [=](double v) { return h(v, xmin) / h(xmax, xmin); };
}

std::function<double(double, double)> growth(Growth m) {
  return [m](double v, double xmin) { return pure_growth(m, v, xmin); };
}

}  // namespace

// Issue 27's power requirement, on every growth design of configs/thesis.json, through the same
// fit_growth as `pcrt fit`, at 2% relative noise for op counts and 5% for times (the committed
// fits' replicate scatter: op counts median 2.3%, times median 10.0%, where the power is lower:
// docs/verdicts.md), 400 seeded data sets per case:
//   the claim exactly true (pure; with a constant; with its lower-order term added or
//   subtracted, as N ln N + c N, or a negative intercept) -> exceeds <= 5%;
//   a violation one class up, pure or added so that it doubles y at x_max -> exceeds >= 90%;
//   a between-class violation (g x^0.25), pure or added -> holds <= 5%.
// The table is printed (the closing note of issue 27 quotes it).
TEST_CASE("verdict power on the thesis designs", "[fit][power][slow]") {
  const int trials = 400;
  int designs = 0, line = 0;
  for (const Design& d : thesis_designs()) {
    FitRules rules;
    rules.min_decades = d.min_decades;
    const double noise = d.timed ? 0.05 : 0.02;
    const auto g = unit(d.x, growth(d.claimed));
    // The lower-order term the fitter allows (x beside x log x; the intercept beside x).
    const Growth below = lower_order_term(d.claimed).value_or(Growth::kConstant);
    const auto l = unit(d.x, growth(below));
    const double xmin = *std::min_element(d.x.begin(), d.x.end());
    const double dip = 0.5 * g(xmin) / l(xmin);  // keeps y >= g / 2
    const auto up = d.claimed == Growth::kCubic
                        ? unit(d.x, [](double v, double) { return v * v * v * v; })
                        : unit(d.x, growth(next_growth(d.claimed)));
    const auto between = unit(d.x, [m = d.claimed](double v, double x0) {
      return pure_growth(m, v, x0) * std::pow(v, 0.25);
    });
    const std::vector<std::pair<std::string, std::function<double(double)>>> truths = {
        {"true", g},
        {"true+1", [&](double v) { return 1 + g(v); }},
        {"true+lower", [&](double v) { return g(v) + l(v); }},
        {"true-lower", [&](double v) { return g(v) - dip * l(v); }}};
    double worst_false = 0;
    std::string worst_truth;
    for (const auto& [name, t] : truths) {
      const double r = simulate_verdicts(d.x, t, d.claimed, noise, trials, 11, rules).exceeds;
      if (r >= worst_false) worst_false = r, worst_truth = name;
    }
    const double up_pure = simulate_verdicts(d.x, up, d.claimed, noise, trials, 12, rules).exceeds;
    const double up_added =
        simulate_verdicts(
            d.x, [&](double v) { return g(v) + up(v); }, d.claimed, noise, trials, 13, rules)
            .exceeds;
    const double between_pure =
        simulate_verdicts(d.x, between, d.claimed, noise, trials, 14, rules).holds;
    const double between_added =
        simulate_verdicts(
            d.x, [&](double v) { return g(v) + between(v); }, d.claimed, noise, trials, 15, rules)
            .holds;
    const double true_holds = simulate_verdicts(d.x, g, d.claimed, noise, trials, 16, rules).holds;
    if (line++ == 0)
      std::printf(
          "power | design | claimed | noise | false exceeds (worst of 4) | class up "
          "pure / added | between holds pure / added | true holds\n");
    std::printf("power | %s | %s | %.0f%% | %.3f (%s) | %.3f / %.3f | %.3f / %.3f | %.2f\n",
                d.name.c_str(), growth_name(d.claimed), 100 * noise, worst_false,
                worst_truth.c_str(), up_pure, up_added, between_pure, between_added, true_holds);
    INFO(d.name);
    CHECK(worst_false <= 0.05);
    CHECK(up_pure >= 0.90);
    CHECK(up_added >= 0.90);
    CHECK(between_pure <= 0.05);
    CHECK(between_added <= 0.05);
    ++designs;
  }
  REQUIRE(designs >= 20);
}

TEST_CASE("claimed growth per variable from the thesis's notation", "[fit][claims]") {
  REQUIRE(expected_growth("O(SMB(log N + IK^2))", "K") == Growth::kQuadratic);
  REQUIRE(expected_growth("O(SMB(log N + IK^2))", "N") == Growth::kLog);
  REQUIRE(expected_growth("O(SMB(log(N) + kIK))", "k") == Growth::kLinear);
  REQUIRE(expected_growth("O(MNIK + SBNIK)", "N") == Growth::kLinear);
  REQUIRE(expected_growth("O(N log N)", "N") == Growth::kLinearLog);
  REQUIRE(expected_growth("O(N^2)", "N") == Growth::kQuadratic);
  REQUIRE(expected_growth("O(1)", "N") == Growth::kConstant);
  REQUIRE(expected_growth("O(k)", "k") == Growth::kLinear);
  REQUIRE_THROWS_AS(expected_growth("O(N ++ K)", "N"), InputError);
  REQUIRE_THROWS_AS(expected_growth("O(N)", "Q"), InputError);
}

TEST_CASE("fit input errors", "[fit]") {
  REQUIRE_THROWS_AS(fit_growth({1, 2, 3, 4}, {1, 2, 3, 4}, Growth::kLinear, "four"), InputError);
  REQUIRE_THROWS_AS(fit_growth({1, 1, 2, 2, 2}, {1, 1, 2, 2, 2}, Growth::kLinear, "two x"),
                    InputError);
  // Replicates do not make up for distinct x: four x values are too few to tell classes apart.
  REQUIRE_THROWS_AS(
      fit_growth({1, 2, 3, 4, 1, 2, 3, 4}, {1, 2, 3, 4, 1, 2, 3, 4}, Growth::kLinear, "four x"),
      InputError);
  REQUIRE_THROWS_AS(fit_growth({1, 2, 3, 4, 5}, {1, 0, 3, 4, 5}, Growth::kLinear, "zero"),
                    InputError);
  REQUIRE_THROWS_AS(fit_growth({1, 2, 3, 4, 5}, {1, NAN, 3, 4, 5}, Growth::kLinear, "nan"),
                    InputError);
}

// The cases the earlier rule got wrong (issue 27), on the thesis's build design (N 2500-640000,
// 3 replicates, 2%) and query design (N 1000-512000): what each is called now.
TEST_CASE("verdicts on the departures the earlier rule missed", "[fit][power]") {
  auto design = [](double lo, double hi, int n) {
    std::vector<double> x;
    for (int i = 0; i < n; ++i)
      for (int r = 0; r < 3; ++r)
        x.push_back(std::round(lo * std::pow(hi / lo, i / double(n - 1))));
    return x;
  };
  const std::vector<double> build = design(2500, 640000, 9), query = design(1000, 512000, 10);
  FitRules rules;
  rules.min_decades = 2;
  auto rate = [&](const std::vector<double>& x, std::function<double(double)> truth, Growth g) {
    return simulate_verdicts(x, truth, g, 0.02, 200, 21, rules);
  };
  const auto nlogn = [](double n) { return n * std::log(n); };
  // N^1.25 and N^1.5 against N log N: never holds; N^1.5 exceeds.
  CHECK(rate(
            build, [](double n) { return std::pow(n, 1.25); }, Growth::kLinearLog)
            .holds <= 0.05);
  CHECK(rate(
            build, [](double n) { return std::pow(n, 1.5); }, Growth::kLinearLog)
            .exceeds >= 0.9);
  // The true build plus an N^2 or N^1.5 term that doubles y at the largest N.
  const double top = 640000;
  CHECK(rate(
            build, [&](double n) { return nlogn(n) + nlogn(top) * n * n / (top * top); },
            Growth::kLinearLog)
            .exceeds >= 0.9);
  CHECK(rate(
            build, [&](double n) { return nlogn(n) + nlogn(top) * std::pow(n / top, 1.5); },
            Growth::kLinearLog)
            .holds <= 0.05);
  // N^0.25 against a claimed log N: never holds.
  CHECK(rate(
            query, [](double n) { return std::pow(n, 0.25); }, Growth::kLog)
            .holds <= 0.05);
  // A true N log N with a large linear term, N (ln N + 30): never exceeds.
  CHECK(rate(
            build, [](double n) { return n * (std::log(n) + 30); }, Growth::kLinearLog)
            .exceeds <= 0.05);
}
