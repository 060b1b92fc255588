#include "harness/run_quantity.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "core/counters.hpp"
#include "methods/method.hpp"

namespace pcrt {

namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

constexpr std::pair<Measure, const char*> kMeasureNames[] = {
    {Measure::kPrepareS, "prepare_s"},
    {Measure::kBuildS, "build_s"},
    {Measure::kStructureBytes, "structure_bytes"},
    {Measure::kMemoryBytes, "memory_bytes"},
    {Measure::kDirectSetupS, "direct_setup_s"},
    {Measure::kDirectFrameS, "direct_frame_s"},
    {Measure::kMeshSetupS, "mesh_setup_s"},
    {Measure::kMeshFrameS, "mesh_frame_s"},
    {Measure::kReconstructS, "reconstruct_s"},
    {Measure::kTriangles, "triangles"},
    {Measure::kCrossoverFrames, "crossover_frames"},
};

const char* measure_name(Measure m) {
  for (const auto& [measure, name] : kMeasureNames)
    if (measure == m) return name;
  return "?";
}

template <typename T>
double or_missing(const std::optional<T>& v) {
  return v ? double(*v) : kMissing;
}

double measure_value(const RunMeasures& m, Measure which) {
  const std::optional<CrossoverMeasures>& x = m.crossover;
  switch (which) {
    case Measure::kPrepareS:
      return or_missing(m.prepare_s);
    case Measure::kBuildS:
      return or_missing(m.build_s);
    case Measure::kStructureBytes:
      return or_missing(m.structure_bytes);
    case Measure::kMemoryBytes:
      return or_missing(m.memory_bytes);
    case Measure::kDirectSetupS:
      return x ? x->direct_setup_s : kMissing;
    case Measure::kDirectFrameS:
      return x ? x->direct_frame_s : kMissing;
    case Measure::kMeshSetupS:
      return x ? x->mesh_setup_s : kMissing;
    case Measure::kMeshFrameS:
      return x ? x->mesh_frame_s : kMissing;
    case Measure::kReconstructS:
      return x ? x->reconstruct_s : kMissing;
    case Measure::kTriangles:
      return x ? double(x->triangles) : kMissing;
    case Measure::kCrossoverFrames:
      return x ? or_missing(x->crossover_frames) : kMissing;
  }
  return kMissing;
}

double count(const std::map<std::string, uint64_t>& counters, const std::string& name) {
  const auto it = counters.find(name);
  return it == counters.end() ? 0.0 : double(it->second);
}

// ops_prep_NAME is a preparation counter where the run has one by that name (runs.csv writes
// those after the frame's counters), else a frame counter; a counter never touched is zero.
double counter_value(const RunResult& r, const std::string& name) {
  if (r.prepare_counters && name.rfind("prep_", 0) == 0) {
    const auto it = r.prepare_counters->find(name.substr(5));
    if (it != r.prepare_counters->end()) return double(it->second);
  }
  return count(r.counters, name);
}

std::optional<double> parameter(const RunSpec& spec, const std::string& name) {
  const auto it = spec.set.find(name);
  return it == spec.set.end() ? std::nullopt : std::optional<double>(it->second);
}

double variable_value(const RunResult& r, Variable v) {
  switch (v) {  // N and M as loaded and rendered replace the grid's values, as in runs.csv
    case Variable::N:
      return r.points ? double(*r.points) : or_missing(r.spec.N);
    case Variable::M:
      return r.pixels ? double(*r.pixels) : or_missing(r.spec.M);
    case Variable::S:
      return or_missing(r.spec.S);
    case Variable::B:
      return or_missing(r.spec.B);
    case Variable::K:
      return or_missing(k_of(r));
    case Variable::k:
      return or_missing(parameter(r.spec, "k"));
    case Variable::I:
      return or_missing(parameter(r.spec, "max_iterations"));
    case Variable::H:
      return or_missing(hits_per_ray(r));
  }
  return kMissing;
}

// The median repetition of an ok run (0 without repetitions, as its result records it); a run
// that failed has no time.
double time_of(const RunResult& r) { return r.ok() ? r.time_median_s() : kMissing; }

// The mean items per visited leaf, where the run visited leaves.
std::optional<double> items_per_leaf(const RunResult& r) {
  if (!(count(r.counters, "leaves_visited") > 0)) return std::nullopt;
  return count(r.counters, "items_visited") / count(r.counters, "leaves_visited");
}

}  // namespace

std::optional<double> method_parameter(const RunSpec& spec, const std::string& name) {
  if (const std::optional<double> given = parameter(spec, name)) return given;
  if (!MethodRegistry::instance().contains(spec.method)) return std::nullopt;
  for (const ParamSpec& p : MethodRegistry::instance().get(spec.method, "method").params)
    if (p.name == name) return p.default_value;
  return std::nullopt;
}

const char* variable_name(Variable v) {
  constexpr const char* kNames[] = {"N", "M", "S", "B", "K", "k", "I", "H"};
  return kNames[size_t(v)];
}

std::optional<Variable> variable_from_name(const std::string& name) {
  for (Variable v : kAllVariables)
    if (name == variable_name(v)) return v;
  return std::nullopt;
}

