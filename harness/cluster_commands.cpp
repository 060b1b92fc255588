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
#include <map>
#include <numeric>
#include <optional>
#include <regex>
#include <set>
#include <string_view>
#include <tuple>

#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/json_input.hpp"
#include "core/point_cloud_io.hpp"
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

// POSIX single quotes, ' written as '\'': one shell word, whatever s holds.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A word no shell and no #SBATCH line reads specially: written as it is.
bool plain_word(const std::string& s) {
  constexpr std::string_view kPlain = "_@%+=:,./-";
  return !s.empty() && std::all_of(s.begin(), s.end(), [&](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           kPlain.find(c) != std::string_view::npos;
  });
}

// A command line printed for a user to read or paste: each word quoted where a shell needs it.
std::string shell_line(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words)
    line += (line.empty() ? "" : " ") + (plain_word(w) ? w : shell_quote(w));
  return line;
}

bool has_control_character(const std::string& s) {
  return std::any_of(s.begin(), s.end(),
                     [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; });
}

// A line of a job script that sbatch reads itself: "#SBATCH OPTION". A shell never sees it, so
// shell quoting alone does not make it safe: sbatch splits the line at blanks, takes '...' and
// "..." as quotes and \ as an escape (inside quotes too) and ends it at the line break (Slurm
// 22.05, sbatch's _get_argument). A control character (a line break) cannot be written there
// and is refused naming `field`; anything else is one word in single quotes, ' as '\'' and \ as
// '\\', which sbatch and a shell read alike.
std::string directive(const std::string& option, const std::string& field) {
  if (has_control_character(option))
    input_error("{}: '{}' holds a control character (a line break?), which no #SBATCH line can",
                field, option);
  if (plain_word(option)) return "#SBATCH " + option + "\n";
  std::string q = "'";
  for (char c : option)
    q += c == '\'' ? std::string("'\\''") : c == '\\' ? std::string("'\\\\'") : std::string(1, c);
  return "#SBATCH " + q + "'\n";
}

// A log path for sbatch --output: Slurm expands %-patterns there (%a, the array task), so a % of
// DIR is written %%; a backslash would turn the patterns off, so DIR must not hold one.
std::string log_pattern(const std::string& dir, const std::string& file) {
  if (dir.find('\\') != std::string::npos)
    input_error("--out {}: a backslash in it would turn off Slurm's %-patterns in the log paths",
                dir);
  std::string pattern;
  for (char c : dir) pattern += c == '%' ? std::string("%%") : std::string(1, c);
  return pattern + file;
}

// A sweep's name becomes Slurm job names and script comments: letters, digits and . _ + - only.
void check_job_name(const std::string& name, const std::string& origin) {
  const bool ok = !name.empty() && name.size() <= 100 && plain_word(name) &&
                  name.find_first_of("@%=:,/") == std::string::npos;
  if (!ok)
    input_error("{}: name '{}' cannot name a Slurm job (letters, digits and . _ + -, at most 100)",
                origin, name);
}

// The values a user gives for sbatch, before anything is written: a partition is a name (or a
// list of them); the others go into #SBATCH lines quoted, so only a control character is refused.
void check_sbatch_values(const ClusterSubmitOptions& o) {
  if (const auto& p = o.partition) {
    const bool ok = !p->empty() && plain_word(*p) &&
                    p->find_first_of("@%+=:/") == std::string::npos && p->front() != ',' &&
                    p->back() != ',';
    if (!ok)
      input_error("--partition '{}': not a partition name (letters, digits, . _ - and commas)", *p);
  }
  std::vector<std::pair<std::string, std::string>> values;
  for (const auto& [flag, value] :
       {std::pair{"--time", &o.time}, std::pair{"--cpus-per-task", &o.cpus_per_task},
        std::pair{"--mem", &o.mem}})
    if (*value) values.emplace_back(flag, **value);
  for (const std::string& a : o.sbatch_args) values.emplace_back("--sbatch-arg", a);
  for (const auto& [flag, value] : values)
    if (has_control_character(value))
      input_error("{} '{}': holds a control character (a line break?), which no #SBATCH line can",
                  flag, value);
}

json read_json(const std::string& path) {
  if (!fs::exists(path))
    input_error("{}: cannot open (is {} a pcrt cluster directory?)", path,
                fs::path(path).parent_path().parent_path().string());
  return read_json_file(path);  // bounded and depth-limited; errors name the file
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
// The resource options in the forms sbatch takes, refused here rather than by sbatch after the
// files are written: --cpus-per-task a count from 1, --mem a size (digits, then K, M, G or T),
// --time minutes, MM:SS, HH:MM:SS or D-HH[:MM[:SS]] (or UNLIMITED).
void check_resources(const ClusterSubmitOptions& o) {
  static const std::regex count("[1-9][0-9]{0,5}"), mem("[0-9]{1,12}([KMGTkmgt][Bb]?)?"),
      time(
          "[0-9]{1,6}(-[0-9]{1,2}(:[0-9]{1,2}){0,2}|(:[0-9]{1,2}){0,2})|[Uu][Nn][Ll][Ii][Mm][Ii]["
          "Tt][Ee][Dd]|[Ii][Nn][Ff][Ii][Nn][Ii][Tt][Ee]");
  for (const auto& [option, value, form, what] :
       {std::tuple{"--cpus-per-task", &o.cpus_per_task, &count, "a count of 1 or more"},
        std::tuple{"--mem", &o.mem, &mem, "a size such as 4000 or 16G"},
        std::tuple{"--time", &o.time, &time, "minutes, MM:SS, HH:MM:SS or D-HH[:MM[:SS]]"}})
    if (*value && !std::regex_match(**value, *form))
      input_error("{} '{}': not an sbatch value ({})", option, **value, what);
}

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
  for (const std::string& o : options) text += directive(o, "an sbatch option");
  return text;
}

