#include "harness/sweep_datasets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"

namespace pcrt {

namespace fs = std::filesystem;

bool is_generator(const std::string& dataset) {
  const std::string name = dataset.substr(0, dataset.find(':'));
  for (const auto& g : generators())
    if (g.name == name) return true;
  return false;
}

bool sets_n(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) return false;
  return spec.find(":n=") == colon || spec.find(",n=", colon) != std::string::npos;
}

std::string dataset_path(const std::string& dataset, const std::string& dataset_dir) {
  if (is_generator(dataset) || dataset_dir.empty() || fs::path(dataset).is_absolute())
    return dataset;
  return (fs::path(dataset_dir) / dataset).lexically_normal().string();
}

namespace {

std::string generator_spec(const std::string& base, double n) {
  return base + (base.find(':') == std::string::npos ? ":" : ",") +
         "n=" + std::to_string(static_cast<long long>(n));
}

}  // namespace

PointCloud run_cloud(const std::string& dataset, std::optional<double> n, uint64_t seed) {
  if (is_generator(dataset)) {
    // A replicate draws its own points; a seed the dataset names wins.
    std::string spec = n ? generator_spec(dataset, *n) : dataset;
    if (seed != 1 && dataset.find("seed=") == std::string::npos)
      spec += fmt::format("{}seed={}", spec.find(':') == std::string::npos ? ':' : ',', seed);
    return load_dataset(spec).cloud;
  }
  PointCloud full = load_dataset(dataset).cloud;
  const size_t want = n ? static_cast<size_t>(*n) : full.size();
  if (want > full.size())
    input_error("{}: N = {} but the file has {} points", dataset, want, full.size());
  if (want == full.size()) return full;
  std::vector<uint32_t> idx(full.size());
  for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  Rng rng(seed, 0x5ab5);
  for (size_t i = 0; i < want; ++i) std::swap(idx[i], idx[i + rng.below(uint32_t(idx.size() - i))]);
  idx.resize(want);
  std::sort(idx.begin(), idx.end());
  return full.subset(idx);
}

}  // namespace pcrt
