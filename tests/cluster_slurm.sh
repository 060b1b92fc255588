#!/usr/bin/env bash
# pcrt cluster on a real one-node Slurm cluster (tests/slurm_cluster.sh brings it up from
# Debian's slurm-wlm and munge, without systemd, and tears it down by PID on exit).
#   1. Without Slurm's commands, submit and status say plainly that sbatch/squeue were not found.
#   2. CONFIG in 4 shards with shard 2 made to fail: shard 2 is named FAILED with its log, the
#      merge is cancelled by its dependency, status exits 1.
#   3. --resume resubmits shard 2 alone; it resumes from the runs it finds (a cut line redone);
#      status exits 0.
#   4. The merged runs equal a single-process sweep's as sets, every ops_* column identical.
#   5. A requeued shard (what preemption does) resumes instead of redoing its runs; its DIR has
#      quotes, a space, $(touch X), # and % in it, which sbatch and bash must take whole.
# Usage: cluster_slurm.sh PCRT CONFIG. Exit 77 (skipped) without slurm-wlm/munge or as non-root.
set -euo pipefail
pcrt=$(realpath "$1")
config=$(realpath "$2")
here=$(cd "$(dirname "$0")" && pwd)
for tool in munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool not installed (scripts/setup.sh installs slurm-wlm and munge)"; exit 77; }
done
[ "$(id -u)" = 0 ] || { echo "SKIP: the test cluster's slurmd must run as root"; exit 77; }

