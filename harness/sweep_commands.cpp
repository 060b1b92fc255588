// The sweep side of the CLI: sweep, merge, fit, report, calibrate, check, and the hidden _run
// that executes one run in a child process.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/json_input.hpp"
#include "harness/build_info.hpp"
#include "harness/command_helpers.hpp"
#include "harness/commands.hpp"
#include "harness/csv_table.hpp"
#include "harness/fit.hpp"
#include "harness/provenance.hpp"
#include "harness/run_child.hpp"
#include "harness/run_executors.hpp"
#include "harness/run_files.hpp"
#include "harness/shard_plan.hpp"
#include "harness/subprocess.hpp"
#include "harness/sweep_config.hpp"
#include "harness/sweep_fits.hpp"
#include "harness/workloads.hpp"

namespace pcrt {
namespace {

namespace fs = std::filesystem;

std::string fmt_duration(double s) {
  if (s < 90) return fmt::format("{:.0f} s", s);
  return fmt::format("{:.0f} min {:.0f} s", std::floor(s / 60), std::fmod(s, 60));
}

// One status line per run on a terminal: where the sweep is and how long it has left.
void show_progress(const RunSpec& spec, size_t i, size_t n, double elapsed_s) {
  const std::string eta = i > 0 ? fmt_duration(elapsed_s / double(i) * double(n - i)) : "?";
  const std::string what = !spec.method.empty()           ? spec.method
                           : !spec.reconstruction.empty() ? spec.reconstruction
                                                          : spec.workload;
  const std::string points = spec.N ? json(*spec.N).dump() : "-";
  std::fprintf(stderr, "\r\033[K[%zu/%zu, ETA %s] %s %s %s N=%s", i + 1, n, eta.c_str(),
               spec.experiment.c_str(), what.c_str(), spec.structure.c_str(), points.c_str());
}

// The keys of the runs already in DIR/runs.jsonl; rewrites it without a truncated tail, so
// appends start on a fresh line, and without the runs a signal ended, which are done again.
std::set<std::string> resume_from(const std::string& jsonl) {
  std::vector<RunResult> kept = read_runs_jsonl(jsonl);
  std::erase_if(kept, killed_by_signal);
  std::set<std::string> done;
  for (const RunResult& r : kept) done.insert(run_key(r));
  write_runs_jsonl(jsonl, kept);
  return done;
}

// A sweep owns its results folder while it runs: an exclusive flock on DIR/.lock, which the
// kernel releases however the sweep ends, with the holder's pid inside for the refusal.
class FolderLock {
 public:
  explicit FolderLock(const std::string& dir) : path_(dir + "/.lock") {
    // The lock file is removed when its holder ends: a lock taken on a file already unlinked is
    // retried on the one now at the path, so two sweeps never both hold one.
    for (int attempt = 0; attempt < 100; ++attempt) {
      take(dir);
      struct stat held {
      }, now{};
      if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &now) == 0 &&
          held.st_ino == now.st_ino && held.st_dev == now.st_dev)
        break;
      ::close(fd_);
      fd_ = -1;
    }
    if (fd_ < 0) input_error("{}: cannot lock the results folder: it keeps changing", path_);
    const std::string mine = std::to_string(getpid());
    if (::ftruncate(fd_, 0) == 0) (void)!::pwrite(fd_, mine.data(), mine.size(), 0);
  }
  ~FolderLock() {
    ::unlink(path_.c_str());
    ::close(fd_);
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  // Opens the lock file and takes its flock, or throws: held by another sweep, or not lockable.
  void take(const std::string& dir) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) input_error("{}: cannot lock the results folder: {}", path_, std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
    const int error = errno;
    if (error != EWOULDBLOCK) {
      ::close(fd_);
      input_error("{}: cannot lock the results folder: {}", path_, std::strerror(error));
    }
    char pid[32] = {};
    const ssize_t n = ::pread(fd_, pid, sizeof pid - 1, 0);
    ::close(fd_);
    std::string holder = n > 0 ? std::string(pid, size_t(n)) : std::string();
    holder.erase(
        std::find_if(holder.begin(), holder.end(), [](char c) { return !std::isdigit(c); }),
        holder.end());
    input_error("--out {}: another sweep (pid {}) is writing it", dir,
                holder.empty() ? std::string("unknown") : holder);
  }

  std::string path_;
  int fd_ = -1;
};

