// One run of a sweep, as the harness passes it around: what to run (RunSpec) and what came of it
// (RunResult). JSON only at the edges: a child process's argument and output, runs.jsonl, plan
// files. The JSON written is the same as ever (committed results and scripts read it): a result
// is its spec's keys, "spec" (the spec as given), and the measurements.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace pcrt {

using nlohmann::json;

// What a run does; each kind has one executor (run_executors.cpp).
enum class RunKind {
  kRender,       // build a method's scene and render frames
  kBuild,        // build a method's scene only
  kReconstruct,  // reconstruct a mesh from the cloud
  kWorkload,     // a calibration workload of known growth
  kCrossover,    // direct tracing against reconstruct-then-trace
};
inline constexpr RunKind kAllRunKinds[] = {RunKind::kRender, RunKind::kBuild, RunKind::kReconstruct,
                                           RunKind::kWorkload, RunKind::kCrossover};
const char* run_kind_name(RunKind k);  // "render", "build", ...
std::optional<RunKind> run_kind_from_name(const std::string& name);
// Whether runs of this kind trace a method (method, structure and its parameters).
bool runs_method(RunKind k);

// What a sweep's runs are for ("measure" in a config): operation counts, times or both. Recorded
// with each run, as part of its key.
enum class MeasureMode { kBoth, kOps, kTime };
const char* measure_mode_name(MeasureMode m);  // "both", "ops", "time"
std::optional<MeasureMode> measure_mode_from_name(const std::string& name);

struct RunSpec {
  std::string experiment;
  RunKind kind = RunKind::kRender;
  int reps = 1, warmup = 0, threads = 2;
  uint64_t seed = 1;
  MeasureMode measure = MeasureMode::kBoth;
  bool camera_inside = false;     // at the centre of the cloud's bounds ("camera": "inside")
  std::string dataset;            // as the config names it (every kind but workload)
  std::string dataset_path;       // where it lies, when that differs from `dataset`
  std::string method, structure;  // structure "": the method traces through its own
  // Renders: a scene file whose "swept" objects the run's method traces on the run's dataset
  // (as the config names it, and where it lies when that differs).
  std::string scene, scene_path;
  std::map<std::string, double> set;  // parameters given (method's and structure's)
  std::string reconstruction, engine, workload;
  // The grid point: points (N), pixels (M), samples per pixel (S), bounces (B), where given.
  std::optional<double> N, M, S, B;
};

// Unknown kinds and wrong types are json exceptions; callers name the input.
void to_json(json& j, const RunSpec& s);
void from_json(const json& j, RunSpec& s);

// A count read from a file (a counter, N as loaded, bytes): a non-negative JSON integer within
// uint64, else InputError naming `what` and the value (json's own conversion would wrap -5000 and
// cast 1e308, which is undefined).
uint64_t count_from_json(const json& v, const std::string& what);

// The identity of a run (its spec, canonically serialised): what --resume, merges and plans
// compare.
std::string run_key(const RunSpec& spec);

enum class RunStatus { kOk, kFailed, kTimeout };
const char* run_status_name(RunStatus s);

// What a crossover run measured (harness/crossover.hpp has how).
struct CrossoverMeasures {
  double direct_setup_s = 0, direct_frame_s = 0, mesh_setup_s = 0, mesh_frame_s = 0;
  double reconstruct_s = 0;
  uint64_t triangles = 0;
  std::optional<double> crossover_frames;  // none: the mesh's frames are not faster
  bool operator==(const CrossoverMeasures&) const = default;
};

// A kind's own measurements besides times and counters, one CSV column each; each is written
// only by the kinds that measure it.
struct RunMeasures {
  std::optional<double> prepare_s, build_s;  // builds and renders: scene preparation and build
  std::optional<uint64_t> structure_bytes;   // builds and renders
  std::optional<uint64_t> memory_bytes;      // reconstructions: the triangulation's estimate
  std::optional<CrossoverMeasures> crossover;
  bool operator==(const RunMeasures&) const = default;
};
void to_json(json& j, const RunMeasures& m);  // flat: one key per measurement present
void from_json(const json& j, RunMeasures& m);

struct RunResult {
  RunSpec spec;
  RunStatus status = RunStatus::kOk;
  std::string error;          // why a run failed or timed out
  std::optional<int> signal;  // the signal that ended a failed run's child, if one did
  // What the run measured (ok runs): N as loaded and M as rendered replace the spec's values.
  std::optional<uint64_t> points;
  std::optional<int64_t> pixels;
  std::map<std::string, uint64_t> counters;
  std::optional<std::map<std::string, uint64_t>> prepare_counters;  // methods' runs
  std::vector<double> times_s;   // one per repetition; summarised in the JSON
  RunMeasures measures;          // written as "extra"
  std::optional<double> wall_s;  // the whole child process, preparation included

  [[nodiscard]] bool ok() const { return status == RunStatus::kOk; }
  // The median repetition's time, 0 without times.
  [[nodiscard]] double time_median_s() const;
};

void to_json(json& j, const RunResult& r);
void from_json(const json& j, RunResult& r);
inline std::string run_key(const RunResult& r) { return run_key(r.spec); }

// A result that never measured anything (the child failed, timed out or printed nonsense).
RunResult failed_run(const RunSpec& spec, RunStatus status, std::string error);

// The error recorded for a run whose child a signal ended ("killed by signal 9"), and whether a
// result is one. The signal mostly comes from outside the run (the OOM killer, a job's cleanup, a
// kill -9), so --resume and pcrt cluster do such a run again rather than keep it as done; a crash
// (SIGSEGV) is redone too, and recorded again if it crashes again. A time-out is kept: its own
// limit ended it.
// The result is typed (RunResult::signal, "signal" in runs.jsonl); the error says it in words.
RunResult killed_run(const RunSpec& spec, int signal);
bool killed_by_signal(const RunResult& result);

}  // namespace pcrt
