#include "harness/sweep_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/json_input.hpp"
#include "harness/claims.hpp"
#include "harness/scene_file.hpp"
#include "harness/sweep_datasets.hpp"
#include "harness/workloads.hpp"
#include "methods/method.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"

namespace pcrt {

namespace fs = std::filesystem;

namespace {

void check_keys(const json& obj, const std::set<std::string>& allowed, const std::string& where) {
  if (!obj.is_object()) input_error("{}: must be an object", where);
  for (const auto& [k, v] : obj.items())
    if (!allowed.count(k) && k.rfind("set.", 0) != 0) input_error("{}: unknown key '{}'", where, k);
}

std::vector<std::string> string_list(const json& v, const std::string& where) {
  std::vector<std::string> out;
  if (v.is_string()) return {v.get<std::string>()};
  if (!v.is_array() || v.empty()) input_error("{}: must be a non-empty list of names", where);
  for (const auto& e : v) {
    if (!e.is_string()) input_error("{}: must be a list of names", where);
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::vector<double> number_list(const json& v, const std::string& where) {
  std::vector<double> out;
  const json list = v.is_array() ? v : json::array({v});
  if (list.empty()) input_error("{}: empty list", where);
  for (const auto& e : list) {
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      input_error("{}: '{}' is not a number", where, e.dump());
    out.push_back(e.get<double>());
  }
  return out;
}

// ---- The settings every run of the config shares ----

struct RunDefaults {
  int threads = 2, reps = 1, warmup = 0;
  uint64_t seed = 1;
  MeasureMode measure = MeasureMode::kBoth;
  double time_limit_s = 300;  // per run, in its child process
};

// A count read from a config: a whole number in [lo, hi], else an error naming where it was.
double whole_number(const json& raw, const char* key, double fallback, double lo, double hi,
                    const std::string& where) {
  const double v = optional_number(raw, key, fallback, where);
  if (!(v >= lo && v <= hi && v == std::floor(v)))
    input_error("{}: {} = {} is impossible (a whole number from {} to {})", where, key, v, lo, hi);
  return v;
}

RunDefaults parse_defaults(const json& raw, const std::string& origin) {
  const double threads = whole_number(raw, "threads", 2, 1, 1024, origin),
               reps = whole_number(raw, "repetitions", 1, 1, 1000, origin),
               warmup = whole_number(raw, "warmup", 0, 0, 100, origin),
               seed = whole_number(raw, "seed", 1, 0, 1e15, origin);
  RunDefaults d;
  d.time_limit_s = optional_number(raw, "time_limit_s", 300.0, origin);
  if (!(d.time_limit_s > 0)) input_error("{}: time_limit_s must be positive", origin);
  d.threads = int(threads);
  d.reps = int(reps);
  d.warmup = int(warmup);
  d.seed = uint64_t(seed);
  const std::string measure = optional_string(raw, "measure", "both", origin);
  const std::optional<MeasureMode> mode = measure_mode_from_name(measure);
  if (!mode) input_error("{}: measure must be 'ops', 'time' or 'both', not '{}'", origin, measure);
  d.measure = *mode;
  return d;
}

// ---- Grid points ----

// One point of an experiment's grid: the variables and parameters it sets.
struct GridPoint {
  std::map<std::string, double> values;  // N, M, S, B
  std::map<std::string, double> set;     // from "set.x" keys
  [[nodiscard]] std::optional<double> get(const std::string& k) const {
    const auto it = values.find(k);
    return it == values.end() ? std::nullopt : std::optional<double>(it->second);
  }
  void assign(const std::string& key, double v) {
    if (key.rfind("set.", 0) == 0)
      set[key.substr(4)] = v;
    else
      values[key] = v;
  }
};

const std::set<std::string> kGridKeys = {"N", "M", "S", "B"};

std::vector<GridPoint> listed_points(const json& list, const std::string& where) {
  if (!list.is_array() || list.empty())
    input_error("{}.points: must be a non-empty list of objects", where);
  std::vector<GridPoint> out;
  for (const auto& p : list) {
    check_keys(p, kGridKeys, where + ".points");
    GridPoint g;
    for (const auto& [k, v] : p.items()) {
      if (!v.is_number()) input_error("{}.points: {} must be a number", where, k);
      g.assign(k, v.get<double>());
    }
    out.push_back(g);
  }
  return out;
}

// The grid's points: the cartesian product of every list (N, M, S, B, set.*), or "points". The
// last key (alphabetically) varies slowest, as it always has: the run order stays.
std::vector<GridPoint> grid_points(const json& e, const std::string& where) {
  if (e.contains("points")) return listed_points(e["points"], where);
  std::vector<GridPoint> points{GridPoint{}};
  const json grid = e.value("grid", json::object());
  check_keys(grid, kGridKeys, where + ".grid");
  double product = 1;  // counted before any point is made: a few lists can name 10^12 points
  for (const auto& [key, values] : grid.items())
    if (values.is_array()) product *= double(std::max<size_t>(values.size(), 1));
  if (product > double(kMaxConfigRuns))
    input_error("{}.grid: {:.3g} points, more than a config may expand to ({} runs)", where,
                product, kMaxConfigRuns);
  for (const auto& [key, values] : grid.items()) {
    std::vector<GridPoint> next;
    for (double v : number_list(values, where + ".grid." + key))
      for (GridPoint p : points) {
        p.assign(key, v);
        next.push_back(p);
      }
    points = std::move(next);
  }
  return points;
}

void check_point_values(const GridPoint& p, RunKind kind, const std::string& where) {
  auto whole = [&](const char* key, int lo, double max) {
    const std::optional<double> v = p.get(key);
    if (v && !(*v >= lo && *v <= max && *v == std::floor(*v)))
      input_error("{}: {} = {} is impossible (a whole number in [{}, {}])", where, key, *v, lo,
                  max);
  };
  // A reconstruction (and a crossover's) triangulates in 3D: fewer than 4 points fail every run.
  whole("N", kind == RunKind::kReconstruct || kind == RunKind::kCrossover ? 4 : 1, 2e8);
  whole("M", 1, 16384.0 * 16384.0);
  // A render is sqrt(M) pixels square: any other M would run as the nearest square, unsaid.
  if (const std::optional<double> m = p.get("M")) {
    const double side = std::round(std::sqrt(*m));
    if (side * side != *m)
      input_error(
          "{}: M = {} is not a square number of pixels (a run renders sqrt(M) x sqrt(M): "
          "{} or {})",
          where, *m, std::floor(std::sqrt(*m)) * std::floor(std::sqrt(*m)),
          std::ceil(std::sqrt(*m)) * std::ceil(std::sqrt(*m)));
  }
  whole("S", 1, 65536);
  whole("B", 0, 64);
  if (kind != RunKind::kWorkload && kind != RunKind::kReconstruct && !p.get("N"))
    input_error("{}: no N given (grid.N or points[].N)", where);
}

// ---- Methods, structures and their parameters ----

// Splits "set.x" values between the method and the structure and checks them as a run would.
void validate_params(const RunSpec& spec, const std::string& where) {
  const MethodInfo& m = MethodRegistry::instance().get(spec.method, "method");
  ParamValues mp, sp;
  const std::string sid = spec.structure.empty() ? m.structure : spec.structure;
  const StructureInfo* s =
      m.own_structure.empty() ? &StructureRegistry::instance().get(sid, "structure") : nullptr;
  for (const auto& [k, v] : spec.set) {
    const std::string& name = k;  // clang 14 cannot capture a structured binding
    auto named = [&](const ParamSpec& p) { return p.name == name; };
    const bool in_m = std::any_of(m.params.begin(), m.params.end(), named);
    const bool in_s = s && std::any_of(s->params.begin(), s->params.end(), named);
    if (!in_m && !in_s)
      input_error("{}: set.{} is not a parameter of {} or {}", where, k, spec.method, sid);
    (in_m ? mp : sp)[k] = v;
  }
  resolve_params(m.params, mp, where + " (" + spec.method + ")");
  if (s) resolve_params(s->params, sp, where + " (" + sid + ")");
}

std::vector<std::string> resolve_methods(const json& methods, const std::string& where) {
  std::vector<std::string> ids;
  for (const std::string& id : string_list(methods, where + ".methods")) {
    if (id == "*" || id == "surveyed") {  // surveyed: the 16 methods, without the references
      for (const auto& m : MethodRegistry::instance().all())
        if (id == "*" || m.surveyed()) ids.push_back(m.id);
    } else {
      (void)MethodRegistry::instance().get(id, "method");
      ids.push_back(id);
    }
  }
  return ids;
}

std::vector<std::string> resolve_structures(const json& e, const MethodInfo& m,
                                            const std::string& where) {
  std::vector<std::string> ids;
  if (!m.own_structure.empty()) return {""};  // traces through its own acceleration
  for (const std::string& id :
       string_list(e.value("structures", json("default")), where + ".structures")) {
    if (id == "default") {
      ids.push_back(m.structure);
    } else if (id == "*") {
      for (const auto& s : StructureRegistry::instance().all())
        if (s.id != "brute_force" || m.structure == "brute_force") ids.push_back(s.id);
    } else {
      (void)StructureRegistry::instance().get(id, "structure");
      ids.push_back(id);
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// ---- Counters and fits ----

// The counts a reconstruction run records (run_executors.cpp), beside the registered counters.
const std::set<std::string> kReconstructionCounts = {"cells",    "facets",         "triangles",
                                                     "vertices", "boundary_edges", "predicates"};

// Whether `column` names a count a run records: "ops_<counter>" or, for preparation,
// "ops_prep_<counter>". A misspelt one would only show after the whole sweep, as a fit of zeros.
bool is_counter_column(const std::string& column) {
  if (column.rfind("ops_", 0) != 0) return false;
  std::string name = column.substr(4);
  if (kReconstructionCounts.count(name)) return true;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t i = 0; i < registered_counter_count(); ++i)
      if (registered_counters()[i].name == name) return true;
    if (name.rfind("prep_", 0) != 0) return false;
    name = name.substr(5);
  }
  return false;
}

// "metric" names run columns (run_quantity.hpp).
RunQuantity metric_term(const std::string& m, const std::string& where) {
  if (m.rfind("ops_", 0) == 0 && !is_counter_column(m))
    input_error("{}.metric: '{}' is not a counter (pcrt list)", where, m);
  const std::optional<RunQuantity> q = run_quantity_from_name(m);
  if (!q)
    input_error(
        "{}.metric: '{}' is not a run column: time, fps, work, ops_COUNTER, one of N M S B K k I "
        "I_run, set_PARAMETER or a kind's measurement (build_s, direct_frame_s, ...)",
        where, m);
  return *q;
}

void parse_fit_metric(const json& f, const std::string& where, FitSpec& s) {
  if (!f.contains("metric")) input_error("{}: 'metric' is required", where);
  for (const std::string& m : string_list(f["metric"], where + ".metric"))
    s.metric.push_back(metric_term(m, where));
  const std::string per = optional_string(f, "per", "", where);
  if (per.empty()) return;
  if (!is_counter_column(per))
    input_error("{}.per: '{}' is not a counter (ops_NAME, pcrt list)", where, per);
  s.per = run_quantity_from_name(per);
}

// What "by" may keep in a group: what an experiment sweeps.
RunQuantity group_column(const std::string& name, const std::string& where) {
  const std::optional<RunQuantity> q = run_quantity_from_name(name);
  const bool swept_kind =
      q && (q->source == RunQuantity::Source::kParameter ||
            (q->source == RunQuantity::Source::kVariable && is_grid_variable(q->variable)));
  if (!swept_kind) input_error("{}.by: '{}' is not one of N M S B or set_PARAMETER", where, name);
  return *q;
}

void check_not_rays_only(const FitSpec& s, const std::string& where) {
  // Rays are S * M * (paths) by construction: a growth fit on them proves nothing.
  const std::set<std::string> rays = {"rays_cast", "primary_rays", "bounce_rays", "shadow_rays",
                                      "ray_hits"};
  auto counts_rays = [&](const RunQuantity& m) {
    return m.source == RunQuantity::Source::kCounter && rays.count(m.name);
  };
  if (!s.is_threshold() && std::all_of(s.metric.begin(), s.metric.end(), counts_rays))
    input_error(
        "{}: metric counts rays only, which grow with S and M by construction; fit "
        "'work' or a method's own counters",
        where);
}

// The variable, x, and the held variables that may move (K, k, I_run).
void parse_fit_variables(const json& f, const std::string& where, FitSpec& s) {
  if (f.contains("free"))
    for (const std::string& v : string_list(f["free"], where + ".free")) {
      if (v != "K" && v != "k" && v != "I_run" && v != "H")
        input_error("{}.free: '{}' is not one of K, k, I_run, H", where, v);
      s.free.push_back(*run_quantity_from_name(v));
    }
  const std::string variable = optional_string(f, "variable", "", where);
  if (!s.is_threshold() && variable.empty())
    input_error("{}: a growth fit needs 'variable' (or 'max'/'min' for a threshold)", where);
  if (!variable.empty() && !(s.variable = variable_from_name(variable)))
    input_error("{}: variable '{}' is not one of S M B N K k I H", where, variable);
  const std::string x = optional_string(f, "x", variable, where);
  if (x.empty()) return;
  s.x = run_quantity_from_name(x);
  using Source = RunQuantity::Source;
  if (!s.x || (s.x->source != Source::kVariable && s.x->source != Source::kIterationsPerRun &&
               s.x->source != Source::kParameter))
    input_error("{}.x: '{}' is not one of S M B N K k I H I_run or set_PARAMETER", where, x);
}

FitSpec parse_fit(const json& f, const std::string& experiment, const std::string& where) {
  check_keys(f,
             {"claim", "variable", "x", "metric", "per", "max", "min", "by", "free", "covariate",
              "short_range"},
             where);
  FitSpec s;
  s.experiment = experiment;
  if (!f.contains("claim") || !f["claim"].is_string())
    input_error("{}: 'claim' is required", where);
  s.claim = f["claim"].get<std::string>();
  parse_fit_metric(f, where, s);
  if (f.contains("by"))
    for (const std::string& b : string_list(f["by"], where + ".by"))
      s.by.push_back(group_column(b, where));
  const std::string covariate = optional_string(f, "covariate", "", where);
  if (!covariate.empty() && covariate != "K")
    input_error("{}.covariate: only K can be a covariate, not '{}'", where, covariate);
  if (!covariate.empty()) s.covariate = Variable::K;
  s.short_range = optional_string(f, "short_range", "", where);
  s.max = optional_number(f, "max", -1.0, where);
  s.min = optional_number(f, "min", -1.0, where);
  parse_fit_variables(f, where, s);
  check_not_rays_only(s, where);
  return s;
}

// Every run the fit will see must name a registered claim that is in its variable.
void check_fit_claims(const FitSpec& f, const std::vector<RunSpec>& runs,
                      const std::string& where) {
  for (const RunSpec& run : runs) {
    if (run.experiment != f.experiment) continue;
    try {
      const Claim& claim = find_claim(fill_claim(f.claim, run_names(run)));
      if (!claim.not_tested.empty())
        input_error("claim '{}' is not tested: {}", claim.id, claim.not_tested);
      if (f.variable && !f.is_threshold())
        (void)expected_growth(claim.complexity, variable_name(*f.variable));
    } catch (const InputError& err) {
      input_error("{}: {}", where, err.what());
    }
  }
}

// What the experiment's grid sweeps (more than one value): N, M, S, B and parameters.
std::vector<RunQuantity> swept_columns(const json& e) {
  std::vector<RunQuantity> swept;
  const json grid = e.value("grid", json::object());
  for (const auto& [k, v] : grid.items()) {
    if (!v.is_array() || v.size() <= 1) continue;
    const std::string column = k.rfind("set.", 0) == 0 ? "set_" + k.substr(4) : k;
    if (const std::optional<RunQuantity> q = run_quantity_from_name(column)) swept.push_back(*q);
  }
  return swept;
}

void parse_fits(const json& e, const std::string& name, const std::string& where, SweepConfig& c) {
  if (!e.contains("fits")) return;
  if (!e["fits"].is_array()) input_error("{}.fits: must be a list", where);
  const std::vector<RunQuantity> swept = swept_columns(e);
  for (size_t f = 0; f < e["fits"].size(); ++f) {
    const std::string fwhere = fmt::format("{}.fits[{}]", where, f);
    c.fits.push_back(parse_fit(e["fits"][f], name, fwhere));
    c.fits.back().swept = swept;
    check_fit_claims(c.fits.back(), c.runs, fwhere);
  }
}

// ---- Experiments ----

// One experiment as its runs need it.
struct Experiment {
  const json& e;
  std::string where, name;
  RunKind kind = RunKind::kRender;
  RunSpec base;  // what every run of it shares
  std::vector<GridPoint> points;
  std::vector<std::string> datasets;
  std::string dataset_dir;
  DatasetCheck check = DatasetCheck::kOpenFiles;
  int replicates = 1;  // data sets per grid point (seeds seed .. seed + replicates - 1)
};

RunKind parse_kind(const json& e, const std::string& where) {
  const std::string kind = optional_string(e, "kind", "", where);
  const std::optional<RunKind> k = run_kind_from_name(kind);
  if (!k)
    input_error("{}: kind must be render, build, reconstruct, workload or crossover, not '{}'",
                where, kind);
  return *k;
}

RunSpec experiment_base(const Experiment& x, const RunDefaults& d) {
  RunSpec s;
  s.experiment = x.name;
  s.kind = x.kind;
  s.reps = int(whole_number(x.e, "repetitions", double(d.reps), 1, 1000, x.where));
  s.warmup = d.warmup;
  s.threads = d.threads;
  s.seed = d.seed;
  s.measure = d.measure;
  const std::string camera = optional_string(x.e, "camera", "outside", x.where);
  if (camera != "outside" && camera != "inside")
    input_error("{}: camera must be 'outside' or 'inside', not '{}'", x.where, camera);
  // Inside a closed surface every bounce hits again, so work per path grows with B.
  s.camera_inside = camera == "inside";
  if (x.e.contains("scene")) {
    if (!x.e["scene"].is_string() || x.e["scene"].get<std::string>().empty())
      input_error("{}: scene must be a scene file's name", x.where);
    if (x.kind != RunKind::kRender) input_error("{}: scene applies only to render runs", x.where);
    if (x.e.contains("camera")) input_error("{}: a scene brings its own camera", x.where);
    s.scene = x.e["scene"].get<std::string>();
    const std::string path = dataset_path(s.scene, x.dataset_dir);
    if (path != s.scene) s.scene_path = path;
    if (x.check == DatasetCheck::kOpenFiles) try {
        check_sweep_scene(path);
      } catch (const InputError& e) {
        input_error("{}: scene: {}", x.where, e.what());
      }
  }
  if (!runs_method(x.kind)) return s;  // the experiment's set.* go to methods only
  for (const auto& [k, v] : x.e.items())
    if (k.rfind("set.", 0) == 0) s.set[k.substr(4)] = v.get<double>();
  return s;
}

void check_set_values(const Experiment& x) {
  for (const auto& [k, v] : x.e.items())
    if (k.rfind("set.", 0) == 0 && !v.is_number())
      input_error("{}: {} must be a number", x.where, k);
}

// A generator's values within their ranges can still make an impossible cloud (a torus of
// R = r = 1e12 puts points beyond kMaxCoordinate): a few of its points are made now, so that every run does
// not fail on it later.
void probe_generator(const Experiment& x, const std::string& spec) {
  double n = 1024;
  for (const GridPoint& p : x.points)
    if (p.get("N")) n = std::min(n, *p.get("N"));
  try {
    (void)run_cloud(spec, n, 1);
  } catch (const InputError& e) {
    input_error("{}.datasets: {}", x.where, e.what());
  }
}

// Generators must leave n to the grid and make a cloud; files must hold the largest N.
void check_datasets(const Experiment& x) {
  for (const std::string& d : x.datasets) {
    if (is_generator(d)) {
      (void)parse_generator_spec(d, nullptr);
      if (sets_n(d))
        input_error("{}.datasets: '{}' sets n; a sweep takes N from its grid", x.where, d);
      probe_generator(x, d);
      continue;
    }
    if (x.check == DatasetCheck::kNamesOnly) continue;
    const PointCloud full = load_dataset(dataset_path(d, x.dataset_dir)).cloud;
    for (const GridPoint& p : x.points)
      if (p.get("N") && *p.get("N") > double(full.size()))
        input_error("{}: N = {} but {} has {} points", x.where, *p.get("N"), d, full.size());
  }
}

// Counted before the runs are made: methods x structures x datasets x points x replicates.
void refuse_too_many_runs(const Experiment& x, size_t earlier_runs, size_t specs) {
  const double runs =
      double(earlier_runs) + double(specs) * double(x.points.size()) * double(x.replicates);
  if (runs > double(kMaxConfigRuns))
    input_error(
        "{}: the config expands to {:.0f} runs with this experiment, more than a config "
        "may ({})",
        x.where, runs, kMaxConfigRuns);
}

std::vector<RunSpec> method_runs(const Experiment& x) {
  const json methods = x.e.contains("methods")
                           ? x.e["methods"]
                           : json(x.kind == RunKind::kBuild ? "reference_splat" : "*");
  std::vector<RunSpec> out;
  for (const std::string& m : resolve_methods(methods, x.where)) {
    const MethodInfo& info = MethodRegistry::instance().get(m, "method");
    for (const std::string& s : resolve_structures(x.e, info, x.where))
      for (const std::string& d : x.datasets) {
        RunSpec spec = x.base;
        spec.dataset = d;
        spec.method = m;
        spec.structure = s;
        if (x.kind == RunKind::kCrossover) {
          spec.reconstruction = string_list(x.e.value("reconstructions", json("afsr")),
                                            x.where + ".reconstructions")[0];
          spec.engine = optional_string(x.e, "engine", "bvh", x.where);
          (void)ReconstructionRegistry::instance().get(spec.reconstruction, "reconstruction");
          (void)MeshEngineRegistry::instance().get(spec.engine, "mesh engine");
        }
        out.push_back(spec);
        refuse_too_many_runs(x, 0, out.size());
      }
  }
  return out;
}

std::vector<RunSpec> reconstruction_runs(const Experiment& x) {
  std::vector<RunSpec> out;
  for (const std::string& r :
       string_list(x.e.value("reconstructions", json()), x.where + ".reconstructions")) {
    (void)ReconstructionRegistry::instance().get(r, "reconstruction");
    for (const std::string& d : x.datasets) {
      RunSpec spec = x.base;
      spec.dataset = d;
      spec.reconstruction = r;
      out.push_back(spec);
    }
  }
  return out;
}

std::vector<RunSpec> workload_runs(const Experiment& x) {
  std::vector<RunSpec> out;
  for (const std::string& w : string_list(x.e.value("workloads", json()), x.where + ".workloads")) {
    if (std::none_of(workloads().begin(), workloads().end(), [&](auto& y) { return y.id == w; }))
      input_error("{}: unknown workload '{}'", x.where, w);
    RunSpec spec = x.base;
    spec.workload = w;
    out.push_back(spec);
  }
  return out;
}

// Each spec at every grid point; a point's "set.x" values join the experiment's, and each
// combination is checked as a run would check it.
void add_runs(const Experiment& x, std::vector<RunSpec> specs, SweepConfig& c) {
  refuse_too_many_runs(x, c.runs.size(), specs.size());
  for (RunSpec& spec : specs) {
    if (spec.kind != RunKind::kWorkload) {
      const std::string path = dataset_path(spec.dataset, x.dataset_dir);
      if (path != spec.dataset) spec.dataset_path = path;
    }
    for (const GridPoint& p : x.points)
      for (int r = 0; r < x.replicates; ++r) {
        RunSpec s = spec;
        for (const auto& [k, v] : p.set) s.set[k] = v;
        s.N = p.get("N");
        s.M = p.get("M");
        s.S = p.get("S");
        s.B = p.get("B");
        s.seed = spec.seed + uint64_t(r);
        if (runs_method(s.kind)) validate_params(s, x.where);
        c.runs.push_back(s);
      }
  }
}

void parse_experiment(const json& e, const std::string& where, size_t index, const RunDefaults& d,
                      const std::string& dataset_dir, DatasetCheck check,
                      std::set<std::string>& names, SweepConfig& c) {
  check_keys(e,
             {"name", "description", "kind", "methods", "structures", "datasets", "grid", "points",
              "reconstructions", "engine", "workloads", "fits", "repetitions", "camera",
              "replicates", "scene"},
             where);
  Experiment x{e,
               where,
               optional_string(e, "name", fmt::format("experiment{}", index), where),
               RunKind::kRender,
               RunSpec{},
               {},
               {},
               dataset_dir,
               check};
  if (!names.insert(x.name).second) input_error("{}: name '{}' used twice", where, x.name);
  x.kind = parse_kind(e, where);
  x.replicates = int(whole_number(e, "replicates", 1, 1, 100, where));
  check_set_values(x);
  x.points = grid_points(e, where);
  for (const GridPoint& p : x.points) check_point_values(p, x.kind, where);
  x.base = experiment_base(x, d);
  if (x.kind != RunKind::kWorkload) {
    x.datasets = string_list(e.value("datasets", json()), where + ".datasets");
    check_datasets(x);
  }
  add_runs(x,
           runs_method(x.kind)               ? method_runs(x)
           : x.kind == RunKind::kReconstruct ? reconstruction_runs(x)
                                             : workload_runs(x),
           c);
  parse_fits(e, x.name, where, c);
}

}  // namespace

std::string fill_claim(std::string claim, const RunNames& run) {
  const std::pair<const char*, const std::string*> kFields[] = {
      {"{method}", &run.method},
      {"{structure}", &run.structure},
      {"{reconstruction}", &run.reconstruction},
      {"{workload}", &run.workload}};
  for (const auto& [key, value] : kFields)
    for (size_t p; (p = claim.find(key)) != std::string::npos;)
      claim.replace(p, std::string(key).size(), *value);
  return claim;
}

SweepConfig parse_sweep_config(const json& raw, const std::string& origin, DatasetCheck datasets) {
  check_keys(raw,
             {"name", "description", "threads", "repetitions", "warmup", "time_limit_s", "measure",
              "seed", "experiments", "dataset_dir"},
             origin);
  if (raw.contains("dataset_dir") && !raw["dataset_dir"].is_string())
    input_error("{}: dataset_dir must be a folder name", origin);
  const std::string dataset_dir = optional_string(raw, "dataset_dir", "", origin);
  SweepConfig c;
  c.raw = raw;
  c.name = optional_string(raw, "name", fs::path(origin).stem().string(), origin);
  // The name is the folder under results/ a sweep writes to by default: one plain name.
  if (c.name.empty() || c.name == "." || c.name == ".." ||
      c.name.find_first_of("/\\") != std::string::npos)
    input_error("{}: name '{}' must be a plain folder name (no '/', not '', '.' or '..')", origin,
                c.name);
  const RunDefaults defaults = parse_defaults(raw, origin);
  c.time_limit_s = defaults.time_limit_s;
  if (!raw.contains("experiments") || !raw["experiments"].is_array() || raw["experiments"].empty())
    input_error("{}: 'experiments' must be a non-empty list", origin);
  std::set<std::string> names;
  for (size_t i = 0; i < raw["experiments"].size(); ++i) {
    const std::string where = fmt::format("{}: experiments[{}]", origin, i);
    try {
      parse_experiment(raw["experiments"][i], where, i, defaults, dataset_dir, datasets, names, c);
    } catch (const InputError& e) {
      // A registry's or a reader's message ("unknown structure 'NaN'") gets the config and the
      // experiment it came from; one that names them already is passed on.
      if (std::string(e.what()).rfind(origin, 0) == 0) throw;
      input_error("{}: {}", where, e.what());
    }
  }
  return c;
}

SweepConfig load_sweep_config(const std::string& path) {
  json raw = read_json_file(path);
  try {
    // Relative dataset files are the config's neighbours, wherever pcrt runs (Mitsuba's rule for
    // scene files). The folder is written into the config so that its copies (context.json, a
    // cluster's config.json) still find them.
    const fs::path folder = fs::absolute(fs::path(path)).parent_path();
    if (!raw.is_object()) input_error("{}: a sweep config is a JSON object", path);
    const std::string given = optional_string(raw, "dataset_dir", "", path);
    std::string dir = (folder / given).lexically_normal().string();
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    raw["dataset_dir"] = dir;
    return parse_sweep_config(raw, path);
  } catch (const json::exception& e) {
    input_error("{}: wrong type: {}", path, e.what());
  }
}

}  // namespace pcrt
