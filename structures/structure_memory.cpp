// Peak memory of one structure build, apart from the rest of a render (whose peak the method's
// own data sets): builds STRUCTURE over a generated sphere of N points with splat footprints like
// reference_splat's (radius 2.4 mean spacings, fixed analytically; disc boxes of half extents
// r sqrt(1 - n_a^2)) and prints one JSON line: resident bytes before the build, the build's peak
// above them (VmHWM, reset through /proc/self/clear_refs just before), what stays resident after
// it, the structure's memory_bytes() and its leaf references, each also per item.
// Usage: pcrt_structure_memory STRUCTURE N
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>

#include "core/dataset.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "structures/structure.hpp"

namespace pcrt {
namespace {

// A field of /proc/self/status in bytes (VmRSS, VmHWM).
size_t status_bytes(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field + ":", 0) == 0)
      return size_t(std::stoull(line.substr(field.size() + 1))) * 1024;
  return 0;
}

void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

int run(const std::string& id, size_t n) {
  PointCloud cloud = load_dataset(fmt::format("sphere:n={},seed=1", n)).cloud;
  const float r = 1.2f * std::sqrt(4.0f * 3.14159265f / float(n));
  std::vector<float> radii(n, r);
  // Discs hit only on the disc and tested a block at a time, as reference_splat's
  // (ItemSet::hits_on_discs, ItemSet::leaf_block).
  ItemSet items{cloud.positions, radii, {}, cloud.normals, true};
  items.leaf_block = kDiscGroup;
  const StructureInfo& info = StructureRegistry::instance().get(id, "structure");
  auto structure = info.create(resolve_params(info.params, {}, id));
  OpCounters counters;
  const size_t before = status_bytes("VmRSS");
  reset_peak();
  structure->build(items, counters);
  const size_t peak = status_bytes("VmHWM"), after = status_bytes("VmRSS");
  const size_t kept = structure->memory_bytes();
  const auto per = [&](size_t b) { return double(b) / double(n); };
  fmt::print(
      "{{\"structure\": \"{}\", \"N\": {}, \"rss_before\": {}, \"build_peak_above\": {}, "
      "\"kept_above\": {}, \"memory_bytes\": {}, \"build_peak_per_item\": {:.2f}, "
      "\"kept_per_item\": {:.2f}, \"memory_bytes_per_item\": {:.2f}, "
      "\"references_per_item\": {:.3f}}}\n",
      id, n, before, peak - before, after - before, kept, per(peak - before), per(after - before),
      per(kept), per(counters.get(kBuildItemRefs)));
  return 0;
}

}  // namespace
}  // namespace pcrt

namespace {

// N as a whole number of points, all of the argument (std::stoull takes "-5", "1e99" and "12x").
std::optional<size_t> point_count(const char* text) {
  size_t n = 0;
  const char* end = text + std::strlen(text);
  const auto [p, ec] = std::from_chars(text, end, n);
  if (ec != std::errc() || p != end || n == 0) return std::nullopt;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: pcrt_structure_memory STRUCTURE N\n");
    return 1;
  }
  try {
    const std::optional<size_t> n = point_count(argv[2]);
    if (!n) {
      std::fprintf(stderr, "pcrt_structure_memory: N '%s' is not a whole number of points\n",
                   argv[2]);
      return 1;
    }
    return pcrt::run(argv[1], *n);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcrt_structure_memory: %s\n", e.what());
    return 1;
  }
}
