#include "harness/run_spec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>
#include <type_traits>

#include "core/error.hpp"

namespace pcrt {

const char* run_kind_name(RunKind k) {
  switch (k) {
    case RunKind::kRender:
      return "render";
    case RunKind::kBuild:
      return "build";
    case RunKind::kReconstruct:
      return "reconstruct";
    case RunKind::kWorkload:
      return "workload";
    case RunKind::kCrossover:
      return "crossover";
  }
  return "?";
}

std::optional<RunKind> run_kind_from_name(const std::string& name) {
  for (RunKind k : kAllRunKinds)
    if (name == run_kind_name(k)) return k;
  return std::nullopt;
}

const char* measure_mode_name(MeasureMode m) {
  switch (m) {
    case MeasureMode::kBoth:
      return "both";
    case MeasureMode::kOps:
      return "ops";
    case MeasureMode::kTime:
      return "time";
  }
  return "?";
}

std::optional<MeasureMode> measure_mode_from_name(const std::string& name) {
  for (MeasureMode m : {MeasureMode::kBoth, MeasureMode::kOps, MeasureMode::kTime})
    if (name == measure_mode_name(m)) return m;
  return std::nullopt;
}

bool runs_method(RunKind k) {
  return k == RunKind::kRender || k == RunKind::kBuild || k == RunKind::kCrossover;
}

namespace {

constexpr std::pair<const char*, std::optional<double> RunSpec::*> kGridVariables[] = {
    {"N", &RunSpec::N}, {"M", &RunSpec::M}, {"S", &RunSpec::S}, {"B", &RunSpec::B}};

// Specs and results are read back from files a user may have edited (runs.jsonl, plan files):
// each field is checked where it is read, and a wrong one is an InputError naming its key, never
// a json exception, a wrapped integer (-5000 as a count) or an undefined conversion (1e308).

std::string text_field(const json& j, const char* key, const std::string& fallback = "") {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_string()) input_error("\"{}\" = {} is not a string", key, j[key].dump());
  return j[key].get<std::string>();
}

// A whole number in [lo, hi] (hi >= 0), written as a JSON integer.
int64_t whole_field(const json& j, const char* key, int64_t fallback, int64_t lo, int64_t hi) {
  if (!j.contains(key)) return fallback;
  const json& v = j[key];
  // Unsigned first: a value beyond int64 must not wrap into the range.
  const bool whole =
      v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t(hi) : v.is_number_integer();
  const int64_t n = whole ? v.get<int64_t>() : 0;
  if (!whole || n < lo || n > hi)
    input_error("\"{}\" = {} is not a whole number from {} to {}", key, v.dump(), lo, hi);
  return n;
}

double number_field(const json& v, const std::string& what) {
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    input_error("{} = {} is not a finite number", what, v.dump());
  return v.get<double>();
}

std::map<std::string, double> numbers_field(const json& j, const char* key) {
  if (!j[key].is_object()) input_error("\"{}\" = {} is not an object", key, j[key].dump());
  std::map<std::string, double> out;
  for (const auto& [name, v] : j[key].items())
    out[name] = number_field(v, fmt::format("\"{}\".{}", key, name));
  return out;
}

// A grid variable: a whole number within the config's ranges (sweep_config.cpp).
std::optional<double> grid_field(const json& j, const char* key) {
  if (!j.contains(key)) return std::nullopt;
  static const std::map<std::string, std::pair<double, double>> kRange = {
      {"N", {1, 2e8}}, {"M", {1, 16384.0 * 16384.0}}, {"S", {1, 65536}}, {"B", {0, 64}}};
  const auto [lo, hi] = kRange.at(key);
  const double v = number_field(j[key], fmt::format("\"{}\"", key));
  if (!(v >= lo && v <= hi && v == std::floor(v)))
    input_error("\"{}\" = {} is not a whole number from {} to {}", key, j[key].dump(), lo, hi);
  return v;
}

}  // namespace

uint64_t count_from_json(const json& v, const std::string& what) {
  if (v.is_number_unsigned()) return v.get<uint64_t>();
  if (v.is_number_integer() && v.get<int64_t>() >= 0) return uint64_t(v.get<int64_t>());
  input_error("{} = {} is not a non-negative integer", what, v.dump());
}

