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
#include "structures/structure.hpp"

namespace pcrt {

// Bytes per point the method's prepare step holds at its peak, besides the cloud.
size_t prepared_bytes_per_point(const MethodInfo& method, const PointCloud& cloud,
                                const ParamValues& method_params);
// The footprint the structure declares (StructureInfo::footprint) for its parameters (none
// given: its defaults); a structure of a method's own, not in the registry, is priced at 80 bytes.
StructureFootprint structure_footprint(const std::string& structure,
                                       const ParamValues& structure_params = {});
// The footprint for the layout the method's parameters choose for this many items (disc_blocks;
// none: item order).
size_t structure_bytes_per_item(const std::string& structure, size_t items,
                                const ParamValues& method_params,
                                const ParamValues& structure_params = {});
// Both, for the cloud's size.
size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params,
                            const ParamValues& structure_params = {});

}  // namespace pcrt
