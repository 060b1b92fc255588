// The datasets of sweep runs: a generator spec gets its N appended, a file dataset gives N points
// drawn from it; relative file names resolve against the config's folder.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/point_cloud.hpp"

namespace pcrt {

// Whether `dataset` names a generator ("sphere", "torus:r=0.3") rather than a file.
bool is_generator(const std::string& dataset);
// Whether a generator spec gives n itself (a sweep appends N to it).
bool sets_n(const std::string& spec);
// A file dataset named relative to the config resolves against `dataset_dir` (empty: the current
// folder); generator specs and absolute paths stay as given.
std::string dataset_path(const std::string& dataset, const std::string& dataset_dir);
// The cloud of a run: a generator at N points, or N points drawn from a file without replacement
// (seeded, so every run of the same spec sees the same subset); without N, the whole file or the
// generator's default size.
PointCloud run_cloud(const std::string& dataset, std::optional<double> n, uint64_t seed);

}  // namespace pcrt
