#include "harness/run_child.hpp"

#include <unistd.h>

#include <filesystem>

#include "core/error.hpp"
#include "harness/subprocess.hpp"

namespace pcrt {

RunResult run_in_child(const RunSpec& spec, double time_limit_s) {
  const std::string exe = std::filesystem::read_symlink("/proc/self/exe").string();
  // The child learns who its sweep is, so that it dies with it (command_run_one). The kernel's
  // parent-death signal follows the spawning thread: runs are spawned from the sweep's own thread.
  CommandOutput out;
  try {
    out = run_command({exe, "_run", json(spec).dump(), std::to_string(getpid())}, time_limit_s);
  } catch (const InputError& e) {
    input_error("sweep: {}", e.what());
  }
  RunResult r = failed_run(spec, RunStatus::kFailed, "");
  if (out.timed_out) {
    r = failed_run(spec, RunStatus::kTimeout,
                   fmt::format("exceeded the time limit of {} s", time_limit_s));
  } else if (out.exit_code == 0) {
    try {
      r = json::parse(out.out).get<RunResult>();
    } catch (const std::exception&) {  // json's own exceptions or InputError
      r.error = "the run printed no valid JSON";
    }
  } else {
    if (out.signal)
      r = killed_run(spec, out.signal);
    else
      r.error = last_line(out.err);
  }
  r.wall_s = out.wall_s;
  return r;
}

}  // namespace pcrt
