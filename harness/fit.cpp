#include "harness/fit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "core/error.hpp"
#include "core/rng.hpp"

namespace pcrt {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Lower-order terms move a finite range's exponent by a few hundredths ((N/2 - 1)^2 Delaunay
// cells give 2.004 over 50..800; a + b S with a < 0 gives 1.01): a CI within this of the claimed
// exponent is taken to reach it.
constexpr double kExponentSlack = 0.02;
// The between-class alternative: the claimed growth times x^this.
constexpr double kBetweenPower = 0.25;
// A linear claim whose y / x moves by less than this over at least kLoopRange of x counts its
// own loop (work per sample in S): a check of the loops, not a test.
constexpr double kLoopFlatness = 0.10;
constexpr double kLoopRange = 30;

double g(Growth m, double x) {
  switch (m) {
    case Growth::kConstant:
      return 0;
    case Growth::kLog:
      return std::log(x);
    case Growth::kSqrt:
      return std::sqrt(x);
    case Growth::kLinear:
      return x;
    case Growth::kLinearLog:
      return x * std::log(x);
    case Growth::kQuadratic:
      return x * x;
    case Growth::kCubic:
      return x * x * x;
  }
  return 0;
}

int rank(Growth m) {
  for (size_t i = 0; i < kModels; ++i)
    if (kAllGrowths[i] == m) return int(i);
  return 0;
}

// Student t quantile (p = 0.975 is the two-sided 95% one) for `dof` degrees of freedom.
double t_quantile(double p, size_t dof) {
  if (dof == 0) return kInf;
  return boost::math::quantile(boost::math::students_t(double(dof)), p);
}

void check_input(const std::vector<double>& x, const std::vector<double>& y, const FitRules& rules,
                 const std::string& what) {
  if (x.size() != y.size()) input_error("{}: x and y differ in length", what);
  for (size_t i = 0; i < x.size(); ++i)
    if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      input_error("{}: x and y must be positive and finite (x = {}, y = {})", what, x[i], y[i]);
  if (!rules.covariate.empty() && rules.covariate.size() != x.size())
    input_error("{}: the covariate {} has {} values for {} points", what, rules.covariate_name,
                rules.covariate.size(), x.size());
  for (double c : rules.covariate)
    if (!std::isfinite(c))
      input_error("{}: the covariate {} is not finite", what, rules.covariate_name);
  // Three coefficients and a variance need n > 4; fewer distinct x than 5 cannot tell a growth
  // class from its neighbour however many replicates there are.
  const std::set<double> distinct(x.begin(), x.end());
  if (distinct.size() < 5)
    input_error("{}: needs at least 5 distinct x values for a growth fit, got {}", what,
                distinct.size());
}

// ---- The log-log exponent ----

struct Slope {
  double exponent = 0, low = 0, high = 0;
};

Slope loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) mx += std::log(x[i]), my += std::log(y[i]);
  mx /= double(n), my /= double(n);
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
  }
  Slope s;
  s.exponent = sxy / sxx;
  double rss = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r = std::log(y[i]) - my - s.exponent * (std::log(x[i]) - mx);
    rss += r * r;
  }
  const double half = t_quantile(0.975, n - 2) * std::sqrt(rss / double(n - 2) / sxx);
  s.low = s.exponent - half, s.high = s.exponent + half;
  return s;
}

}  // namespace

double pure_growth(Growth m, double x, double xmin) {
  // Where log x would fall under 1 (x_min < e), its argument is rescaled so that it starts at 1:
  // the same class without a constant term.
  const double lift = std::max(0.0, 1 - std::log(xmin));
  switch (m) {
    case Growth::kConstant:
      return 1;
    case Growth::kLog:
      return std::log(x) + lift;
    case Growth::kLinearLog:
      return x * (std::log(x) + lift);
    default:
      return g(m, x);
  }
}

