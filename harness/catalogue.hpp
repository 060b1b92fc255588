// Everything registered, as one JSON document: methods, structures, generators, reconstructions,
// mesh engines, claims and counters. The one serialisation of the registries: `pcrt list --json`
// prints it and the Python module's pcrt.methods() and pcrt.structures() return its lists.
#pragma once

#include <nlohmann/json.hpp>

namespace pcrt {

nlohmann::json catalogue_json();

}  // namespace pcrt
