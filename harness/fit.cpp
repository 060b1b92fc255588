#include "harness/fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/error.hpp"

namespace pcrt {
namespace {

double g(Growth m, double x) {
  switch (m) {
    case Growth::kConstant:
      return 0;
    case Growth::kLog:
      return std::log(x);
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
  for (int i = 0; i < 6; ++i)
    if (kAllGrowths[i] == m) return i;
  return 0;
}

// Two-sided 95% Student t quantile for `dof` degrees of freedom.
double t95(size_t dof) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                                 2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                                 2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                                 2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof == 0) return std::numeric_limits<double>::infinity();
  return dof <= 30 ? table[dof - 1] : 1.96 + 2.4 / double(dof);
}

}  // namespace

GrowthFit fit_growth(const std::vector<double>& x, const std::vector<double>& y, Growth expected,
                     const std::string& what) {
  const size_t n = x.size();
  if (n != y.size()) input_error("{}: x and y differ in length", what);
  // AICc of a model with 2 coefficients (and the variance) needs n > 4.
  if (n < 5) input_error("{}: needs at least 5 points for a growth fit, got {}", what, n);
  std::set<double> distinct(x.begin(), x.end());
  if (distinct.size() < 3)
    input_error("{}: needs at least 3 distinct x values, got {}", what, distinct.size());
  for (size_t i = 0; i < n; ++i)
    if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      input_error("{}: x and y must be positive and finite (x = {}, y = {})", what, x[i], y[i]);
  GrowthFit f;
  f.points = n;
  // Log-log OLS.
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) mx += std::log(x[i]), my += std::log(y[i]);
  mx /= double(n), my /= double(n);
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
  }
  f.exponent = sxy / sxx;
  double rss_log = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r = std::log(y[i]) - my - f.exponent * (std::log(x[i]) - mx);
    rss_log += r * r;
  }
  const double se = n > 2 ? std::sqrt(rss_log / double(n - 2) / sxx) : 0;
  f.ci_low = f.exponent - t95(n - 2) * se;
  f.ci_high = f.exponent + t95(n - 2) * se;
  // Weighted least squares per model, y = a + b g(x) / g(x_max), weights 1 / y^2.
  const double xmax = *std::max_element(x.begin(), x.end());
  double best = std::numeric_limits<double>::infinity();
  for (int m = 0; m < 6; ++m) {
    const Growth model = kAllGrowths[m];
    const int k = model == Growth::kConstant ? 1 : 2;
    f.aicc[size_t(m)] = std::numeric_limits<double>::infinity();
    if (int(n) - k - 2 <= 0) continue;
    Eigen::MatrixXd a(n, k);
    Eigen::VectorXd b(n);
    const double scale = model == Growth::kConstant ? 1 : g(model, xmax);
    for (size_t i = 0; i < n; ++i) {
      const double w = 1.0 / y[i];
      a(Eigen::Index(i), 0) = w;
      if (k == 2) a(Eigen::Index(i), 1) = w * g(model, x[i]) / scale;
      b(Eigen::Index(i)) = 1.0;  // w * y
    }
    const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
    if (k == 2 && !(c[1] > 0)) continue;  // a shrinking fit is no growth model
    const double rss = std::max((a * c - b).squaredNorm(), 1e-300);
    const double params = double(k + 1);  // coefficients and the variance
    f.aicc[size_t(m)] = double(n) * std::log(rss / double(n)) + 2 * params +
                        2 * params * (params + 1) / (double(n) - params - 1);
    f.slope[size_t(m)] = k == 2 ? c[1] : 0;
    if (f.aicc[size_t(m)] < best) {
      best = f.aicc[size_t(m)];
      f.best = model;
      // Weighted R^2 against the weighted mean (relative residuals).
      double mean = 0;
      for (size_t i = 0; i < n; ++i) mean += 1.0 / y[i];
      const double wmean = double(n) / mean;  // the constant that best fits in relative terms
      double tss = 0;
      for (size_t i = 0; i < n; ++i) tss += std::pow((y[i] - wmean) / y[i], 2);
      f.r2 = tss > 0 ? 1.0 - rss / tss : 1.0;
    }
  }
  // Parsimony: the constant (one coefficient fewer) wins when it is within 2 AICc of the best, or
  // when the best model changes y by under 10% across the whole x range (no growth to speak of).
  if (f.best != Growth::kConstant) {
    const double xmin = *std::min_element(x.begin(), x.end());
    const size_t b = size_t(rank(f.best));
    double ymean = 0;
    for (double v : y) ymean += v / double(n);
    const double change = f.slope[b] * (g(f.best, xmax) - g(f.best, xmin)) / g(f.best, xmax);
    if (f.aicc[0] - best <= 2.0 || change < 0.1 * ymean) {
      f.best = Growth::kConstant;
      best = f.aicc[0];
    }
  }
  f.delta_aicc_expected = f.aicc[size_t(rank(expected))] - best;
  if (f.delta_aicc_expected <= 2.0)
    f.verdict = "consistent";
  else
    f.verdict = rank(f.best) > rank(expected) ? "faster" : "slower";
  return f;
}

}  // namespace pcrt