namespace {

// The log-log slope the pure model shows over the design x.
double model_exponent(Growth m, const std::vector<double>& x) {
  if (m == Growth::kConstant) return 0;
  const double xmin = *std::min_element(x.begin(), x.end());
  std::vector<double> y;
  for (double v : x) y.push_back(pure_growth(m, v, xmin));
  return loglog_slope(x, y).exponent;
}

// ---- Weighted least squares on relative errors ----

struct Lsq {
  Eigen::VectorXd coef;
  Eigen::MatrixXd cov;  // of the coefficients
  double rss = 0;
  size_t dof = 0;
  bool ok = false;
};

// y ~ sum_j c_j columns[j], every row divided by y (relative residuals).
Lsq relative_lsq(const std::vector<std::vector<double>>& columns, const std::vector<double>& y) {
  const Eigen::Index n = Eigen::Index(y.size()), p = Eigen::Index(columns.size());
  Lsq r;
  if (n <= p + 1) return r;
  Eigen::MatrixXd a(n, p);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < p; ++j) a(i, j) = columns[size_t(j)][size_t(i)] / y[size_t(i)];
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  const auto qr = a.colPivHouseholderQr();
  if (qr.rank() < p) return r;
  r.coef = qr.solve(b);
  r.rss = std::max((a * r.coef - b).squaredNorm(), 1e-300);
  r.dof = size_t(n - p);
  // Exact data (deterministic counts that the model describes exactly) leave rounding as the
  // residual: the variance is floored at a relative residual of 1e-9, so that no sign of a
  // coefficient comes from rounding alone.
  const double variance = std::max(r.rss / double(r.dof), 1e-18);
  r.cov = (a.transpose() * a).ldlt().solve(Eigen::MatrixXd::Identity(p, p)) * variance;
  r.ok = r.coef.allFinite() && r.cov.allFinite() && (r.cov.diagonal().array() >= 0).all();
  return r;
}

double aicc(double rss, size_t n, int coefficients) {
  const double params = double(coefficients + 1);  // and the variance
  return double(n) * std::log(rss / double(n)) + 2 * params +
         2 * params * (params + 1) / (double(n) - params - 1);
}

// ---- Model selection (the report's best model; a slower best joins the claimed model) ----

std::vector<double> growth_column(Growth m, const std::vector<double>& x) {
  const double xmin = *std::min_element(x.begin(), x.end());
  const double xmax = *std::max_element(x.begin(), x.end());
  std::vector<double> c;
  for (double v : x) c.push_back(pure_growth(m, v, xmin) / pure_growth(m, xmax, xmin));
  return c;
}

void select_models(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                   GrowthFit& f) {
  const std::vector<double> ones(x.size(), 1.0);
  double best = kInf;
  std::array<double, kModels> rss{};
  for (size_t m = 0; m < kModels; ++m) {
    const bool constant = kAllGrowths[m] == Growth::kConstant;
    const Lsq fit = constant ? relative_lsq({ones}, y)
                             : relative_lsq({ones, growth_column(kAllGrowths[m], x)}, y);
    // A shrinking fit is no growth model.
    const bool valid = fit.ok && (constant || fit.coef[1] > 0);
    f.aicc[m] = valid ? aicc(fit.rss, x.size(), constant ? 1 : 2) : kInf;
    rss[m] = fit.rss;
    if (f.aicc[m] < best) best = f.aicc[m], f.best = kAllGrowths[m];
  }
  // The constant (one coefficient fewer) is named best when within 2 AICc of the best.
  if (f.aicc[0] - best <= 2.0) f.best = Growth::kConstant;
  double total = 0;
  for (size_t m = 0; m < kModels; ++m) total += f.weight[m] = std::exp(-0.5 * (f.aicc[m] - best));
  for (double& w : f.weight) w /= total;
  // Against the weighted least-squares constant (the constant model's residuals).
  f.r2 = rss[0] > 0 ? 1.0 - rss[size_t(rank(f.best))] / rss[0] : 1.0;
  // Pairwise: the best faster model against the best at or below the claim (summing over every
  // faster model would count one extra coefficient several times).
  const int c = rank(expected);
  double hold = kInf, fast = kInf;
  for (int m = 0; m < int(kModels); ++m) {
    double& group = m <= c ? hold : fast;
    group = std::min(group, f.aicc[size_t(m)]);
  }
  if (!std::isfinite(fast))
    f.weight_faster = 0;
  else if (!std::isfinite(hold))
    f.weight_faster = 1;
  else
    f.weight_faster = 1.0 / (1.0 + std::exp(std::min(50.0, 0.5 * (fast - hold))));
}

