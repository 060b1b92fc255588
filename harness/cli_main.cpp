#include "harness/cli_main.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "harness/cli.hpp"

namespace {

// One line whatever a message quotes (a path with a newline, bytes from a file): control
// characters and backslashes are printed as C escapes.
std::string escaped(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else if (c == '\t')
      out += "\\t";
    else if (c == '\r')
      out += "\\r";
    else if (c < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", c);
    else
      out += char(c);
  }
  return out;
}

// What an out-of-memory error names: the values of the input options, the leading positional
// argument (a file, directory or generator spec) and the other arguments that are existing files
// or directories, outputs excepted.
std::string inputs_of(const std::vector<std::string>& args) {
  auto follows = [&](size_t i, std::initializer_list<const char*> options) {
    return i > 0 && std::any_of(options.begin(), options.end(),
                                [&](const char* o) { return args[i - 1] == o; });
  };
  std::string names;
  for (size_t i = 0; i < args.size(); ++i) {
    std::error_code ec;
    const bool input =
        follows(i, {"--data", "--truth", "--mesh", "--rays", "--config", "--baseline"}) ||
        (i == 0 && args[i].rfind("--", 0) != 0) ||
        (args[i].rfind("--", 0) != 0 && !follows(i, {"--out", "--stats", "--depth", "--normals"}) &&
         std::filesystem::exists(args[i], ec));
    if (input) names += (names.empty() ? "" : ", ") + args[i];
  }
  return names;
}

// "pcrt CMD: error: WHAT" on one line ("pcrt: error: WHAT" before a command is recognised).
int fail(const std::string& cmd, const std::string& what) {
  const std::string who = cmd.empty() ? "pcrt" : "pcrt " + escaped(cmd);
  std::fprintf(stderr, "%s: error: %s\n", who.c_str(), escaped(what).c_str());
  return 1;
}

// The arguments after the command's name (for "cluster submit", after both words).
std::vector<std::string> after_command(const std::vector<std::string>& args,
                                       const std::string& cmd) {
  const auto words = cmd.empty() ? 0 : std::count(cmd.begin(), cmd.end(), ' ') + 1;
  return {args.begin() + std::min<std::ptrdiff_t>(words, std::ssize(args)), args.end()};
}

}  // namespace

int pcrt::cli_main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  pcrt::CommandLine line;
  if (args.empty()) {
    std::fputs(line.help().c_str(), stderr);
    return 1;
  }
  try {
    if (!line.parse(args)) {
      std::fputs(line.help().c_str(), stdout);
      return 0;
    }
    pcrt::NoteHold notes;  // printed after a command that ran to its end, dropped on an error
    const int status = line.run();
    notes.print();
    return status;
  } catch (const pcrt::InputError& e) {
    // Messages that already name the command are not prefixed twice.
    const std::string cmd = line.command();
    std::string what = e.what();
    const std::string own = "pcrt " + cmd + ": ";
    if (what.rfind(own, 0) == 0) what.erase(0, own.size());
    return fail(cmd, what);
  } catch (const std::bad_alloc&) {
    const std::string cmd = line.command();
    const std::string inputs = inputs_of(after_command(args, cmd));
    return fail(cmd, inputs.empty()
                         ? "out of memory (the input is too large for this machine)"
                         : "out of memory: " + inputs + " is too large for this machine");
  } catch (const std::exception& e) {
    const std::string cmd = line.command();
    std::fprintf(stderr, "pcrt %s: internal error: %s\n", escaped(cmd).c_str(),
                 escaped(e.what()).c_str());
    return 3;
  }
}
