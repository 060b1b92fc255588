// Growth fits (DESIGN.md, "Measuring"): the log-log OLS exponent with a 95% confidence interval,
// and model selection with intercept among {1, log x, x^0.5, x, x log x, x^2, x^3} by AICc, on
// relative errors (weights 1/y^2, so that small and large x count alike).
//
// The thesis's O() are upper bounds on the worst case (Def. 5.1), so a verdict says where the
// measured growth lies against the bound. Two witnesses can speak against a claim: w, the Akaike
// weight of the best model growing faster than the claim, taken pairwise against the best model
// at or below it, reaches 0.95; and the log-log exponent's CI lies above the exponent the claimed
// model itself shows over the same x (slack 0.02 for lower-order terms; for claims stated as
// exact powers, the exponent of y minus the fitted constant against the power).
//   exceeds       both witnesses speak: the claim fails;
//   inconclusive  w >= 0.95 without the exponent (a late upturn of a flat series), or
//                 0.5 < w < 0.95 (a faster model fits better, not decisively), or an exact power
//                 whose growth term's exponent CI lies above it;
//   below         a slower model is decisively preferred to the claimed one: the bound holds,
//                 loose on this input;
//   within        otherwise: the bound holds and is tight as far as the data can tell (fit_runs
//                 further requires the design to catch a violation one class up at least 90%
//                 of the time at the fit's own noise, else it says inconclusive).
// Pairwise, because summing over all faster models would count one extra coefficient several
// times. The rule keeps false `exceeds` at or under 5% when the claim is exactly true and detects
// a violation one class up at least 90% of the time at the noise our op counts show: checked by
// simulation (fit_test.cpp, and per fit in `power_one_up` / `false_exceeds`).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/claims.hpp"

namespace pcrt {

enum class ClaimVerdict {
  kWithin,        // growth: the bound holds and is tight
  kBelow,         // growth: the bound holds, loose on this input
  kExceeds,       // growth: the claim fails
  kInconclusive,  // growth: the data cannot separate the claimed model from a neighbour
  kMeets,         // threshold claim met by every run
  kMisses,        // threshold claim missed by a run
  kIdentity,      // y / x is constant by construction: a loop-structure check, not a test
  kDrifted,       // a variable that should be fixed moved by more than 20%: not judged
  kError,         // too few distinct points, no runs, an unknown claim
};
inline constexpr ClaimVerdict kAllVerdicts[] = {
    ClaimVerdict::kWithin,       ClaimVerdict::kBelow,   ClaimVerdict::kExceeds,
    ClaimVerdict::kInconclusive, ClaimVerdict::kMeets,   ClaimVerdict::kMisses,
    ClaimVerdict::kIdentity,     ClaimVerdict::kDrifted, ClaimVerdict::kError};
const char* verdict_name(ClaimVerdict v);  // "within", "below", ...
// Growth verdicts and threshold verdicts are tallied apart; the rest are not tallied at all.
enum class VerdictKind { kGrowth, kThreshold, kNotJudged };
VerdictKind verdict_kind(ClaimVerdict v);

inline constexpr size_t kModels = std::size(kAllGrowths);

struct GrowthFit {
  size_t points = 0;
  double exponent = 0, ci_low = 0, ci_high = 0;  // log-log slope and its 95% CI
  // The smallest change of the log-log exponent this design detects with 90% power at the 5%
  // level (two-sided t test on the slope): what "no departure" can mean here.
  double detectable_exponent = 0;
  // The 95% CI of the exponent of y minus the claimed model's constant (its growth term).
  double power_ci_low = 0, power_ci_high = 0;
  double claimed_exponent = 0;      // the log-log slope of the pure claimed model over the same x
  Growth best = Growth::kConstant;  // the lowest-AICc model (the constant when within 2)
  double r2 = 0;                    // of `best` (weighted, relative residuals)
  double noise = 0;                 // relative residual sd of `best`
  std::array<double, kModels> aicc{};    // per model, kAllGrowths order; +inf where not fitted
  std::array<double, kModels> weight{};  // Akaike weights
  std::array<double, kModels> slope{};   // b of y = a + b g(x), g scaled to 1 at the largest x
  double weight_faster = 0;        // pairwise: best faster model vs best at or below the claim
  double weight_slower = 0;        // pairwise: best slower model vs the claimed one
  double delta_aicc_expected = 0;  // AICc(claimed) - AICc(best)
  ClaimVerdict verdict = ClaimVerdict::kError;
  std::string reason;  // why, in words (which neighbour keeps weight, which CI ...)
};

// Needs at least 5 points with 5 distinct x > 0, and every y > 0 (InputError naming `what`
// otherwise).
GrowthFit fit_growth(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                     const std::string& what);

// The model one class above `g` (log x -> x^0.5 -> x -> x log x -> x^2 -> x^3; x^3 stays).
Growth next_growth(Growth g);

struct VerdictRates {
  double exceeds = 0, within = 0, below = 0, inconclusive = 0;
};
// Verdict frequencies over `trials` synthetic data sets at the design `x`: y = g_truth(x) (scaled
// to 1 at the largest x) plus `intercept`, times exp(N(0, noise)), judged against `claimed`.
VerdictRates simulate_verdicts(const std::vector<double>& x, Growth truth, Growth claimed,
                               double noise, double intercept, int trials, uint64_t seed);

}  // namespace pcrt
