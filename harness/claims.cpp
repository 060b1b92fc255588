#include "harness/claims.hpp"

#include <cctype>
#include <cmath>
#include <map>
#include <set>

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
  for (char c : std::string("SMBNKkIH"))
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
    case Growth::kSqrt:
      return "x^0.5";
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
  if (variable.size() != 1 || std::string("SMBNKkIH").find(variable[0]) == std::string::npos)
    input_error("claim variable '{}' is not one of S M B N K k I H", variable);
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
  if (e < 0.75) return Growth::kSqrt;
  const int whole = int(std::lround(e));
  if (whole == 1) return e - 1 > 0.02 && e_low - 1 > 0.02 ? Growth::kLinearLog : Growth::kLinear;
  if (whole == 2) return Growth::kQuadratic;
  return Growth::kCubic;
}

namespace {

void structure_claims(std::vector<Claim>& c) {
  for (const StructureInfo& s : StructureRegistry::instance().all()) {
    // Table 5.4's row without a structure (Tejada 2006: "-", O(1)) is the brute-force oracle.
    const bool brute = s.id == "brute_force";
    // The SAH BVH is no structure of the thesis: the industrial baseline, judged by the usual
    // claims of binned SAH builds and BVH traversal.
    const bool industrial = s.id == "bvh";
    c.push_back({s.id + "/build",
                 s.id,
                 brute ? "no structure: nothing to build" : "construction cost in N",
                 brute ? "O(1)" : s.build_claim,
                 {"N"},
                 brute ? "Table 5.4 ([58])"
                       : (industrial ? "Wald 2007 (binned SAH; not in the thesis)" : "Table 5.4")});
    // The thesis builds nothing for Tejada 2006; pcrt's oracle lists the N item indices. The bvh
    // is pcrt's engineering, its claims the textbooks': neither is the thesis's.
    if (brute || industrial) c.back().about = ClaimAbout::kPcrt;
    c.push_back({s.id + "/query",
                 s.id,
                 "traversal cost to a leaf in N",
                 s.query_claim,
                 {"N"},
                 brute ? "section 5.4 (brute force)"
                       : (industrial ? "pbrt-v4 BVH (not in the thesis)" : "section 5.4")});
    if (industrial) c.back().about = ClaimAbout::kPcrt;
  }
  c.push_back({"grid/occupancy",
               "grid",
               "K = N/G points per cell: with G = N/c, K does not grow with N (uniform cloud)",
               "O(1)",
               {"N"},
               "section 5.4"});
  c.back().precondition = Precondition::kUniformVolume;
}

void method_claims(std::vector<Claim>& c) {
  for (const MethodInfo& m : MethodRegistry::instance().all()) {
    for (const MethodClaim& mc : m.claims) {
      const bool leaf = mc.quantity == "leaf intersection";
      c.push_back({m.id + "/" + (leaf ? "leaf" : "frame"), m.id, mc.quantity + " cost",
                   mc.complexity, mc.variables, mc.source});
      if (leaf) continue;
      // The reduced column keeps M and N only: O(MN) where the frame rasterizes every point.
      const bool raster = mc.complexity.find("log") == std::string::npos;
      c.push_back({m.id + "/frame_reduced",
                   m.id,
                   "frame cost, reduced to M and N",
                   raster ? "O(MN)" : "O(M log N)",
                   {"M", "N"},
                   "Table 6.1 (reduced)"});
      c.push_back({m.id + "/requery",
                   m.id,
                   "leaves a ray visits: O(1) re-queries (T4 = T_query + T_int; O(N) worst case)",
                   "O(1)",
                   {"N"},
                   "section 5.5.1"});
    }
    // Table 5.1's columns and Table 5.4's own items, as each method declares them.
    if (!m.real_time_claim.empty())
      c.push_back({m.id + "/real_time",
                   m.id,
                   "real time: at least 1 frame per second",
                   ">= 1 fps",
                   {},
                   m.real_time_claim});
    if (!m.iterative_claim.empty())
      c.push_back({m.id + "/iterations",
                   m.id,
                   "iterations few enough not to matter (<= 3 per iterative run)",
                   "I <= 3",
                   {},
                   "chapter 6"});  // the claim is chapter 6's; Table 5.1 marks the method
    if (m.own_items)
      c.push_back({m.id + "/build",
                   m.id,
                   "structure built over the method's own items",
                   "O(N log N)",
                   {"N"},
                   "Table 5.4"});
    for (const MethodInfo::OtherClaim& o : m.other_claims)
      c.push_back({m.id + "/" + o.name, m.id, o.statement, o.complexity, o.variables, o.source,
                   o.not_tested, m.surveyed() ? ClaimAbout::kThesis : ClaimAbout::kLater});
  }
}

void reconstruction_claims(std::vector<Claim>& c) {
  c.push_back({"delaunay/uniform",
               "delaunay",
               "3D Delaunay (randomized incremental) of N points uniform in a ball",
               "O(N log N)",
               {"N"},
               "section 5.1.1"});
  c.push_back({"delaunay/worst",
               "delaunay",
               "3D Delaunay worst case (two skew lines)",
               "O(N^2)",
               {"N"},
               "section 5.1.1"});
  const std::string no_gift =
      "pcrt has no gift-wrapping triangulation (CGAL implements randomized incremental "
      "insertion only)";
  c.push_back({"gift_wrapping/uniform",
               "gift_wrapping",
               "gift wrapping, uniform in a ball",
               "O(N)",
               {"N"},
               "section 5.1.1",
               no_gift});
  c.push_back({"gift_wrapping/worst",
               "gift_wrapping",
               "gift wrapping worst case",
               "O(N^3)",
               {"N"},
               "section 5.1.1",
               no_gift});
  c.push_back({"afsr/reconstruct",
               "afsr",
               "advancing front reconstruction (on its Delaunay)",
               "O(N log N)",
               {"N"},
               "not a thesis claim: pcrt's expectation from the Delaunay it builds on"});
  c.back().about = ClaimAbout::kPcrt;
  c.push_back({"direct/total",
               "*",
               "direct tracing: setup and a frame",
               "O((N + M) log N)",
               {"N", "M"},
               "chapter 7"});
  c.push_back({"reconstruction/total",
               "*",
               "reconstruct, then trace a frame",
               "O(N^2 + M log N)",
               {"N", "M"},
               "chapter 7"});
  c.push_back({"reconstruction/crossover",
               "*",
               "direct tracing O((N + M) log N) beats reconstruct-then-trace O(N^2 + M log N)",
               "crossover frames",
               {"N", "M"},
               "chapter 7"});
}

}  // namespace