// Moves every entry of DIR but its lock and earlier copies into DIR/previous.N (N the first free).
void move_aside(const std::string& dir) {
  fs::path aside;
  for (int n = 1;; ++n)
    if (!fs::exists(aside = fs::path(dir) / fmt::format("previous.{}", n))) break;
  fs::create_directory(aside);
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name == ".lock" || name.rfind("previous.", 0) == 0) continue;
    fs::rename(e.path(), aside / name);
  }
  std::printf("%s: the earlier sweep's files are now in %s\n", dir.c_str(), aside.c_str());
}

// The files a sweep (and a fit and report of it) writes in its folder.
constexpr std::array<const char*, 7> kSweepFiles = {"runs.jsonl", "runs.csv", "context.json",
                                                    "fits.json",  "fits.csv", "fit_context.json",
                                                    "report.md"};

// Whether DIR holds a file a sweep would write, other than an empty runs.jsonl (what a sweep
// killed before its first run leaves, with its context.json).
bool holds_sweep_files(const std::string& dir) {
  std::error_code ec;
  const std::string jsonl = dir + "/runs.jsonl";
  if (fs::exists(jsonl, ec) && fs::file_size(jsonl, ec) > 0) return true;
  const bool started = fs::exists(jsonl, ec);
  for (const char* name : kSweepFiles)
    if (std::string(name) != "runs.jsonl" && !(started && std::string(name) == "context.json") &&
        fs::exists(dir + "/" + name, ec))
      return true;
  return false;
}

// Without --resume a folder holding an earlier sweep's runs (or files of a sweep's names) is
// never overwritten: refused, or moved aside with --overwrite.
void claim_folder(const std::string& dir, bool resume, bool overwrite) {
  if (resume || !holds_sweep_files(dir)) return;
  if (!overwrite)
    input_error(
        "--out {} holds the runs of an earlier sweep (or files of its names): give --resume to "
        "continue it, or "
        "--overwrite to start again (its files are moved to {}/previous.N)",
        dir, dir);
  move_aside(dir);
}

// A folder resumes the sweep that made it, or one that extends it: every run already done must
// be one this config plans (another config's runs would join runs.jsonl unnoticed, as merge
// refuses shards of two configs), while new experiments and fit specs may be added.
void check_resumed_runs(const std::string& dir, const SweepConfig& config,
                        const std::set<std::string>& done) {
  std::set<std::string> planned;
  for (const RunSpec& s : config.runs) planned.insert(run_key(s));
  for (const std::string& key : done)
    if (!planned.count(key))
      input_error(
          "--out {}: holds a run {} does not plan ({}); --resume continues or extends only the "
          "sweep that made it (--overwrite starts again)",
          dir, config.name, key.substr(0, 160));
}

// Where the runs already in DIR were made, kept when --resume rewrites context.json: the earlier
// contexts' commits, machines and run counts, oldest first, each without its config.
json earlier_runs_context(const std::string& dir, size_t runs_done) {
  const std::string path = dir + "/context.json";
  if (!fs::is_regular_file(path)) return json::array();
  json old = read_json_file(path);
  if (!old.is_object()) input_error("{}: not an object", path);
  json earlier = old.value("earlier", json::array());
  if (!earlier.is_array()) input_error("{}: \"earlier\" is not a list", path);
  size_t counted = 0;
  for (const json& e : earlier)
    counted += size_t(std::max(0.0, optional_number(e, "runs", 0, path + ": earlier")));
  old.erase("config");
  old.erase("earlier");
  old.erase("shard");
  old["runs"] = runs_done - std::min(counted, runs_done);
  if (old["runs"] != 0) earlier.push_back(old);  // a resume that ran nothing made no run
  return earlier;
}

// A sweep's files in DIR must not be one of its inputs (the config, a baseline, a plan).
void check_sweep_outputs(const std::string& dir, const std::vector<NamedPath>& inputs) {
  std::error_code ec;  // a folder not made yet holds no input (and a refused sweep makes none)
  if (!fs::is_directory(dir, ec)) return;
  std::vector<NamedPath> outputs;
  for (const char* name : kSweepFiles) outputs.push_back({dir + "/" + name, "--out"});
  check_outputs(outputs, inputs);
}

