// `pcrt cluster submit` and `pcrt cluster status`: a sweep as a Slurm job array of shards (each
// a resumable `pcrt sweep --shard i/n` on a fixed plan) and one merge + fit + report job that
// runs after every shard succeeded. Everything lives in the output directory:
//   DIR/slurm/config.json   the config as submitted (editing the original changes nothing here)
//   DIR/slurm/plan.json     each shard's runs, balanced on estimated run time, fixed for resumes
//   DIR/slurm/*.sbatch      the job scripts;  DIR/slurm/logs/  their logs
//   DIR/slurm/jobs.json     every submission's job ids
//   DIR/shards/I/           shard I's sweep;  DIR/runs.jsonl, fits.json, report.md  the merge
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

#include "core/error.hpp"
#include "harness/command_helpers.hpp"
#include "harness/commands.hpp"
#include "harness/run_files.hpp"
#include "harness/shard_plan.hpp"
#include "harness/slurm.hpp"
#include "harness/sweep_config.hpp"

namespace pcrt {
namespace {

namespace fs = std::filesystem;

struct ClusterDir {
  std::string root;  // absolute
  [[nodiscard]] std::string slurm() const { return root + "/slurm"; }
  [[nodiscard]] std::string config() const { return slurm() + "/config.json"; }
  [[nodiscard]] std::string plan() const { return slurm() + "/plan.json"; }
  [[nodiscard]] std::string jobs() const { return slurm() + "/jobs.json"; }
  [[nodiscard]] std::string shard_script() const { return slurm() + "/shard.sbatch"; }
  [[nodiscard]] std::string merge_script() const { return slurm() + "/merge.sbatch"; }
  [[nodiscard]] std::string shard_dir(size_t i) const {
    return root + "/shards/" + std::to_string(i);
  }
  [[nodiscard]] std::string shard_log(size_t i) const {
    return slurm() + "/logs/shard-" + std::to_string(i) + ".log";
  }
  [[nodiscard]] std::string merge_log() const { return slurm() + "/logs/merge.log"; }
};

// Where a shard or the merge stands, for status and for --resume.
enum class Progress { Finished, Active, Failed };

struct Part {
  std::string name;  // "shard 2", "merge"
  std::string job;   // "45_2", "46"; empty if never submitted
  JobStatus slurm;
  size_t done = 0, planned = 0;
  std::string log;
  Progress progress = Progress::Failed;
};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    input_error("{}: cannot open (is {} a pcrt cluster directory?)", path,
                fs::path(path).parent_path().parent_path().string());
  const json j = json::parse(in, nullptr, false);
  if (j.is_discarded()) input_error("{}: not valid JSON", path);
  return j;
}

void write_script(const std::string& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& o) { o << text; });
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string s;
  for (size_t i = 0; i < parts.size(); ++i) s += (i ? sep : "") + parts[i];
  return s;
}

// Sorted shard indices in sbatch --array syntax, consecutive ones as ranges: "0-3,5,7-9".
std::string index_list(const std::vector<size_t>& shards) {
  std::vector<std::string> parts;
  for (size_t i = 0; i < shards.size();) {
    size_t j = i;
    while (j + 1 < shards.size() && shards[j + 1] == shards[j] + 1) ++j;
    parts.push_back(j == i ? std::to_string(shards[i])
                           : fmt::format("{}-{}", shards[i], shards[j]));
    i = j + 1;
  }
  return join(parts, ",");
}

// --partition, --time, --cpus-per-task, --mem and every --sbatch-arg, as sbatch options.
std::vector<std::string> resource_options(const ClusterSubmitOptions& o) {
  std::vector<std::string> opts;
  for (const auto& [name, value] :
       {std::pair{"partition", &o.partition}, std::pair{"time", &o.time},
        std::pair{"cpus-per-task", &o.cpus_per_task}, std::pair{"mem", &o.mem}})
    if (*value) opts.push_back(fmt::format("--{}={}", name, **value));
  opts.insert(opts.end(), o.sbatch_args.begin(), o.sbatch_args.end());
  return opts;
}

std::string directives(const std::vector<std::string>& options) {
  std::string text;
  for (const std::string& o : options) text += "#SBATCH " + o + "\n";
  return text;
}

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

