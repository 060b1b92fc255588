#include "harness/csv_table.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/file_output.hpp"

namespace pcrt {

std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number_float()) {
    const double d = v.get<double>();
    return std::isfinite(d) ? fmt::format("{:.9g}", d) : "";  // JSON has no inf: null there
  }
  if (!v.is_string()) return v.dump();
  const std::string s = v.get<std::string>();
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<json>& rows) {
  write_file_atomically(path, [&](std::ostream& o) {
    for (size_t i = 0; i < columns.size(); ++i) o << (i ? "," : "") << csv_cell(columns[i]);
    o << '\n';
    for (const json& row : rows) {
      for (size_t i = 0; i < columns.size(); ++i)
        o << (i ? "," : "") << csv_cell(row.value(columns[i], json(nullptr)));
      o << '\n';
    }
  });
}

}  // namespace pcrt
