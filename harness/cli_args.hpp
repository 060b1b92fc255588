// Strict command-line options: every option is declared with its help text; anything undeclared,
// a missing value or a malformed number is an InputError naming the option.
#pragma once

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
};

class CliArgs {
 public:
  CliArgs(std::string command, std::string usage, std::vector<OptionSpec> options,
          size_t min_positional, size_t max_positional);
  // Throws InputError for anything malformed; returns false if --help was asked (help printed).
  bool parse(const std::vector<std::string>& args);

  [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) > 0; }
  [[nodiscard]] std::string get(const std::string& name, const std::string& fallback = "") const;
  [[nodiscard]] std::string require(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> all(const std::string& name) const;
  [[nodiscard]] long long integer(const std::string& name, long long fallback, long long lo,
                                  long long hi) const;
  [[nodiscard]] double number(const std::string& name, double fallback) const;
  [[nodiscard]] const std::vector<std::string>& positional() const { return positional_; }
  [[nodiscard]] std::string help() const;

 private:
  std::string command_, usage_;
  std::vector<OptionSpec> options_;
  size_t min_pos_, max_pos_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace pcrt