std::string shard_script(const ClusterDir& d, const std::string& name, size_t n,
                         const std::vector<std::string>& options) {
  const std::string head =
      directives({"--job-name=pcrt-" + name, "--output=" + d.slurm() + "/logs/shard-%a.log",
                  "--open-mode=append", "--requeue", "--chdir=" + fs::current_path().string()});
  return fmt::format(
      "#!/bin/bash\n"
      "# pcrt cluster: one shard of sweep {name} per array task (written by pcrt cluster submit).\n"
      "# --resume: a requeued or resubmitted task skips the runs it already did.\n"
      "{head}{options}"
      "set -euo pipefail\n"
      "echo \"pcrt: shard $SLURM_ARRAY_TASK_ID of {n}, job ${{SLURM_ARRAY_JOB_ID}}_"
      "$SLURM_ARRAY_TASK_ID on $(hostname), $(date)\"\n"
      "exec {exe} sweep {config} --out {root}/shards/\"$SLURM_ARRAY_TASK_ID\" --resume "
      "--shard \"$SLURM_ARRAY_TASK_ID/{n}\" --plan {plan}\n",
      fmt::arg("name", name), fmt::arg("head", head), fmt::arg("options", directives(options)),
      fmt::arg("n", n), fmt::arg("exe", shell_quote(self_exe())),
      fmt::arg("config", shell_quote(d.config())), fmt::arg("root", shell_quote(d.root)),
      fmt::arg("plan", shell_quote(d.plan())));
}

std::string merge_script(const ClusterDir& d, const std::string& name, size_t n,
                         const std::vector<std::string>& options) {
  std::vector<std::string> shards;
  for (size_t i = 0; i < n; ++i) shards.push_back(shell_quote(d.shard_dir(i)));
  const std::string head = directives(
      {"--job-name=pcrt-" + name + "-merge", "--output=" + d.merge_log(), "--open-mode=append",
       "--kill-on-invalid-dep=yes", "--chdir=" + fs::current_path().string()});
  return fmt::format(
      "#!/bin/bash\n"
      "# pcrt cluster: merge, fit and report sweep {name} once every shard succeeded\n"
      "# (submitted with --dependency=afterok on the shards' job array).\n"
      "{head}{options}"
      "set -euo pipefail\n"
      "echo \"pcrt: merge, job $SLURM_JOB_ID on $(hostname), $(date)\"\n"
      "{exe} merge {shards} --out {root}\n"
      "{exe} fit {root}\n"
      "{exe} report {root}\n",
      fmt::arg("name", name), fmt::arg("head", head), fmt::arg("options", directives(options)),
      fmt::arg("exe", shell_quote(self_exe())), fmt::arg("shards", join(shards, " ")),
      fmt::arg("root", shell_quote(d.root)));
}

// Shards in the plan, and each shard's planned run keys.
std::vector<std::vector<std::string>> planned_keys(const json& plan, const std::string& origin) {
  std::vector<std::vector<std::string>> keys;
  for (const json& shard : plan.at("shards")) {
    keys.emplace_back();
    for (const json& spec : shard.at("runs")) keys.back().push_back(planned_run_key(spec, origin));
  }
  return keys;
}

// Runs of `keys` recorded in DIR/runs.jsonl (a truncated last line does not count).
size_t runs_done(const std::string& dir, const std::vector<std::string>& keys) {
  const std::string path = dir + "/runs.jsonl";
  if (!fs::exists(path)) return 0;
  std::set<std::string> have;
  for (const RunResult& r : read_runs_jsonl(path)) have.insert(run_key(r));
  return size_t(std::count_if(keys.begin(), keys.end(),
                              [&](const std::string& k) { return have.count(k) > 0; }));
}

Progress judge(const Part& p, bool outputs_complete) {
  if (is_active(p.slurm.state)) return Progress::Active;
  if (outputs_complete && !is_failure(p.slurm.state)) return Progress::Finished;
  return Progress::Failed;
}

// Each shard's newest job (a resubmission takes over its shards), and the newest merge job.
struct JobIds {
  std::vector<std::pair<std::string, std::string>> shard;  // (array job, task)
  std::string merge;
};

JobIds newest_jobs(const json& jobs, size_t n) {
  JobIds ids;
  ids.shard.resize(n);
  for (const json& sub : jobs.value("submissions", json::array())) {
    for (const json& s : sub.value("shards", json::array()))
      if (s.get<size_t>() < n) ids.shard[s.get<size_t>()] = {sub.at("array_job"), s.dump()};
    ids.merge = sub.at("merge_job");
  }
  return ids;
}

