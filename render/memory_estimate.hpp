// The memory a method on a structure will add to a loaded cloud, estimated before it prepares or
// builds anything, so that a run that will not fit stops with the estimate instead of being
// killed. A model of the data layouts (per point: the prepared per-point arrays, their build
// scratch, the structure at its build peak), checked against measured peaks by the scale
// benchmark (results/scale/).
#pragma once

#include <cstddef>
#include <string>

#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/method.hpp"

namespace pcrt {

// Bytes per point the method's prepare step holds at its peak, besides the cloud.
size_t prepared_bytes_per_point(const MethodInfo& method, const PointCloud& cloud,
                                const ParamValues& method_params);
// Bytes per item the structure holds at its build peak.
size_t structure_bytes_per_item(const std::string& structure);
// Leaf references per item the structure stores (the entries of data a method lays out in leaf
// order, such as reference_splat's disc blocks: one slot per reference).
double structure_references_per_item(const std::string& structure);
// Both, for the cloud's size.
size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params);

}  // namespace pcrt
