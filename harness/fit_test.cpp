// The fitter on exact and noisy synthetic growth (no timing here: the timed and counted
// calibration workloads run through `pcrt calibrate`).
#include "harness/fit.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.hpp"
#include "core/rng.hpp"

using namespace pcrt;

namespace {
double model(Growth m, double x) {
  switch (m) {
    case Growth::kConstant:
      return 5;
    case Growth::kLog:
      return 5 + 3 * std::log(x);
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
      REQUIRE(f.verdict == "consistent");
    }
  }
}

TEST_CASE("verdicts: faster and slower than claimed", "[fit]") {
  std::vector<double> x, y;
  for (int e = 6; e <= 16; ++e)
    x.push_back(std::pow(2.0, e)), y.push_back(model(Growth::kQuadratic, x.back()));
  REQUIRE(fit_growth(x, y, Growth::kLinear, "q").verdict == "faster");
  REQUIRE(fit_growth(x, y, Growth::kCubic, "q").verdict == "slower");
  const GrowthFit f = fit_growth(x, y, Growth::kQuadratic, "q");
  REQUIRE(f.exponent == Approx(2.0).margin(0.05));
  REQUIRE(f.ci_low <= 2.0);
  REQUIRE(f.ci_high >= 1.9);
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
  REQUIRE_THROWS_AS(fit_growth({1, 2, 3, 4, 5}, {1, 0, 3, 4, 5}, Growth::kLinear, "zero"),
                    InputError);
}
