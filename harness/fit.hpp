// Growth fits and verdicts (docs/verdicts.md). The thesis's O() are upper bounds on the worst
// case (Def. 5.1), so a verdict on O(g) in x asks how much of the measured y could come from
// growth faster than g. Relative errors throughout (weights 1/y^2): small and large x count alike.
//
// The claimed model is a + b g(x) (plus the class below g when the replicates show the pure form
// misfits: lower-order terms are inside O(g)). Against it stand two explicit faster terms c h(x),
// one class up (h = the next class), between classes (h = g x^0.25) and two classes up. For each,
// the share of y at x_max that c h carries, with one-sided bounds from the fit's covariance:
//   exceeds       a faster term's share is above 0 at 99% (with and without the claim's
//                 lower-order term), and the log-log exponent's CI lies above the claimed
//                 model's own exponent over this x (a second, independent witness);
//   holds         every faster term's 95% upper bound is under the tolerance (25%), the claimed
//                 model fits its replicates, x spans the variable's minimum range;
//   inconclusive  otherwise, naming the faster term it could not exclude and how much of y it
//                 could carry.
// A verdict that changes when the points at any one x are left out (with 6 or more distinct x) is
// inconclusive. Whether the
// bound is also tight is a secondary statement with the same machinery one class down.
// Model selection by AICc among {1, log x, x^0.5, x, x log x, x^2, x^3} stays for the report (the
// best model; a slower best joins the claimed model); no verdict rests on it alone. Google
// Benchmark's BigO has no intercept and no penalty.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "harness/claims.hpp"

namespace pcrt {

enum class ClaimVerdict {
  kHolds,         // growth: faster growth carries at most the tolerance of y at x_max
  kExceeds,       // growth: a faster term is significantly present
  kInconclusive,  // growth: the data can neither exclude nor establish a faster term
  kMeets,         // threshold claim met by every run
  kMisses,        // threshold claim missed by a run
  kLoopCheck,  // y / x constant by construction (or within 10% over 30x): the loops, not the claim
  kDrifted,    // a variable that should be fixed moved, and the claim cannot absorb it
  kNotJudged,  // the input does not meet the claim's stated precondition
  kError,      // a missing measure, too few distinct points, no runs, an unknown claim
};
inline constexpr ClaimVerdict kAllVerdicts[] = {
    ClaimVerdict::kHolds,   ClaimVerdict::kExceeds,   ClaimVerdict::kInconclusive,
    ClaimVerdict::kMeets,   ClaimVerdict::kMisses,    ClaimVerdict::kLoopCheck,
    ClaimVerdict::kDrifted, ClaimVerdict::kNotJudged, ClaimVerdict::kError};
const char* verdict_name(ClaimVerdict v);  // "holds", "exceeds", ...
// Growth verdicts and threshold verdicts are tallied apart; the rest are not tallied as verdicts.
enum class VerdictKind { kGrowth, kThreshold, kNotJudged };
VerdictKind verdict_kind(ClaimVerdict v);

// Whether the data also exclude the class below the claim (only asked of a bound that holds).
enum class Tightness { kNotTested, kTight, kLoose, kUndetermined };
const char* tightness_name(Tightness t);  // "not tested", "tight", "loose", "undetermined"

inline constexpr size_t kModels = std::size(kAllGrowths);
// The most of y at x_max a faster term may carry for a bound to hold.
inline constexpr double kHoldsTolerance = 0.25;

// The claimed model plus c h(x): how much of y at x_max the faster term h carries.
struct FasterTerm {
  std::string model;                        // h, e.g. "x^2" or "x log x * x^0.25"
  double share = 0;                         // c h(x_max) / y(x_max), fitted
  double low95 = 0, high95 = 0, low99 = 0;  // one-sided bounds of the share
};

// The design rules a fit is held to, and what it may adjust for.
struct FitRules {
  double min_decades = 0;    // x_max / x_min must reach 10^this for holds or exceeds
  std::string range_waiver;  // why a shorter range is all there is (waives the rule; shown)
  // A measured variable the claim adds linearly (K in log N + K), one value per point: fitted
  // as a term of its own, so that the claim in x is judged at fixed covariate.
  std::vector<double> covariate;
  std::string covariate_name;
  bool leave_one_out = true;
};

struct GrowthFit {
  size_t points = 0, distinct_x = 0;
  double decades = 0;                            // log10(x_max / x_min)
  double exponent = 0, ci_low = 0, ci_high = 0;  // log-log slope and its 95% CI
  double claimed_exponent = 0;      // the log-log slope of the pure claimed model over the same x
  Growth best = Growth::kConstant;  // the lowest-AICc model (the constant when within 2)
  double r2 = 0;                    // of `best` (weighted, relative residuals)
  double noise = 0;                 // relative residual sd of the claimed model
  std::array<double, kModels> aicc{};    // per model, kAllGrowths order; +inf where not fitted
  std::array<double, kModels> weight{};  // Akaike weights
  double weight_faster = 0;  // pairwise: best faster model vs best at or below the claim
  // The explicit faster terms, and the largest 95% upper bound of their shares: how much of y
  // at x_max a holds could be hiding.
  std::vector<FasterTerm> faster;
  double hidden = 0;
  // The extra term the claimed model carries: a slower class the data prefer, or the lower-order
  // term the replicates ask for.
  std::optional<Growth> lower;
  // Lack of fit of the claimed model against the replicates' pure error (F test at 1%).
  bool lof_tested = false, lack_of_fit = false;
  double lof_f = 0, lof_critical = 0, pure_noise = 0;
  Tightness tightness = Tightness::kNotTested;
  FasterTerm claimed_term;  // the share of the claimed class over the class below (tightness)
  std::string flip;         // the leave-one-out change that made the verdict inconclusive
  ClaimVerdict verdict = ClaimVerdict::kError;
  std::string reason;  // why, in words, with the numbers
};

// Needs at least 5 distinct x > 0 and every y > 0, finite (InputError naming `what` otherwise).
// Points at equal x are replicates.
GrowthFit fit_growth(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                     const std::string& what, const FitRules& rules = {});

// The model one class above `g` (log x -> x^0.5 -> x -> x log x -> x^2 -> x^3; x^3 stays).
Growth next_growth(Growth g);
// The lower-order term O(m) is allowed beside its intercept when the replicates ask for one: x
// beside x log x and x^2, x^2 beside x^3; none beside x, x^0.5, log x and 1.
std::optional<Growth> lower_order_term(Growth m);
// The smallest range of x, in decades, a growth verdict in `variable` rests on: 2 in N and M, 1 in
// K, k, S, B and I.
double min_decades(const std::string& variable);
// A class's pure form over a design whose smallest x is `xmin`, positive everywhere.
double pure_growth(Growth m, double x, double xmin);

struct VerdictRates {
  double exceeds = 0, holds = 0, inconclusive = 0;
};
// Verdict frequencies over `trials` synthetic data sets at the design `x` (replicates repeat x):
// y = truth(x) times exp(N(0, noise)), judged against `claimed` under `rules`.
VerdictRates simulate_verdicts(const std::vector<double>& x,
                               const std::function<double(double)>& truth, Growth claimed,
                               double noise, int trials, uint64_t seed, const FitRules& rules = {});

}  // namespace pcrt
