#include "harness/cli_args.hpp"

#include <charconv>
#include <cstdio>
#include <stdexcept>

#include "core/error.hpp"
#include "core/params.hpp"

namespace pcrt {

CliArgs::CliArgs(std::string command, std::string usage, std::vector<OptionSpec> options,
                 size_t min_positional, size_t max_positional)
    : command_(std::move(command)),
      usage_(std::move(usage)),
      options_(std::move(options)),
      min_pos_(min_positional),
      max_pos_(max_positional) {}

bool CliArgs::parse(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::fputs(help().c_str(), stdout);
      return false;
    }
    if (a.rfind("--", 0) != 0 || a.size() == 2) {
      if (!a.empty() && a[0] == '-' && a.size() > 1 &&
          !(a.size() > 1 && (std::isdigit(a[1]) || a[1] == '.')))
        input_error("pcrt {}: unknown option '{}' (see pcrt {} --help)", command_, a, command_);
      positional_.push_back(a);
      continue;
    }
    std::string name = a.substr(2);
    std::optional<std::string> inline_value;
    if (const size_t eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    const OptionSpec* spec = nullptr;
    for (const auto& o : options_)
      if (o.name == name) spec = &o;
    if (!spec && name == "help") input_error("pcrt {}: --help takes no value", command_);
    if (!spec)
      input_error("pcrt {}: unknown option '--{}' (see pcrt {} --help)", command_, name, command_);
    if (!spec->repeatable && values_.count(name))
      input_error("pcrt {}: --{} given twice", command_, name);
    if (spec->value_name.empty()) {
      if (inline_value) input_error("pcrt {}: --{} takes no value", command_, name);
      values_[name].push_back("1");
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= args.size())
        input_error("pcrt {}: --{} needs a value ({})", command_, name, spec->value_name);
      inline_value = args[++i];
    }
    values_[name].push_back(*inline_value);
  }
  if (positional_.size() > max_pos_)  // name the stray one: a value given to a flag, say
    input_error("pcrt {}: unexpected argument '{}' (takes {}{}): usage: {}", command_,
                positional_[max_pos_], max_pos_ == 0 ? "no arguments" : "at most ",
                max_pos_ == 0 ? "" : std::to_string(max_pos_), usage_);
  if (positional_.size() < min_pos_)
    input_error("pcrt {}: expected {}{} argument(s), got {}: usage: {}", command_, min_pos_,
                max_pos_ != min_pos_ ? fmt::format(" to {}", max_pos_) : "", positional_.size(),
                usage_);
  return true;
}

const OptionSpec& CliArgs::spec(const std::string& name) const {
  for (const auto& o : options_)
    if (o.name == name) return o;
  throw std::logic_error("pcrt " + command_ + ": option --" + name + " is not declared");
}

std::string CliArgs::get(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? spec(name).default_value : it->second.back();
}

std::string CliArgs::require(const std::string& name) const {
  if (!has(name)) input_error("pcrt {}: --{} is required: usage: {}", command_, name, usage_);
  return get(name);
}

std::vector<std::string> CliArgs::all(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

long long CliArgs::integer(const std::string& name) const {
  const OptionSpec& o = spec(name);
  const long long lo = o.min_value, hi = o.max_value;
  const std::string v = get(name);
  long long x = 0;
  auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size())
    input_error("pcrt {}: --{} '{}' is not an integer", command_, name, v);
  if (x < lo || x > hi)
    input_error("pcrt {}: --{} {} is outside [{}, {}]", command_, name, x, lo, hi);
  return x;
}

double CliArgs::number(const std::string& name) const {
  return parse_number(get(name), fmt::format("pcrt {}: --{}", command_, name));
}

std::string CliArgs::help() const {
  std::string h = fmt::format("usage: {}\n\noptions:\n", usage_);
  for (const auto& o : options_) {
    const std::string left =
        o.value_name.empty() ? "--" + o.name : fmt::format("--{} {}", o.name, o.value_name);
    const std::string dflt =
        o.default_value.empty() ? "" : fmt::format(" (default {})", o.default_value);
    h += fmt::format("  {:<26} {}{}\n", left, o.help, dflt);
  }
  h += fmt::format("  {:<26} {}\n", "--help", "show this help");
  return h;
}

}  // namespace pcrt