// Runs the `selected` runs of `config` not yet in DIR/runs.jsonl (with --resume); returns all
// results in DIR afterwards. A shard's `shard_record` (its index and runs) goes into
// context.json, so that a merge can tell a complete shard from a cut one.
std::vector<RunResult> run_sweep(const SweepConfig& config, const std::string& dir, bool resume,
                                 bool overwrite, const std::vector<size_t>& selected, bool quiet,
                                 const json& shard_record = json()) {
  make_output_directory(dir, "--out");
  const FolderLock lock(dir);
  // Read before --overwrite moves the folder's committed results aside, which would make the
  // source tree read as modified (git status) when only the results are.
  json context = machine_context(config.raw);
  claim_folder(dir, resume, overwrite);
  const std::string jsonl = dir + "/runs.jsonl";
  const bool resuming = resume && fs::exists(jsonl);
  const std::set<std::string> done = resuming ? resume_from(jsonl) : std::set<std::string>{};
  if (resuming) check_resumed_runs(dir, config, done);
  if (!shard_record.is_null()) context["shard"] = shard_record;
  if (resuming) context["earlier"] = earlier_runs_context(dir, done.size());
  // Written first: on a read-only or full file system this is the one-line error, before the
  // old results are touched.
  write_json(dir + "/context.json", context);
  // A shard with nothing (left) to run still leaves a readable, empty runs.jsonl.
  if (!resuming) write_file_atomically(jsonl, [](std::ostream&) {});
  std::vector<const RunSpec*> todo;
  for (size_t i : selected)
    if (!done.count(run_key(config.runs[i]))) todo.push_back(&config.runs[i]);
  const bool tty = isatty(2) && !quiet;
  const auto start = std::chrono::steady_clock::now();
  size_t failed = 0;
  for (size_t i = 0; i < todo.size(); ++i) {
    if (tty)
      show_progress(
          *todo[i], i, todo.size(),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const RunResult result = run_in_child(*todo[i], config.time_limit_s);
    if (!result.ok()) ++failed;
    append_run(jsonl, result);
  }
  if (tty) std::fprintf(stderr, "\r\033[K");
  std::vector<RunResult> all = read_runs_jsonl(jsonl);
  write_runs_csv(dir + "/runs.csv", all);
  if (!quiet)
    std::printf("%s: %zu runs done (%zu already done, %zu failed or timed out)\n", dir.c_str(),
                todo.size(), done.size(), failed);
  return all;
}

void write_fits(const std::string& dir, const std::vector<json>& fits) {
  // The runs keep their own commit (context.json); this is the fitter's, which may be later,
  // taken before this writes anything (its own output is no uncommitted change).
  const json fitter = source_context();
  write_json(dir + "/fits.json", json(fits));
  write_json(dir + "/fit_context.json", fitter);
  const std::vector<std::string> cols = {"claim",
                                         "about",
                                         "method",
                                         "structure",
                                         "dataset",
                                         "variable",
                                         "x",
                                         "metric",
                                         "points",
                                         "distinct_x",
                                         "decades",
                                         "exponent",
                                         "ci_low",
                                         "ci_high",
                                         "claimed_exponent",
                                         "best_model",
                                         "expected_model",
                                         "r2",
                                         "noise",
                                         "pure_noise",
                                         "weight_faster",
                                         "hidden_at_most",
                                         "tolerance",
                                         "lower_term",
                                         "tightness",
                                         "claimed",
                                         "measured",
                                         "threshold",
                                         "verdict",
                                         "verdict_if_fixed",
                                         "reason",
                                         "leave_one_out",
                                         "source",
                                         "failed_runs",
                                         "missing_runs",
                                         "error"};
  write_csv(dir + "/fits.csv", cols, fits);
}

SweepConfig config_of(const std::string& dir, DatasetCheck datasets = DatasetCheck::kOpenFiles) {
  const std::string path = dir + "/context.json";
  if (!fs::is_regular_file(path))
    input_error("{}: no such file (is {} a sweep directory?)", path, dir);
  json ctx = read_json_file(path);
  if (!ctx.is_object() || !ctx.contains("config")) input_error("{}: has no \"config\"", path);
  try {
    return parse_sweep_config(ctx["config"], path, datasets);
  } catch (const json::exception& e) {
    input_error("{}: config of the wrong type: {}", path, e.what());
  }
}

std::vector<size_t> all_runs(const SweepConfig& config) {
  std::vector<size_t> all(config.runs.size());
  std::iota(all.begin(), all.end(), size_t(0));
  return all;
}

// The runs of shard i/n: from a plan file when given (a cluster sweep fixes its split once),
// else balanced on estimated costs (the model's, or an earlier sweep's times).
std::vector<size_t> shard_runs(const SweepConfig& config, const SweepOptions& o) {
  if (!o.shard) {
    if (o.plan || o.costs) input_error("--plan and --costs need --shard");
    return all_runs(config);
  }
  const auto [i, n] = *o.shard;
  if (o.plan && o.costs) input_error("--plan fixes the shards; --costs cannot move them");
  if (o.plan) return plan_shard(read_json_file(*o.plan), config.runs, i, n, *o.plan);
  const std::vector<RunResult> earlier =
      o.costs ? read_runs_jsonl(*o.costs + "/runs.jsonl") : std::vector<RunResult>{};
  return plan_shards(run_costs(config.runs, earlier), n).shards[i];
}

// What a shard records of itself in context.json: which shard it is and every run it must do.
json shard_record(const ShardIndex& shard, const SweepConfig& config,
                  const std::vector<size_t>& selected) {
  json runs = json::array();
  for (size_t i : selected) runs.push_back(json(config.runs[i]));
  return {{"index", shard.index}, {"count", shard.count}, {"runs", runs}};
}

// Merging shards of different sweeps or builds would mix results that cannot be compared: the
// config and the commit must agree.
void check_same_sweep(const json& ctx, const json& first, const std::string& dir,
                      const std::string& first_dir) {
  if (ctx.value("config", json()) != first.value("config", json()))
    input_error("{}: its config differs from {}'s; only shards of one sweep merge", dir, first_dir);
  const json commit = ctx.value("git_commit", json());
  const json first_commit = first.value("git_commit", json());
  if (commit != first_commit)
    input_error("{}: made at commit {}, {} at {}; only shards of one build merge", dir,
                commit.dump(), first_dir, first_commit.dump());
}

std::string python() { return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3"; }

// The runs a sweep directory was to do: a shard's own list (context.json's "shard"), else the
// whole config's.
std::vector<std::string> planned_runs(const std::string& dir, const json& ctx) {
  const std::string origin = dir + "/context.json";
  std::vector<std::string> keys;
  if (!ctx.contains("shard")) {
    for (const RunSpec& spec : config_of(dir, DatasetCheck::kNamesOnly).runs)
      keys.push_back(run_key(spec));
    return keys;
  }
  const json& shard = ctx["shard"];
  if (!shard.is_object() || !shard.contains("runs") || !shard["runs"].is_array())
    input_error("{}: \"shard\" has no list of \"runs\"", origin);
  for (const json& spec : shard["runs"]) keys.push_back(planned_run_key(spec, origin));
  return keys;
}

// How a shard's runs.jsonl differs from its plan; nothing when it is whole.
struct ShardGaps {
  std::vector<std::string> missing;  // planned run keys without a result
  size_t unplanned = 0, duplicates = 0;
  bool torn_tail = false;
  [[nodiscard]] bool any() const {
    return !missing.empty() || unplanned > 0 || duplicates > 0 || torn_tail;
  }
  [[nodiscard]] std::string summary(size_t planned) const {
    std::vector<std::string> parts;
    if (!missing.empty())
      parts.push_back(fmt::format("{} of its {} planned runs missing", missing.size(), planned));
    auto runs = [](size_t n) { return fmt::format("{} run{}", n, n == 1 ? "" : "s"); };
    if (unplanned > 0) parts.push_back(runs(unplanned) + " not in its plan");
    if (duplicates > 0) parts.push_back(runs(duplicates) + " recorded twice");
    if (torn_tail) parts.push_back("its last line torn (no newline or not valid JSON)");
    return fmt::format("{}", fmt::join(parts, ", "));
  }
};

// The results of DIR that are whole and planned, each once. A shard cut short (a killed or
// failed task, a full disk) is refused naming its file, or with `keep_partial` merged as far as
// it goes, saying what was kept and what is missing.
std::vector<RunResult> whole_runs_of_shard(const std::string& dir, const json& ctx,
                                           bool keep_partial) {
  const std::string path = dir + "/runs.jsonl";
  RunsFile file = read_runs_file(path);
  const std::vector<std::string> planned = planned_runs(dir, ctx);
  std::set<std::string> unseen(planned.begin(), planned.end()), seen;
  ShardGaps gaps;
  gaps.torn_tail = file.torn_tail;
  std::vector<RunResult> kept;
  for (RunResult& r : file.runs) {
    const std::string key = run_key(r);
    if (!seen.insert(key).second) {
      ++gaps.duplicates;
    } else if (!unseen.erase(key)) {
      ++gaps.unplanned;
    } else {
      kept.push_back(std::move(r));
    }
  }
  for (const std::string& key : planned)
    if (unseen.count(key)) gaps.missing.push_back(key);
  if (!gaps.any()) return kept;
  if (!keep_partial)
    input_error("{}: does not match its plan: {}; --keep-partial merges what is whole", path,
                gaps.summary(planned.size()));
  std::printf("%s: kept %zu of %zu planned runs; %s\n", path.c_str(), kept.size(), planned.size(),
              gaps.summary(planned.size()).c_str());
  for (const std::string& key : gaps.missing) std::printf("  missing: %s\n", key.c_str());
  return kept;
}

}  // namespace

namespace {

// A run dies with the sweep that started it (SIGKILL included): the kernel kills it when its parent
// exits, and a parent already gone before that was arranged ends it here. So a killed sweep leaves
// no run behind past its time limit, and a resumed sweep never races a leftover one.
void die_with_parent(const std::string& parent_pid) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (std::to_string(getppid()) != parent_pid) _exit(1);
}

}  // namespace

