// The claims registry: every complexity claim of the thesis that the harness tests (DESIGN.md,
// "Claims the harness tests"), each with its source. Structure and method claims are read from
// their registrations; the rest are listed here. A claim's complexity string (as printed, e.g.
// "O(SMB(log N + IK^2))") is parsed, so the growth expected in any one swept variable follows
// from it (in K: x^2; in N: log x).
#pragma once

#include <string>
#include <vector>

namespace pcrt {

// x^0.5 is not a class the thesis claims, but it is the class between log x and x that a real
// departure lands in (a surface fills G^(2/3) of a grid's cells; N^0.5 against log N).
enum class Growth { kConstant, kLog, kSqrt, kLinear, kLinearLog, kQuadratic, kCubic };
inline constexpr Growth kAllGrowths[] = {Growth::kConstant, Growth::kLog,       Growth::kSqrt,
                                         Growth::kLinear,   Growth::kLinearLog, Growth::kQuadratic,
                                         Growth::kCubic};

const char* growth_name(Growth g);  // "1", "log x", "x^0.5", "x", "x log x", "x^2", "x^3"
// The growth of `complexity` (e.g. "O(MNIK + SBNIK)") in `variable` (one of S M B N K k I H), the
// others held fixed. Throws InputError if the string does not parse or lacks the variable.
Growth expected_growth(const std::string& complexity, const std::string& variable);

// Whom a verdict is about: the thesis; a paper after it (the claims of a method the thesis did
// not survey, e.g. 3DGRT's); or pcrt's own scaffolding and expectations (the brute-force oracle's
// build, the calibration workloads, pcrt's own observations). Each is tallied apart.
enum class ClaimAbout { kThesis, kLater, kPcrt };
const char* claim_about_name(ClaimAbout a);  // "thesis", "later", "pcrt"
// What the input must be for the claim to apply; a fit on other input is not judged.
enum class Precondition { kNone, kUniformVolume };

struct Claim {
  std::string id;          // "<subject>/<what>", e.g. "kd_tree/build", "cai_2011/leaf"
  std::string subject;     // a structure, method or reconstruction id; "*" for general claims
  std::string statement;   // what is claimed, in words
  std::string complexity;  // as printed in the thesis, or a threshold ("I <= 3", ">= 1 fps")
  std::vector<std::string> variables;
  std::string source;           // "Table 5.4", "section 5.5.2", ...
  std::string not_tested = {};  // why pcrt cannot judge it (empty: it is judged)
  ClaimAbout about = ClaimAbout::kThesis;
  Precondition precondition = Precondition::kNone;
};

const std::vector<Claim>& all_claims();
const Claim& find_claim(const std::string& id);  // InputError for an unknown id

}  // namespace pcrt
