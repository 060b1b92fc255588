// The command line, with CLI11 (Debian libcli11-dev): one subcommand per command, each option bound
// to a field of the command's options struct (command_options.hpp, where the defaults are) by one
// bind() per command below, with its value name, help text and range. This is the one translation
// unit that includes CLI11 (a header-only library that costs seconds per file to compile).
//
// Errors are one line naming the option and its value, as before CLI11: the bindings' own value
// checks throw InputError themselves (CLI11 passes any exception that is not its own through), and
// CLI11's parse errors are translated by reading the parse's state (which option was given twice,
// which arguments were left over), never by parsing CLI11's message texts.
#include "harness/cli.hpp"

#include <CLI/CLI.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "harness/commands.hpp"
#include "render/mesh_truth.hpp"

namespace pcrt {
namespace {

// ---- Values: each check throws InputError naming the option, and leaves the text in the one
// form CLI11 converts as meant (CLI11 alone would read 010 as octal 8).

CLI::Validator integer_in(const std::string& option, long long lo, long long hi) {
  return {[option, lo, hi](std::string& text) {
            long long x = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
            if (text.empty() || ec != std::errc() || end != text.data() + text.size())
              input_error("{} '{}' is not an integer", option, text);
            if (x < lo || x > hi) input_error("{} {} is outside [{}, {}]", option, x, lo, hi);
            text = std::to_string(x);
            return std::string();
          },
          ""};
}

// A ray's offset from a surface stays within the coordinate range (kMaxCoordinate, as written).
constexpr double kMaxRayEpsilon = 1e12;
static_assert(float(kMaxRayEpsilon) == kMaxCoordinate);

// A finite number in [lo, hi] (no NaN, no infinity).
CLI::Validator number_in(const std::string& option, double lo, double hi) {
  return {[option, lo, hi](std::string& text) {
            const double x = parse_number(text, option);
            if (!(x >= lo)) input_error("{} must be >= {}", option, lo);
            if (!(x <= hi)) input_error("{} must be <= {:g}", option, hi);
            text = fmt::format("{}", x);
            return std::string();
          },
          ""};
}

// "x,y,z" -> a unit vector, read and normalised in double (in float a component of 1e20 squares
// to infinity, and one of 1e39 is infinite), as a scene file's directions.
Vec3 parse_direction(const std::string& text, const std::string& option) {
  std::vector<double> v;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t comma = text.find(',', pos);
    if (comma == std::string::npos) comma = text.size();
    v.push_back(parse_number(text.substr(pos, comma - pos), option));
    pos = comma + 1;
  }
  if (v.size() != 3) input_error("{}: '{}' is not x,y,z", option, text);
  const Vec3d r(v[0], v[1], v[2]);
  const double scale = r.cwiseAbs().maxCoeff();  // finite: parse_number refuses the rest
  if (!(scale > 0)) input_error("{}: '{}' is the zero vector", option, text);
  const Vec3d unit = (r / scale).normalized();  // scaled first: 1e-200 squares to 0 in double
  return unit.cast<float>();
}

// "i/n" -> shard i of n, 0 <= i < n <= kMaxShards (as cluster submit --shards).
ShardIndex parse_shard(const std::string& text) {
  const size_t slash = text.find('/');
  if (slash == std::string::npos) input_error("--shard {}: expected i/n", text);
  const double i = parse_number(text.substr(0, slash), "--shard");
  const double n = parse_number(text.substr(slash + 1), "--shard");
  if (!(n >= 1 && i >= 0 && i < n && i == std::floor(i) && n == std::floor(n)))
    input_error("--shard {}: needs whole numbers 0 <= i < n", text);
  if (n > double(kMaxShards)) input_error("--shard {}: n is outside [1, {}]", text, kMaxShards);
  return {size_t(i), size_t(n)};
}

// ---- Bindings: an option, the field it fills, its value name and its help. Not repeatable
// unless said so: a second use is an error.

CLI::Option* once(CLI::Option* o, const char* value_name) {
  return o->type_name(value_name)->multi_option_policy(CLI::MultiOptionPolicy::Throw);
}

CLI::Option* text(CLI::App& c, const std::string& name, std::string& field, const char* value_name,
                  const std::string& help) {
  return once(c.add_option(name, field, help), value_name)->capture_default_str();
}

CLI::Option* text(CLI::App& c, const std::string& name, std::optional<std::string>& field,
                  const char* value_name, const std::string& help) {
  return once(c.add_option_function<std::string>(
                  name, [&field](const std::string& v) { field = v; }, help),
              value_name);
}

template <class Int>
CLI::Option* integer(CLI::App& c, const std::string& name, Int& field, const char* value_name,
                     const std::string& help, long long lo, long long hi) {
  return once(c.add_option(name, field, help), value_name)
      ->transform(integer_in(name, lo, hi))
      ->capture_default_str();
}

template <class Int>
CLI::Option* integer(CLI::App& c, const std::string& name, std::optional<Int>& field,
                     const char* value_name, const std::string& help, long long lo, long long hi) {
  return once(c.add_option_function<Int>(
                  name, [&field](const Int& v) { field = v; }, help),
              value_name)
      ->transform(integer_in(name, lo, hi));
}

template <class Real>
CLI::Option* number(CLI::App& c, const std::string& name, Real& field, const char* value_name,
                    const std::string& help, double lo,
                    double hi = std::numeric_limits<double>::max()) {
  return once(c.add_option(name, field, help), value_name)
      ->transform(number_in(name, lo, hi))
      ->capture_default_str();
}

CLI::Option* flag(CLI::App& c, const std::string& name, bool& field, const std::string& help) {
  return c.add_flag(name, field, help)
      ->multi_option_policy(CLI::MultiOptionPolicy::Throw)
      ->disable_flag_override();
}

// Repeatable: every use adds a value.
CLI::Option* texts(CLI::App& c, const std::string& name, std::vector<std::string>& field,
                   const char* value_name, const std::string& help) {
  return c.add_option(name, field, help)->type_name(value_name)->allow_extra_args(false);
}

// --set NAME=VALUE, repeatable, each name once.
CLI::Option* assignments(CLI::App& c, const std::string& name, ParamValues& field,
                         const std::string& help) {
  const auto fill = [&field, name](const std::vector<std::string>& items) {
    for (const std::string& item : items) {
      auto [param, value] = parse_assignment(item);
      if (field.count(param)) input_error("{} {} given twice", name, param);
      field[param] = value;
    }
  };
  return c.add_option_function<std::vector<std::string>>(name, fill, help)
      ->type_name("NAME=VALUE")
      ->allow_extra_args(false);
}

std::string vector_text(const Vec3& v) { return fmt::format("{},{},{}", v.x(), v.y(), v.z()); }

// `given`, if any, says the option was given (a default direction is a direction too).
CLI::Option* direction(CLI::App& c, const std::string& name, Vec3& field, const std::string& help,
                       bool* given = nullptr) {
  return once(c.add_option_function<std::string>(
                  name,
                  [&field, name, given](const std::string& v) {
                    field = parse_direction(v, name);
                    if (given) *given = true;
                  },
                  help),
              "X,Y,Z")
      ->default_str(vector_text(field));
}

CLI::Option* threads(CLI::App& c, int& field) {
  return integer(c, "--threads", field, "N", "worker threads (0: all cores)", 0, 1024);
}

CLI::Option* json_flag(CLI::App& c, bool& field) { return flag(c, "--json", field, "print JSON"); }

// ---- One bind() per command: its options, in the order --help lists them.

void bind_scene(CLI::App& c, SceneArgs& o, const std::string& engine_help) {
  text(c, "--method", o.method, "ID", "method id (pcrt list)");
  text(c, "--data", o.data, "DATA", "point cloud file or generator spec");
  text(c, "--mesh", o.mesh, "FILE", "trace this triangle mesh (.ply/.off) instead of a method");
  text(c, "--engine", o.engine, "ID", engine_help)->default_str(kDefaultMeshEngine);
  text(c, "--structure", o.structure, "ID",
       "acceleration structure (default: the method's paper's)");
  assignments(c, "--set", o.set, "method or structure parameter (repeatable)");
  threads(c, o.threads);
}

const char* const kMeshEngineHelp = "triangle engine for --mesh: bvh, cgal_aabb or embree";

// --width, --height, --spp, --bounces of a frame.
void bind_frame(CLI::App& c, RenderSettings& s) {
  integer(c, "--width", s.width, "W", "image width in pixels", 1, FrameLimits::kMaxSide);
  integer(c, "--height", s.height, "H", "image height in pixels", 1, FrameLimits::kMaxSide);
  integer(c, "--spp", s.spp, "S", "samples per pixel", 1, FrameLimits::kMaxSpp);
  integer(c, "--bounces", s.bounces, "B", "BRDF bounces after the primary hit", 0,
          FrameLimits::kMaxBounces);
}

void bind(CLI::App& c, InfoOptions& o) {
  c.add_option("DATA", o.data, "point cloud file or generator spec")->required();
  json_flag(c, o.json);
  threads(c, o.threads);
}

void bind(CLI::App& c, RenderOptions& o) {
  bind_scene(c, o.scene, kMeshEngineHelp);
  text(c, "--scene", o.scene_file, "FILE.json",
       "a scene file (materials, objects, lights, camera) instead of one method or mesh");
  text(c, "--out", o.out, "FILE.png", "image to write (.exr: 32-bit float radiance)")->required();
  bind_frame(c, o.settings);
  integer(c, "--seed", o.settings.seed, "N", "random seed", 0, 1ll << 62);
  c.add_flag_callback(
       "--no-light", [&o] { o.settings.point_light = false; },
       "no point light: sky illumination only")
      ->multi_option_policy(CLI::MultiOptionPolicy::Throw)
      ->disable_flag_override();
  direction(c, "--view", o.settings.view, "direction from the cloud's centre to the camera",
            &o.view_given);
  direction(c, "--up", o.settings.up, "camera up vector", &o.up_given);
  number(c, "--ray-epsilon", o.settings.ray_epsilon, "E",
         "offset of secondary ray origins (0: 1e-3 x scene diagonal)", 0.0, kMaxRayEpsilon);
  text(c, "--depth", o.depth, "FILE.png|.exr",
       "also write the primary-hit depth image (EXR: distance in scene units, inf: no hit)");
  text(c, "--normals", o.normals, "FILE.png|.exr",
       "also write the primary-hit normal image (EXR: the signed normal)");
  text(c, "--stats", o.stats, "FILE.json", "write parameters, counters and timings as JSON");
  flag(c, "--stream", o.stream,
       "stream a generator's points or a PLY, XYZ or PWN file's (with normals) into the method, "
       "never holding the cloud (methods that stream: hubo_2006 with quantized=1)");
}

void bind(CLI::App& c, TraceOptions& o) {
  bind_scene(c, o.scene, kMeshEngineHelp);
  text(c, "--rays", o.rays, "RAYS.csv", "rays, header ox,oy,oz,dx,dy,dz")->required();
  text(c, "--out", o.out, "HITS.csv",
       "hits: ray,hit,t,px,py,pz,nx,ny,nz (t along the unit direction)")
      ->required();
  text(c, "--stats", o.stats, "FILE.json", "write parameters, counters and timings as JSON");
}

void bind_truth(CLI::App& c, TruthArgs& t) {
  text(c, "--truth", t.mesh, "MESH",
       "judge against this triangle mesh (.off/.ply); the cloud is sampled on it by area");
  text(c, "--sample", t.sample, "SPEC",
       "sampling of --truth: n=..,seed=..,noise=.. (in h),density=..,"
       "normals=exact|estimated|none")
      ->default_str(describe(MeshSampling{}));
  text(c, "--truth-engine", t.engine, "ID", "triangle engine tracing --truth")
      ->default_str(kDefaultMeshEngine);
}

void bind(CLI::App& c, FurnaceOptions& o) {
  bind_scene(c, o.scene, kMeshEngineHelp);
  bind_truth(c, o.truth);
  bind_frame(c, o.settings);
  integer(c, "--seed", o.settings.seed, "N", "random seed", 0, 1ll << 62);
  direction(c, "--view", o.settings.view, "direction from the cloud's centre to the camera");
  direction(c, "--up", o.settings.up, "camera up vector");
  number(c, "--ray-epsilon", o.settings.ray_epsilon, "E",
         "offset of secondary ray origins (0: 1e-3 x scene diagonal)", 0.0, kMaxRayEpsilon);
  text(c, "--out", o.out, "FILE.png|.exr", "also write the furnace image");
  flag(c, "--exact", o.exact,
       "trace the generator's exact surface (the floor of what the shape itself loses)");
  json_flag(c, o.json);
}

void bind(CLI::App& c, AccuracyOptions& o) {
  bind_scene(c, o.scene, "triangle engine for --reconstruction: bvh, cgal_aabb or embree");
  integer(c, "--rays", o.rays, "N", "number of rays", 1, 100000000);
  integer(c, "--seed", o.seed, "N", "ray seed", 0, 1ll << 62);
  text(c, "--reconstruction", o.reconstruction, "ID",
       "reconstruct a mesh (delaunay's surface is not a mesh: afsr) and judge it on --engine "
       "instead of a point method");
  bind_truth(c, o.truth);
  integer(c, "--secondary", o.secondary, "N",
          "also N secondary rays from true surface points, half outward, half inward", 0,
          100000000);
  json_flag(c, o.json);
}

void bind(CLI::App& c, CompareOptions& o) {
  bind_scene(c, o.scene, "refused: the cloud comes from --truth");
  bind_truth(c, o.truth);
  text(c, "--out", o.out, "DIFF.png", "difference picture (red missing, blue extra, yellow normal)")
      ->required();
  text(c, "--images", o.images, "PREFIX", "also write PREFIX.method.png and PREFIX.truth.png");
  integer(c, "--width", o.width, "W", "image width", 1, 16384);
  integer(c, "--height", o.height, "H", "image height", 1, 16384);
  integer(c, "--seed", o.seed, "N", "random seed", 0, 1ll << 62);
  direction(c, "--view", o.view, "direction from the cloud's centre to the camera");
  direction(c, "--up", o.up, "camera up vector");
  json_flag(c, o.json);
}

void bind(CLI::App& c, AnchorOptions& o) {
  text(c, "--data", o.data, "DATA", "point cloud file or generator spec");
  text(c, "--mesh", o.mesh, "MESH.ply",
       "instead of --data: our triangle BVH against Embree's triangles on this mesh");
  text(c, "--method", o.method, "M", "only this splat-family method (default: all of them)");
  text(c, "--structure", o.structure, "S", "only this structure (default: all but brute_force)");
  assignments(c, "--set", o.set, "a parameter of the candidates' method or structure (repeatable)");
  integer(c, "--width", o.width, "W", "image width", 1, 16384);
  integer(c, "--height", o.height, "H", "image height", 1, 16384);
  integer(c, "--reps", o.reps, "R",
          "timed passes of each scene after one warm-up; medians are reported", 1, 1000);
  threads(c, o.threads);
  json_flag(c, o.json);
}

void bind(CLI::App& c, ReconstructOptions& o) {
  text(c, "--method", o.method, "ID", "reconstruction id (pcrt list)")->required();
  text(c, "--data", o.data, "DATA", "point cloud file or generator spec")->required();
  text(c, "--out", o.out, "MESH.ply", "write the mesh (reconstructions that make one)");
  threads(c, o.threads);
  json_flag(c, o.json);
}

void bind(CLI::App& c, CrossoverOptions& o) {
  text(c, "--data", o.data, "DATA", "point cloud file or generator spec")->required();
  text(c, "--method", o.method, "ID", "direct method")->required();
  text(c, "--structure", o.structure, "ID", "its structure (default: the paper's)");
  text(c, "--reconstruction", o.reconstruction, "ID", "reconstruction");
  text(c, "--engine", o.engine, "ID", "triangle engine");
  bind_frame(c, o.settings);
  integer(c, "--reps", o.reps, "R", "frames measured per side, median taken", 1, 1000);
  integer(c, "--frames", o.frames, "F", "report the time to F frames too", 1, 1ll << 40);
  threads(c, o.threads);
  json_flag(c, o.json);
}

void bind(CLI::App& c, ListOptions& o) { json_flag(c, o.json); }

void bind(CLI::App& c, ConvertOptions& o) {
  c.add_option("DATA", o.data, "point cloud file or generator spec")->required();
  text(c, "--out", o.out, "FILE.ply", "PLY file to write")->required();
  flag(c, "--ascii", o.ascii, "ASCII PLY (default binary little endian)");
}

void bind(CLI::App& c, SweepOptions& o) {
  c.add_option("CONFIG", o.config, "sweep configuration (JSON)")->required();
  text(c, "--out", o.out, "DIR", "output directory")->default_str("results/<config name>");
  CLI::Option* resume = flag(c, "--resume", o.resume, "skip the runs already in DIR/runs.jsonl");
  flag(c, "--overwrite", o.overwrite,
       "start again in a DIR holding runs: its files are moved to DIR/previous.N first")
      ->excludes(resume);
  once(c.add_option_function<std::string>(
           "--shard", [&o](const std::string& v) { o.shard = parse_shard(v); },
           "run only shard i (0-based) of n, shards balanced on estimated run time"),
       "i/n");
  text(c, "--costs", o.costs, "DIR", "estimate run times from an earlier sweep's DIR/runs.jsonl");
  text(c, "--plan", o.plan, "FILE", "take the shard's runs from a plan file (pcrt cluster submit)");
  flag(c, "--fit", o.fit, "also write DIR/fits.json and fits.csv");
  flag(c, "--no-limit", o.no_limit,
       "run a sweep of more than 100000 runs or 7 days of estimated run time anyway");
}

void bind(CLI::App& c, MergeOptions& o) {
  c.add_option("DIR", o.dirs, "sweep directories (shards of one sweep)")->required();
  text(c, "--out", o.out, "DIR", "merged directory")->required();
  flag(c, "--keep-partial", o.keep_partial,
       "merge shards that miss runs or end in a torn line as far as they go, listing what is "
       "missing (refused without it)");
  flag(c, "--overwrite", o.overwrite,
       "--out holds an earlier merge: move its files (runs, context, fits, report) to "
       "DIR/previous.N first");
}

void bind(CLI::App& c, FitOptions& o) { c.add_option("DIR", o.dir, "sweep directory")->required(); }

void bind(CLI::App& c, ReportOptions& o) {
  c.add_option("DIR", o.dir, "sweep directory")->required();
}

void bind(CLI::App& c, CalibrateOptions& o) {
  text(c, "--out", o.out, "DIR", "keep the sweep's runs and fits here")
      ->default_str("a temporary directory");
  json_flag(c, o.json);
}

void bind(CLI::App& c, CheckOptions& o) {
  text(c, "--config", o.config, "CONFIG.json", "the sweep to run (deterministic op counts)")
      ->required();
  text(c, "--baseline", o.baseline, "BASELINE.json", "committed counters and verdicts")->required();
  number(c, "--tolerance", o.tolerance, "P", "relative change allowed per counter, in percent", 0);
  flag(c, "--update", o.update, "rewrite the baseline from this run");
  text(c, "--out", o.out, "DIR", "keep the sweep here")->default_str("a temporary directory");
}

void bind(CLI::App& c, ClusterSubmitOptions& o) {
  c.add_option("CONFIG", o.target, "sweep configuration (with --resume: the cluster DIR)")
      ->required();
  text(c, "--out", o.out, "DIR", "output directory: scripts in DIR/slurm, shards in DIR/shards");
  integer(c, "--shards", o.shards, "N", "array tasks, balanced on estimated run time", 1,
          kMaxShards);
  text(c, "--partition", o.partition, "P", "sbatch --partition");
  text(c, "--time", o.time, "HH:MM:SS", "sbatch --time, per shard and for the merge");
  text(c, "--cpus-per-task", o.cpus_per_task, "C", "sbatch --cpus-per-task")
      ->default_str("the config's threads");
  text(c, "--mem", o.mem, "M", "sbatch --mem");
  texts(c, "--sbatch-arg", o.sbatch_args, "ARG",
        "any further sbatch option, e.g. --sbatch-arg=--qos=long (repeatable)");
  text(c, "--costs", o.costs, "DIR", "balance on an earlier sweep's run times (DIR/runs.jsonl)");
  flag(c, "--resume", o.resume, "resubmit the unfinished shards (and the merge) of DIR");
  flag(c, "--dry-run", o.dry_run, "write the scripts and print the sbatch commands only");
}

void bind(CLI::App& c, ClusterStatusOptions& o) {
  c.add_option("DIR", o.dir, "cluster directory (pcrt cluster submit --out)")->required();
}

void bind(CLI::App& c, RunOneOptions& o) {
  c.add_option("SPEC", o.spec, "the run, as JSON")->required();
  c.add_option_function<std::string>(
      "PARENT_PID", [&o](const std::string& v) { o.parent_pid = v; },
      "the sweep's process id: the run dies with it");
}

// ---- Help: our usage line first, defaults after each option's help.

class HelpFormatter : public CLI::Formatter {
 public:
  std::map<const CLI::App*, std::string> usage;