// ---- The claimed model, its replicates, and the explicit faster terms ----

// One term of a linear model, normalised to 1 at x_max.
struct Term {
  std::string name;
  std::vector<double> column;
};

Term power_term(const std::string& name, const std::vector<double>& x,
                const std::function<double(double)>& h) {
  const double xmax = *std::max_element(x.begin(), x.end());
  Term t{name, {}};
  for (double v : x) t.column.push_back(h(v) / h(xmax));
  return t;
}

// The class `steps` above `m`, as a term: beyond x^3 the powers x^4, x^5.
Term class_up(Growth m, int steps, const std::vector<double>& x) {
  const double xmin = *std::min_element(x.begin(), x.end());
  const int r = rank(m) + steps;
  if (r < int(kModels)) {
    const Growth h = kAllGrowths[r];
    return power_term(growth_name(h), x, [=](double v) { return pure_growth(h, v, xmin); });
  }
  const double power = 3 + (r - int(kModels) + 1);
  return power_term(fmt::format("x^{}", power), x, [=](double v) { return std::pow(v, power); });
}

// The faster terms a claim of class `m` is tested against: the next class, m x^0.25 between
// classes, and two classes up (a violation far beyond the next class would otherwise inflate
// the residuals of every fit that cannot follow it, and hide).
std::vector<Term> faster_terms(Growth m, const std::vector<double>& x) {
  const double xmin = *std::min_element(x.begin(), x.end());
  const std::string between = m == Growth::kConstant
                                  ? fmt::format("x^{}", kBetweenPower)
                                  : fmt::format("{} * x^{}", growth_name(m), kBetweenPower);
  return {
      class_up(m, 1, x),
      power_term(between, x,
                 [=](double v) { return pure_growth(m, v, xmin) * std::pow(v, kBetweenPower); }),
      class_up(m, 2, x)};
}

// The data of one fit.
struct Data {
  std::vector<double> x, y, covariate;
  std::string covariate_name;
  double xmin = 0, xmax = 0;
};

// The data of a fit. A covariate that moves by under 1% is no term of its own: it would be
// collinear with the intercept.
Data make_data(std::vector<double> x, std::vector<double> y, std::vector<double> covariate,
               std::string covariate_name) {
  Data d{std::move(x), std::move(y), std::move(covariate), std::move(covariate_name)};
  d.xmin = *std::min_element(d.x.begin(), d.x.end());
  d.xmax = *std::max_element(d.x.begin(), d.x.end());
  if (!d.covariate.empty()) {
    const auto [lo, hi] = std::minmax_element(d.covariate.begin(), d.covariate.end());
    if (!(*hi > *lo * 1.01)) d.covariate.clear();
  }
  return d;
}

// The lower-order term O(g) allows beside its intercept: x beside x log x and x^2, x^2 beside
// x^3; none beside x, x^0.5, log x and 1 (their intercept is their lower-order term).
std::optional<Growth> lower_order(Growth m) {
  switch (m) {
    case Growth::kLinearLog:
    case Growth::kQuadratic:
      return Growth::kLinear;
    case Growth::kCubic:
      return Growth::kQuadratic;
    default:
      return std::nullopt;
  }
}

// The class just below `m` in kAllGrowths (what tightness asks the data to exclude); none below
// log x, whose class below is the intercept itself.
std::optional<Growth> class_below(Growth m) {
  return rank(m) >= 2 ? std::optional<Growth>(kAllGrowths[rank(m) - 1]) : std::nullopt;
}