int command_run_one(const RunOneOptions& o) {
  if (o.parent_pid) die_with_parent(*o.parent_pid);
  RunSpec spec;
  try {
    spec = json::parse(o.spec).get<RunSpec>();
  } catch (const json::exception&) {
    input_error("_run: the run spec is not valid JSON");
  } catch (const InputError& e) {
    input_error("_run: {}", e.what());
  }
  auto limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     size_t(spec.threads));
  std::printf("%s\n", json(execute_run(spec)).dump().c_str());
  return 0;
}

namespace {

// The sweep's size and the shard planner's estimate of its time, said before any run; a sweep
// over the limits is refused unless --no-limit.
void announce_sweep(const SweepConfig& config, const std::vector<size_t>& selected,
                    const SweepOptions& o) {
  double seconds = 0;
  for (size_t i : selected) seconds += model_run_cost(config.runs[i]);
  const std::string time = seconds < 120    ? fmt::format("{:.0f} s", seconds)
                           : seconds < 7200 ? fmt::format("{:.0f} min", seconds / 60)
                                            : fmt::format("{:.1f} h", seconds / 3600);
  const std::string estimate = fmt::format(
      "{} runs, about {} of run time by the shard planner's model", selected.size(), time);
  if (!o.no_limit &&
      (selected.size() > SweepOptions::kMaxSweepRuns || seconds > SweepOptions::kMaxSweepSeconds))
    input_error("{}: {}, over the limit of {} runs or {} days; --no-limit runs it anyway", o.config,
                estimate, SweepOptions::kMaxSweepRuns, SweepOptions::kMaxSweepSeconds / 86400.0);
  std::printf("%s: %s\n", o.config.c_str(), estimate.c_str());
  std::fflush(stdout);
}

}  // namespace