  std::string make_help(const CLI::App* app, std::string name,
                        CLI::AppFormatMode mode) const override {
    std::string out = make_usage(app, std::move(name));
    if (!app->get_description().empty()) out += "\n" + app->get_description() + "\n";
    out += make_positionals(app) + make_groups(app, mode) + make_subcommands(app, mode);
    if (!app->get_footer().empty()) out += "\n" + app->get_footer() + "\n";
    return out;
  }
  std::string make_usage(const CLI::App* app, std::string) const override {
    const auto it = usage.find(app);
    return "usage: " + (it == usage.end() ? app->get_name() : it->second) + "\n";
  }
  std::string make_option_opts(const CLI::Option* o) const override {
    return o->get_positional() || o->get_items_expected_max() == 0 ? "" : " " + o->get_type_name();
  }
  std::string make_option_desc(const CLI::Option* o) const override {
    std::string d = o->get_description();
    if (o->get_required())
      d += " (required)";
    else if (o->get_items_expected_max() != 0 && !o->get_default_str().empty())
      d += " (default: " + o->get_default_str() + ")";
    return d;
  }
};

// ---- Translating what CLI11 found wrong into our one-line messages.

// The command path of an app: "render", "cluster submit"; "" for the root.
std::string path_of(const CLI::App& c) {
  std::string path;
  for (const CLI::App* a = &c; a->get_parent() != nullptr; a = a->get_parent())
    path = a->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

// The deepest (sub)command the parse reached.
const CLI::App& reached(const CLI::App& root) {
  const CLI::App* a = &root;
  while (!a->get_subcommands().empty()) a = a->get_subcommands().front();
  return *a;
}

bool looks_like_option(const std::string& a) {
  return a.size() > 1 && a[0] == '-' && !std::isdigit(static_cast<unsigned char>(a[1])) &&
         a[1] != '.';
}

}  // namespace

struct CommandLine::Impl {
  CLI::App app{"pcrt: point cloud ray tracing benchmark harness", "pcrt"};
  std::shared_ptr<HelpFormatter> formatter = std::make_shared<HelpFormatter>();
  AllOptions options;
  std::map<const CLI::App*, std::function<int()>> runs;