// The claimed model's terms: 1, an extra lower term (when given), g, and the covariate.
std::vector<Term> claimed_terms(const Data& d, Growth m, std::optional<Growth> lower) {
  std::vector<Term> t = {{"1", std::vector<double>(d.x.size(), 1.0)}};
  if (lower) t.push_back({growth_name(*lower), growth_column(*lower, d.x)});
  if (m != Growth::kConstant) t.push_back({growth_name(m), growth_column(m, d.x)});
  if (!d.covariate.empty()) {
    const double top = *std::max_element(d.covariate.begin(), d.covariate.end());
    Term c{d.covariate_name, {}};
    for (double v : d.covariate) c.column.push_back(top > 0 ? v / top : v);
    t.push_back(c);
  }
  return t;
}

Lsq fit_terms(const std::vector<Term>& terms, const std::vector<double>& y) {
  std::vector<std::vector<double>> cols;
  for (const Term& t : terms) cols.push_back(t.column);
  return relative_lsq(cols, y);
}

// The share of y at x_max that term `j` of `terms` carries, s = c_j / yhat(x_max), with its
// one-sided bounds; its variance by the delta method, the uncertainty of yhat included.
FasterTerm share_of(const Data& d, const std::vector<Term>& terms, size_t j) {
  const Lsq fit = fit_terms(terms, d.y);
  FasterTerm s{terms[j].name};
  s.low95 = s.low99 = -kInf, s.high95 = kInf;  // unidentifiable unless shown otherwise
  if (!fit.ok) return s;                       // collinear: the data cannot tell this term apart
  // The columns' mean value over the points at x_max (a covariate differs between replicates).
  Eigen::VectorXd v = Eigen::VectorXd::Zero(Eigen::Index(terms.size()));
  int at = 0;
  for (size_t i = 0; i < d.x.size(); ++i) {
    if (d.x[i] != d.xmax) continue;
    for (size_t k = 0; k < terms.size(); ++k) v[Eigen::Index(k)] += terms[k].column[i];
    ++at;
  }
  v /= double(at);
  const double top = v.dot(fit.coef);
  const Eigen::Index jj = Eigen::Index(j);
  s.share = fit.coef[jj] / top;
  const double var = (fit.cov(jj, jj) - 2 * s.share * (fit.cov.row(jj) * v)(0) +
                      s.share * s.share * v.dot(fit.cov * v)) /
                     (top * top);
  if (!(top > 0) || !std::isfinite(s.share) || !(var >= 0)) {
    s.share = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  const double se = std::sqrt(var);
  s.low95 = s.share - t_quantile(0.95, fit.dof) * se;
  s.high95 = s.share + t_quantile(0.95, fit.dof) * se;
  s.low99 = s.share - t_quantile(0.99, fit.dof) * se;
  return s;
}

// Lack of fit of `terms` against the pure error of the replicates (points at equal x), on the
// relative scale. Not tested without replicates that differ.
void lack_of_fit(const Data& d, const std::vector<Term>& terms, GrowthFit& f) {
  std::map<double, std::vector<double>> groups;
  for (size_t i = 0; i < d.x.size(); ++i) groups[d.x[i]].push_back(d.y[i]);
  // On the fit's own scale: each group's weighted least-squares constant c = sum(1/y) /
  // sum(1/y^2), and the relative residuals c / y - 1 about it.
  double pure = 0;
  for (const auto& [x, ys] : groups) {
    double inv = 0, inv2 = 0;
    for (double y : ys) inv += 1 / y, inv2 += 1 / (y * y);
    for (double y : ys) pure += std::pow(inv / inv2 / y - 1, 2);
  }
  const size_t df_pure = d.x.size() - groups.size();
  const Lsq fit = fit_terms(terms, d.y);
  f.lof_tested = false, f.lack_of_fit = false;
  // A covariate differs between replicates, so it would explain part of their scatter.
  if (!d.covariate.empty()) return;
  // Replicates that agree to rounding (1e-9 relative, the variance floor) carry no pure error.
  if (df_pure < 2 || !(pure / double(df_pure) > 1e-18) || !fit.ok || groups.size() <= terms.size())
    return;
  const size_t df_lof = groups.size() - terms.size();
  f.lof_tested = true;
  f.pure_noise = std::sqrt(pure / double(df_pure));
  f.lof_f = std::max(fit.rss - pure, 0.0) / double(df_lof) / (pure / double(df_pure));
  f.lof_critical =
      boost::math::quantile(boost::math::fisher_f(double(df_lof), double(df_pure)), 0.99);
  f.lack_of_fit = f.lof_f > f.lof_critical;
}

double rss_of(const std::vector<Term>& terms, const std::vector<double>& y) {
  const Lsq fit = fit_terms(terms, y);
  return fit.ok ? fit.rss : kInf;
}

// The extra term the claimed model a + b g carries, if any (everything slower than g is inside
// O(g)). A slower class the data prefer (the AICc best is below the claim) joins it: a bound that
// holds loosely must not be judged on a model that cannot follow the data. Otherwise the
// lower-order term joins when the replicates reject the pure form and it explains the misfit
// better than any faster term does.
std::optional<Growth> choose_lower(const Data& d, Growth m, const std::vector<Term>& faster,
                                   GrowthFit& f) {
  const std::vector<Term> pure = claimed_terms(d, m, std::nullopt);
  lack_of_fit(d, pure, f);
  if (rank(f.best) < rank(m) && f.best != Growth::kConstant) {
    lack_of_fit(d, claimed_terms(d, m, f.best), f);
    return f.best;
  }
  if (!f.lack_of_fit || !lower_order(m)) return std::nullopt;
  const std::vector<Term> lower = claimed_terms(d, m, lower_order(m));
  double best_faster = kInf;
  for (const Term& h : faster) {
    std::vector<Term> t = pure;
    t.push_back(h);
    best_faster = std::min(best_faster, rss_of(t, d.y));
  }
  GrowthFit probe;
  lack_of_fit(d, lower, probe);
  if (probe.lack_of_fit || rss_of(lower, d.y) > best_faster) return std::nullopt;
  f.lof_tested = probe.lof_tested, f.lof_f = probe.lof_f, f.lof_critical = probe.lof_critical;
  f.lack_of_fit = false;
  return lower_order(m);
}

// The faster term h on top of `claimed`: its share, and its 99% lower bound (what exceeds rests
// on) taken with the lower-order term in the model too: over a finite range N log N - c N bends
// upward like N log N + c' N^2, and only a term that survives both is a faster one.
FasterTerm test_faster(const Data& d, Growth m, const std::vector<Term>& claimed, const Term& h) {
  std::vector<Term> terms = claimed;
  terms.push_back(h);
  FasterTerm t = share_of(d, terms, terms.size() - 1);
  const std::optional<Growth> lower = lower_order(m);
  const bool has_lower = lower && std::any_of(claimed.begin(), claimed.end(), [&](const Term& c) {
                           return c.name == growth_name(*lower);
                         });
  if (!lower || has_lower) return t;
  std::vector<Term> with_lower = claimed;
  with_lower.insert(with_lower.begin() + 1, {growth_name(*lower), growth_column(*lower, d.x)});
  with_lower.push_back(h);
  t.low99 = std::min(t.low99, share_of(d, with_lower, with_lower.size() - 1).low99);
  return t;
}

// The faster term with the largest upper bound; a NaN bound counts as unbounded.
const FasterTerm& largest_bound(const GrowthFit& f) {
  auto bound = [](const FasterTerm& t) { return std::isnan(t.high95) ? kInf : t.high95; };
  return *std::max_element(f.faster.begin(), f.faster.end(),
                           [&](auto& a, auto& b) { return bound(a) < bound(b); });
}

std::string percent(double v) {
  if (std::isnan(v)) return "an unknown part";
  if (!std::isfinite(v)) return v > 0 ? "any part" : "none";
  return fmt::format("{:.0f}%", 100 * v);
}

// ---- The verdict ----

void decide(const Data& d, Growth expected, GrowthFit& f) {
  const std::string claimed = growth_name(expected);
  const double xmax = d.xmax;
  const auto strongest = std::max_element(f.faster.begin(), f.faster.end(),
                                          [](auto& a, auto& b) { return a.low99 < b.low99; });
  // Required with a covariate too: the covariate model alone can credit N with what a K that
  // moves the other way took away (collinear terms), and a false exceeds costs more than a
  // missed one.
  // A constant has no lower-order term to move its exponent: no slack there.
  const double slack = expected == Growth::kConstant ? 0 : kExponentSlack;
  const bool exponent_witness = f.ci_low > f.claimed_exponent + slack;
  // A share under 10^-6 of y is no faster term, whatever its sign: numerical zero.
  if (exponent_witness && strongest->low99 > 1e-6) {
    f.verdict = ClaimVerdict::kExceeds;
    f.reason = fmt::format(
        "{} carries {} of y at x = {:g} (99% lower bound {}), and the exponent CI [{:.3f}, "
        "{:.3f}] lies above {}'s {:.3f}",
        strongest->model, percent(strongest->share), xmax, percent(strongest->low99), f.ci_low,
        f.ci_high, claimed, f.claimed_exponent);
    return;
  }
  const FasterTerm& open = largest_bound(f);
  if (f.lack_of_fit) {
    f.verdict = ClaimVerdict::kInconclusive;
    f.reason = fmt::format(
        "{} does not fit its replicates (lack of fit F = {:.1f} > {:.1f} at 1%), with or "
        "without its lower-order term: no basis for a bound (were it one, faster growth could "
        "carry up to {} of y at x = {:g})",
        claimed, f.lof_f, f.lof_critical, percent(std::max(0.0, open.high95)), xmax);
    return;
  }
  f.hidden = std::max(0.0, open.high95);  // a share's bound under 0: nothing faster can hide
  if (open.high95 < kHoldsTolerance) {
    f.verdict = ClaimVerdict::kHolds;
    std::vector<std::string> bounds;
    for (const FasterTerm& t : f.faster) bounds.push_back(t.model + " " + percent(t.high95));
    f.reason = fmt::format(
        "at most {} of y at x = {:g} can come from growth faster than {} (95% bounds: {}; "
        "tolerance {}){}",
        percent(f.hidden), xmax, claimed, fmt::join(bounds, ", "), percent(kHoldsTolerance),
        f.lower ? fmt::format(", with {} as a lower-order term", growth_name(*f.lower)) : "");
    return;
  }
  f.verdict = ClaimVerdict::kInconclusive;
  f.reason = fmt::format(
      "{} could carry up to {} of y at x = {:g} (95% bound; fitted {}), over the {} tolerance",
      open.model, percent(open.high95), xmax, percent(open.share), percent(kHoldsTolerance));
}

// Whether the claimed class is needed on top of the class below (asked of a bound that holds).
void judge_tightness(const Data& d, Growth expected, GrowthFit& f) {
  f.tightness = Tightness::kNotTested;
  if (f.verdict != ClaimVerdict::kHolds || expected == Growth::kConstant) return;
  const std::vector<Term> terms = claimed_terms(d, expected, class_below(expected));
  size_t j = 0;
  while (terms[j].name != growth_name(expected)) ++j;
  f.claimed_term = share_of(d, terms, j);
  f.tightness = f.claimed_term.low95 > 0                  ? Tightness::kTight
                : f.claimed_term.high95 < kHoldsTolerance ? Tightness::kLoose
                                                          : Tightness::kUndetermined;
}

// Everything but the design rules and the leave-one-out check; `fixed_lower` imposes the
// claimed model's extra term instead of choosing it.
GrowthFit analyse(const Data& d, Growth expected,
                  const std::optional<Growth>* fixed_lower = nullptr) {
  GrowthFit f;
  f.points = d.x.size();
  f.distinct_x = std::set<double>(d.x.begin(), d.x.end()).size();
  const Slope s = loglog_slope(d.x, d.y);
  f.exponent = s.exponent, f.ci_low = s.low, f.ci_high = s.high;
  f.claimed_exponent = model_exponent(expected, d.x);
  select_models(d.x, d.y, expected, f);
  const std::vector<Term> faster = faster_terms(expected, d.x);
  f.lower = fixed_lower ? *fixed_lower : choose_lower(d, expected, faster, f);
  const std::vector<Term> claimed = claimed_terms(d, expected, f.lower);
  const Lsq base = fit_terms(claimed, d.y);
  f.noise = base.ok ? std::sqrt(base.rss / double(base.dof)) : 0;
  for (const Term& h : faster) f.faster.push_back(test_faster(d, expected, claimed, h));
  decide(d, expected, f);
  judge_tightness(d, expected, f);
  return f;
}

Data without_x(const Data& d, double x) {
  std::vector<double> xs, ys, cs;
  for (size_t i = 0; i < d.x.size(); ++i) {
    if (d.x[i] == x) continue;
    xs.push_back(d.x[i]);
    ys.push_back(d.y[i]);
    if (!d.covariate.empty()) cs.push_back(d.covariate[i]);
  }
  return make_data(xs, ys, cs, d.covariate_name);
}

bool is_judged(const GrowthFit& f) {
  return f.verdict == ClaimVerdict::kHolds || f.verdict == ClaimVerdict::kExceeds;
}

// A holds or exceeds that a design rule does not allow becomes inconclusive, saying why.
void withdraw(GrowthFit& f, Growth expected, const std::string& why) {
  f.reason =
      fmt::format("{} would be {}, but {}", growth_name(expected), verdict_name(f.verdict), why);
  f.verdict = ClaimVerdict::kInconclusive;
  f.tightness = Tightness::kNotTested;
}

// A holds or exceeds (or a tight) that changes when the points at any one x are left out is not
// one the data carry. With 5 distinct x no point can be left out, and none is.
void leave_one_out(const Data& d, Growth expected, GrowthFit& f) {
  if (!is_judged(f) || f.distinct_x < 6) return;
  for (double x : std::set<double>(d.x.begin(), d.x.end())) {
    // The claimed model's form stays the full data's: the check is on the bounds, and a 1% lack
    // of fit test asked once per x would fail somewhere by chance.
    const GrowthFit l = analyse(without_x(d, x), expected, &f.lower);
    if (l.verdict != f.verdict) {
      f.flip = fmt::format("leaving out x = {:g} makes it {} ({})", x, verdict_name(l.verdict),
                           l.reason);
      withdraw(f, expected, f.flip);
      return;
    }
    if (f.tightness == Tightness::kTight && l.tightness != Tightness::kTight)
      f.tightness = Tightness::kUndetermined;
  }
}

// The smallest and largest mean of y / x over the points at one x.
std::pair<double, double> mean_ratio_range(const Data& d) {
  std::map<double, std::pair<double, int>> at;  // x -> (sum of y / x, points)
  for (size_t i = 0; i < d.x.size(); ++i) {
    auto& [sum, n] = at[d.x[i]];
    sum += d.y[i] / d.x[i], ++n;
  }
  double lo = kInf, hi = 0;
  for (const auto& [x, s] : at)
    lo = std::min(lo, s.first / s.second), hi = std::max(hi, s.first / s.second);
  return {lo, hi};
}

// y / x the same at every x (exactly, or within 10% over 30x for a linear claim): the metric
// counts its own loop.
bool loop_check(const Data& d, Growth expected, GrowthFit& f) {
  // Only a linear claim can be its own loop; y proportional to x under a slower claim is growth.
  if (expected != Growth::kLinear) return false;
  double lo = kInf, hi = 0;
  for (size_t i = 0; i < d.x.size(); ++i)
    lo = std::min(lo, d.y[i] / d.x[i]), hi = std::max(hi, d.y[i] / d.x[i]);
  const double range = d.xmax / d.xmin;
  if (hi - lo <= 1e-9 * lo) {
    f.verdict = ClaimVerdict::kLoopCheck;
    f.reason = fmt::format(
        "y / x = {:.6g} at every x: the metric counts x by construction (a check of the loops, "
        "not a test of the claim)",
        lo);
    return true;
  }
  // The trend of y / x, not its scatter: replicates (other seeds of a cloud) scatter about the
  // same work per unit of x, and judged point by point that scatter once passed for movement.
  const auto [mean_lo, mean_hi] = mean_ratio_range(d);
  if (range < kLoopRange || mean_hi >= mean_lo * (1 + kLoopFlatness)) return false;
  f.verdict = ClaimVerdict::kLoopCheck;
  f.reason = fmt::format(
      "y / x (its mean at each x) moves by {:.1f}% while x grows {:.0f}x: any tracer that does "
      "the same work per unit of x passes (a check of the loops, not a confirmation)",
      100 * (mean_hi / mean_lo - 1), range);
  return true;
}

}  // namespace

