// JSON written by someone else (sweep configs, baselines, a sweep's context.json and runs.jsonl):
// parsed with a nesting limit, so a hostile file can neither overflow the stack (nlohmann's
// values copy and compare recursively) nor make a written copy grow quadratically; NUL bytes and
// anything but whitespace after the value are errors.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace pcrt {

// Deeper than any config pcrt writes or reads (they nest about 6 levels).
inline constexpr size_t kMaxJsonDepth = 64;

// Throws InputError naming `source` (a file, or a file and line) and the line of the problem.
nlohmann::json parse_json_text(std::string_view text, const std::string& source);
// read_file (bounded, directories rejected) then parse_json_text.
nlohmann::json read_json_file(const std::string& path);

// An optional member of an object someone else wrote: `fallback` when absent, else its value.
// Present with another type is an InputError naming `where` and the key (nlohmann's value()
// would throw its own type_error, which names neither).
std::string optional_string(const nlohmann::json& obj, const char* key, const std::string& fallback,
                            const std::string& where);
double optional_number(const nlohmann::json& obj, const char* key, double fallback,
                       const std::string& where);

}  // namespace pcrt
