// Named numeric parameters with defaults and valid ranges, shared by methods, structures and
// generators, so that `--set name=value` and `pcrt list` treat them all alike.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace pcrt {

struct ParamSpec {
  std::string name;
  double default_value = 0;
  double min_value = 0;  // inclusive
  double max_value = 0;  // inclusive
  std::string description;
  bool integer = false;
};

using ParamValues = std::map<std::string, double>;

// Defaults for every spec, overridden by `given` (which must only name specs in `specs`).
// Throws InputError "<context>: ..." for unknown names, non-integers and out-of-range values.
ParamValues resolve_params(const std::vector<ParamSpec>& specs, const ParamValues& given,
                           const std::string& context);

// Checks one value against its spec; throws InputError naming `context` and the parameter.
void check_param(const ParamSpec& spec, double value, const std::string& context);

// Parses "name=value" (as given to --set); throws InputError naming the text.
std::pair<std::string, double> parse_assignment(const std::string& text);

// Parses a finite number, or throws InputError "<what>: '<text>' is not a number".
double parse_number(const std::string& text, const std::string& what);

}  // namespace pcrt