// What every script sets: job name, log, and the folder it runs in (where pcrt was submitted).
std::string script_head(const std::string& job_name, const std::string& log,
                        const std::vector<std::string>& fixed) {
  std::string head =
      directive("--job-name=" + job_name, "name") + directive("--output=" + log, "--out");
  for (const std::string& o : fixed) head += "#SBATCH " + o + "\n";
  return head + directive("--chdir=" + fs::current_path().string(), "the current directory");
}

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

std::string shard_script(const ClusterDir& d, const std::string& name, size_t n,
                         const std::vector<std::string>& options) {
  const std::string head =
      script_head("pcrt-" + name, log_pattern(d.root, "/slurm/logs/shard-%a.log"),
                  {"--open-mode=append", "--requeue"});
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
  const std::string head =
      script_head("pcrt-" + name + "-merge", log_pattern(d.root, "/slurm/logs/merge.log"),
                  {"--open-mode=append", "--kill-on-invalid-dep=yes"});
  return fmt::format(
      "#!/bin/bash\n"
      "# pcrt cluster: merge, fit and report sweep {name} once every shard succeeded\n"
      "# (submitted with --dependency=afterok on the shards' job array).\n"
      "{head}{options}"
      "set -euo pipefail\n"
      "echo \"pcrt: merge, job $SLURM_JOB_ID on $(hostname), $(date)\"\n"
      "{exe} merge {shards} --out {root} --overwrite\n"
      "{exe} fit {root}\n"
      "{exe} report {root}\n",
      fmt::arg("name", name), fmt::arg("head", head), fmt::arg("options", directives(options)),
      fmt::arg("exe", shell_quote(self_exe())), fmt::arg("shards", join(shards, " ")),
      fmt::arg("root", shell_quote(d.root)));
}

// Runs of `keys` recorded in DIR/runs.jsonl (a truncated last line does not count, nor does a run
// a signal ended: the shard's --resume does it again).
size_t runs_done(const std::string& dir, const std::vector<std::string>& keys) {
  const std::string path = dir + "/runs.jsonl";
  if (!fs::exists(path)) return 0;
  std::set<std::string> have;
  for (const RunResult& r : read_runs_jsonl(path))
    if (!killed_by_signal(r)) have.insert(run_key(r));
  return size_t(std::count_if(keys.begin(), keys.end(),
                              [&](const std::string& k) { return have.count(k) > 0; }));
}

Progress judge(const Part& p, bool outputs_complete) {
  if (is_active(p.slurm.state)) return Progress::Active;
  if (outputs_complete && !is_failure(p.slurm.state)) return Progress::Finished;
  return Progress::Failed;
}

std::vector<Part> survey(const ClusterDir& d) {
  const auto keys = read_plan(read_json(d.plan()), d.plan());
  const json jobs =
      fs::exists(d.jobs()) ? read_json(d.jobs()) : json{{"submissions", json::array()}};
  const JobIds ids = newest_jobs(jobs, keys.size(), d.jobs());
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
      std::printf("would run: sbatch --parsable %s\n", shell_line(array_cmd).c_str());
      merge_cmd.push_back("--dependency=afterok:<array job>");
    }
    merge_cmd.push_back(d.merge_script());
    std::printf("would run: sbatch --parsable %s\n", shell_line(merge_cmd).c_str());
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
  std::vector<std::string> options = resource_options(o);
  if (!o.cpus_per_task)  // a run uses the config's threads
    options.insert(options.begin(),
                   fmt::format("--cpus-per-task={}", config.raw.value("threads", 2)));
  // The scripts first: a value they cannot hold is refused before anything is written.
  check_job_name(config.name, o.target);
  const std::string shard = shard_script(d, config.name, n, options);
  const std::string merge = merge_script(d, config.name, n, resource_options(o));
  const std::vector<RunResult> earlier =
      o.costs ? read_runs_jsonl(*o.costs + "/runs.jsonl") : std::vector<RunResult>{};
  const ShardPlan plan = plan_shards(run_costs(config.runs, earlier), n);
  make_output_directory(d.slurm() + "/logs", "--out");
  write_json(d.config(), config.raw);
  write_json(d.plan(), plan_json(plan, config.runs, o.costs.value_or("model")));
  write_script(d.shard_script(), shard);
  write_script(d.merge_script(), merge);
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

// A merge job written before a merge refused an earlier merge's runs has no --overwrite, and a
// resubmitted merge meets its first attempt's files: its merge line is brought up to date.
void update_merge_script(const ClusterDir& d) {
  std::string text = read_file(d.merge_script());
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line(text.data() + start, end - start);
    if (!line.starts_with("#") && line.find(" merge ") != std::string_view::npos &&
        line.find(" --out ") != std::string_view::npos) {
      if (line.find("--overwrite") == std::string_view::npos) {
        text.insert(end, " --overwrite");
        write_script(d.merge_script(), text);
      }
      return;
    }
    start = end + 1;
  }
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
  update_merge_script(d);
  submit(d, s, o.dry_run);
  return 0;
}

}  // namespace

int command_cluster_submit(const ClusterSubmitOptions& o) {
  if (!o.dry_run) require_slurm_command("sbatch");
  check_sbatch_values(o);
  check_resources(o);
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