std::vector<Part> survey(const ClusterDir& d) {
  const json plan = read_json(d.plan());
  const json jobs = fs::exists(d.jobs()) ? read_json(d.jobs()) : json::object();
  const auto keys = planned_keys(plan, d.plan());
  const JobIds ids = newest_jobs(jobs, keys.size());
  std::map<std::string, std::map<std::string, JobStatus>> queried;
  auto state_of = [&](const std::string& job, const std::string& task) {
    if (job.empty()) return JobStatus{};
    if (!queried.count(job)) queried[job] = squeue_job(job);
    const auto& states = queried[job];
    const auto it = states.find(task.empty() ? job : job + "_" + task);
    return it == states.end() ? JobStatus{} : it->second;
  };
  std::vector<Part> parts;
  std::vector<std::string> all_keys;
  for (size_t i = 0; i < keys.size(); ++i) {
    const auto& [array, task] = ids.shard[i];
    Part p{"shard " + std::to_string(i),
           array.empty() ? "" : array + "_" + task,
           state_of(array, task),
           runs_done(d.shard_dir(i), keys[i]),
           keys[i].size(),
           d.shard_log(i)};
    p.progress = judge(p, p.done == p.planned);
    parts.push_back(p);
    all_keys.insert(all_keys.end(), keys[i].begin(), keys[i].end());
  }
  Part merge{"merge",         ids.merge,    state_of(ids.merge, ""), runs_done(d.root, all_keys),
             all_keys.size(), d.merge_log()};
  merge.progress = judge(merge, merge.done == merge.planned && fs::exists(d.root + "/report.md"));
  parts.push_back(merge);
  return parts;
}

void print_part(const Part& p) {
  std::string line = fmt::format("{:<9} {:<14} {:>5} of {:<5} runs", p.name + ":",
                                 p.job.empty() ? "NOT SUBMITTED" : job_state_name(p.slurm.state),
                                 p.done, p.planned);
  if (!p.job.empty()) line += "  job " + p.job;
  if (!p.slurm.reason.empty() && p.slurm.reason != "None") line += " (" + p.slurm.reason + ")";
  if (p.progress == Progress::Failed) line += "  log " + p.log;
  std::printf("%s\n", line.c_str());
}

ClusterDir cluster_dir(const std::string& dir) { return {fs::absolute(dir).lexically_normal()}; }

struct Submission {
  std::vector<size_t> shards;  // array tasks to submit (may be empty: merge only)
  std::vector<std::string> extra_options;
};

// Submits the array and the merge that depends on it, records the ids, prints them.
void submit(const ClusterDir& d, const Submission& s, bool dry_run) {
  std::vector<std::string> array_cmd = {"--array=" + index_list(s.shards)};
  array_cmd.insert(array_cmd.end(), s.extra_options.begin(), s.extra_options.end());
  array_cmd.push_back(d.shard_script());
  if (dry_run) {
    std::vector<std::string> merge_cmd = s.extra_options;
    if (!s.shards.empty()) {
      std::printf("would run: sbatch --parsable %s\n", join(array_cmd, " ").c_str());
      merge_cmd.push_back("--dependency=afterok:<array job>");
    }
    merge_cmd.push_back(d.merge_script());
    std::printf("would run: sbatch --parsable %s\n", join(merge_cmd, " ").c_str());
    return;
  }
  std::string array_job;
  if (!s.shards.empty()) array_job = sbatch(array_cmd);
  // Recorded before the merge is submitted: if that fails, status still finds the shards.
  json jobs = fs::exists(d.jobs()) ? read_json(d.jobs()) : json{{"submissions", json::array()}};
  jobs["submissions"].push_back(
      {{"array_job", array_job}, {"shards", s.shards}, {"merge_job", ""}});
  write_json(d.jobs(), jobs);
  std::vector<std::string> merge_cmd = s.extra_options;
  if (!array_job.empty()) merge_cmd.push_back("--dependency=afterok:" + array_job);
  merge_cmd.push_back(d.merge_script());
  const std::string merge_job = sbatch(merge_cmd);
  jobs["submissions"].back()["merge_job"] = merge_job;
  write_json(d.jobs(), jobs);
  if (!array_job.empty())
    std::printf("shards %s: job array %s\n", index_list(s.shards).c_str(), array_job.c_str());
  const std::string after = array_job.empty() ? "" : " (afterok:" + array_job + ")";
  std::printf("merge, fit, report: job %s%s\n", merge_job.c_str(), after.c_str());
}

