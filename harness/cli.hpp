// The pcrt command line: CLI11 subcommands, each bound to its command's options struct
// (command_options.hpp). CLI11 is included by cli.cpp alone; this header does not need it.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace pcrt {

struct AllOptions;  // harness/command_options.hpp (not included: main.cpp need not compile it)

class CommandLine {
 public:
  CommandLine();
  ~CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  // Parses the arguments after the program's name into options(). Returns false when help was
  // asked (`--help` anywhere, or `pcrt help`): help() then has it. Throws InputError, naming the
  // option and its value, for anything malformed: an unknown command or option, a value missing,
  // given twice, not a number or outside its range, a required option or argument missing.
  bool parse(const std::vector<std::string>& args);
  // Runs the command parsed; its exit status.
  int run() const;
  // The command recognised so far, e.g. "render" or "cluster submit" (empty: none), which an
  // error message names.
  [[nodiscard]] std::string command() const;
  // `pcrt --help`, or the recognised command's help.
  [[nodiscard]] std::string help() const;
  [[nodiscard]] const AllOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcrt
