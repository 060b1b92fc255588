#include "harness/sweep.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/json_input.hpp"
#include "core/point_cloud_io.hpp"
#include "core/rng.hpp"
#include "harness/build_info.hpp"
#include "harness/claims.hpp"
#include "harness/command_helpers.hpp"
#include "harness/crossover.hpp"
#include "harness/fit.hpp"
#include "harness/slurm.hpp"
#include "harness/workloads.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "methods/method.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

extern char** environ;

namespace pcrt {

namespace fs = std::filesystem;

namespace {

const std::set<std::string> kKinds = {"render", "build", "reconstruct", "workload", "crossover"};
const std::set<std::string> kGridVariables = {"N", "M", "S", "B"};

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

bool is_generator(const std::string& base) {
  const std::string name = base.substr(0, base.find(':'));
  for (const auto& g : generators())
    if (g.name == name) return true;
  return false;
}

// Whether a generator spec gives n itself (a sweep appends N to it).
bool sets_n(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) return false;
  return spec.find(":n=") == colon || spec.find(",n=", colon) != std::string::npos;
}

std::string generator_spec(const std::string& base, double n) {
  return base + (base.find(':') == std::string::npos ? ":" : ",") +
         "n=" + std::to_string(static_cast<long long>(n));
}

// A file dataset named relative to the config resolves against `dataset_dir` (empty: the
// current folder); generator specs and absolute paths stay as given.
std::string dataset_path(const std::string& dataset, const std::string& dataset_dir) {
  if (is_generator(dataset) || dataset_dir.empty() || fs::path(dataset).is_absolute())
    return dataset;
  return (fs::path(dataset_dir) / dataset).lexically_normal().string();
}

// The cloud of a run: a generator at N points, or N points drawn from a file without
// replacement (seeded, so every run of the same spec sees the same subset).
PointCloud run_cloud(const std::string& base, double n, uint64_t seed) {
  if (is_generator(base)) return load_dataset(generator_spec(base, n)).cloud;
  PointCloud full = load_dataset(base).cloud;
  const auto want = static_cast<size_t>(n);
  if (want > full.size())
    input_error("{}: N = {} but the file has {} points", base, want, full.size());
  if (want == full.size()) return full;
  std::vector<uint32_t> idx(full.size());
  for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  Rng rng(seed, 0x5ab5);
  for (size_t i = 0; i < want; ++i) std::swap(idx[i], idx[i + rng.below(uint32_t(idx.size() - i))]);
  idx.resize(want);
  std::sort(idx.begin(), idx.end());
  return full.subset(idx);
}

// Splits "set.x" values between the method and the structure and checks them as a run would.
void validate_params(const std::string& method, const std::string& structure,
                     const ParamValues& set, const std::string& where) {
  const MethodInfo& m = MethodRegistry::instance().get(method, "method");
  ParamValues mp, sp;
  const std::string sid = structure.empty() ? m.structure : structure;
  const StructureInfo* s =
      m.own_structure.empty() ? &StructureRegistry::instance().get(sid, "structure") : nullptr;
  for (const auto& [k, v] : set) {
    const std::string& name = k;  // clang 14 cannot capture a structured binding
    auto named = [&](const ParamSpec& p) { return p.name == name; };
    const bool in_m = std::any_of(m.params.begin(), m.params.end(), named);
    const bool in_s = s && std::any_of(s->params.begin(), s->params.end(), named);
    if (!in_m && !in_s)
      input_error("{}: set.{} is not a parameter of {} or {}", where, k, method, sid);
    (in_m ? mp : sp)[k] = v;
  }
  resolve_params(m.params, mp, where + " (" + method + ")");
  if (s) resolve_params(s->params, sp, where + " (" + sid + ")");
}

std::vector<std::string> resolve_methods(const json& e, const std::string& where) {
  std::vector<std::string> ids;
  for (const std::string& id : string_list(e.value("methods", json("*")), where + ".methods")) {
    if (id == "*" || id == "surveyed") {  // surveyed: the 16 methods, without the references
      for (const auto& m : MethodRegistry::instance().all())
        if (id == "*" || m.thesis_ref != "-") ids.push_back(m.id);
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

// The grid's points: the cartesian product of every list (N, M, S, B, set.*), or "points".
std::vector<json> grid_points(const json& e, const std::string& where) {
  std::vector<json> points{json::object()};
  if (e.contains("points")) {
    if (!e["points"].is_array() || e["points"].empty())
      input_error("{}.points: must be a non-empty list of objects", where);
    std::vector<json> out;
    for (const auto& p : e["points"]) {
      check_keys(p, kGridVariables, where + ".points");
      out.push_back(p);
    }
    return out;
  }
  const json grid = e.value("grid", json::object());
  check_keys(grid, kGridVariables, where + ".grid");
  for (const auto& [key, values] : grid.items()) {
    std::vector<json> next;
    for (double v : number_list(values, where + ".grid." + key))
      for (json p : points) {
        p[key] = v;
        next.push_back(p);
      }
    points = std::move(next);
  }
  return points;
}

void check_point_values(const json& p, const std::string& kind, const std::string& where) {
  auto positive_int = [&](const char* key, double max) {
    if (!p.contains(key)) return;
    const double v = p[key].get<double>();
    if (!(v >= 1 && v <= max && v == std::floor(v)))
      input_error("{}: {} = {} is impossible (a whole number in [1, {}])", where, key, v, max);
  };
  positive_int("N", 2e8);
  positive_int("M", 16384.0 * 16384.0);
  positive_int("S", 65536);
  if (p.contains("B")) {
    const double b = p["B"].get<double>();
    if (!(b >= 0 && b <= 64 && b == std::floor(b)))
      input_error("{}: B = {} is impossible (a whole number in [0, 64])", where, b);
  }
  if (kind != "workload" && kind != "reconstruct" && !p.contains("N"))
    input_error("{}: no N given (grid.N or points[].N)", where);
}

// Fills a claim template ({method}, {structure}, ...) from a run spec or row.
std::string substitute(std::string s, const json& row) {
  for (const char* k : {"method", "structure", "reconstruction", "workload"}) {
    const std::string key = std::string("{") + k + "}";
    for (size_t p; (p = s.find(key)) != std::string::npos;)
      s.replace(p, key.size(), row.value(k, std::string()));
  }
  return s;
}

// The counts a reconstruction run records (execute_run), beside the registered counters.
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

FitSpec parse_fit(const json& f, const std::string& experiment, const std::string& where) {
  check_keys(f, {"claim", "variable", "x", "metric", "per", "max", "min", "by", "free"}, where);
  FitSpec s;
  s.experiment = experiment;
  if (!f.contains("claim") || !f["claim"].is_string())
    input_error("{}: 'claim' is required", where);
  s.claim = f["claim"].get<std::string>();
  s.variable = f.value("variable", std::string());
  s.x = f.value("x", s.variable);
  if (!f.contains("metric")) input_error("{}: 'metric' is required", where);
  s.metric = string_list(f["metric"], where + ".metric");
  // Other metric names are run columns (time, fps, I_run, a crossover's times, ...).
  for (const std::string& m : s.metric)
    if (m.rfind("ops_", 0) == 0 && !is_counter_column(m))
      input_error("{}.metric: '{}' is not a counter (pcrt list)", where, m);
  s.per = f.value("per", std::string());
  if (!s.per.empty() && !is_counter_column(s.per))
    input_error("{}.per: '{}' is not a counter (ops_NAME, pcrt list)", where, s.per);
  if (f.contains("by")) s.by = string_list(f["by"], where + ".by");
  if (f.contains("free")) s.free = string_list(f["free"], where + ".free");
  for (const std::string& v : s.free)
    if (v != "K" && v != "k" && v != "I_run")
      input_error("{}.free: '{}' is not one of K, k, I_run", where, v);
  s.max = f.value("max", -1.0);
  s.min = f.value("min", -1.0);
  if (s.max < 0 && s.min < 0 && s.variable.empty())
    input_error("{}: a growth fit needs 'variable' (or 'max'/'min' for a threshold)", where);
  if (!s.variable.empty() && std::string("SMBNKkI").find(s.variable) == std::string::npos)
    input_error("{}: variable '{}' is not one of S M B N K k I", where, s.variable);
  const std::set<std::string> columns = {"S", "M", "B", "N", "K", "k", "I", "I_run"};
  if (!s.x.empty() && !columns.count(s.x) && s.x.rfind("set_", 0) != 0)
    input_error("{}.x: '{}' is not one of S M B N K k I I_run or set_PARAMETER", where, s.x);
  // Rays are S * M * (paths) by construction: a growth fit on them proves nothing.
  const std::set<std::string> rays = {"ops_rays_cast", "ops_primary_rays", "ops_bounce_rays",
                                      "ops_shadow_rays", "ops_ray_hits"};
  if (s.max < 0 && s.min < 0 &&
      std::all_of(s.metric.begin(), s.metric.end(), [&](auto& m) { return rays.count(m); }))
    input_error(
        "{}: metric counts rays only, which grow with S and M by construction; fit "
        "'work' or a method's own counters",
        where);
  return s;
}

}  // namespace

SweepConfig parse_sweep_config(const json& raw, const std::string& origin) {
  check_keys(raw,
             {"name", "description", "threads", "repetitions", "warmup", "time_limit_s", "measure",
              "seed", "experiments", "dataset_dir"},
             origin);
  if (raw.contains("dataset_dir") && !raw["dataset_dir"].is_string())
    input_error("{}: dataset_dir must be a folder name", origin);
  const std::string dataset_dir = raw.value("dataset_dir", std::string());
  SweepConfig c;
  c.raw = raw;
  c.name = raw.value("name", std::filesystem::path(origin).stem().string());
  const double threads = raw.value("threads", 2.0), reps = raw.value("repetitions", 1.0),
               warmup = raw.value("warmup", 0.0), seed = raw.value("seed", 1.0);
  c.time_limit_s = raw.value("time_limit_s", 300.0);
  if (!(threads >= 1 && threads <= 1024))
    input_error("{}: threads = {} is impossible", origin, threads);
  if (!(reps >= 1 && reps <= 1000)) input_error("{}: repetitions = {} is impossible", origin, reps);
  if (!(warmup >= 0 && warmup <= 100)) input_error("{}: warmup = {} is impossible", origin, warmup);
  if (!(c.time_limit_s > 0)) input_error("{}: time_limit_s must be positive", origin);
  const std::string measure = raw.value("measure", std::string("both"));
  if (measure != "both" && measure != "ops" && measure != "time")
    input_error("{}: measure must be 'ops', 'time' or 'both', not '{}'", origin, measure);
  if (!raw.contains("experiments") || !raw["experiments"].is_array() || raw["experiments"].empty())
    input_error("{}: 'experiments' must be a non-empty list", origin);
  std::set<std::string> names;
  for (size_t i = 0; i < raw["experiments"].size(); ++i) {
    const json& e = raw["experiments"][i];
    const std::string where = fmt::format("{}: experiments[{}]", origin, i);
    check_keys(
        e,
        {"name", "description", "kind", "methods", "structures", "datasets", "grid", "points",
         "reconstructions", "engine", "workloads", "fits", "repetitions", "camera"},
        where);
    const std::string name = e.value("name", fmt::format("experiment{}", i));
    if (!names.insert(name).second) input_error("{}: name '{}' used twice", where, name);
    const std::string kind = e.value("kind", std::string());
    if (!kKinds.count(kind))
      input_error("{}: kind must be render, build, reconstruct, workload or crossover, not '{}'",
                  where, kind);
    ParamValues set;
    for (const auto& [k, v] : e.items())
      if (k.rfind("set.", 0) == 0) {
        if (!v.is_number()) input_error("{}: {} must be a number", where, k);
        set[k.substr(4)] = v.get<double>();
      }
    const std::vector<json> points = grid_points(e, where);
    for (const json& p : points) check_point_values(p, kind, where);
    const int run_reps = int(e.value("repetitions", reps));
    const std::string camera = e.value("camera", std::string("outside"));
    if (camera != "outside" && camera != "inside")
      input_error("{}: camera must be 'outside' or 'inside', not '{}'", where, camera);
    json base = {{"experiment", name},      {"kind", kind},
                 {"reps", run_reps},        {"warmup", int(warmup)},
                 {"threads", int(threads)}, {"seed", uint64_t(seed)},
                 {"measure", measure}};
    // Inside a closed surface every bounce hits again, so work per path grows with B.
    if (camera == "inside") base["camera"] = camera;
    std::vector<std::string> datasets;
    if (kind != "workload") {
      datasets = string_list(e.value("datasets", json()), where + ".datasets");
      for (const std::string& d : datasets) {
        if (is_generator(d)) {
          (void)parse_generator_spec(d, nullptr);
          if (sets_n(d))
            input_error("{}.datasets: '{}' sets n; a sweep takes N from its grid", where, d);
        } else {
          const PointCloud full = load_dataset(dataset_path(d, dataset_dir)).cloud;
          for (const json& p : points)
            if (p.contains("N") && p["N"].get<double>() > double(full.size()))
              input_error("{}: N = {} but {} has {} points", where, p["N"].get<double>(), d,
                          full.size());
        }
      }
    }
    // A point's "set.x" values join the experiment's; each combination is checked as a run
    // would check it.
    auto emit = [&](json spec) {
      if (spec.contains("dataset")) {
        const std::string path = dataset_path(spec["dataset"], dataset_dir);
        if (path != spec["dataset"]) spec["dataset_path"] = path;
      }
      for (const json& p : points) {
        json s = spec;
        for (const auto& [k, v] : p.items()) {
          if (k.rfind("set.", 0) == 0)
            s["set"][k.substr(4)] = v;
          else
            s[k] = v;
        }
        if (s.contains("method")) {
          ParamValues merged;
          for (const auto& [k, v] : s["set"].items()) merged[k] = v.get<double>();
          validate_params(s["method"], s["structure"], merged, where);
        }
        c.runs.push_back(s);
      }
    };
    if (kind == "render" || kind == "build" || kind == "crossover") {
      const json default_methods = kind == "build" ? json("reference_splat") : json("*");
      json e2 = e;
      if (!e.contains("methods")) e2["methods"] = default_methods;
      for (const std::string& m : resolve_methods(e2, where)) {
        const MethodInfo& info = MethodRegistry::instance().get(m, "method");
        for (const std::string& s : resolve_structures(e, info, where)) {
          for (const std::string& d : datasets) {
            json spec = base;
            spec.update({{"dataset", d}, {"method", m}, {"structure", s}, {"set", set}});
            if (kind == "crossover") {
              spec["reconstruction"] = e.value("reconstructions", json("afsr")).is_array()
                                           ? e["reconstructions"][0]
                                           : e.value("reconstructions", json("afsr"));
              spec["engine"] = e.value("engine", std::string("bvh"));
              (void)ReconstructionRegistry::instance().get(spec["reconstruction"],
                                                           "reconstruction");
              (void)MeshEngineRegistry::instance().get(spec["engine"], "mesh engine");
            }
            emit(spec);
          }
        }
      }
    } else if (kind == "reconstruct") {
      for (const std::string& r :
           string_list(e.value("reconstructions", json()), where + ".reconstructions")) {
        (void)ReconstructionRegistry::instance().get(r, "reconstruction");
        for (const std::string& d : datasets) {
          json spec = base;
          spec.update({{"dataset", d}, {"reconstruction", r}});
          emit(spec);
        }
      }
    } else {  // workload
      for (const std::string& w : string_list(e.value("workloads", json()), where + ".workloads")) {
        if (std::none_of(workloads().begin(), workloads().end(),
                         [&](auto& x) { return x.id == w; }))
          input_error("{}: unknown workload '{}'", where, w);
        json spec = base;
        spec["workload"] = w;
        emit(spec);
      }
    }
    if (e.contains("fits")) {
      if (!e["fits"].is_array()) input_error("{}.fits: must be a list", where);
      std::vector<std::string> swept;
      const json grid = e.value("grid", json::object());
      for (const auto& [k, v] : grid.items())
        if (v.is_array() && v.size() > 1)
          swept.push_back(k.rfind("set.", 0) == 0 ? "set_" + k.substr(4) : k);
      for (size_t f = 0; f < e["fits"].size(); ++f) {
        const std::string fwhere = fmt::format("{}.fits[{}]", where, f);
        c.fits.push_back(parse_fit(e["fits"][f], name, fwhere));
        c.fits.back().swept = swept;
        // Every run the fit will see must name a registered claim that is in its variable.
        for (const json& run : c.runs) {
          if (run.value("experiment", "") != name) continue;
          try {
            const Claim& claim = find_claim(substitute(c.fits.back().claim, run));
            if (!claim.not_tested.empty())
              input_error("claim '{}' is not tested: {}", claim.id, claim.not_tested);
            if (!c.fits.back().variable.empty() && c.fits.back().max < 0 && c.fits.back().min < 0)
              (void)expected_growth(claim.complexity, c.fits.back().variable);
          } catch (const InputError& err) {
            input_error("{}: {}", fwhere, err.what());
          }
        }
      }
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
    const std::string given = raw.value("dataset_dir", std::string());
    std::string dir = (folder / given).lexically_normal().string();
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    raw["dataset_dir"] = dir;
    return parse_sweep_config(raw, path);
  } catch (const json::exception& e) {
    input_error("{}: wrong type: {}", path, e.what());
  }
}

std::string run_key(const json& spec) {
  json s = spec.contains("spec") ? spec["spec"] : spec;  // a result: the spec it ran
  // Where the dataset lies on this machine is not what the run is (a cluster node, a moved
  // checkout): the key keeps the name the config gives.
  for (const char* k :
       {"status", "error", "counters", "prepare_counters", "times_s", "extra", "spec", "wall_s",
        "time_median_s", "time_min_s", "time_max_s", "time_spread", "dataset_path"})
    s.erase(k);
  return s.dump();
}

namespace {

void summarize_times(json& r, std::vector<double> t) {
  r["times_s"] = t;
  std::sort(t.begin(), t.end());
  const double med = t.empty() ? 0 : t[t.size() / 2];
  r["time_median_s"] = med;
  r["time_min_s"] = t.empty() ? 0 : t.front();
  r["time_max_s"] = t.empty() ? 0 : t.back();
  r["time_spread"] = med > 0 ? (t.back() - t.front()) / med : 0.0;
}

RenderSettings render_settings(const json& spec, const PointCloud& cloud) {
  RenderSettings rs;
  const double m = spec.value("M", 64.0 * 64.0);
  rs.width = rs.height = std::max(1, int(std::lround(std::sqrt(m))));
  rs.spp = int(spec.value("S", 1.0));
  rs.bounces = int(spec.value("B", 1.0));
  rs.threads = spec.value("threads", 2);
  rs.seed = spec.value("seed", uint64_t(1));
  if (spec.value("camera", std::string()) == "inside") {
    // At the centre of the cloud's bounds, looking along the default view, 90 degrees wide.
    const Aabb b = cloud.bounds();
    rs.camera = Camera(b.center(), b.center() - rs.view, rs.up, 90.0f, rs.width, rs.height);
  }
  return rs;
}

}  // namespace

json execute_run(const json& spec) {
  json r = spec;
  r["spec"] = spec;  // as given: what --resume and merges identify the run by
  const std::string kind = spec.at("kind");
  const int reps = spec.value("reps", 1), warmup = spec.value("warmup", 0);
  const uint64_t seed = spec.value("seed", uint64_t(1));
  std::vector<double> times;
  json extra = json::object();
  if (kind == "workload") {
    OpCounters first;
    for (int i = 0; i < warmup + reps; ++i) {
      OpCounters c;
      const double s =
          run_workload(spec.at("workload"), size_t(spec.at("N").get<double>()), seed, c);
      if (i >= warmup) times.push_back(s);
      if (i == 0) first = c;
    }
    r["counters"] = counters_json(first);
  } else {
    const PointCloud cloud =
        run_cloud(spec.value("dataset_path", spec.at("dataset")), spec.value("N", 0.0), seed);
    r["N"] = cloud.size();
    if (kind == "reconstruct") {
      const auto& info =
          ReconstructionRegistry::instance().get(spec.at("reconstruction"), "reconstruction");
      json counts;
      for (int i = 0; i < warmup + reps; ++i) {
        const ReconstructionReport rec = info.run(cloud);
        if (i >= warmup) times.push_back(rec.seconds);
        counts = json::object();
        for (const auto& [k, v] :
             std::map<std::string, std::optional<uint64_t>>{{"cells", rec.cells},
                                                            {"facets", rec.facets},
                                                            {"triangles", rec.triangles},
                                                            {"boundary_edges", rec.boundary_edges},
                                                            {"predicates", rec.predicates}})
          if (v) counts[k] = *v;
        counts["vertices"] = rec.vertices;
        extra["memory_bytes"] = rec.memory_bytes;
      }
      r["counters"] = counts;
    } else {
      SceneOptions so;
      so.method = spec.at("method");
      so.structure = spec.at("structure");
      for (const auto& [k, v] : spec.at("set").items()) so.set[k] = v.get<double>();
      const RenderSettings rs = render_settings(spec, cloud);
      if (kind == "crossover") {
        const CrossoverResult x =
            measure_crossover(cloud, so, spec.at("reconstruction"), spec.at("engine"), rs, reps);
        extra = {
            {"direct_setup_s", x.direct_setup_s()},
            {"direct_frame_s", x.direct_frame_s},
            {"mesh_setup_s", x.mesh_setup_s()},
            {"mesh_frame_s", x.mesh_frame_s},
            {"reconstruct_s", x.reconstruct_s},
            {"triangles", x.triangles},
            {"crossover_frames", x.crossover_frames ? json(*x.crossover_frames) : json(nullptr)}};
        times.push_back(x.mesh_setup_s() + x.mesh_frame_s);
        r["counters"] = json::object();
      } else {
        OpCounters prep, frame;
        for (int i = 0; i < warmup + reps; ++i) {
          Timings t;
          OpCounters p;
          const PointScene scene(cloud, so, p, t);
          if (i == 0) prep = p;
          if (kind == "build") {
            if (i >= warmup) times.push_back(t["build"]);
            extra["prepare_s"] = t["prepare"];
            extra["structure_bytes"] = scene.structure_bytes();
            continue;
          }
          RenderResult res = render(scene, cloud, rs);
          if (i >= warmup) times.push_back(res.seconds);
          if (i == 0) frame = res.counters;
          extra["prepare_s"] = t["prepare"];
          extra["build_s"] = t["build"];
          extra["structure_bytes"] = scene.structure_bytes();
        }
        r["counters"] = counters_json(frame);
        r["prepare_counters"] = counters_json(prep);
        r["M"] = rs.width * rs.height;
      }
    }
  }
  summarize_times(r, times);
  r["extra"] = extra;
  r["status"] = "ok";
  return r;
}

json run_in_child(const json& spec, double time_limit_s) {
  int out_pipe[2], err_pipe[2];
  if (pipe(out_pipe) != 0 || pipe(err_pipe) != 0) input_error("sweep: cannot create a pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  posix_spawn_file_actions_addclose(&actions, out_pipe[0]);
  posix_spawn_file_actions_addclose(&actions, err_pipe[0]);
  const std::string arg = spec.dump();
  std::string exe = std::filesystem::read_symlink("/proc/self/exe").string();
  // The child learns who its sweep is, so that it dies with it (command_run_one). The kernel's
  // parent-death signal follows the spawning thread: runs are spawned from the sweep's own thread.
  std::string parent = std::to_string(getpid());
  char* argv[] = {exe.data(), const_cast<char*>("_run"), const_cast<char*>(arg.c_str()),
                  parent.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (rc != 0) input_error("sweep: cannot start {}: {}", exe, std::strerror(rc));
  std::string out, err;
  const auto start = std::chrono::steady_clock::now();
  bool timed_out = false;
  int status = 0;
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  bool open_out = true, open_err = true;
  char buf[65536];
  while (open_out || open_err) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!timed_out && elapsed > time_limit_s) {
      kill(pid, SIGKILL);
      timed_out = true;
    }
    if (poll(fds, 2, 100) <= 0) continue;
    for (int i = 0; i < 2; ++i) {
      if (!(fds[i].revents & (POLLIN | POLLHUP))) continue;
      const ssize_t n = read(fds[i].fd, buf, sizeof(buf));
      if (n > 0) {
        (i == 0 ? out : err).append(buf, size_t(n));
      } else {
        (i == 0 ? open_out : open_err) = false;
        fds[i].fd = -1;
      }
    }
  }
  close(out_pipe[0]);
  close(err_pipe[0]);
  waitpid(pid, &status, 0);
  // The whole run's wall time, preparation and process included: what shard plans balance on.
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  json r = spec;
  r["spec"] = spec;
  r["wall_s"] = wall_s;
  if (timed_out) {
    r["status"] = "timeout";
    r["error"] = fmt::format("exceeded the time limit of {} s", time_limit_s);
    return r;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    try {
      json result = json::parse(out);
      result["wall_s"] = wall_s;
      return result;
    } catch (const json::exception&) {
      r["status"] = "failed";
      r["error"] = "the run printed no valid JSON";
      return r;
    }
  }
  while (!err.empty() && err.back() == '\n') err.pop_back();
  const size_t nl = err.rfind('\n');
  r["status"] = "failed";
  r["error"] = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                   : (nl == std::string::npos ? err : err.substr(nl + 1));
  return r;
}

namespace {

// The default of a method's own K parameter (MLS neighbours, fan size, ...), if it declares one.
std::optional<double> method_k_parameter(const std::string& method) {
  if (!MethodRegistry::instance().contains(method)) return std::nullopt;
  for (const ParamSpec& p : MethodRegistry::instance().get(method, "method").params)
    if (p.name == "K") return p.default_value;
  return std::nullopt;
}

}  // namespace

json run_row(const json& r) {
  json row = json::object();
  for (const char* k : {"experiment", "kind", "method", "structure", "dataset", "reconstruction",
                        "engine", "workload", "status", "error"})
    row[k] = r.value(k, json(""));
  for (const char* k : {"N", "M", "S", "B"}) row[k] = r.contains(k) ? r[k] : json(nullptr);
  const json set = r.value("set", json::object());
  const json counters = r.value("counters", json::object());
  // K: the method's K when it has one (given, or its default), else the measured mean items per
  // visited leaf.
  const std::optional<double> method_k = method_k_parameter(r.value("method", ""));
  if (set.contains("K"))
    row["K"] = set["K"];
  else if (method_k)
    row["K"] = *method_k;
  else if (counters.value("leaves_visited", 0.0) > 0)
    row["K"] = counters.value("items_visited", 0.0) / counters.value("leaves_visited", 1.0);
  else
    row["K"] = nullptr;
  row["k"] = set.contains("k") ? set["k"] : json(nullptr);
  row["I"] = set.contains("max_iterations") ? set["max_iterations"] : json(nullptr);
  // I as measured: iterations per iterative run (Newton, MLS, height difference), whatever the
  // cap; what the drift check and iteration fits look at.
  const double steps = counters.value("newton_steps", 0.0) + counters.value("mls_fits", 0.0) +
                       counters.value("height_steps", 0.0);
  const double runs = counters.value("newton_runs", 0.0) + counters.value("mls_runs", 0.0) +
                      counters.value("height_starts", 0.0);
  row["I_run"] = runs > 0 ? json(steps / runs) : json(nullptr);
  for (const auto& [k, v] : set.items()) row["set_" + k] = v;
  for (const auto& [k, v] : counters.items()) row["ops_" + k] = v;
  // (Each json is held in a local: items() of a temporary would dangle in a range-for.)
  const json prepare = r.value("prepare_counters", json::object());
  for (const auto& [k, v] : prepare.items()) row["ops_prep_" + k] = v;
  for (const char* k : {"time_median_s", "time_min_s", "time_max_s", "time_spread"})
    row[k] = r.contains(k) ? r[k] : json(nullptr);
  // Flagged, never dropped: repetitions more than 20% apart.
  row["time_noisy"] =
      r.value("times_s", json::array()).size() > 1 && r.value("time_spread", 0.0) > 0.2;
  const json extra = r.value("extra", json::object());
  for (const auto& [k, v] : extra.items()) row[k] = v;
  return row;
}

void write_runs_csv(const std::string& path, const std::vector<json>& results) {
  std::vector<json> rows;
  std::vector<std::string> columns = {
      "experiment", "kind",     "method", "structure", "dataset", "reconstruction",
      "engine",     "workload", "N",      "M",         "S",       "B",
      "K",          "k",        "I",      "I_run"};
  std::set<std::string> seen(columns.begin(), columns.end()), rest;
  for (const json& r : results) {
    rows.push_back(run_row(r));
    for (const auto& [k, v] : rows.back().items())
      if (!seen.count(k)) rest.insert(k);
  }
  // Parameters, then counters, then times and the rest, each alphabetically.
  auto take = [&](auto pred) {
    for (const std::string& k : rest)
      if (pred(k)) columns.push_back(k);
  };
  take([](const std::string& k) { return k.rfind("set_", 0) == 0; });
  take([](const std::string& k) { return k.rfind("ops_", 0) == 0; });
  take([](const std::string& k) { return k.rfind("time_", 0) == 0; });
  take([](const std::string& k) {
    return k.rfind("set_", 0) != 0 && k.rfind("ops_", 0) != 0 && k.rfind("time_", 0) != 0 &&
           k != "status" && k != "error";
  });
  columns.push_back("status");
  columns.push_back("error");
  auto cell = [](const json& v) -> std::string {
    if (v.is_null()) return "";
    if (v.is_string()) {
      std::string s = v.get<std::string>();
      if (s.find_first_of(",\"\n") == std::string::npos) return s;
      std::string q = "\"";
      for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
    if (v.is_number_float()) return fmt::format("{:.9g}", v.get<double>());
    return v.dump();
  };
  write_file_atomically(path, [&](std::ostream& o) {
    for (size_t i = 0; i < columns.size(); ++i) o << (i ? "," : "") << columns[i];
    o << '\n';
    for (const json& row : rows) {
      for (size_t i = 0; i < columns.size(); ++i)
        o << (i ? "," : "") << cell(row.value(columns[i], json(nullptr)));
      o << '\n';
    }
  });
}

std::vector<json> read_runs_jsonl(const std::string& path) {
  if (!std::filesystem::exists(path)) input_error("{}: cannot open: no such file", path);
  // Bounded (runs.jsonl may be a link to a device); a running sweep may be appending to it (pcrt
  // cluster status reads the shards' while they run): what was there when reading began.
  const std::string text = read_file(path, kMaxStreamBytes, FileGrowth::kSnapshot);
  std::vector<json> runs;
  size_t n = 0;
  for (size_t pos = 0; pos < text.size();) {
    size_t end = text.find('\n', pos);
    const bool last = end == std::string::npos || end + 1 == text.size();
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++n;
    if (line.empty()) continue;
    try {
      runs.push_back(parse_json_text(line, fmt::format("{}: line {}", path, n)));
    } catch (const InputError&) {
      // A sweep killed mid-write leaves at most a truncated last line: that run is redone.
      if (last) break;
      input_error("{}: line {} is not valid JSON", path, n);
    }
  }
  return runs;
}

namespace {

// The source tree's commit and whether tracked files differ from it (results made from a dirty
// tree cannot be reproduced from the commit alone). Asks git; "unknown" without it.
std::pair<std::string, json> source_revision() {
  // Run without a shell, so no path needs quoting; "unknown" when git is missing or fails.
  auto git = [](std::vector<std::string> args, bool& ok) {
    args.insert(args.begin(), {"git", "-C", build_info().source_dir});
    try {
      CommandOutput out = run_command(args);
      ok = out.exit_code == 0;
      return out.out;
    } catch (const InputError&) {
      ok = false;
      return std::string();
    }
  };
  bool ok = false;
  std::string commit = git({"rev-parse", "HEAD"}, ok);
  while (!commit.empty() && std::isspace(static_cast<unsigned char>(commit.back())))
    commit.pop_back();
  if (!ok || commit.empty()) return {"unknown", nullptr};
  const std::string status = git({"status", "--porcelain", "--untracked-files=no"}, ok);
  return {commit, ok ? json(!status.empty()) : json(nullptr)};
}

}  // namespace

json machine_context(const json& config) {
  auto first_line_of = [](const std::string& file, const std::string& key) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind(key, 0) == 0) {
        const size_t colon = line.find(':');
        std::string v = colon == std::string::npos ? line : line.substr(colon + 1);
        v.erase(0, v.find_first_not_of(" \t"));
        return v;
      }
    return std::string();
  };
  auto read_all = [](const std::string& file) {
    std::ifstream in(file);
    std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
  };
  const auto [commit, dirty] = source_revision();
  return {{"machine",
           {{"cpu", first_line_of("/proc/cpuinfo", "model name")},
            {"cores", std::thread::hardware_concurrency()},
            {"memory", first_line_of("/proc/meminfo", "MemTotal")},
            {"governor", read_all("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor")}}},
          {"compiler", build_info().compiler},
          {"flags", build_info().flags},
          {"build_type", build_info().build_type},
          {"leaf_simd", disc_lanes_name()},
          {"dependencies", build_info().dependencies},
          {"git_commit", commit},
          {"git_dirty", dirty},
          {"config", config}};
}

namespace {

double column(const json& row, const std::string& name) {
  if (name == "time") return row.value("time_median_s", 0.0);
  if (name == "fps") {
    const double t = row.value("time_median_s", 0.0);
    return t > 0 ? 1.0 / t : 0.0;
  }
  const json v = row.value(name, json(nullptr));
  if (v.is_number()) return v.get<double>();
  // A counter a run never touched is zero (a method that does no rasterization, say).
  return name.rfind("ops_", 0) == 0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
}

// The columns a metric names: "work" is a method's declared work (traversal nodes and items, and
// its own leaf counters, MethodInfo::work), so frame claims are judged on work, never on rays.
std::vector<std::string> metric_columns(const std::vector<std::string>& metric, const json& row) {
  std::vector<std::string> cols;
  for (const std::string& m : metric) {
    if (m != "work") {
      cols.push_back(m);
      continue;
    }
    cols.push_back("ops_nodes_visited");
    cols.push_back("ops_items_visited");
    const std::string method = row.value("method", "");
    if (MethodRegistry::instance().contains(method))
      for (const Counter* c : MethodRegistry::instance().get(method, "method").work)
        cols.push_back("ops_" + registered_counters()[c->id()].name);
  }
  return cols;
}

// The variables a run must hold while another is swept, as run columns.
constexpr std::array<const char*, 3> kHeldColumns = {"K", "k", "I_run"};

struct FitPoint {
  double x, y;
  std::array<double, 3> held;  // kHeldColumns of the run; NaN where the run has none
};

// Variables that the claim does not sweep must stay put: K (the method's K or the measured
// items per leaf), k, and I (the measured iterations per run).
std::string drift_of(const std::vector<FitPoint>& pts, const FitSpec& f) {
  for (size_t i = 0; i < kHeldColumns.size(); ++i) {
    const std::string v = kHeldColumns[i];
    if (f.variable == v || (f.variable == "I" && v == "I_run")) continue;
    if (std::find(f.free.begin(), f.free.end(), v) != f.free.end()) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const FitPoint& p : pts)
      if (std::isfinite(p.held[i])) lo = std::min(lo, p.held[i]), hi = std::max(hi, p.held[i]);
    if (hi > 0 && lo < hi && (hi - lo) > 0.2 * lo)
      return fmt::format("{} moved from {:.3g} to {:.3g} (+{:.0f}%) while it should be fixed",
                         v == "I_run" ? "I (iterations per run)" : v, lo, hi, 100 * (hi - lo) / lo);
  }
  return {};
}

// y / x the same at every x: the metric counts x by construction (a loop over K items adds K).
bool is_identity(const std::vector<FitPoint>& pts) {
  const double r0 = pts.front().y / pts.front().x;
  return std::all_of(pts.begin(), pts.end(),
                     [&](const FitPoint& p) { return std::abs(p.y / p.x - r0) <= 1e-9 * r0; });
}

void fit_threshold(const FitSpec& f, const std::vector<FitPoint>& pts, json& out) {
  double worst = f.max >= 0 ? 0 : std::numeric_limits<double>::infinity();
  for (const FitPoint& p : pts) worst = f.max >= 0 ? std::max(worst, p.y) : std::min(worst, p.y);
  out["measured"] = pts.empty() ? json(nullptr) : json(worst);
  out["threshold"] = f.max >= 0 ? fmt::format("<= {}", f.max) : fmt::format(">= {}", f.min);
  const bool met = f.max >= 0 ? worst <= f.max : worst >= f.min;
  out["verdict"] = verdict_name(pts.empty() ? ClaimVerdict::kError
                                : met       ? ClaimVerdict::kMeets
                                            : ClaimVerdict::kMisses);
}

// Fits one group and writes its numbers into `out`; returns its verdict (also written).
ClaimVerdict fit_growth_group(const FitSpec& f, const Claim& claim, std::vector<FitPoint> pts,
                              json& out) {
  // Identical points (parameters that build the same structure) are one observation.
  std::sort(pts.begin(), pts.end(), [](const FitPoint& a, const FitPoint& b) {
    return std::tie(a.x, a.y) < std::tie(b.x, b.y);
  });
  pts.erase(
      std::unique(pts.begin(), pts.end(),
                  [](const FitPoint& a, const FitPoint& b) { return a.x == b.x && a.y == b.y; }),
      pts.end());
  std::vector<double> xs, ys;
  for (const FitPoint& p : pts) xs.push_back(p.x), ys.push_back(p.y);
  out["x_values"] = xs;
  out["y_values"] = ys;
  const Growth expected = expected_growth(claim.complexity, f.variable);
  out["expected_model"] = growth_name(expected);
  const GrowthFit g = fit_growth(xs, ys, expected, out["claim"].get<std::string>());
  json weights = json::object();
  for (size_t m = 0; m < kModels; ++m) weights[growth_name(kAllGrowths[m])] = g.weight[m];
  out.update({{"points", g.points},
              {"exponent", g.exponent},
              {"ci_low", g.ci_low},
              {"ci_high", g.ci_high},
              {"detectable_exponent", g.detectable_exponent},
              {"best_model", growth_name(g.best)},
              {"r2", g.r2},
              {"noise", g.noise},
              {"akaike_weights", weights},
              {"weight_faster", g.weight_faster},
              {"weight_slower", g.weight_slower},
              {"delta_aicc_expected", g.delta_aicc_expected}});
  ClaimVerdict verdict = g.verdict;
  std::string reason = g.reason;
  // What this design could detect at the noise it shows (floor 0.5%): a violation one class up,
  // and how often an exactly true claim would be called `exceeds`.
  const double noise = std::max(g.noise, 0.005);
  if (next_growth(expected) != expected)
    out["power_one_up"] =
        simulate_verdicts(xs, next_growth(expected), expected, noise, 0, 200, 7).exceeds;
  out["false_exceeds"] = simulate_verdicts(xs, expected, expected, noise, 0, 200, 8).exceeds;
  // "Within" is a claim about what was not seen: it needs a design that would have seen a
  // violation one class up at this noise at least 90% of the time.
  const double power = out.value("power_one_up", 1.0);
  if (verdict == ClaimVerdict::kWithin && power < 0.9) {
    verdict = ClaimVerdict::kInconclusive;
    reason = fmt::format(
        "no faster model is preferred, but at this noise ({:.1f}%) the design would catch {} only "
        "{:.0f}% of the time",
        100 * g.noise, growth_name(next_growth(expected)), 100 * power);
  }
  if (is_identity(pts)) {
    verdict = ClaimVerdict::kIdentity;
    reason = fmt::format(
        "y / x = {:.6g} at every x: the metric counts x by construction "
        "(a loop-structure check, not a test of the claim)",
        pts.front().y / pts.front().x);
  }
  out["verdict"] = verdict_name(verdict);
  out["reason"] = reason;
  return verdict;
}

json fit_group(const FitSpec& f, const std::string& key, const std::vector<json>& rows) {
  const json& first = rows.front();
  json out = {{"claim", substitute(f.claim, first)},
              {"experiment", f.experiment},
              {"method", first.value("method", "")},
              {"structure", first.value("structure", "")},
              {"dataset", first.value("dataset", "")},
              {"reconstruction", first.value("reconstruction", "")},
              {"workload", first.value("workload", "")},
              {"variable", f.variable},
              {"x", f.x},
              {"group", json::parse(key)}};
  const std::vector<std::string> cols = metric_columns(f.metric, first);
  out["metric"] = fmt::format("{}{}", fmt::join(cols, "+"), f.per.empty() ? "" : " per " + f.per);
  std::vector<FitPoint> pts;
  size_t failed = 0;
  for (const json& row : rows) {
    if (row.value("status", "") != "ok") {
      ++failed;
      continue;
    }
    double y = 0;
    for (const std::string& m : cols) y += column(row, m);
    if (!f.per.empty()) y /= column(row, f.per);
    std::array<double, 3> held{};
    for (size_t i = 0; i < kHeldColumns.size(); ++i) {
      const json v = row.value(kHeldColumns[i], json(nullptr));
      held[i] = v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
    }
    pts.push_back({f.x.empty() ? 0.0 : column(row, f.x), y, held});
  }
  out["runs"] = rows.size();
  out["failed_runs"] = failed;
  try {
    const Claim& claim = find_claim(out["claim"].get<std::string>());
    out["claimed"] = claim.complexity;
    out["source"] = claim.source;
    if (f.max >= 0 || f.min >= 0) {
      fit_threshold(f, pts, out);
      return out;
    }
    const std::string drift = drift_of(pts, f);
    const ClaimVerdict verdict = fit_growth_group(f, claim, pts, out);
    if (!drift.empty() && verdict != ClaimVerdict::kIdentity) {
      out["verdict_if_fixed"] = out["verdict"];
      out["verdict"] = verdict_name(ClaimVerdict::kDrifted);
      out["reason"] = drift;
    }
  } catch (const InputError& e) {
    out["verdict"] = verdict_name(ClaimVerdict::kError);
    out["error"] = e.what();
  }
  return out;
}

// The key of a run's group: everything but x, the measurements and what the experiment sweeps.
std::string group_key(const FitSpec& f, const json& row) {
  json key = row;
  for (const auto& [k, v] : row.items())
    if (k.rfind("ops_", 0) == 0 || k.rfind("time_", 0) == 0 || k == "K" || k == "k" || k == "I" ||
        k == "I_run" || k == "error" || k == "status" || k == f.x || (f.x == "K" && k == "set_K"))
      key.erase(k);
  for (const char* k : {"prepare_s", "build_s", "structure_bytes", "memory_bytes", "direct_setup_s",
                        "direct_frame_s", "mesh_setup_s", "mesh_frame_s", "reconstruct_s",
                        "crossover_frames", "triangles"})
    key.erase(k);
  for (const std::string& k : f.swept)
    if (std::find(f.by.begin(), f.by.end(), k) == f.by.end()) key.erase(k);
  return key.dump();
}

}  // namespace

std::vector<json> fit_runs(const SweepConfig& config, const std::vector<json>& results) {
  std::vector<json> fits;
  for (const FitSpec& f : config.fits) {
    std::map<std::string, std::vector<json>> groups;
    for (const json& r : results)
      if (r.value("experiment", "") == f.experiment) {
        const json row = run_row(r);
        groups[group_key(f, row)].push_back(row);
      }
    for (const auto& [key, rows] : groups) fits.push_back(fit_group(f, key, rows));
  }
  return fits;
}

}  // namespace pcrt
