// The pcrt commands. Each takes its options struct (command_options.hpp, filled by the command
// line in cli.cpp) and returns the process exit code; InputError escapes to main, which prints it
// on one line.
#pragma once

#include "harness/command_options.hpp"

namespace pcrt {

int command_info(const InfoOptions& o);
int command_render(const RenderOptions& o);
int command_trace(const TraceOptions& o);
int command_furnace(const FurnaceOptions& o);
int command_list(const ListOptions& o);
int command_convert(const ConvertOptions& o);
int command_accuracy(const AccuracyOptions& o);
int command_compare(const CompareOptions& o);
int command_anchor(const AnchorOptions& o);
int command_reconstruct(const ReconstructOptions& o);
int command_crossover(const CrossoverOptions& o);
int command_sweep(const SweepOptions& o);
int command_merge(const MergeOptions& o);
int command_fit(const FitOptions& o);
int command_report(const ReportOptions& o);
int command_calibrate(const CalibrateOptions& o);
int command_check(const CheckOptions& o);
int command_cluster_submit(const ClusterSubmitOptions& o);
int command_cluster_status(const ClusterStatusOptions& o);
int command_run_one(const RunOneOptions& o);

}  // namespace pcrt
