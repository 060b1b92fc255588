// The little of Slurm that `pcrt cluster` needs: submitting with sbatch and asking squeue for job
// states. Accounting (sacct) is often disabled, so states come from squeue alone; a job squeue no
// longer lists (it forgets finished jobs after MinJobAge) is `Gone`, and callers judge it by its
// outputs.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "harness/subprocess.hpp"

namespace pcrt {

enum class JobState {
  Pending,
  Running,
  Completing,
  Completed,
  Failed,
  Cancelled,
  Timeout,
  OutOfMemory,
  NodeFail,
  Preempted,
  Requeued,
  Suspended,
  Gone,  // squeue does not know the job (any more)
};

// squeue's %T names (PENDING, RUNNING, ...); a state pcrt does not know is Failed.
JobState parse_job_state(std::string_view name);
std::string_view job_state_name(JobState state);
// Still queued or running: it may yet finish.
bool is_active(JobState state);
// Ended without success: afterok dependencies on it can never be met.
bool is_failure(JobState state);

struct JobStatus {
  JobState state = JobState::Gone;
  std::string reason;  // squeue's %r, e.g. DependencyNeverSatisfied
};

bool on_path(const std::string& program);
// InputError saying plainly that `program` (sbatch, squeue) is not there.
void require_slurm_command(const std::string& program);

// A job id as sbatch --parsable prints it: decimal digits within Slurm's 32-bit ids.
bool is_job_id(const std::string& text);

// sbatch --parsable ARGS...; returns the job id, or InputError with sbatch's own message.
std::string sbatch(const std::vector<std::string>& args);
// States of a job, or of every task of a job array ("123_4"), by squeue -r -t all.
std::map<std::string, JobStatus> squeue_job(const std::string& job_id);

// Each shard's newest job (a resubmission takes over its shards), and the newest merge job.
struct JobIds {
  std::vector<std::pair<std::string, std::string>> shard;  // (array job, task)
  std::string merge;
};

// jobs.json (`pcrt cluster submit` records every submission's job ids there), every field checked
// where it is read: a hand-edited or cut file is an InputError naming `origin` and the field.
// `n` is the plan's number of shards.
JobIds newest_jobs(const nlohmann::json& jobs, size_t n, const std::string& origin);

}  // namespace pcrt
