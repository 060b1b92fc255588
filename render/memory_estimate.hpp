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
// What a structure adds per item at the process's peak (its build or its final arrays with the
// method's leaf data): with the disc blocks adapted in item order (also the figure for methods
// without disc blocks) or copied in leaf order, and the leaf references it stores per item.
struct StructureFootprint {
  size_t item_order = 0;
  size_t leaf_order = 0;
  double references_per_item = 1;
  // For methods without disc blocks, whose items a structure keeps by their boxes alone (no disc
  // plane test, ItemSet::hits_on_discs); 0: as item_order.
  size_t by_boxes = 0;
};
// The structure's own parameters count where they change its bytes (the octree's compact_refs);
// none given: its defaults.
StructureFootprint structure_footprint(const std::string& structure,
                                       const ParamValues& structure_params = {});
// The footprint for the layout the method's parameters choose (disc_blocks; none: item order).
size_t structure_bytes_per_item(const std::string& structure, const ParamValues& method_params,
                                const ParamValues& structure_params = {});
// Both, for the cloud's size.
size_t estimate_scene_bytes(const MethodInfo& method, const std::string& structure,
                            const PointCloud& cloud, const ParamValues& method_params,
                            const ParamValues& structure_params = {});

}  // namespace pcrt
