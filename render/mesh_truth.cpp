#include "render/mesh_truth.hpp"

#include <random>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/morton.hpp"
#include "core/params.hpp"
#include "core/rng.hpp"
#include "preprocess/point_attributes.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {
namespace {

const char* normal_source_name(NormalSource s) {
  switch (s) {
    case NormalSource::kExact:
      return "exact";
    case NormalSource::kEstimated:
      return "estimated";
    case NormalSource::kNone:
      return "none";
  }
  return "?";
}

NormalSource parse_normal_source(const std::string& text, const std::string& spec) {
  for (NormalSource s : {NormalSource::kExact, NormalSource::kEstimated, NormalSource::kNone})
    if (text == normal_source_name(s)) return s;
  input_error("--sample '{}': normals must be exact, estimated or none, not '{}'", spec, text);
}

const std::vector<ParamSpec>& numeric_specs() {
  static const std::vector<ParamSpec> specs = {
      {"n", 100000, 10, 2e8, "points sampled by area", true},
      {"seed", 1, 0, 1e18, "random seed", true},
      {"noise", 0, 0, 100, "standard deviation of Gaussian position noise, in h"},
      {"density", 0, 0, 0.99, "density falls linearly along x from 1 to 1-density"}};
  return specs;
}

}  // namespace

MeshSampling parse_mesh_sampling(const std::string& spec) {
  MeshSampling s;
  ParamValues given;
  size_t pos = 0;
  while (!spec.empty() && pos <= spec.size()) {
    size_t comma = spec.find(',', pos);
    if (comma == std::string::npos) comma = spec.size();
    const std::string item = spec.substr(pos, comma - pos);
    pos = comma + 1;
    const size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      input_error("--sample '{}': '{}' is not key=value", spec, item);
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    if (given.count(key)) input_error("--sample '{}': '{}' given twice", spec, key);
    if (key == "normals") {
      s.normals = parse_normal_source(value, spec);
      given[key] = 0;
      continue;
    }
    given[key] = parse_number(value, fmt::format("--sample '{}': {}", spec, key));
  }
  given.erase("normals");
  const ParamValues p = resolve_params(numeric_specs(), given, fmt::format("--sample '{}'", spec));
  s.n = size_t(p.at("n"));
  s.seed = uint64_t(p.at("seed"));
  s.noise_h = p.at("noise");
  s.density = p.at("density");
  return s;
}

namespace {

// Gaussian noise of s.noise_h spacings, from its own stream (the noise does not change which
// points are drawn) and drawn in the sampler's order (point k's is draw order[k]), so that the
// noisy cloud is the same set of points whatever order it is kept in; then Morton-ordered again by
// its noisy positions, as a loaded cloud would be.
void add_noise(PointCloud& c, const std::vector<uint32_t>& order, const MeshSampling& s,
               double spacing, const std::string& name) {
  std::mt19937_64 engine(mix64(s.seed ^ 0x6e6f697365ull));
  std::normal_distribution<double> gauss(0.0, s.noise_h * spacing);
  std::vector<Vec3> noise(c.size());
  for (Vec3& x : noise) x = Vec3(float(gauss(engine)), float(gauss(engine)), float(gauss(engine)));
  for (size_t k = 0; k < c.size(); ++k) c.positions[k] += noise[order[k]];
  std::vector<Vec3>().swap(noise);
  require_memory(morton_sort_bytes(c.size()), name);
  morton_sort(c);
}

}  // namespace

std::string describe(const MeshSampling& s) {
  return fmt::format("n={},seed={},noise={},density={},normals={}", s.n, s.seed, s.noise_h,
                     s.density, normal_source_name(s.normals));
}

SampledCloud sample_cloud(const Surface& truth, const MeshSampling& s, const std::string& name,
                          OpCounters& counters) {
  SampledCloud out;
  out.cloud = sample_surface(truth, s.n, s.seed, 0.0, s.density, name);
  PointCloud& c = out.cloud;
  c.origin = truth.origin();
  // In Morton order like every loaded cloud (core/morton.hpp), so that the k-NN passes here and
  // everything downstream walk memory coherently.
  require_memory(morton_sort_bytes(c.size()), name);
  const std::vector<uint32_t> order = morton_sort(c);
  const KnnIndex clean(c.positions);
  out.spacing = mean_spacing(c.positions, clean, counters);
  if (s.noise_h > 0) add_noise(c, order, s, out.spacing, name);
  if (s.normals == NormalSource::kEstimated) {
    const KnnIndex noisy(c.positions);
    c.normals = estimate_normals(c.positions, noisy, s.normal_k, counters);
  } else if (s.normals == NormalSource::kNone) {
    c.normals.clear();
  }
  return out;
}

}  // namespace pcrt
