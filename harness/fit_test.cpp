// The fitter on exact and noisy synthetic growth (no timing here: the timed and counted
// calibration workloads run through `pcrt calibrate`).
#include "harness/fit.hpp"

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
}  // namespace

TEST_CASE("fit_growth picks the generating model and its exponent", "[fit]") {
  Rng rng(11, 2);
  for (Growth truth : kAllGrowths) {
    for (double noise : {0.0, 0.02}) {
      std::vector<double> x, y;
      for (int e = 6; e <= 18; ++e)
        for (int rep = 0; rep < 3; ++rep) {
          x.push_back(std::pow(2.0, e));
          y.push_back(model(truth, x.back()) * (1 + noise * (2 * rng.uniform_double() - 1)));
        }
      const GrowthFit f = fit_growth(x, y, truth, "synthetic");
      INFO(growth_name(truth) << " noise " << noise << " -> " << growth_name(f.best));
      REQUIRE(f.best == truth);
      REQUIRE(f.verdict == ClaimVerdict::kWithin);
    }
  }
}

TEST_CASE("verdicts against an upper bound: exceeds, below, within", "[fit]") {
  std::vector<double> x, y;
  for (int e = 6; e <= 16; ++e)
    x.push_back(std::pow(2.0, e)), y.push_back(model(Growth::kQuadratic, x.back()));
  REQUIRE(fit_growth(x, y, Growth::kLinear, "q").verdict == ClaimVerdict::kExceeds);
  REQUIRE(fit_growth(x, y, Growth::kCubic, "q").verdict == ClaimVerdict::kBelow);
  REQUIRE(fit_growth(x, y, Growth::kLinear, "q").weight_faster >= 0.95);
  const GrowthFit f = fit_growth(x, y, Growth::kQuadratic, "q");
  REQUIRE(f.verdict == ClaimVerdict::kWithin);
  REQUIRE(f.exponent == Approx(2.0).margin(0.05));
  REQUIRE(f.ci_low <= 2.0);
  REQUIRE(f.ci_high >= 1.9);
  REQUIRE(!f.reason.empty());
}

TEST_CASE("verdicts: a neighbour the data cannot rule out is inconclusive", "[fit]") {
  // Five points over a factor 4 of x at 10% noise: x and x log x cannot be told apart.
  Rng rng(3, 1);
  int inconclusive = 0;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> x, y;
    for (double v : {1000.0, 1400.0, 2000.0, 2800.0, 4000.0})
      x.push_back(v), y.push_back(v * std::log(v) * (1 + 0.1 * (2 * rng.uniform_double() - 1)));
    inconclusive += fit_growth(x, y, Growth::kLinear, "x").verdict == ClaimVerdict::kInconclusive;
  }
  REQUIRE(inconclusive >= 25);
}

// The power requirement of the verdicts (issue 12), on every growth design configs/thesis.json
// sweeps (its grid values of the fit's variable), at the noise its op counts show (up to 4%
// relative; `noise` in fits.json): (a) with the claim exactly true, `exceeds` at most 5% of the
// time; (b) a violation one class up detected at least 90% of the time. 1000 seeded data sets per
// design, through the same fit_growth as `pcrt fit`.
TEST_CASE("verdict power on the thesis designs: false exceeds <= 5%, one class up >= 90%",
          "[fit][power]") {
  std::ifstream in(pcrt::test::source_dir() / "configs/thesis.json");
  REQUIRE(in);
  const nlohmann::json config = nlohmann::json::parse(in);
  int designs = 0;
  for (const auto& e : config["experiments"]) {
    for (const auto& fit : e.value("fits", nlohmann::json::array())) {
      if (!fit.contains("variable") || fit.contains("x")) continue;  // thresholds; measured x
      const std::string var = fit["variable"];
      const std::string key = var == "K" || var == "k" ? "set." + var : var;
      if (!e["grid"].contains(key)) continue;  // x measured (points per leaf): no design
      std::string claim = fit["claim"];
      auto fill = [&](const std::string& tag, const std::string& list, const std::string& dflt) {
        const size_t at = claim.find(tag);
        if (at == std::string::npos) return;
        std::string v = e.contains(list) ? std::string(e[list][0]) : dflt;
        if (v == "surveyed") v = dflt;
        claim.replace(at, tag.size(), v);
      };
      fill("{method}", "methods", "hubo_2006");
      fill("{structure}", "structures", "kd_tree");
      const Growth claimed = expected_growth(find_claim(claim).complexity, var);
      const std::vector<double> x = e["grid"][key].get<std::vector<double>>();
      const VerdictRates a = simulate_verdicts(x, claimed, claimed, 0.04, 0, 1000, 1);
      const VerdictRates b = simulate_verdicts(x, next_growth(claimed), claimed, 0.04, 0, 1000, 2);
      INFO(e["name"] << " " << claim << " in " << var << ": claimed " << growth_name(claimed)
                     << ", false exceeds " << a.exceeds << ", one class up ("
                     << growth_name(next_growth(claimed)) << ") detected " << b.exceeds);
      CHECK(a.exceeds <= 0.05);
      if (next_growth(claimed) != claimed) CHECK(b.exceeds >= 0.90);
      ++designs;
    }
  }
  REQUIRE(designs >= 20);
}

TEST_CASE("verdicts with an intercept: a constant term does not make a claim fail",
          "[fit][power]") {
  // y = 1 + log x / log x_max: half the range is fixed overhead.
  std::vector<double> x;
  for (int i = 0; i < 8; ++i) x.push_back(1000 * std::pow(2.0, i));
  const VerdictRates r = simulate_verdicts(x, Growth::kLog, Growth::kLog, 0.04, 1.0, 1000, 3);
  REQUIRE(r.exceeds <= 0.05);
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
  // Repetitions do not make up for distinct x: four x values are too few to tell classes apart.
  REQUIRE_THROWS_AS(
      fit_growth({1, 2, 3, 4, 1, 2, 3, 4}, {1, 2, 3, 4, 1, 2, 3, 4}, Growth::kLinear, "four x"),
      InputError);
  REQUIRE_THROWS_AS(fit_growth({1, 2, 3, 4, 5}, {1, 0, 3, 4, 5}, Growth::kLinear, "zero"),
                    InputError);
}