// Keys appear only where the kind uses them, as the config expansion always wrote them: run keys
// of committed results and baselines stay the same.
void to_json(json& j, const RunSpec& s) {
  j = {{"experiment", s.experiment},
       {"kind", run_kind_name(s.kind)},
       {"reps", s.reps},
       {"warmup", s.warmup},
       {"threads", s.threads},
       {"seed", s.seed},
       {"measure", measure_mode_name(s.measure)}};
  if (s.camera_inside) j["camera"] = "inside";
  if (s.kind != RunKind::kWorkload) j["dataset"] = s.dataset;
  if (!s.dataset_path.empty()) j["dataset_path"] = s.dataset_path;
  if (!s.scene.empty()) j["scene"] = s.scene;
  if (!s.scene_path.empty()) j["scene_path"] = s.scene_path;
  if (runs_method(s.kind)) {
    j["method"] = s.method;
    j["structure"] = s.structure;
  }
  if (runs_method(s.kind) || !s.set.empty()) j["set"] = s.set;
  if (s.kind == RunKind::kReconstruct || s.kind == RunKind::kCrossover)
    j["reconstruction"] = s.reconstruction;
  if (s.kind == RunKind::kCrossover) j["engine"] = s.engine;
  if (s.kind == RunKind::kWorkload) j["workload"] = s.workload;
  for (const auto& [name, member] : kGridVariables)
    if (s.*member) j[name] = *(s.*member);
}

void from_json(const json& j, RunSpec& s) {
  if (!j.is_object()) input_error("a run spec is a JSON object");
  if (!j.contains("kind")) input_error("a run spec has its \"kind\"");
  const std::string kind = text_field(j, "kind");
  const std::optional<RunKind> k = run_kind_from_name(kind);
  if (!k) input_error("unknown run kind '{}'", kind);
  s = RunSpec{};
  s.kind = *k;
  s.experiment = text_field(j, "experiment");
  // The config's ranges (sweep_config.cpp): repetitions, warmup, threads.
  s.reps = int(whole_field(j, "reps", 1, 1, 1000));
  s.warmup = int(whole_field(j, "warmup", 0, 0, 100));
  s.threads = int(whole_field(j, "threads", 2, 1, 1024));
  if (j.contains("seed")) s.seed = count_from_json(j["seed"], "\"seed\"");
  const std::string measure = text_field(j, "measure", "both");
  const std::optional<MeasureMode> mode = measure_mode_from_name(measure);
  if (!mode) input_error("\"measure\" = \"{}\" is not ops, time or both", measure);
  s.measure = *mode;
  s.camera_inside = text_field(j, "camera") == "inside";
  s.dataset = text_field(j, "dataset");
  s.dataset_path = text_field(j, "dataset_path");
  s.scene = text_field(j, "scene");
  s.scene_path = text_field(j, "scene_path");
  s.method = text_field(j, "method");
  s.structure = text_field(j, "structure");
  s.reconstruction = text_field(j, "reconstruction");
  s.engine = text_field(j, "engine");
  s.workload = text_field(j, "workload");
  if (j.contains("set")) s.set = numbers_field(j, "set");
  for (const auto& [name, member] : kGridVariables) s.*member = grid_field(j, name);
}

std::string run_key(const RunSpec& spec) {
  json s = spec;
  // Where the dataset lies on this machine is not what the run is (a cluster node, a moved
  // checkout): the key keeps the name the config gives.
  s.erase("dataset_path");
  s.erase("scene_path");
  return s.dump();
}

const char* run_status_name(RunStatus s) {
  switch (s) {
    case RunStatus::kOk:
      return "ok";
    case RunStatus::kFailed:
      return "failed";
    case RunStatus::kTimeout:
      return "timeout";
  }
  return "?";
}

double RunResult::time_median_s() const {
  std::vector<double> t = times_s;
  std::sort(t.begin(), t.end());
  return t.empty() ? 0 : t[t.size() / 2];
}

namespace {

// The repetitions and their median, range and relative spread.
void write_times(json& j, std::vector<double> t) {
  j["times_s"] = t;
  std::sort(t.begin(), t.end());
  const double med = t.empty() ? 0 : t[t.size() / 2];
  j["time_median_s"] = med;
  j["time_min_s"] = t.empty() ? 0 : t.front();
  j["time_max_s"] = t.empty() ? 0 : t.back();
  j["time_spread"] = med > 0 ? (t.back() - t.front()) / med : 0.0;
}

RunStatus status_from_name(const std::string& name) {
  for (RunStatus s : {RunStatus::kOk, RunStatus::kFailed, RunStatus::kTimeout})
    if (name == run_status_name(s)) return s;
  input_error("unknown run status '{}'", name);
}

}  // namespace

namespace {

template <typename T>
void put(json& j, const char* key, const std::optional<T>& v) {
  if (v) j[key] = *v;
}

template <typename T>
void take(const json& j, const char* key, std::optional<T>& v) {
  if (!j.contains(key)) return;
  if constexpr (std::is_same_v<T, uint64_t>)
    v = count_from_json(j[key], fmt::format("\"{}\"", key));
  else
    v = j[key].get<T>();
}

// A run's counters: name to count, each a non-negative JSON integer within uint64.
std::map<std::string, uint64_t> counters_field(const json& j, const char* key) {
  if (!j[key].is_object()) input_error("\"{}\" = {} is not an object", key, j[key].dump());
  std::map<std::string, uint64_t> out;
  for (const auto& [name, v] : j[key].items())
    out[name] = count_from_json(v, fmt::format("counter \"{}\" in \"{}\"", name, key));
  return out;
}

}  // namespace