std::optional<Growth> lower_order_term(Growth m) { return lower_order(m); }

double min_decades(const std::string& variable) {
  return variable == "N" || variable == "M" ? 2.0 : 1.0;
}

const char* verdict_name(ClaimVerdict v) {
  switch (v) {
    case ClaimVerdict::kHolds:
      return "holds";
    case ClaimVerdict::kExceeds:
      return "exceeds";
    case ClaimVerdict::kInconclusive:
      return "inconclusive";
    case ClaimVerdict::kMeets:
      return "meets";
    case ClaimVerdict::kMisses:
      return "misses";
    case ClaimVerdict::kLoopCheck:
      return "loop_check";
    case ClaimVerdict::kDrifted:
      return "drifted";
    case ClaimVerdict::kNotJudged:
      return "not_judged";
    case ClaimVerdict::kError:
      return "error";
  }
  return "?";
}

VerdictKind verdict_kind(ClaimVerdict v) {
  switch (v) {
    case ClaimVerdict::kHolds:
    case ClaimVerdict::kExceeds:
    case ClaimVerdict::kInconclusive:
      return VerdictKind::kGrowth;
    case ClaimVerdict::kMeets:
    case ClaimVerdict::kMisses:
      return VerdictKind::kThreshold;
    default:
      return VerdictKind::kNotJudged;
  }
}

