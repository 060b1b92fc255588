// The one CSV writer of the harness (runs.csv, fits.csv): RFC 4180 quoting (a cell with a comma, a
// quote or a line break is quoted, quotes doubled), null and non-finite numbers as an empty cell
// (the JSON files hold null there), floating-point numbers with 9 significant digits (the JSON
// files hold every digit), other values as JSON writes them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pcrt {

using nlohmann::json;

std::string csv_cell(const json& value);
// A header of `columns`, then one line per row (a JSON object; absent columns are empty cells).
void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<json>& rows);

}  // namespace pcrt