int command_sweep(const SweepOptions& o) {
  const SweepConfig config = load_sweep_config(o.config);
  const std::string dir = o.out.value_or("results/" + config.name);
  std::vector<NamedPath> inputs = {{o.config, "CONFIG"}};
  if (o.plan) inputs.push_back({*o.plan, "--plan"});
  check_sweep_outputs(dir, inputs);
  const std::vector<size_t> selected = shard_runs(config, o);
  announce_sweep(config, selected, o);
  const json shard = o.shard ? shard_record(*o.shard, config, selected) : json();
  const std::vector<RunResult> results =
      run_sweep(config, dir, o.resume, o.overwrite, selected, false, shard);
  if (o.fit) write_fits(dir, fits_json(fit_runs(config, results)));
  return 0;
}

// The files a merge writes, and the fit and report made from them.
constexpr std::array<const char*, 8> kMergedFiles = {"runs.jsonl", "runs.csv", "context.json",
                                                     "fits.json",  "fits.csv", "fit_context.json",
                                                     "report.md",  "plots"};

// A merge never writes into one of its shards, and never over an earlier merge's runs: refused,
// or with --overwrite that merge's files (only those: --out may hold the shards, as a cluster
// folder does) are moved to previous.N.
void claim_merge_folder(const MergeOptions& o) {
  std::error_code ec;
  for (const std::string& dir : o.dirs)
    if (fs::exists(o.out, ec) && fs::equivalent(o.out, dir, ec) && !ec)
      input_error("--out {}: is also the shard {}; merge into another directory", o.out, dir);
  const std::string jsonl = o.out + "/runs.jsonl";
  if (!fs::exists(jsonl, ec) || fs::file_size(jsonl, ec) == 0) return;
  if (!o.overwrite)
    input_error(
        "--out {} holds an earlier merge's runs: give --overwrite to move its files to "
        "{}/previous.N",
        o.out, o.out);
  fs::path aside;
  for (int n = 1;; ++n)
    if (!fs::exists(aside = fs::path(o.out) / fmt::format("previous.{}", n), ec)) break;
  fs::create_directory(aside, ec);
  if (ec) input_error("--out {}: cannot create {}: {}", o.out, aside.string(), ec.message());
  for (const char* name : kMergedFiles)
    if (fs::exists(fs::path(o.out) / name, ec)) {
      fs::rename(fs::path(o.out) / name, aside / name, ec);
      if (ec) input_error("--out {}: cannot move {} aside: {}", o.out, name, ec.message());
    }
  std::printf("%s: the earlier merge's files are now in %s\n", o.out.c_str(), aside.c_str());
}

