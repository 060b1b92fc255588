#!/usr/bin/env bash
# Issue 29, finding 10: `pcrt cluster status` on a corrupted jobs.json or plan.json said "internal
# error" (exit 3) for half the corruptions, and "shards": [1e30] was undefined behaviour. Every
# field is now checked where it is read: each corruption below must give exit 1 and one stderr
# line naming the file, for status and for submit --resume. Also: a run whose child was killed
# by a signal counts as not done, so status calls its shard unfinished and --resume retries it.
# Slurm is faked: squeue knows no job (Slurm forgot them), so parts are judged by their outputs.
set -euo pipefail
pcrt=$(realpath "$1")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
mkdir "$dir/fake"
printf '#!/bin/sh\nexit 0\n' >"$dir/fake/squeue"
chmod +x "$dir/fake/squeue"
export PATH=$dir/fake:$PATH
cat >"$dir/c.json" <<'JSON'
{"name": "files", "threads": 1, "experiments": [
  {"name": "b", "kind": "build", "methods": ["reference_splat"], "structures": ["kd_tree", "grid"],
   "datasets": ["sphere"], "grid": {"N": [500, 1000, 2000]}}]}
JSON
out=$dir/sweep
"$pcrt" cluster submit "$dir/c.json" --out "$out" --shards 2 --dry-run >/dev/null
echo '{"submissions": [{"array_job": "100", "shards": [0, 1], "merge_job": "101"}]}' >"$out/slurm/jobs.json"
# Slurm's part, done by hand: the array's two tasks, then the merge job.
run_shard() { SLURM_ARRAY_TASK_ID=$1 SLURM_ARRAY_JOB_ID=100 bash "$out/slurm/shard.sbatch" >"$dir/shard.log" 2>&1; }
run_shard 0 && run_shard 1 || fail "a shard failed: $(cat "$dir/shard.log")"
SLURM_JOB_ID=101 bash "$out/slurm/merge.sbatch" >"$dir/merge.log" 2>&1 || fail "merge: $(cat "$dir/merge.log")"
"$pcrt" cluster status "$out" >"$dir/status" || fail "status of a finished sweep: $(cat "$dir/status")"
cp "$out/slurm/plan.json" "$dir/plan.good"
cp "$out/slurm/jobs.json" "$dir/jobs.good"

# corrupt FILE PYTHON: FILE (plan or jobs) rewritten by a Python statement on its text t or its
# JSON j; then status and submit --resume must each fail in one line naming the file.
cases=0
corrupt() {
  local file=$1 edit=$2 path="$out/slurm/$1.json"
  /usr/bin/python3 - "$dir/$file.good" "$path" "$edit" <<'PY'
import json, sys
good, path, edit = sys.argv[1:]
t = open(good).read()
j = json.loads(t)
r = j["shards"][0]["runs"][0] if "shards" in j and isinstance(j["shards"], list) else None
s = j["submissions"][0] if "submissions" in j else None
exec(edit)
if isinstance(t, str) and t != open(good).read():
    open(path, "w").write(t)
else:
    open(path, "w").write(json.dumps(j))
PY
  for cmd in "cluster status $out" "cluster submit --resume $out --dry-run"; do
    set +e
    # shellcheck disable=SC2086
    "$pcrt" $cmd >/dev/null 2>"$dir/err"
    local rc=$?
    set -e
    [ $rc = 1 ] || fail "$file.json [$edit]: $cmd: exit $rc, not 1: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "$file.json [$edit]: $cmd: not one line: $(cat "$dir/err")"
    grep -qF "$path" "$dir/err" || fail "$file.json [$edit]: $cmd: does not name $path: $(cat "$dir/err")"
    grep -q "internal error" "$dir/err" && fail "$file.json [$edit]: $cmd: $(cat "$dir/err")"
  done
  echo "ok: $file.json [$edit]: $(cat "$dir/err")"
  cases=$((cases + 1))
  cp "$dir/$file.good" "$path"
}
for edit in \
  't = t[: len(t) // 2]' 't = ""' 't = "[" * 100000' 'j = []' 'j = {}' 'j = {"shards": 3}' \
  'j["shards"] = []' 'j["shards"] = [1e30]' 'j["shards"] = [j["shards"]]' 'j["shards"][0] = {}' \
  'j["shards"][0]["runs"] = {}' 'j["shards"][0]["estimated_s"] = -1' \
  'j["shards"][0]["estimated_s"] = "soon"' 'j["shards"][0]["runs"][0] = "run"' \
  'r["reps"] = -5' 'r["reps"] = 1e30' 'r["threads"] = 2.5' 'r["seed"] = -1' 'r["seed"] = 1e30' \
  'r["N"] = 1e30' 'r["N"] = -3' 'del r["kind"]' 'r["kind"] = 7' 'r["set"] = {"K": "x"}' \
  'r["method"] = ["x"]' 'j["shards"][1]["runs"].append(r)' 'j["cost_source"] = 5' \
  'j["shards"] = [{"runs": []}] * 100001'; do
  corrupt plan "$edit"