  Impl();
  template <class Options>
  void add(CLI::App& parent, const char* name, const char* summary, Options& o,
           int (*run)(const Options&));
  [[nodiscard]] std::string usage(const CLI::App& c) const { return formatter->usage.at(&c); }
  void check_leftovers(const CLI::App& c) const;
  [[noreturn]] void missing(const CLI::App& c) const;
  [[noreturn]] void mismatch(const CLI::App& c, const std::vector<std::string>& args) const;
};

template <class Options>
void CommandLine::Impl::add(CLI::App& parent, const char* name, const char* summary, Options& o,
                            int (*run)(const Options&)) {
  CLI::App* c = parent.add_subcommand(name, summary);
  c->group("commands");
  c->get_help_ptr()->group("options")->disable_flag_override();  // made before option defaults
  formatter->usage[c] = Options::usage;
  bind(*c, o);
  runs[c] = [run, &o] { return run(o); };
}

CommandLine::Impl::Impl() {
  formatter->label("Positionals", "arguments");
  formatter->column_width(28);
  app.formatter(formatter);
  formatter->usage[&app] = "pcrt <command> [options]   (pcrt <command> --help for each)";
  app.option_defaults()->group("options");
  app.set_help_flag("-h,--help", "show this help")->disable_flag_override();
  app.require_subcommand(0, 1);
  app.allow_extras();  // left over: reported by check_leftovers, in our words
  app.footer(
      "DATA is a file (.ply .xyz .pwn .off) or a generator spec such as "
      "sphere:n=100000,seed=1,noise=0.001");
  AllOptions& o = options;
  add(app, "info", "points, bounds, attributes, mean spacing of a dataset", o.info, command_info);
  add(app, "render", "render an image (Algorithms 1-2)", o.render, command_render);
  add(app, "trace", "closest hits of given rays", o.trace, command_trace);
  add(app, "furnace",
      "white furnace: albedo 1 under radiance 1; every dark pixel is a self-hit or a leak",
      o.furnace, command_furnace);
  add(app, "accuracy",
      "holes, see-through, early and phantom hits, distance and normal error vs the exact surface",
      o.accuracy, command_accuracy);
  add(app, "compare",
      "the method's frame vs the mesh's (same camera, B=0): missing, extra, normal-off pixels, "
      "RMSE",
      o.compare, command_compare);
  add(app, "anchor", "our fastest splat method against Embree's oriented discs, same rays",
      o.anchor, command_anchor);
  add(app, "reconstruct", "global reconstruction (CGAL)", o.reconstruct, command_reconstruct);
  add(app, "crossover", "frames after which reconstruct + trace beats direct tracing", o.crossover,
      command_crossover);
  add(app, "sweep", "run a sweep", o.sweep, command_sweep);
  CLI::App* cluster = app.add_subcommand(
      "cluster", "the sweep as a Slurm job array, then merge, fit, report; its state");
  cluster->group("commands")->require_subcommand(0, 1);
  cluster->get_help_ptr()->group("options")->disable_flag_override();
  formatter->usage[cluster] =
      std::string(ClusterSubmitOptions::usage) + " | " + ClusterStatusOptions::usage;
  add(*cluster, "submit", "submit a sweep, or --resume what is unfinished", o.cluster_submit,
      command_cluster_submit);
  add(*cluster, "status", "Slurm state and runs done per shard; exit 0 when finished",
      o.cluster_status, command_cluster_status);
  add(app, "merge", "join the shards of one sweep", o.merge, command_merge);
  add(app, "fit", "fits and verdicts: DIR/fits.json, DIR/fits.csv", o.fit, command_fit);
  add(app, "report", "DIR/report.md with plots (matplotlib)", o.report, command_report);
  add(app, "calibrate", "the fitter on workloads of known complexity", o.calibrate,
      command_calibrate);
  add(app, "check", "op-count regression gate", o.check, command_check);
  add(app, "list", "methods, structures, reconstructions, engines, generators, counters", o.list,
      command_list);
  add(app, "convert", "write a dataset (e.g. a generated cloud) as PLY", o.convert,
      command_convert);
  add(app, "_run", "one sweep run in a child process (internal)", o.run_one, command_run_one);
  app.get_subcommand("_run")->group("");  // not listed
}

// What CLI11 could not place: an unknown command or option, or one argument too many; a command
// that needs a subcommand (pcrt cluster) and got none.
void CommandLine::Impl::check_leftovers(const CLI::App& c) const {
  if (!app.remaining().empty())
    input_error("unknown command '{}' (pcrt --help lists them)", app.remaining().front());
  const std::vector<std::string> extra = c.remaining();
  for (const std::string& a : extra)
    if (looks_like_option(a))
      input_error("unknown option '{}' (see pcrt {} --help)", a.substr(0, a.find('=')), path_of(c));
  if (!runs.count(&c) && !extra.empty())
    input_error("unknown subcommand '{}': usage: {}", extra.front(), usage(c));
  if (!runs.count(&c)) input_error("usage: {}", usage(c));
  if (extra.empty()) return;
  int most = 0;
  for (const CLI::Option* o : c.get_options())
    if (o->get_positional()) most += o->get_items_expected_max();
  input_error("unexpected argument '{}' (takes {}): usage: {}", extra.front(),
              most == 0 ? "no arguments" : fmt::format("at most {}", most), usage(c));
}

// A required option or argument not given.
void CommandLine::Impl::missing(const CLI::App& c) const {
  int given = 0, needed = 0;
  bool open_ended = false;  // DIR...
  for (const CLI::Option* o : c.get_options())
    if (o->get_positional()) {
      given += int(o->count());
      needed += o->get_required() ? o->get_items_expected_min() : 0;
      open_ended = open_ended || o->get_items_expected_max() > o->get_items_expected_min();
    }
  for (const CLI::Option* o : c.get_options())
    if (o->get_required() && o->count() == 0) {
      if (o->get_positional())
        input_error("expected {}{} argument(s), got {}: usage: {}", open_ended ? "at least " : "",
                    needed, given, usage(c));
      input_error("{} is required: usage: {}", o->get_name(), usage(c));
    }
  input_error("a required option is missing: usage: {}", usage(c));
}

// An option given twice, a flag given a value, or a value missing at the end.
void CommandLine::Impl::mismatch(const CLI::App& c, const std::vector<std::string>& args) const {
  for (const CLI::Option* o : c.get_options())
    if (o->count() > 1 && o->get_multi_option_policy() == CLI::MultiOptionPolicy::Throw)
      input_error("{} given twice", o->get_name());
  for (const std::string& a : args) {
    const size_t eq = a.find('=');
    const CLI::Option* o = a.rfind("--", 0) == 0 && eq != std::string::npos
                               ? c.get_option_no_throw(a.substr(0, eq))
                               : nullptr;
    if (o && o->get_items_expected_max() == 0) input_error("{} takes no value", o->get_name());
  }
  const std::string last = args.empty() ? "" : args.back().substr(0, args.back().find('='));
  if (const CLI::Option* o = last.empty() ? nullptr : c.get_option_no_throw(last))
    input_error("{} needs a value ({})", o->get_name(), o->get_type_name());
  input_error("malformed arguments: usage: {}", usage(c));
}

CommandLine::CommandLine() : impl_(std::make_unique<Impl>()) {}
CommandLine::~CommandLine() = default;

bool CommandLine::parse(const std::vector<std::string>& args) {
  if (!args.empty() && args[0] == "help") return false;
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  const auto help_asked = [&] {
    const CLI::Option* h = reached(impl_->app).get_help_ptr();
    return h != nullptr && h->count() > 0;
  };
  try {
    impl_->app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    return false;
  } catch (const CLI::ParseError& e) {
    if (help_asked()) return false;
    const CLI::App& c = reached(impl_->app);
    if (!c.remaining().empty() || !impl_->app.remaining().empty()) impl_->check_leftovers(c);
    if (dynamic_cast<const CLI::RequiredError*>(&e)) impl_->missing(c);
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e)) impl_->mismatch(c, args);
    input_error("{}", e.what());  // anything else, in CLI11's words
  } catch (const InputError&) {   // a value the bindings refused; unknown options come first
    if (help_asked()) return false;
    const CLI::App& c = reached(impl_->app);
    if (!c.remaining().empty() || !impl_->app.remaining().empty()) impl_->check_leftovers(c);
    throw;
  }
  impl_->check_leftovers(reached(impl_->app));
  return true;
}

int CommandLine::run() const { return impl_->runs.at(&reached(impl_->app))(); }

std::string CommandLine::command() const { return path_of(reached(impl_->app)); }

std::string CommandLine::help() const { return impl_->app.help(); }

const AllOptions& CommandLine::options() const { return impl_->options; }

}  // namespace pcrt