int command_merge(const MergeOptions& o) {
  std::map<std::string, RunResult> runs;
  json contexts = json::array();
  for (size_t i = 0; i < o.dirs.size(); ++i) {
    const std::string& dir = o.dirs[i];
    const json ctx = read_json_file(dir + "/context.json");
    if (!ctx.is_object()) input_error("{}/context.json: not an object", dir);
    if (i > 0) check_same_sweep(ctx, contexts[0], dir, o.dirs[0]);
    contexts.push_back(ctx);
    for (RunResult& r : whole_runs_of_shard(dir, ctx, o.keep_partial)) {
      const std::string key = run_key(r);
      if (runs.count(key)) {
        if (!o.keep_partial)
          input_error(
              "{}/runs.jsonl: a run of it is also in an earlier directory; only distinct shards "
              "merge (--keep-partial keeps the first)",
              dir);
        std::printf("%s/runs.jsonl: also in an earlier directory, which is kept: %s\n", dir.c_str(),
                    key.c_str());
      }
      runs.emplace(key, std::move(r));
    }
  }
  make_output_directory(o.out, "--out");
  claim_merge_folder(o);
  std::vector<RunResult> all;
  for (auto& [k, r] : runs) all.push_back(r);
  write_runs_jsonl(o.out + "/runs.jsonl", all);
  write_runs_csv(o.out + "/runs.csv", all);
  // The merged directory is the whole sweep, no shard; each shard's list of runs is its runs.
  json merged = contexts[0];
  merged.erase("shard");
  for (json& ctx : contexts)
    if (ctx.contains("shard") && ctx["shard"].is_object()) ctx["shard"].erase("runs");
  merged["shards"] = contexts;
  write_json(o.out + "/context.json", merged);
  std::printf("%s: %zu runs from %zu directories\n", o.out.c_str(), all.size(), o.dirs.size());
  return 0;
}

int command_fit(const FitOptions& o) {
  // Fitting reads runs.jsonl only: the folder alone is enough, without the data it was made from.
  const SweepConfig config = config_of(o.dir, DatasetCheck::kNamesOnly);
  const std::vector<json> fits =
      fits_json(fit_runs(config, read_runs_jsonl(o.dir + "/runs.jsonl")));
  write_fits(o.dir, fits);
  std::map<std::string, int> verdicts;
  for (const json& f : fits) ++verdicts[f.value("verdict", "")];
  std::printf("%s/fits.json: %zu fits", o.dir.c_str(), fits.size());
  for (const auto& [v, n] : verdicts) std::printf(", %d %s", n, v.c_str());
  std::printf("\n");
  return 0;
}

int command_report(const ReportOptions& o) {
  if (!fs::exists(o.dir + "/fits.json")) command_fit({o.dir});
  // Run without a shell, so that no quote in a path can break the command.
  const std::string script = installed_script("report.py");
  const CommandOutput out = run_command({python(), script, o.dir});
  std::fputs(out.out.c_str(), stdout);
  if (out.exit_code == 0) {
    std::fputs(out.err.c_str(), stderr);  // matplotlib's warnings, if any
    return 0;
  }
  // The script's own one-line error names the input (scripts/verdicts.py, run_main); anything
  // else is a fault of the script, shown whole.
  std::string last = out.err.substr(0, out.err.find_last_not_of('\n') + 1);
  last = last.substr(last.find_last_of('\n') + 1);
  if (last.rfind("report.py: ", 0) == 0) input_error("report: {}", last);
  std::fputs(out.err.c_str(), stderr);
  input_error("report: {} failed (exit {})", script, out.exit_code);
}