bool is_grid_variable(Variable v) {
  return v == Variable::N || v == Variable::M || v == Variable::S || v == Variable::B;
}

std::optional<RunQuantity> run_quantity_from_name(const std::string& column) {
  using S = RunQuantity::Source;
  if (const std::optional<Variable> v = variable_from_name(column)) return RunQuantity::of(*v);
  constexpr std::pair<const char*, S> kNamed[] = {
      {"I_run", S::kIterationsPerRun}, {"time", S::kTime}, {"fps", S::kFps}, {"work", S::kWork}};
  for (const auto& [name, source] : kNamed)
    if (column == name) return RunQuantity::of(source);
  if (column.size() > 4 && column.rfind("set_", 0) == 0)
    return RunQuantity::parameter(column.substr(4));
  if (column.size() > 4 && column.rfind("ops_", 0) == 0)
    return RunQuantity::counter(column.substr(4));
  for (const auto& [measure, name] : kMeasureNames)
    if (column == name) return RunQuantity{S::kMeasure, Variable::N, {}, measure};
  return std::nullopt;
}

std::string run_quantity_name(const RunQuantity& q) {
  switch (q.source) {
    case RunQuantity::Source::kVariable:
      return variable_name(q.variable);
    case RunQuantity::Source::kIterationsPerRun:
      return "I_run";
    case RunQuantity::Source::kParameter:
      return "set_" + q.name;
    case RunQuantity::Source::kCounter:
      return "ops_" + q.name;
    case RunQuantity::Source::kTime:
      return "time";
    case RunQuantity::Source::kFps:
      return "fps";
    case RunQuantity::Source::kWork:
      return "work";
    case RunQuantity::Source::kMeasure:
      return measure_name(q.measure);
  }
  return "?";
}

// Frame claims are judged on work, never on rays.
std::vector<RunQuantity> work_counters(const std::string& method) {
  std::vector<RunQuantity> terms = {RunQuantity::counter("nodes_visited"),
                                    RunQuantity::counter("items_visited")};
  if (MethodRegistry::instance().contains(method))
    for (const Counter* c : MethodRegistry::instance().get(method, "method").work)
      terms.push_back(RunQuantity::counter(registered_counters()[c->id()].name));
  return terms;
}

double run_value(const RunResult& r, const RunQuantity& q) {
  switch (q.source) {
    case RunQuantity::Source::kVariable:
      return variable_value(r, q.variable);
    case RunQuantity::Source::kIterationsPerRun:
      return or_missing(iterations_per_run(r));
    case RunQuantity::Source::kParameter:
      return or_missing(parameter(r.spec, q.name));
    case RunQuantity::Source::kCounter:
      return counter_value(r, q.name);
    case RunQuantity::Source::kTime:
      return time_of(r);
    case RunQuantity::Source::kFps:
      return time_of(r) > 0 ? 1.0 / time_of(r) : kMissing;
    case RunQuantity::Source::kMeasure:
      return measure_value(r.measures, q.measure);
    case RunQuantity::Source::kWork:
      break;
  }
  double work = 0;  // summed term by term, as a fit sums its metric's terms
  for (const RunQuantity& c : work_counters(r.spec.method)) work += run_value(r, c);
  return work;
}

std::optional<double> k_of(const RunResult& r) {
  if (const std::optional<double> method_k = method_parameter(r.spec, "K")) return method_k;
  return items_per_leaf(r);
}

std::optional<double> held_k_of(const RunResult& r) {
  if (const std::optional<double> measured = items_per_leaf(r)) return measured;
  return k_of(r);
}

std::optional<double> iterations_per_run(const RunResult& r) {
  if (!MethodRegistry::instance().contains(r.spec.method)) return std::nullopt;
  const IterationCounters& it = MethodRegistry::instance().get(r.spec.method, "method").iterations;
  if (!it.steps || !it.runs) return std::nullopt;
  const double runs = count(r.counters, registered_counters()[it.runs->id()].name);
  if (!(runs > 0)) return std::nullopt;
  return count(r.counters, registered_counters()[it.steps->id()].name) / runs;
}

RunNames run_names(const RunSpec& s) {
  RunNames n;  // the keys to_json(RunSpec) writes for the kind
  n.experiment = s.experiment;
  n.kind = run_kind_name(s.kind);
  if (s.kind != RunKind::kWorkload) n.dataset = s.dataset;
  if (runs_method(s.kind)) n.method = s.method, n.structure = s.structure;
  if (s.kind == RunKind::kReconstruct || s.kind == RunKind::kCrossover)
    n.reconstruction = s.reconstruction;
  if (s.kind == RunKind::kCrossover) n.engine = s.engine;
  if (s.kind == RunKind::kWorkload) n.workload = s.workload;
  return n;
}

std::optional<double> hits_per_ray(const RunResult& r) {
  if (!MethodRegistry::instance().contains(r.spec.method)) return std::nullopt;
  const Counter* hits = MethodRegistry::instance().get(r.spec.method, "method").hits;
  const double rays = count(r.counters, "rays_cast");
  if (!hits || !(rays > 0)) return std::nullopt;
  return count(r.counters, registered_counters()[hits->id()].name) / rays;
}

}  // namespace pcrt