void to_json(json& j, const RunMeasures& m) {
  j = json::object();
  put(j, "prepare_s", m.prepare_s);
  put(j, "build_s", m.build_s);
  put(j, "structure_bytes", m.structure_bytes);
  put(j, "memory_bytes", m.memory_bytes);
  if (const auto& x = m.crossover) {
    j["direct_setup_s"] = x->direct_setup_s;
    j["direct_frame_s"] = x->direct_frame_s;
    j["mesh_setup_s"] = x->mesh_setup_s;
    j["mesh_frame_s"] = x->mesh_frame_s;
    j["reconstruct_s"] = x->reconstruct_s;
    j["triangles"] = x->triangles;
    j["crossover_frames"] = x->crossover_frames ? json(*x->crossover_frames) : json(nullptr);
  }
}

void from_json(const json& j, RunMeasures& m) {
  m = RunMeasures{};
  take(j, "prepare_s", m.prepare_s);
  take(j, "build_s", m.build_s);
  take(j, "structure_bytes", m.structure_bytes);
  take(j, "memory_bytes", m.memory_bytes);
  if (!j.contains("direct_setup_s")) return;
  CrossoverMeasures x;
  x.direct_setup_s = j.at("direct_setup_s").get<double>();
  x.direct_frame_s = j.at("direct_frame_s").get<double>();
  x.mesh_setup_s = j.at("mesh_setup_s").get<double>();
  x.mesh_frame_s = j.at("mesh_frame_s").get<double>();
  x.reconstruct_s = j.at("reconstruct_s").get<double>();
  x.triangles = count_from_json(j.at("triangles"), "\"triangles\"");
  if (!j.at("crossover_frames").is_null()) x.crossover_frames = j["crossover_frames"].get<double>();
  m.crossover = x;
}

void to_json(json& j, const RunResult& r) {
  j = r.spec;
  j["spec"] = r.spec;  // as given: what --resume and merges identify the run by
  if (r.points) j["N"] = *r.points;
  if (r.pixels) j["M"] = *r.pixels;
  j["status"] = run_status_name(r.status);
  if (r.ok()) {
    j["counters"] = r.counters;
    if (r.prepare_counters) j["prepare_counters"] = *r.prepare_counters;
    write_times(j, r.times_s);
    j["extra"] = r.measures;
  } else {
    j["error"] = r.error;
    if (r.signal) j["signal"] = *r.signal;
  }
  if (r.wall_s) j["wall_s"] = *r.wall_s;
}

void from_json(const json& j, RunResult& r) {
  if (!j.is_object() || !j.contains("spec")) input_error("a run result has its \"spec\"");
  r = RunResult{};
  r.spec = j["spec"].get<RunSpec>();
  if (!j.contains("status")) input_error("a run result has its \"status\"");
  r.status = status_from_name(text_field(j, "status"));
  r.error = text_field(j, "error");
  if (j.contains("signal")) r.signal = int(whole_field(j, "signal", 0, 1, 128));
  // N and M as measured (integers; the spec's are the grid's doubles).
  if (r.ok() && j.contains("N") && j["N"].is_number_integer())
    r.points = count_from_json(j["N"], "\"N\"");
  if (r.ok() && j.contains("M") && j["M"].is_number_integer())
    r.pixels = whole_field(j, "M", 0, 0, std::numeric_limits<int64_t>::max());
  if (j.contains("counters")) r.counters = counters_field(j, "counters");
  if (j.contains("prepare_counters")) r.prepare_counters = counters_field(j, "prepare_counters");
  if (j.contains("times_s")) r.times_s = j["times_s"].get<std::vector<double>>();
  if (j.contains("extra")) r.measures = j["extra"].get<RunMeasures>();
  if (j.contains("wall_s") && j["wall_s"].is_number()) r.wall_s = j["wall_s"].get<double>();
}

RunResult failed_run(const RunSpec& spec, RunStatus status, std::string error) {
  RunResult r;
  r.spec = spec;
  r.status = status;
  r.error = std::move(error);
  return r;
}

RunResult killed_run(const RunSpec& spec, int signal) {
  RunResult r = failed_run(spec, RunStatus::kFailed, fmt::format("killed by signal {}", signal));
  r.signal = signal;
  return r;
}

bool killed_by_signal(const RunResult& result) {
  return result.status == RunStatus::kFailed && result.signal.has_value();
}

}  // namespace pcrt