namespace {

// One experiment per workload, fitted in operations and in time: the same sweep and fit path as
// the methods'.
json calibration_config() {
  json experiments = json::array();
  for (const WorkloadInfo& w : workloads()) {
    experiments.push_back(
        {{"name", w.id},
         {"kind", "workload"},
         {"workloads", {w.id}},
         {"grid", {{"N", w.sizes}}},
         {"fits",
          {{{"claim", "calibration/" + w.id},
            {"variable", "N"},
            {"metric", "ops_workload_operations"}},
           {{"claim", "calibration/" + w.id}, {"variable", "N"}, {"metric", "time"}}}}});
  }
  return {{"name", "calibrate"}, {"threads", 1},        {"repetitions", 5},
          {"warmup", 1},         {"time_limit_s", 120}, {"experiments", experiments}};
}

// Whether a workload's fit found the growth it has by construction.
json calibration_row(const json& f) {
  const std::string id = f.value("workload", "");
  const auto& w =
      *std::find_if(workloads().begin(), workloads().end(), [&](auto& x) { return x.id == id; });
  const bool ok = f.value("best_model", "") == std::string(growth_name(w.expected));
  return {{"workload", id},
          {"metric", f.value("metric", "") == "time" ? "time" : "operations"},
          {"expected", growth_name(w.expected)},
          {"best_model", f.value("best_model", json(nullptr))},
          {"exponent", f.value("exponent", json(nullptr))},
          {"ci_low", f.value("ci_low", json(nullptr))},
          {"ci_high", f.value("ci_high", json(nullptr))},
          {"correct", ok}};
}

void print_calibration(const json& rows) {
  for (const json& o : rows)
    std::printf("  %-14s %-10s expected %-8s best %-8s exponent %.3f  %s\n",
                o["workload"].get<std::string>().c_str(), o["metric"].get<std::string>().c_str(),
                o["expected"].get<std::string>().c_str(),
                o["best_model"].is_null() ? "-" : o["best_model"].get<std::string>().c_str(),
                o["exponent"].is_null() ? 0.0 : o["exponent"].get<double>(),
                o["correct"].get<bool>() ? "ok" : "WRONG");
}

// DIR given, or a temporary directory named after the command and this process.
std::string sweep_dir(const std::optional<std::string>& out, const std::string& command) {
  if (out) return *out;
  return (fs::temp_directory_path() / ("pcrt_" + command + "_" + std::to_string(getpid())))
      .string();
}

}  // namespace

int command_calibrate(const CalibrateOptions& o) {
  const SweepConfig config = parse_sweep_config(calibration_config(), "calibrate");
  const std::string dir = sweep_dir(o.out, "calibrate");
  const std::vector<RunResult> results =
      run_sweep(config, dir, false, true, all_runs(config), true);
  const std::vector<json> fits = fits_json(fit_runs(config, results));
  if (o.out)
    write_fits(dir, fits);
  else
    fs::remove_all(dir);
  json out = json::array();
  bool all_ok = true;
  for (const json& f : fits) {
    out.push_back(calibration_row(f));
    all_ok = all_ok && out.back()["correct"].get<bool>();
  }
  if (o.json)
    std::printf("%s\n", out.dump(2).c_str());
  else
    print_calibration(out);
  return all_ok ? 0 : 1;
}