done
for edit in \
  't = t[: len(t) // 2]' 't = ""' 'j = []' 'j = {}' 'j = {"submissions": {}}' \
  'j["submissions"] = [j["submissions"]]' 'j["submissions"] = [5]' 's["shards"] = [1e30]' \
  's["shards"] = [-1]' 's["shards"] = [2]' 's["shards"] = ["0"]' 's["shards"] = [0.5]' \
  's["shards"] = 3' 'del s["shards"]' 's["array_job"] = 100' 's["array_job"] = "abc"' \
  's["array_job"] = "99999999999"' 'del s["array_job"]' 's["merge_job"] = None' \
  's["merge_job"] = "101;rm -rf /"' 's["array_job"] = ""' 'del s["merge_job"]' \
  's["shards"] = [[0]]'; do
  corrupt jobs "$edit"
done
echo "$cases corruptions of plan.json and jobs.json: one line naming the file, exit 1"

# A run whose child a signal ended (the OOM killer, a node's cleanup) is not done: its shard is
# unfinished, --resume resubmits that shard, and the shard's sweep --resume redoes the run.
/usr/bin/python3 - "$out/shards/1/runs.jsonl" <<'PY'
import json, sys
path = sys.argv[1]
lines = open(path).read().splitlines()
r = json.loads(lines[0])
killed = {k: v for k, v in r.items() if k not in ("counters", "prepare_counters", "extra") and not k.startswith("time")}
killed.update(status="failed", error="killed by signal 9", signal=9)
lines[0] = json.dumps(killed)
open(path, "w").write("\n".join(lines) + "\n")
PY
planned=$(wc -l <"$out/shards/1/runs.jsonl")
set +e
"$pcrt" cluster status "$out" >"$dir/status"
rc=$?
set -e
[ $rc = 1 ] || fail "status with a killed run exited $rc: $(cat "$dir/status")"
grep -q "^shard 1: .* $((planned - 1)) of $planned .*log " "$dir/status" || fail "shard 1 not unfinished: $(cat "$dir/status")"
# A merge job written before merges refused an earlier merge's runs: --resume adds --overwrite.
sed -i 's/ --overwrite$//' "$out/slurm/merge.sbatch"
"$pcrt" cluster submit --resume "$out" --dry-run >"$dir/resume"
grep -q "^would run: sbatch --parsable --array=1 " "$dir/resume" || fail "--resume: $(cat "$dir/resume")"
grep -q " merge .* --out .* --overwrite$" "$out/slurm/merge.sbatch" || fail "--resume left the merge line: $(grep ' merge ' "$out/slurm/merge.sbatch")"
run_shard 1 || fail "the resubmitted shard failed: $(cat "$dir/shard.log")"
grep -q "1 runs done ($((planned - 1)) already done" "$dir/shard.log" || fail "the killed run was not redone: $(cat "$dir/shard.log")"
test "$(wc -l <"$out/shards/1/runs.jsonl")" = "$planned" || fail "the redone run is recorded twice"
SLURM_JOB_ID=102 bash "$out/slurm/merge.sbatch" >"$dir/merge.log" 2>&1 || fail "merge: $(cat "$dir/merge.log")"
"$pcrt" cluster status "$out" >"$dir/status" || fail "status after the redo: $(cat "$dir/status")"
echo "cluster_files: a killed run is unfinished, resubmitted and redone: ok"
