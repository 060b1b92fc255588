#include "harness/slurm.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <utility>

#include "core/error.hpp"

namespace pcrt {
namespace {

constexpr std::array<std::pair<JobState, std::string_view>, 13> kStateNames = {{
    {JobState::Pending, "PENDING"},
    {JobState::Running, "RUNNING"},
    {JobState::Completing, "COMPLETING"},
    {JobState::Completed, "COMPLETED"},
    {JobState::Failed, "FAILED"},
    {JobState::Cancelled, "CANCELLED"},
    {JobState::Timeout, "TIMEOUT"},
    {JobState::OutOfMemory, "OUT_OF_MEMORY"},
    {JobState::NodeFail, "NODE_FAIL"},
    {JobState::Preempted, "PREEMPTED"},
    {JobState::Requeued, "REQUEUED"},
    {JobState::Suspended, "SUSPENDED"},
    {JobState::Gone, "GONE"},
}};

}  // namespace

JobState parse_job_state(std::string_view name) {
  // squeue may append a qualifier ("CANCELLED by 0").
  const std::string_view word = name.substr(0, name.find(' '));
  for (const auto& [state, text] : kStateNames)
    if (text == word) return state;
  if (word == "CONFIGURING" || word == "RESIZING" || word == "SIGNALING" || word == "STAGE_OUT")
    return JobState::Running;
  if (word == "REQUEUE_HOLD" || word == "REQUEUE_FED" || word == "RESV_DEL_HOLD")
    return JobState::Requeued;
  return JobState::Failed;  // BOOT_FAIL, DEADLINE, REVOKED, SPECIAL_EXIT, ...
}

std::string_view job_state_name(JobState state) {
  for (const auto& [s, text] : kStateNames)
    if (s == state) return text;
  return "UNKNOWN";
}

bool is_active(JobState state) {
  switch (state) {
    case JobState::Pending:
    case JobState::Running:
    case JobState::Completing:
    case JobState::Requeued:
    case JobState::Suspended:
      return true;
    default:
      return false;
  }
}

bool is_failure(JobState state) {
  return !is_active(state) && state != JobState::Completed && state != JobState::Gone;
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
    if (access(candidate.c_str(), X_OK) == 0) return true;
  }
  return false;
}

void require_slurm_command(const std::string& program) {
  if (!on_path(program))
    input_error(
        "{} was not found on PATH: pcrt cluster needs Slurm's commands (Debian: apt-get "
        "install slurm-client) on a machine of the cluster",
        program);
}

bool is_job_id(const std::string& text) {
  if (text.empty() || text.size() > 10 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  return std::stoull(text) <= 0xffffffffULL;
}

std::string sbatch(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandOutput r = run_command(argv);
  const std::string id = last_line(r.out);
  if (r.exit_code != 0 || id.empty())
    input_error("sbatch failed (exit {}): {}", r.exit_code, last_line(r.err));
  const std::string job = id.substr(0, id.find(';'));  // "123;cluster" on federated set-ups
  // Recorded in jobs.json and read back by status: what is not a job id is refused now.
  if (!is_job_id(job)) input_error("sbatch printed '{}', not a job id", id);
  return job;
}

std::map<std::string, JobStatus> squeue_job(const std::string& job_id) {
  const CommandOutput r = run_command(
      {"squeue", "--noheader", "--array", "--states=all", "--jobs=" + job_id, "--format=%i|%T|%r"});
  std::map<std::string, JobStatus> jobs;
  if (r.exit_code != 0) {
    // squeue refuses an id it has forgotten; that job is simply gone.
    if (r.err.find("Invalid job id") != std::string::npos) return jobs;
    input_error("squeue failed (exit {}): {}", r.exit_code, last_line(r.err));
  }
  std::stringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    const size_t a = line.find('|'), b = line.find('|', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    jobs[line.substr(0, a)] = {parse_job_state(line.substr(a + 1, b - a - 1)), line.substr(b + 1)};
  }
  return jobs;
}

namespace {

using nlohmann::json;

// A job id field of jobs.json: what sbatch printed, or empty (the merge not submitted yet).
std::string job_field(const json& submission, const char* key, const std::string& where) {
  if (!submission.contains(key) || !submission[key].is_string())
    input_error("{}.{} is missing or not a string", where, key);
  const std::string id = submission[key].get<std::string>();
  if (!id.empty() && !is_job_id(id))
    input_error("{}.{} = {} is not a Slurm job id", where, key, submission[key].dump());
  return id;
}

// The shards a submission's array ran: indices into the plan's n shards.
std::vector<size_t> submitted_shards(const json& submission, size_t n, const std::string& where) {
  if (!submission.contains("shards") || !submission["shards"].is_array())
    input_error("{}.shards is missing or not a list of shard indices", where);
  std::vector<size_t> shards;
  for (size_t k = 0; k < submission["shards"].size(); ++k) {
    const json& v = submission["shards"][k];
    if (!v.is_number_unsigned() || v.get<uint64_t>() >= n)
      input_error("{}.shards[{}] = {} is not a shard of the plan (0 to {})", where, k, v.dump(),
                  n - 1);
    shards.push_back(size_t(v.get<uint64_t>()));
  }
  return shards;
}

}  // namespace

JobIds newest_jobs(const nlohmann::json& jobs, size_t n, const std::string& origin) {
  if (!jobs.is_object() || !jobs.contains("submissions") || !jobs["submissions"].is_array())
    input_error("{}: \"submissions\" is missing or not a list (written by pcrt cluster submit)",
                origin);
  JobIds ids;
  ids.shard.resize(n);
  const json& submissions = jobs["submissions"];
  for (size_t i = 0; i < submissions.size(); ++i) {
    const std::string where = fmt::format("{}: submissions[{}]", origin, i);
    if (!submissions[i].is_object()) input_error("{} is not an object", where);
    const std::string array = job_field(submissions[i], "array_job", where);
    const std::vector<size_t> shards = submitted_shards(submissions[i], n, where);
    if (array.empty() && !shards.empty())
      input_error("{}.array_job is empty, but the submission lists shards", where);
    for (size_t s : shards) ids.shard[s] = {array, std::to_string(s)};
    ids.merge = job_field(submissions[i], "merge_job", where);
  }
  return ids;
}

}  // namespace pcrt