// DIR/slurm: the config, the plan and both job scripts.
void write_cluster_files(const ClusterDir& d, const SweepConfig& config, size_t n,
                         const ClusterSubmitOptions& o) {
  fs::create_directories(d.slurm() + "/logs");
  const std::vector<RunResult> earlier =
      o.costs ? read_runs_jsonl(*o.costs + "/runs.jsonl") : std::vector<RunResult>{};
  const ShardPlan plan = plan_shards(run_costs(config.runs, earlier), n);
  write_json(d.config(), config.raw);
  write_json(d.plan(), plan_json(plan, config.runs, o.costs.value_or("model")));
  std::vector<std::string> options = resource_options(o);
  if (!o.cpus_per_task)  // a run uses the config's threads
    options.insert(options.begin(),
                   fmt::format("--cpus-per-task={}", config.raw.value("threads", 2)));
  write_script(d.shard_script(), shard_script(d, config.name, n, options));
  write_script(d.merge_script(), merge_script(d, config.name, n, resource_options(o)));
  const auto [lo, hi] = std::minmax_element(plan.cost.begin(), plan.cost.end());
  std::printf("%s: %zu runs in %zu shards, estimated %.1f to %.1f s each\n", d.slurm().c_str(),
              config.runs.size(), n, *lo, *hi);
}

int submit_fresh(const ClusterSubmitOptions& o) {
  const SweepConfig config = load_sweep_config(o.target);
  const ClusterDir d = cluster_dir(required(o.out, "--out", ClusterSubmitOptions::usage));
  if (!o.shards) input_error("--shards N is required");
  const size_t n = *o.shards;
  if (n > config.runs.size())
    input_error("--shards {} is more than the {} runs of {}", n, config.runs.size(), o.target);
  if (fs::exists(d.jobs()))
    input_error(
        "{}: already submitted; pcrt cluster submit --resume {} resubmits what is "
        "unfinished",
        d.root, d.root);
  write_cluster_files(d, config, n, o);
  std::vector<size_t> all(n);
  std::iota(all.begin(), all.end(), size_t(0));
  submit(d, {all, {}}, o.dry_run);
  return 0;
}

int submit_resume(const ClusterSubmitOptions& o) {
  const ClusterDir d = cluster_dir(o.target);
  require_slurm_command("squeue");  // even for --dry-run: what is unfinished comes from squeue
  if (!fs::exists(d.jobs())) input_error("{}: nothing was submitted yet", d.jobs());
  const std::vector<Part> parts = survey(d);
  for (const Part& p : parts)
    if (p.progress == Progress::Active)
      input_error("{} is still {} (job {}): wait for it, or scancel it, before --resume", p.name,
                  job_state_name(p.slurm.state), p.job);
  Submission s{{}, resource_options(o)};
  for (size_t i = 0; i + 1 < parts.size(); ++i)
    if (parts[i].progress != Progress::Finished) s.shards.push_back(i);
  if (s.shards.empty() && parts.back().progress == Progress::Finished) {
    std::printf("%s: every shard and the merge finished; nothing to resubmit\n", d.root.c_str());
    return 0;
  }
  submit(d, s, o.dry_run);
  return 0;
}

}  // namespace

int command_cluster_submit(const ClusterSubmitOptions& o) {
  if (!o.dry_run) require_slurm_command("sbatch");
  if (o.resume) {
    if (o.out || o.shards || o.costs)
      input_error(
          "--resume DIR takes the shards and plan of DIR; --out, --shards and --costs "
          "belong to a first submission");
    return submit_resume(o);
  }
  return submit_fresh(o);
}

int command_cluster_status(const ClusterStatusOptions& o) {
  require_slurm_command("squeue");
  const ClusterDir d = cluster_dir(o.dir);
  if (fs::exists(d.plan()) && !fs::exists(d.jobs()))
    input_error("{}: not submitted (only scripts written, by --dry-run?)", d.root);
  const std::vector<Part> parts = survey(d);
  std::vector<std::string> failed;
  bool active = false;
  for (const Part& p : parts) {
    print_part(p);
    if (p.progress == Progress::Failed) failed.push_back(p.name);
    active = active || p.progress == Progress::Active;
  }
  if (active) {
    std::printf("%s: in progress\n", d.root.c_str());
    return 2;
  }
  if (!failed.empty()) {
    std::printf("%s: failed: %s; pcrt cluster submit --resume %s resubmits what is unfinished\n",
                d.root.c_str(), join(failed, ", ").c_str(), d.root.c_str());
    return 1;
  }
  std::printf("%s: finished\n", d.root.c_str());
  return 0;
}

}  // namespace pcrt