namespace {

// The baseline, read and checked before the sweep runs.
json read_baseline(const std::string& path) {
  if (!fs::exists(path)) input_error("{}: no such file (create it with --update)", path);
  json base = read_json_file(path);
  if (!base.is_object() || !base.contains("runs") || !base["runs"].is_object() ||
      !base.contains("verdicts") || !base["verdicts"].is_object())
    input_error("{}: not a baseline (written by pcrt check --update)", path);
  // A counter is a count; anything else in its place is a damaged file, not a regression.
  for (const auto& [key, old] : base["runs"].items()) {
    if (!old.is_object()) input_error("{}: run {} is not an object of counters", path, key);
    for (const auto& [name, v] : old.items())
      if (name == "status" ? !v.is_string() : !v.is_number_unsigned())
        input_error("{}: run {}: {} is {}, not a count", path, key, name, v.dump());
  }
  for (const auto& [key, v] : base["verdicts"].items())
    if (!v.is_string()) input_error("{}: verdict {} is {}, not a verdict", path, key, v.dump());
  return base;
}

// Counters per run, verdicts per op-count fit (time fits are not gated: machines differ).
json gate_record(const std::vector<RunResult>& results, const std::vector<json>& fits) {
  json now = {{"runs", json::object()}, {"verdicts", json::object()}};
  for (const RunResult& r : results) {
    json c = r.counters;
    if (r.prepare_counters)
      for (const auto& [k, v] : *r.prepare_counters) c["prep_" + k] = v;
    c["status"] = run_status_name(r.status);
    // Operation counts do not depend on the thread count, so the gate's keys leave it out.
    json spec = json::parse(run_key(r));
    spec.erase("threads");
    now["runs"][spec.dump()] = c;
  }
  for (const json& f : fits) {
    const std::string m = f.value("metric", "");
    if (m.find("time") != std::string::npos || m.find("fps") != std::string::npos) continue;
    now["verdicts"][f.value("claim", "") + " | " + f.value("dataset", "") + " | " +
                    f["group"].dump()] = f.value("verdict", "");
  }
  return now;
}

// The counters of one run that differ beyond the tolerance (percent), printed; their number.
size_t counter_differences(const std::string& key, const json& old, const json& cur,
                           double tolerance) {
  std::set<std::string> names;
  for (const auto& [k, v] : old.items()) names.insert(k);
  for (const auto& [k, v] : cur.items()) names.insert(k);
  size_t problems = 0;
  for (const std::string& k : names) {
    const json o = old.value(k, json(nullptr)), c = cur.value(k, json(nullptr));
    if (o.is_number() && c.is_number()) {
      const double ov = o.get<double>(), cv = c.get<double>();
      if (std::abs(cv - ov) <= tolerance / 100.0 * std::abs(ov)) continue;
    } else if (o == c) {
      continue;
    }
    std::printf("%s\n  %s: %s -> %s\n", key.c_str(), k.c_str(), o.dump().c_str(), c.dump().c_str());
    ++problems;
  }
  return problems;
}

// Every difference between the baseline and this run, printed; their number.
size_t gate_differences(const json& base, const json& now, double tolerance) {
  size_t problems = 0;
  for (const auto& [key, old] : base["runs"].items()) {
    if (now["runs"].contains(key)) {
      problems += counter_differences(key, old, now["runs"][key], tolerance);
    } else {
      std::printf("run missing now: %s\n", key.c_str());
      ++problems;
    }
  }
  for (const auto& [key, cur] : now["runs"].items())
    if (!base["runs"].contains(key))
      std::printf("new run (not in the baseline): %s\n", key.c_str()), ++problems;
  const json& base_verdicts = base["verdicts"];
  for (const auto& [key, cur] : now["verdicts"].items())
    if (!base_verdicts.contains(key))
      std::printf("new verdict (not in the baseline): %s\n", key.c_str()), ++problems;
  for (const auto& [key, old] : base_verdicts.items()) {
    const json cur = now["verdicts"].value(key, json(nullptr));
    if (cur != old) {
      std::printf("verdict changed: %s: %s -> %s\n", key.c_str(), old.dump().c_str(),
                  cur.dump().c_str());
      ++problems;
    }
  }
  return problems;
}

}  // namespace

int command_check(const CheckOptions& o) {
  const SweepConfig config = load_sweep_config(o.config);
  if (o.update) check_outputs({{o.baseline, "--baseline"}}, {{o.config, "--config"}});
  const json base = o.update ? json() : read_baseline(o.baseline);
  const std::string dir = sweep_dir(o.out, "check");
  check_sweep_outputs(dir, {{o.config, "--config"}, {o.baseline, "--baseline"}});
  const std::vector<RunResult> results =
      run_sweep(config, dir, false, true, all_runs(config), true);
  const json now = gate_record(results, fits_json(fit_runs(config, results)));
  if (!o.out) fs::remove_all(dir);
  // A gate that compares no measurement passes nothing: every run failing in the baseline too
  // would read "0 differences".
  if (std::none_of(results.begin(), results.end(), [](const RunResult& r) { return r.ok(); }))
    input_error("{}: every one of its {} runs failed or timed out: nothing to compare", o.config,
                results.size());
  if (o.update) {
    write_json(o.baseline, now);
    std::printf("%s: baseline written (%zu runs, %zu verdicts)\n", o.baseline.c_str(),
                now["runs"].size(), now["verdicts"].size());
    return 0;
  }
  const size_t problems = gate_differences(base, now, o.tolerance);
  std::printf("%s: %zu runs, %zu verdicts compared: %zu differences\n", o.baseline.c_str(),
              now["runs"].size(), now["verdicts"].size(), problems);
  return problems == 0 ? 0 : 1;
}

}  // namespace pcrt
