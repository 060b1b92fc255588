// Small pieces every command shares: JSON of parameters and counters, atomic JSON output, the
// --threads limit, options a command needs in one use.
#pragma once

#include <tbb/global_control.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/counters.hpp"
#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/params.hpp"

namespace pcrt {

using nlohmann::json;

inline json params_json(const std::vector<ParamSpec>& specs) {
  json a = json::array();
  for (const auto& p : specs)
    a.push_back({{"name", p.name},
                 {"default", p.default_value},
                 {"min", p.min_value},
                 {"max", p.max_value},
                 {"integer", p.integer},
                 {"description", p.description}});
  return a;
}

inline json counters_json(const OpCounters& c) {
  json j = json::object();
  for (const auto& [name, value] : c.to_map()) j[name] = value;
  return j;
}

// A writer owning its JSON, for OutputFiles::stage.
inline StreamWriter json_writer(json j) {
  return [j = std::move(j)](std::ostream& out) { out << j.dump(2) << '\n'; };
}

inline void write_json(const std::string& path, const json& j) {
  write_file_atomically(path, json_writer(j));
}

// --threads for every parallel phase (TBB's global limit); 0: all cores.
inline std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads == 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(threads));
}

// The value of an option this use of a command needs (--data without --mesh, say).
inline const std::string& required(const std::optional<std::string>& value, const char* option,
                                   const char* usage) {
  if (!value) input_error("{} is required: usage: {}", option, usage);
  return *value;
}

}  // namespace pcrt