const std::vector<Claim>& all_claims() {
  static const std::vector<Claim> claims = [] {
    std::vector<Claim> c;
    structure_claims(c);
    method_claims(c);
    reconstruction_claims(c);
    c.push_back({"mls/iterations",
                 "*",
                 "MLS iterations per intersection run (Algorithm 3's refinement): 2 or 3 suffice",
                 "I <= 3",
                 {},
                 "section 5.5.2"});
    c.push_back({"mls/fits_per_hit",
                 "*",
                 "MLS fits per hitting ray, summed over every leaf it visits (pcrt's observation)",
                 "I <= 3",
                 {},
                 "pcrt's own observation beside section 5.5.2"});
    c.back().about = ClaimAbout::kPcrt;
    for (const WorkloadInfo& w : workloads()) {
      c.push_back({"calibration/" + w.id,
                   "*",
                   "calibration workload " + w.id,
                   w.complexity,
                   {"N"},
                   "known complexity (validates the fitter)"});
      c.back().about = ClaimAbout::kPcrt;
    }
    return c;
  }();
  return claims;
}

const char* claim_about_name(ClaimAbout a) {
  switch (a) {
    case ClaimAbout::kThesis:
      return "thesis";
    case ClaimAbout::kLater:
      return "later";
    case ClaimAbout::kPcrt:
      break;
  }
  return "pcrt";
}

const Claim& find_claim(const std::string& id) {
  for (const Claim& c : all_claims())
    if (c.id == id) return c;
  input_error("unknown claim '{}' (pcrt list --json lists them under \"claims\")", id);
}

}  // namespace pcrt
