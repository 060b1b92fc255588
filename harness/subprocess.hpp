// Child processes without a shell (no argument needs quoting): git, python3, Slurm's commands, and
// the child process each sweep run executes in.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace pcrt {

struct CommandOutput {
  int exit_code = -1;  // 128 + the signal when a signal ended it
  int signal = 0;      // the signal that ended it, 0 if it exited
  bool timed_out = false;
  std::string out, err;
  double wall_s = 0;
};

// Runs argv (argv[0] found on PATH unless it names a path) with stdin from /dev/null, reads its
// output, and waits for it; after `time_limit_s` it is killed (SIGKILL) and `timed_out` set.
// InputError if it cannot start.
CommandOutput run_command(const std::vector<std::string>& argv,
                          double time_limit_s = std::numeric_limits<double>::infinity());

// The last non-empty line of `text` (a failed program's error line).
std::string last_line(std::string text);

}  // namespace pcrt
