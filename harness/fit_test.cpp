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

// The power requirement of the verdicts (issue 12), on the designs configs/thesis.json uses, at
// the noise its op counts show (up to 4% relative; `noise` in fits.json): (a) with the claim
// exactly true, `exceeds` at most 5% of the time; (b) a violation one class up detected at least
// 90% of the time. 1000 seeded data sets per case, through the same fit_growth as `pcrt fit`.
TEST_CASE("verdict power on the thesis designs: false exceeds <= 5%, one class up >= 90%",
          "[fit][power]") {
  auto geometric = [](double lo, double hi, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(lo * std::pow(hi / lo, double(i) / (n - 1)));
    return v;
  };
  struct Design {
    const char* name;
    std::vector<double> x;
    Growth claimed;
  };
  const std::vector<Design> designs = {
      {"frame/query in N (sphere)", geometric(1000, 128000, 8), Growth::kLog},
      {"frame in N (scan)", geometric(1563, 100000, 7), Growth::kLog},
      {"build in N", geometric(5000, 320000, 7), Growth::kLinearLog},
      {"grid build in N", geometric(2500, 640000, 9), Growth::kLinear},
      {"leaf in K", geometric(4, 64, 7), Growth::kLinear},
      {"frame in M", geometric(256, 16384, 7), Growth::kLinear},
      {"Delaunay in N", geometric(2000, 128000, 7), Growth::kLinearLog},
      {"Delaunay worst in N", geometric(100, 3200, 11), Growth::kQuadratic},
  };
  const double noise = 0.04;
  for (const Design& d : designs) {
    const VerdictRates a = simulate_verdicts(d.x, d.claimed, d.claimed, noise, 0, 1000, 1);
    const VerdictRates b =
        simulate_verdicts(d.x, next_growth(d.claimed), d.claimed, noise, 0, 1000, 2);
    INFO(d.name << ": claimed " << growth_name(d.claimed) << ", false exceeds " << a.exceeds
                << ", one class up (" << growth_name(next_growth(d.claimed)) << ") detected "
                << b.exceeds);
    CHECK(a.exceeds <= 0.05);
    CHECK(b.exceeds >= 0.90);
  }
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
