// The numbers fits read from a run (harness/sweep_fits.cpp): the thesis's variables, parameters,
// counters, times and a kind's own measurements, named as the run columns of runs.csv are. A
// config's names ("x", "metric", "per", "by", "free", "covariate", "variable") become these types
// once, where the config is read (sweep_config.cpp); the fits never look a name up again.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "harness/run_spec.hpp"

namespace pcrt {

// The thesis's variables: points, pixels, samples per pixel, bounces, items per leaf (or a
// method's K), the k of kNN, iterations (the cap, max_iterations); and H, the hits per ray of the
// methods that declare what a hit is (MethodInfo::hits: 3DGRT's "cost follows the hits"), as
// measured.
enum class Variable { N, M, S, B, K, k, I, H };
inline constexpr Variable kAllVariables[] = {Variable::N, Variable::M, Variable::S, Variable::B,
                                             Variable::K, Variable::k, Variable::I, Variable::H};
const char* variable_name(Variable v);  // "N", "M", ...
std::optional<Variable> variable_from_name(const std::string& name);
// N, M, S and B: the grid's variables, which say what a run is (K, k and I are measured or set).
bool is_grid_variable(Variable v);

// A kind's own measurements (RunMeasures), by their runs.csv column.
enum class Measure {
  kPrepareS,
  kBuildS,
  kStructureBytes,
  kMemoryBytes,
  kDirectSetupS,
  kDirectFrameS,
  kMeshSetupS,
  kMeshFrameS,
  kReconstructS,
  kTriangles,
  kCrossoverFrames,
};

// One number of a run, as a fit's "x", "metric" or "per" names it.
struct RunQuantity {
  enum class Source {
    kVariable,          // N, M, S, B, K, k, I (N and M as measured where the run has them)
    kIterationsPerRun,  // "I_run": I as measured, the method's iteration steps per iterative run
    kParameter,         // "set_NAME": a parameter given to the run
    kCounter,           // "ops_NAME" ("ops_prep_NAME": one counted while preparing the scene)
    kTime,              // "time": the median repetition, seconds
    kFps,               // "fps": 1 / time
    kWork,              // "work": traversal nodes and items and the method's own work counters
    kMeasure,           // a kind's own measurement ("build_s", "direct_frame_s", ...)
  };
  Source source = Source::kTime;
  Variable variable = Variable::N;       // kVariable
  std::string name;                      // kParameter and kCounter (without set_ and ops_)
  Measure measure = Measure::kPrepareS;  // kMeasure

  static RunQuantity of(Variable v) { return {Source::kVariable, v, {}, {}}; }
  static RunQuantity of(Source s) { return {s, Variable::N, {}, {}}; }  // time, fps, work, I_run
  static RunQuantity parameter(std::string name) {
    return {Source::kParameter, Variable::N, std::move(name), {}};
  }
  static RunQuantity counter(std::string name) {
    return {Source::kCounter, Variable::N, std::move(name), {}};
  }
  bool operator==(const RunQuantity&) const = default;
};

// None for a name that is not a run column a fit can read.
std::optional<RunQuantity> run_quantity_from_name(const std::string& column);
std::string run_quantity_name(const RunQuantity& q);  // the run column, as fits.json names it

// What "work" is for a method: ops_nodes_visited, ops_items_visited and MethodInfo::work.
std::vector<RunQuantity> work_counters(const std::string& method);

// The value of `q` in a run: NaN where the run has none (a run without a time has no time, never
// a zero one), except that a counter the run never touched is zero.
double run_value(const RunResult& r, const RunQuantity& q);

// A method parameter of the run: given (--set), else the method's default; none where the method
// has no such parameter.
std::optional<double> method_parameter(const RunSpec& spec, const std::string& name);
// K as runs.csv has it: the method's K when it has one (given, or its default), else the
// measured mean items per visited leaf; none without either.
std::optional<double> k_of(const RunResult& r);
// K as a fit holds it fixed (or fits it as a covariate): the measured mean items per visited
// leaf where the run visited leaves, whatever the method's K says (a method's K of 8 neighbours
// does not stop the structure's leaves filling up as N grows, and the work counts their items),
// else k_of.
std::optional<double> held_k_of(const RunResult& r);
// I as measured (I_run): the method's declared iteration steps per iterative run
// (MethodInfo::iterations), whatever the cap; none for a method without an iterative kernel.
std::optional<double> iterations_per_run(const RunResult& r);
// H: the method's declared hits (MethodInfo::hits) per ray cast; none for a method without them.
std::optional<double> hits_per_ray(const RunResult& r);

// The names that say what a run is, as its result's JSON has them: "" where its kind has none
// (a workload has no method, a render no workload).
struct RunNames {
  std::string experiment, kind, method, structure, dataset, reconstruction, engine, workload;
};
RunNames run_names(const RunSpec& spec);

}  // namespace pcrt
