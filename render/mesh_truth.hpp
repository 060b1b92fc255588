// Point clouds sampled on a triangle mesh, the input of `pcrt accuracy --truth MESH`: points by
// area (the generators' sampler), optionally scanner-like (Gaussian noise in units of the spacing
// h, density falling across the object, normals estimated by PCA or absent).
#pragma once

#include <cstdint>
#include <string>

#include "core/counters.hpp"
#include "core/point_cloud.hpp"
#include "core/surfaces.hpp"

namespace pcrt {

enum class NormalSource : uint8_t { kExact, kEstimated, kNone };

struct MeshSampling {
  size_t n = 100000;
  uint64_t seed = 1;
  double noise_h = 0;  // standard deviation of the position noise, in h
  double density = 0;  // density falls linearly along x from 1 to 1 - density
  NormalSource normals = NormalSource::kExact;
  size_t normal_k = 16;  // neighbours of a PCA normal (kEstimated)
};

// "n=..,seed=..,noise=..,density=..,normals=exact|estimated|none" (any subset, any order).
// Throws InputError naming the spec for unknown keys and bad or out-of-range values.
MeshSampling parse_mesh_sampling(const std::string& spec);
[[nodiscard]] std::string describe(const MeshSampling& s);

struct SampledCloud {
  PointCloud cloud;
  double spacing = 0;  // h of the noise-free samples (noise would inflate it)
};

// Samples the cloud; counts the k-NN work of the spacing and normal estimation into `counters`.
SampledCloud sample_cloud(const Surface& truth, const MeshSampling& s, const std::string& name,
                          OpCounters& counters);

}  // namespace pcrt
