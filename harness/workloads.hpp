// Workloads of known complexity that validate the fitter through the same sweep and fit path as
// the methods (`pcrt calibrate`): std::sort (N log N), std::nth_element (N), binary search
// (log N per lookup), a triple loop (N^3) and a hash lookup (1 per lookup). Each counts its
// elementary operations (comparisons, multiply-adds, equality probes) exactly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/counters.hpp"
#include "harness/claims.hpp"

namespace pcrt {

inline const Counter kWorkloadOperations{"workload_operations",
                                         "elementary operations of a calibration workload"};

struct WorkloadInfo {
  std::string id;
  Growth expected;
  std::string complexity;     // as a claim, e.g. "O(N log N)"
  std::vector<double> sizes;  // the N swept by `pcrt calibrate`
};

const std::vector<WorkloadInfo>& workloads();
// Runs workload `id` at size n (deterministic input from `seed`), counting into `counters`;
// returns the seconds of the measured part alone (input generation and set-up excluded).
double run_workload(const std::string& id, size_t n, uint64_t seed, OpCounters& counters);

}  // namespace pcrt
