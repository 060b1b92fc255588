#include "core/params.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"

namespace pcrt {

double parse_number(const std::string& text, const std::string& what) {
  double v = 0;
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  auto [end, ec] = std::from_chars(b, e, v);
  if (text.empty() || ec != std::errc() || end != e)
    input_error("{}: '{}' is not a number", what, text);
  if (!std::isfinite(v)) input_error("{}: '{}' is not finite", what, text);
  return v;
}

void check_param(const ParamSpec& spec, double value, const std::string& context) {
  if (!std::isfinite(value)) input_error("{}: {} must be finite", context, spec.name);
  if (spec.integer && value != std::floor(value))
    input_error("{}: {} must be an integer, not {}", context, spec.name, value);
  if (value < spec.min_value || value > spec.max_value)
    input_error("{}: {}={} is outside its range [{}, {}]", context, spec.name, value,
                spec.min_value, spec.max_value);
}

ParamValues resolve_params(const std::vector<ParamSpec>& specs, const ParamValues& given,
                           const std::string& context) {
  ParamValues out;
  for (const auto& s : specs) out[s.name] = s.default_value;
  for (const auto& [name, value] : given) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.name == name) spec = &s;
    if (!spec) {
      std::string known;
      for (const auto& s : specs) known += (known.empty() ? "" : ", ") + s.name;
      input_error("{}: unknown parameter '{}' (known: {})", context, name,
                  known.empty() ? "none" : known);
    }
    check_param(*spec, value, context);
    out[name] = value;
  }
  return out;
}

std::pair<std::string, double> parse_assignment(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) input_error("--set '{}': expected name=value", text);
  const std::string name = text.substr(0, eq);
  return {name, parse_number(text.substr(eq + 1), "--set " + name)};
}

}  // namespace pcrt
