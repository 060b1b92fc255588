// Datasets by name: a generator spec such as `sphere:n=100000,seed=1,noise=0.001` or a file path.
// Generated clouds carry exact normals and the exact Surface they were drawn from.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "core/surfaces.hpp"

namespace pcrt {

struct Dataset {
  PointCloud cloud;
  std::shared_ptr<const Surface> truth;  // null for files
};

struct GeneratorInfo {
  std::string name;
  std::string description;
  std::vector<ParamSpec> params;  // the common ones (n, seed, noise, density) come first
};

const std::vector<GeneratorInfo>& generators();

// Loads a file if `spec` names one, else parses and runs a generator, and puts the cloud in Morton
// order (core/morton.hpp): point i of the result is not the input's point i. Throws InputError
// naming the spec for unknown generators, unknown keys, malformed or out-of-range values.
Dataset load_dataset(const std::string& spec);
// The same in the file's or the generator's own order (tests of order independence, convert).
Dataset load_dataset_in_input_order(const std::string& spec);

// n points drawn uniformly by area from `surface` with its exact normals, thinned so that density
// falls linearly along x from 1 to 1 - density, moved by isotropic Gaussian noise of standard
// deviation `noise` (absolute): what every surface generator does.
PointCloud sample_surface(const Surface& surface, size_t n, uint64_t seed, double noise,
                          double density, const std::string& name);

// Parses `name:key=value,...` into the generator's full parameter set (defaults filled in).
ParamValues parse_generator_spec(const std::string& spec, const GeneratorInfo** info);

}  // namespace pcrt
