#include "harness/run_files.hpp"

#include <filesystem>
#include <optional>
#include <set>

#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/json_input.hpp"
#include "core/point_cloud_io.hpp"
#include "harness/csv_table.hpp"
#include "harness/run_quantity.hpp"

namespace pcrt {

RunsFile read_runs_file(const std::string& path) {
  if (!std::filesystem::exists(path)) input_error("{}: cannot open: no such file", path);
  // Bounded (runs.jsonl may be a link to a device); a running sweep may be appending to it (pcrt
  // cluster status reads the shards' while they run): what was there when reading began.
  const std::string text = read_file(path, kMaxStreamBytes, FileGrowth::kSnapshot);
  RunsFile file;
  file.torn_tail = !text.empty() && text.back() != '\n';
  size_t n = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    const bool last = end == std::string::npos || end + 1 == text.size();
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++n;
    if (line.empty()) continue;
    json j;
    try {
      j = parse_json_text(line, fmt::format("{}: line {}", path, n));
    } catch (const InputError&) {
      if (!last) input_error("{}: line {} is not valid JSON", path, n);
      file.torn_tail = true;
      break;
    }
    try {
      file.runs.push_back(j.get<RunResult>());
    } catch (const std::exception& e) {  // json's own exceptions or InputError
      input_error("{}: line {} is not a run result: {}", path, n, e.what());
    }
  }
  return file;
}

std::vector<RunResult> read_runs_jsonl(const std::string& path) {
  return read_runs_file(path).runs;
}

void write_runs_jsonl(const std::string& path, const std::vector<RunResult>& results) {
  write_file_atomically(path, [&](std::ostream& o) {
    for (const RunResult& r : results) o << json(r).dump() << '\n';
  });
}

void append_run(const std::string& path, const RunResult& result) {
  append_line(path, json(result).dump());
}

namespace {

json optional_json(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json optional_set(const RunResult& r, const char* name) {
  return r.spec.set.count(name) ? json(r.spec.set.at(name)) : json(nullptr);
}

}  // namespace

json run_row(const RunResult& r) {
  const json spec = r;  // the result as written: spec keys with the measured N and M
  json row = json::object();
  for (const char* k : {"experiment", "kind", "method", "structure", "dataset", "reconstruction",
                        "engine", "workload", "status", "error"})
    row[k] = spec.value(k, json(""));
  for (const char* k : {"N", "M", "S", "B"}) row[k] = spec.value(k, json(nullptr));
  if (!r.spec.scene.empty()) row["scene"] = r.spec.scene;  // a column only where a sweep has one
  row["K"] = optional_json(k_of(r));
  row["k"] = optional_set(r, "k");
  row["I"] = optional_set(r, "max_iterations");
  row["I_run"] = optional_json(iterations_per_run(r));
  row["H"] = optional_json(hits_per_ray(r));
  for (const auto& [k, v] : r.spec.set) row["set_" + k] = v;
  for (const auto& [k, v] : r.counters) row["ops_" + k] = v;
  if (r.prepare_counters)
    for (const auto& [k, v] : *r.prepare_counters) row["ops_prep_" + k] = v;
  for (const char* k : {"time_median_s", "time_min_s", "time_max_s", "time_spread"})
    row[k] = spec.value(k, json(nullptr));
  // Flagged, never dropped: repetitions more than 20% apart.
  row["time_noisy"] = r.times_s.size() > 1 && spec.value("time_spread", 0.0) > 0.2;
  const json measures = r.measures;
  for (const auto& [k, v] : measures.items()) row[k] = v;
  return row;
}

namespace {

// The identity columns first, then parameters, counters, times and the rest, each alphabetically,
// then status and error.
std::vector<std::string> csv_columns(const std::vector<json>& rows) {
  std::vector<std::string> columns = {
      "experiment", "kind",     "method", "structure", "dataset", "reconstruction",
      "engine",     "workload", "N",      "M",         "S",       "B",
      "K",          "k",        "I",      "I_run"};
  std::set<std::string> seen(columns.begin(), columns.end()), rest;
  for (const json& row : rows)
    for (const auto& [k, v] : row.items())
      if (!seen.count(k)) rest.insert(k);
  auto starts = [](const std::string& k, const char* prefix) { return k.rfind(prefix, 0) == 0; };
  for (const char* prefix : {"set_", "ops_", "time_"})
    for (const std::string& k : rest)
      if (starts(k, prefix)) columns.push_back(k);
  for (const std::string& k : rest)
    if (!starts(k, "set_") && !starts(k, "ops_") && !starts(k, "time_") && k != "status" &&
        k != "error")
      columns.push_back(k);
  columns.push_back("status");
  columns.push_back("error");
  return columns;
}

}  // namespace

void write_runs_csv(const std::string& path, const std::vector<RunResult>& results) {
  std::vector<json> rows;
  for (const RunResult& r : results) rows.push_back(run_row(r));
  write_csv(path, csv_columns(rows), rows);
}

}  // namespace pcrt
