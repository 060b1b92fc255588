#include "harness/run_spec.hpp"

#include <algorithm>

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

bool runs_method(RunKind k) {
  return k == RunKind::kRender || k == RunKind::kBuild || k == RunKind::kCrossover;
}

namespace {

constexpr std::pair<const char*, std::optional<double> RunSpec::*> kGridVariables[] = {
    {"N", &RunSpec::N}, {"M", &RunSpec::M}, {"S", &RunSpec::S}, {"B", &RunSpec::B}};

}  // namespace

// Keys appear only where the kind uses them, as the config expansion always wrote them: run keys
// of committed results and baselines stay the same.
void to_json(json& j, const RunSpec& s) {
  j = {{"experiment", s.experiment}, {"kind", run_kind_name(s.kind)}, {"reps", s.reps},
       {"warmup", s.warmup},         {"threads", s.threads},          {"seed", s.seed},
       {"measure", s.measure}};
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
  const std::string kind = j.at("kind").get<std::string>();
  const std::optional<RunKind> k = run_kind_from_name(kind);
  if (!k) input_error("unknown run kind '{}'", kind);
  s = RunSpec{};
  s.kind = *k;
  s.experiment = j.value("experiment", std::string());
  s.reps = j.value("reps", 1);
  s.warmup = j.value("warmup", 0);
  s.threads = j.value("threads", 2);
  s.seed = j.value("seed", uint64_t(1));
  s.measure = j.value("measure", std::string("both"));
  s.camera_inside = j.value("camera", std::string()) == "inside";
  s.dataset = j.value("dataset", std::string());
  s.dataset_path = j.value("dataset_path", std::string());
  s.scene = j.value("scene", std::string());
  s.scene_path = j.value("scene_path", std::string());
  s.method = j.value("method", std::string());
  s.structure = j.value("structure", std::string());
  s.reconstruction = j.value("reconstruction", std::string());
  s.engine = j.value("engine", std::string());
  s.workload = j.value("workload", std::string());
  if (j.contains("set")) s.set = j["set"].get<std::map<std::string, double>>();
  for (const auto& [name, member] : kGridVariables)
    if (j.contains(name)) s.*member = j[name].get<double>();
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
  if (j.contains(key)) v = j[key].get<T>();
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
  x.triangles = j.at("triangles").get<uint64_t>();
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
  }
  if (r.wall_s) j["wall_s"] = *r.wall_s;
}

void from_json(const json& j, RunResult& r) {
  if (!j.is_object() || !j.contains("spec")) input_error("a run result has its \"spec\"");
  r = RunResult{};
  r.spec = j["spec"].get<RunSpec>();
  r.status = status_from_name(j.at("status").get<std::string>());
  r.error = j.value("error", std::string());
  if (r.ok() && j.contains("N") && j["N"].is_number_integer()) r.points = j["N"].get<uint64_t>();
  if (r.ok() && j.contains("M") && j["M"].is_number_integer()) r.pixels = j["M"].get<int64_t>();
  if (j.contains("counters")) r.counters = j["counters"].get<std::map<std::string, uint64_t>>();
  if (j.contains("prepare_counters"))
    r.prepare_counters = j["prepare_counters"].get<std::map<std::string, uint64_t>>();
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

}  // namespace pcrt
