// Strict command-line options: every option is declared with its help text; anything undeclared,
// a missing value or a malformed number is an InputError naming the option.
#pragma once

#include <climits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pcrt {

struct OptionSpec {
  std::string name;        // without the leading "--"
  std::string value_name;  // empty for a flag
  std::string help;
  bool repeatable = false;
  // The default, written here only: --help shows it and get(), integer() and number() return it
  // when the option is not given. Empty: no default (or one described in the help text).
  std::string default_value = {};
  // The range an integer() value must lie in.
  long long min_value = LLONG_MIN, max_value = LLONG_MAX;
};

// An integer option with its default and range, declared once.
inline OptionSpec integer_option(std::string name, std::string value_name, std::string help,
                                 long long default_value, long long min_value,
                                 long long max_value) {
  return {std::move(name), std::move(value_name),         std::move(help),
          false,           std::to_string(default_value), min_value,
          max_value};
}

class CliArgs {
 public:
  CliArgs(std::string command, std::string usage, std::vector<OptionSpec> options,
          size_t min_positional, size_t max_positional);
  // Throws InputError for anything malformed; returns false if --help was asked (help printed).
  bool parse(const std::vector<std::string>& args);

  [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) > 0; }
  // The value given, else the option's declared default (else "").
  [[nodiscard]] std::string get(const std::string& name) const;
  [[nodiscard]] std::string require(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> all(const std::string& name) const;
  // The value given or the declared default, checked against the declared range.
  [[nodiscard]] long long integer(const std::string& name) const;
  // The value given or the declared default, a finite number.
  [[nodiscard]] double number(const std::string& name) const;
  [[nodiscard]] const std::vector<std::string>& positional() const { return positional_; }
  [[nodiscard]] std::string help() const;

 private:
  [[nodiscard]] const OptionSpec& spec(const std::string& name) const;

  std::string command_, usage_;
  std::vector<OptionSpec> options_;
  size_t min_pos_, max_pos_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace pcrt
