// pcrt: point cloud ray tracing benchmark harness.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "core/error.hpp"
#include "harness/commands.hpp"

namespace {

// Every command, listed once: its name, what runs it and its line in `pcrt --help`.
struct Command {
  const char* name;
  int (*run)(const pcrt::Args&);
  const char* synopsis;
};

constexpr Command kCommands[] = {
    {"info", pcrt::command_info,
     "info DATA [--json]          points, bounds, attributes, mean spacing of a dataset"},
    {"render", pcrt::command_render,
     "render (--method ID --data DATA | --mesh FILE --engine ID) --out FILE.png|.exr ...   "
     "render an image (Algorithms 1-2)"},
    {"trace", pcrt::command_trace,
     "trace (--method ID --data DATA | --mesh FILE --engine ID) --rays RAYS.csv --out HITS.csv "
     "...   closest hits of given rays"},
    {"accuracy", pcrt::command_accuracy,
     "accuracy --method ID (--data GENERATOR | --truth MESH) ...   holes, see-through, early and "
     "phantom hits, distance and normal error vs the exact surface"},
    {"compare", pcrt::command_compare,
     "compare --method ID --truth MESH --out DIFF.png ...   the method's frame vs the mesh's "
     "(same camera, B=0): missing, extra, normal-off pixels, RMSE"},
    {"anchor", pcrt::command_anchor,
     "anchor --data DATA [--json]   our fastest splat method against Embree's oriented discs, "
     "same rays"},
    {"reconstruct", pcrt::command_reconstruct,
     "reconstruct --method delaunay|afsr --data DATA [--out MESH.ply] [--json]   global "
     "reconstruction (CGAL)"},
    {"crossover", pcrt::command_crossover,
     "crossover --data DATA --method ID [--reconstruction afsr --engine bvh] [--json]   frames "
     "after which reconstruct + trace beats direct tracing"},
    {"sweep", pcrt::command_sweep,
     "sweep CONFIG.json [--out DIR] [--resume] [--shard i/n] [--fit]   run a sweep"},
    {"cluster", pcrt::command_cluster,
     "cluster submit CONFIG.json --out DIR --shards N [...]   the sweep as a Slurm job array, "
     "then merge, fit, report\n  cluster status DIR          Slurm state and runs done per shard; "
     "exit 0 when finished"},
    {"merge", pcrt::command_merge, "merge DIR... --out DIR      join the shards of one sweep"},
    {"fit", pcrt::command_fit,
     "fit DIR                     fits and verdicts: DIR/fits.json, DIR/fits.csv"},
    {"report", pcrt::command_report,
     "report DIR                  DIR/report.md with plots (matplotlib)"},
    {"calibrate", pcrt::command_calibrate,
     "calibrate [--json]          the fitter on workloads of known complexity"},
    {"check", pcrt::command_check,
     "check --config C --baseline B [--tolerance P] [--update]   op-count regression gate"},
    {"list", pcrt::command_list,
     "list [--json]               methods, structures, reconstructions, engines, generators, "
     "counters"},
    {"convert", pcrt::command_convert,
     "convert DATA --out FILE.ply [--ascii]   write a dataset (e.g. a generated cloud) as PLY"},
    {"_run", pcrt::command_run_one, nullptr},  // one sweep run in a child process (internal)
};

std::string usage() {
  std::string u =
      "usage: pcrt <command> [options]   (pcrt <command> --help for each)\n\ncommands:\n";
  for (const Command& c : kCommands)
    if (c.synopsis) u += fmt::format("  {}\n", c.synopsis);
  return u +
         "\nDATA is a file (.ply .xyz .pwn .off) or a generator spec such as "
         "sphere:n=100000,seed=1,noise=0.001\n";
}

// One line whatever a message quotes (a path with a newline, bytes from a file): control
// characters and backslashes are printed as C escapes.
std::string escaped(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else if (c == '\t')
      out += "\\t";
    else if (c == '\r')
      out += "\\r";
    else if (c < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", c);
    else
      out += char(c);
  }
  return out;
}

// What an out-of-memory error names: the values of the input options, the leading positional
// argument (a file, directory or generator spec) and the other arguments that are existing files
// or directories, outputs excepted.
std::string inputs_of(const pcrt::Args& args) {
  auto follows = [&](size_t i, std::initializer_list<const char*> options) {
    return i > 0 && std::any_of(options.begin(), options.end(),
                                [&](const char* o) { return args[i - 1] == o; });
  };
  std::string names;
  for (size_t i = 0; i < args.size(); ++i) {
    std::error_code ec;
    const bool input =
        follows(i, {"--data", "--truth", "--mesh", "--rays", "--config", "--baseline"}) ||
        (i == 0 && args[i].rfind("--", 0) != 0) ||
        (args[i].rfind("--", 0) != 0 && !follows(i, {"--out", "--stats", "--depth", "--normals"}) &&
         std::filesystem::exists(args[i], ec));
    if (input) names += (names.empty() ? "" : ", ") + args[i];
  }
  return names;
}

int fail(const std::string& cmd, const std::string& what) {
  std::fprintf(stderr, "pcrt %s: error: %s\n", escaped(cmd).c_str(), escaped(what).c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(usage().c_str(), stderr);
    return 1;
  }
  const std::string cmd = argv[1];
  const pcrt::Args args(argv + 2, argv + argc);
  try {
    for (const Command& c : kCommands)
      if (cmd == c.name) return c.run(args);
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::fputs(usage().c_str(), stdout);
      return 0;
    }
    std::fprintf(stderr, "pcrt: error: unknown command '%s' (pcrt --help lists them)\n",
                 escaped(cmd).c_str());
    return 1;
  } catch (const pcrt::InputError& e) {
    // Messages that already name the command are not prefixed twice.
    std::string what = e.what();
    const std::string own = "pcrt " + cmd + ": ";
    if (what.rfind(own, 0) == 0) what.erase(0, own.size());
    return fail(cmd, what);
  } catch (const std::bad_alloc&) {
    const std::string inputs = inputs_of(args);
    return fail(cmd, inputs.empty()
                         ? "out of memory (the input is too large for this machine)"
                         : "out of memory: " + inputs + " is too large for this machine");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcrt %s: internal error: %s\n", escaped(cmd).c_str(),
                 escaped(e.what()).c_str());
    return 3;
  }
}
