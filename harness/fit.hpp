// Growth fits (DESIGN.md, "Measuring"): the log-log OLS exponent with a 95% confidence interval,
// and model selection with intercept among {1, log x, x, x log x, x^2, x^3} by AICc, on relative
// errors (weights 1/y^2, so that small and large x count alike). The verdict compares the best
// model with the claimed one: consistent when the claimed model is within 2 AICc of the best
// (substantial support), else faster or slower by the models' order of growth.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "harness/claims.hpp"

namespace pcrt {

struct GrowthFit {
  size_t points = 0;
  double exponent = 0, ci_low = 0, ci_high = 0;  // log-log slope and its 95% CI
  Growth best = Growth::kConstant;
  double r2 = 0;                   // of the best model (weighted)
  std::array<double, 6> aicc{};    // per model, in kAllGrowths order; +inf where not fitted
  std::array<double, 6> slope{};   // b of y = a + b g(x), g scaled to 1 at the largest x
  std::string verdict;             // "consistent", "faster" or "slower"
  double delta_aicc_expected = 0;  // AICc(claimed) - AICc(best)
};

// Needs at least 5 points with 3 distinct x > 0, and every y > 0 (InputError naming `what`
// otherwise).
GrowthFit fit_growth(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                     const std::string& what);

}  // namespace pcrt