const char* tightness_name(Tightness t) {
  switch (t) {
    case Tightness::kNotTested:
      return "not tested";
    case Tightness::kTight:
      return "tight";
    case Tightness::kLoose:
      return "loose";
    case Tightness::kUndetermined:
      return "undetermined";
  }
  return "?";
}

Growth next_growth(Growth g) {
  const size_t r = size_t(rank(g));
  return r + 1 < kModels ? kAllGrowths[r + 1] : g;
}

GrowthFit fit_growth(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                     const std::string& what, const FitRules& rules) {
  check_input(x, y, rules, what);
  const Data d = make_data(x, y, rules.covariate, rules.covariate_name);
  GrowthFit f = analyse(d, expected);
  f.decades = std::log10(d.xmax / d.xmin);
  if (loop_check(d, expected, f)) return f;
  if (rules.leave_one_out) leave_one_out(d, expected, f);
  if (is_judged(f) && rules.range_waiver.empty() && f.decades < rules.min_decades - 1e-9)
    withdraw(f, expected,
             fmt::format("x spans {:.2f} decades, under the {:g} its variable needs", f.decades,
                         rules.min_decades));
  return f;
}

VerdictRates simulate_verdicts(const std::vector<double>& x,
                               const std::function<double(double)>& truth, Growth claimed,
                               double noise, int trials, uint64_t seed, const FitRules& rules) {
  Rng rng(seed, 0x5eed);
  VerdictRates r;
  std::vector<double> y(x.size());
  for (int t = 0; t < trials; ++t) {
    for (size_t i = 0; i < x.size(); ++i) {
      // Box-Muller: a standard normal from two uniforms.
      const double u1 = std::max(rng.uniform_double(), 1e-300), u2 = rng.uniform_double();
      const double z = std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
      y[i] = truth(x[i]) * std::exp(noise * z);
    }
    const ClaimVerdict v = fit_growth(x, y, claimed, "simulation", rules).verdict;
    (v == ClaimVerdict::kExceeds ? r.exceeds
     : v == ClaimVerdict::kHolds ? r.holds
                                 : r.inconclusive) += 1;
  }
  for (double* v : {&r.exceeds, &r.holds, &r.inconclusive}) *v /= trials;
  return r;
}

}  // namespace pcrt