source "$here/slurm_cluster.sh"
work=$(mktemp -d "${TMPDIR:-/tmp}/pcrt_cluster_test.XXXXXX")
chmod 0711 "$work"  # the cluster's munge socket lies below: every parent needs o+x
finish() {
  local rc=$?
  cluster_down
  if [ $rc != 0 ]; then
    echo "FAIL (exit $rc); logs:"
    for f in "$work"/sweep/slurm/logs/*.log "$work"/cluster/slurmctld.log; do
      [ -f "$f" ] && { echo "== $f"; tail -n 15 "$f"; }
    done
  fi
  rm -rf "$work"
  exit $rc
}
trap finish EXIT
trap 'exit 143' TERM INT  # so that a killed test still tears its cluster down
fail() { echo "FAIL: $*"; exit 1; }
start=$(date +%s)

# 1. No Slurm on PATH: one plain line, exit 1.
mkdir "$work/empty_path"
if PATH=$work/empty_path "$pcrt" cluster submit "$config" --out "$work/x" --shards 2 2>"$work/err"; then
  fail "submit succeeded without sbatch"
fi
grep -q "sbatch was not found" "$work/err" || fail "submit without sbatch said: $(cat "$work/err")"
if PATH=$work/empty_path "$pcrt" cluster status "$work/x" 2>"$work/err"; then fail "status succeeded without squeue"; fi
grep -q "squeue was not found" "$work/err" || fail "status without squeue said: $(cat "$work/err")"

"$pcrt" sweep "$config" --out "$work/single" >/dev/null
cluster_up "$work/cluster"
echo "cluster up after $(($(date +%s) - start)) s"

# Polls status until nothing is queued or running (exit 2); leaves its output in $work/status.
wait_for_sweep() {
  local rc
  for _ in $(seq 600); do
    rc=0
    "$pcrt" cluster status "$work/sweep" >"$work/status" || rc=$?
    [ $rc != 2 ] && return $rc
    sleep 0.5
  done
  cat "$work/status"
  fail "the sweep did not finish in 300 s"
}

# 2. Shard 2 cannot create its output directory (a file is in the way): it fails, the merge is
# cancelled instead of pending forever, and status names the shard and its log.
mkdir -p "$work/sweep/shards"
echo "in the way" >"$work/sweep/shards/2"
"$pcrt" cluster submit "$config" --out "$work/sweep" --shards 4 --cpus-per-task 1 --time 0:10:00 \
  >"$work/submit.out"
grep -q "shards 0-3: job array [0-9]" "$work/submit.out" || fail "submit printed: $(cat "$work/submit.out")"
grep -q "merge, fit, report: job [0-9]* (afterok:" "$work/submit.out" || fail "no merge job id"
rc=0; wait_for_sweep || rc=$?
[ $rc = 1 ] || { cat "$work/status"; fail "status exited $rc with shard 2 failed, not 1"; }
grep -q "^shard 2: *FAILED .*log $work/sweep/slurm/logs/shard-2.log" "$work/status" || { cat "$work/status"; fail "shard 2 not named as failed with its log"; }
grep -q "^merge: *CANCELLED .*DependencyNeverSatisfied" "$work/status" || { cat "$work/status"; fail "the merge was not cancelled"; }
for i in 0 1 3; do grep -q "^shard $i: *COMPLETED" "$work/status" || fail "shard $i did not complete"; done
grep -q "failed: shard 2, merge" "$work/status" || fail "the summary does not name shard 2"

# 3. Fixed, shard 2 resumes: give it three of its runs (from the single sweep) and a cut line,
# as a preempted task would leave them, then resubmit only what is unfinished.
rm "$work/sweep/shards/2"
mkdir -p "$work/sweep/shards/2"
/usr/bin/python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
plan = json.load(open(w + "/sweep/slurm/plan.json"))
mine = {json.dumps(s, sort_keys=True) for s in plan["shards"][2]["runs"]}
done = [l for l in open(w + "/single/runs.jsonl") if json.dumps(json.loads(l)["spec"], sort_keys=True) in mine][:4]
with open(w + "/sweep/shards/2/runs.jsonl", "w") as f:
    f.writelines(done[:3])
    f.write(done[3][: len(done[3]) // 2])  # cut short by the kill: redone
PY
"$pcrt" cluster submit --resume "$work/sweep" >"$work/resume.out"
grep -q "^shards 2: job array" "$work/resume.out" || fail "--resume submitted: $(cat "$work/resume.out")"
rc=0; wait_for_sweep || rc=$?
[ $rc = 0 ] || { cat "$work/status"; fail "status exited $rc after the resume"; }
grep -q "(3 already done" "$work/sweep/slurm/logs/shard-2.log" || fail "shard 2 did not resume"
"$pcrt" cluster submit --resume "$work/sweep" | grep -q "nothing to resubmit" || fail "a finished sweep was resubmitted"
test -s "$work/sweep/report.md" && test -s "$work/sweep/fits.json" || fail "no report or fits"

# 4. The same runs and operation counts as one process.
/usr/bin/python3 - "$work/single" "$work/sweep" <<'PY'
import csv, json, sys
def runs(d):
    out = {}
    for line in open(d + "/runs.jsonl"):
        r = json.loads(line)
        out[json.dumps(r["spec"], sort_keys=True)] = r
    return out
def ops_rows(d):
    rows = list(csv.DictReader(open(d + "/runs.csv")))
    keep = lambda c: not c.startswith("time_") and c not in ("build_s", "prepare_s", "memory_bytes", "structure_bytes")
    return sorted(tuple(sorted((k, v) for k, v in r.items() if keep(k))) for r in rows)
a, b = runs(sys.argv[1]), runs(sys.argv[2])
assert set(a) == set(b), f"{len(set(a) - set(b))} runs only single, {len(set(b) - set(a))} only merged"
for k in a:
    for part in ("status", "counters", "prepare_counters"):
        assert a[k].get(part) == b[k].get(part), (k, part, a[k].get(part), b[k].get(part))
ra, rb = ops_rows(sys.argv[1]), ops_rows(sys.argv[2])
assert ra == rb, "runs.csv rows differ outside the times"
print(f"merged = single: {len(a)} runs, identical counters and ops_* columns")
PY

# 5. A requeued task (as on preemption) resumes: requeue the only shard of a slower sweep once it
# has recorded two runs; its second start skips them. Its DIR holds a space, quotes, $(touch X),
# a # and a %: real sbatch must read the quoted #SBATCH lines whole (the log lands in DIR) and no
# injected command may run (issue 29).
cat >"$work/slow.json" <<'JSON'
{"name": "slow", "threads": 1, "experiments": [{"name": "worst", "kind": "reconstruct",
 "reconstructions": ["delaunay"], "datasets": ["skew_lines"],
 "grid": {"N": [3000, 3001, 3002, 3003, 3004, 3005, 3006, 3007]}}]}
JSON
slow="$work/slow 'q' \$(touch X) #%p"
"$pcrt" cluster submit "$work/slow.json" --out "$slow" --shards 1 --cpus-per-task 1 >"$work/submit.out"
array=$(sed -n 's/^shards 0: job array \([0-9]*\)$/\1/p' "$work/submit.out")
for _ in $(seq 600); do
  [ "$(cat "$slow/shards/0/runs.jsonl" 2>/dev/null | wc -l)" -ge 2 ] && break
  sleep 0.1
done
scontrol requeue "${array}_0"
# Slurm holds a requeued job back (BeginTime) for a while; release it at once.
sleep 1
scontrol update JobId="${array}_0" StartTime=now
rc=0; for _ in $(seq 600); do
  rc=0; "$pcrt" cluster status "$slow" >"$work/status" || rc=$?
  [ $rc != 2 ] && break
  sleep 0.5
done
[ $rc = 0 ] || { cat "$work/status"; fail "the requeued sweep did not finish (status $rc)"; }
grep -q "DUE TO JOB REQUEUE" "$slow/slurm/logs/shard-0.log" || fail "the shard was not requeued"
grep -q "([1-9][0-9]* already done" "$slow/slurm/logs/shard-0.log" || { cat "$slow/slurm/logs/shard-0.log"; fail "the requeued shard redid its runs"; }
test "$(wc -l <"$slow/runs.jsonl")" -eq 8 || fail "the requeued sweep lost or doubled runs"
[ -z "$(find "$work" -name X)" ] && [ ! -e X ] || fail "a command injected through --out ran"

cluster_down
while read -r pid name; do kill -0 "$pid" 2>/dev/null && fail "$name ($pid) still running"; done <"$work/cluster/pids.down"
echo "cluster test ok in $(($(date +%s) - start)) s"
