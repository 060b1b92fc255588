#include "harness/claims.hpp"

#include <cctype>
#include <cmath>
#include <map>

#include "core/error.hpp"
#include "harness/workloads.hpp"
#include "methods/method.hpp"
#include "reconstruction/reconstruction.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

// Recursive descent over the thesis's complexity notation: sums, implicit products of
// one-letter variables, ^integer, log(...) or "log N", parentheses.
class Expression {
 public:
  Expression(std::string text, const std::map<char, double>& values) : values_(values) {
    for (char c : text)
      if (!std::isspace(static_cast<unsigned char>(c))) s_ += c;
    if (s_.size() > 3 && s_.rfind("O(", 0) == 0 && s_.back() == ')')
      s_ = s_.substr(2, s_.size() - 3);
  }
  double evaluate() {
    pos_ = 0;
    const double v = sum();
    if (pos_ != s_.size()) fail();
    return v;
  }

 private:
  [[noreturn]] void fail() const { input_error("complexity '{}': cannot parse at {}", s_, pos_); }
  bool eat(char c) {
    if (pos_ < s_.size() && s_[pos_] == c) return ++pos_, true;
    return false;
  }
  double sum() {
    double v = product();
    while (eat('+')) v += product();
    return v;
  }
  double product() {
    double v = power();
    while (pos_ < s_.size() && s_[pos_] != '+' && s_[pos_] != ')') v *= power();
    return v;
  }
  double power() {
    double v = atom();
    if (eat('^')) {
      const size_t start = pos_;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      if (start == pos_) fail();
      v = std::pow(v, std::stod(s_.substr(start, pos_ - start)));
    }
    return v;
  }
  double atom() {
    if (s_.compare(pos_, 3, "log") == 0) {
      pos_ += 3;
      return std::log(std::max(atom(), 2.0));
    }
    if (eat('(')) {
      const double v = sum();
      if (!eat(')')) fail();
      return v;
    }
    if (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
      const size_t start = pos_;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      return std::stod(s_.substr(start, pos_ - start));
    }
    if (pos_ < s_.size()) {
      const auto it = values_.find(s_[pos_]);
      if (it != values_.end()) return ++pos_, it->second;
    }
    fail();
  }

  std::string s_;
  size_t pos_ = 0;
  const std::map<char, double>& values_;
};

double evaluate(const std::string& complexity, char variable, double x) {
  std::map<char, double> v;
  for (char c : std::string("SMBNKkI"))
    v[c] = c == variable ? x : 1.0;  // others at 1: no term hides another
  return Expression(complexity, v).evaluate();
}

}  // namespace

const char* growth_name(Growth g) {
  switch (g) {
    case Growth::kConstant:
      return "1";
    case Growth::kLog:
      return "log x";
    case Growth::kLinear:
      return "x";
    case Growth::kLinearLog:
      return "x log x";
    case Growth::kQuadratic:
      return "x^2";
    case Growth::kCubic:
      return "x^3";
  }
  return "?";
}

Growth expected_growth(const std::string& complexity, const std::string& variable) {
  if (variable.size() != 1 || std::string("SMBNKkI").find(variable[0]) == std::string::npos)
    input_error("claim variable '{}' is not one of S M B N K k I", variable);
  const char v = variable[0];
  if (complexity.find(v) == std::string::npos) {  // e.g. "O(1)": parse it, then it is constant
    (void)evaluate(complexity, v, 1.0);
    return Growth::kConstant;
  }
  // The asymptotic exponent from three far-apart points; a log factor shows as a drift.
  const double a = evaluate(complexity, v, 1e3), b = evaluate(complexity, v, 1e6),
               c = evaluate(complexity, v, 1e9);
  const double e = std::log(c / b) / std::log(1e3);
  const double e_low = std::log(b / a) / std::log(1e3);
  if (e < 0.25) return c / a > 1.5 ? Growth::kLog : Growth::kConstant;
  const int whole = int(std::lround(e));
  if (whole == 1) return e - 1 > 0.02 && e_low - 1 > 0.02 ? Growth::kLinearLog : Growth::kLinear;
  if (whole == 2) return Growth::kQuadratic;
  return Growth::kCubic;
}

const std::vector<Claim>& all_claims() {
  static const std::vector<Claim> claims = [] {
    std::vector<Claim> c;
    for (const StructureInfo& s : StructureRegistry::instance().all()) {
      if (s.id == "brute_force") continue;
      c.push_back(
          {s.id + "/build", s.id, "construction cost in N", s.build_claim, {"N"}, "Table 5.4"});
      c.push_back({s.id + "/query",
                   s.id,
                   "traversal cost to a leaf in N",
                   s.query_claim,
                   {"N"},
                   "section 5.4"});
    }
    for (const MethodInfo& m : MethodRegistry::instance().all())
      for (const MethodClaim& mc : m.claims) {
        const std::string what = mc.quantity == "leaf intersection" ? "leaf" : "frame";
        c.push_back({m.id + "/" + what, m.id, mc.quantity + " cost", mc.complexity, mc.variables,
                     mc.source});
      }
    c.push_back({"delaunay/uniform",
                 "delaunay",
                 "3D Delaunay of N uniform points",
                 "O(N log N)",
                 {"N"},
                 "section 5.1.1"});
    c.push_back({"delaunay/worst",
                 "delaunay",
                 "3D Delaunay worst case (two skew lines)",
                 "O(N^2)",
                 {"N"},
                 "section 5.1.1"});
    c.push_back({"afsr/reconstruct",
                 "afsr",
                 "mesh reconstruction (its Delaunay) in N",
                 "O(N log N)",
                 {"N"},
                 "section 5.1.1"});
    c.push_back({"mls/iterations",
                 "*",
                 "MLS iterations per ray: 2 or 3 suffice",
                 "I <= 3",
                 {},
                 "section 5.5.2"});
    c.push_back({"*/real_time",
                 "*",
                 "real time: at least 1 frame per second",
                 ">= 1 fps",
                 {},
                 "Table 5.1"});
    c.push_back({"reconstruction/crossover",
                 "*",
                 "direct tracing O((N + M) log N) beats reconstruct-then-trace O(N^2 + M log N)",
                 "crossover frames",
                 {"N", "M"},
                 "chapter 7"});
    for (const WorkloadInfo& w : workloads())
      c.push_back({"calibration/" + w.id,
                   "*",
                   "calibration workload " + w.id,
                   w.complexity,
                   {"N"},
                   "known complexity (validates the fitter)"});
    return c;
  }();
  return claims;
}

const Claim& find_claim(const std::string& id) {
  for (const Claim& c : all_claims())
    if (c.id == id) return c;
  input_error("unknown claim '{}' (pcrt list --json lists them under \"claims\")", id);
}

}  // namespace pcrt
