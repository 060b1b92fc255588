// The pcrt subcommands. Each takes its arguments (after the subcommand name) and returns the
// process exit code; InputError escapes to main, which prints it on one line.
#pragma once

#include <string>
#include <vector>

namespace pcrt {

using Args = std::vector<std::string>;
int command_info(const Args& args);
int command_render(const Args& args);
int command_trace(const Args& args);
int command_list(const Args& args);
int command_convert(const Args& args);
int command_accuracy(const Args& args);
int command_compare(const Args& args);
int command_anchor(const Args& args);
int command_reconstruct(const Args& args);
int command_crossover(const Args& args);
int command_sweep(const Args& args);
int command_merge(const Args& args);
int command_fit(const Args& args);
int command_report(const Args& args);
int command_calibrate(const Args& args);
int command_check(const Args& args);
int command_cluster(const Args& args);
int command_run_one(const Args& args);

}  // namespace pcrt
