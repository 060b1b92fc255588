// What a sweep's numbers were made on (DIR/context.json): the machine, the build (build_info),
// the source revision and the config.
#pragma once

#include <nlohmann/json.hpp>

namespace pcrt {

using nlohmann::json;

json machine_context(const json& config);

}  // namespace pcrt
