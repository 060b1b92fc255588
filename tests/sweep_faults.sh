#!/usr/bin/env bash
# Faults a sweep must survive (issue 14): SIGKILL at several points (no run left behind; a resume
# redoes at most the run in flight and ends with the counters of an uninterrupted sweep), a run's
# child killed by SIGKILL (recorded, and redone by --resume: issue 29), and an
# output folder on a full or a read-only file system (one line naming the file, exit 1,
# runs.jsonl still readable and unchanged where nothing could be written).
set -euo pipefail
pcrt=$(realpath "$1")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
cat >"$dir/c.json" <<'JSON'
{"name": "faults", "threads": 1, "experiments": [
  {"name": "r", "kind": "render", "methods": ["reference_splat"], "structures": ["kd_tree", "grid"],
   "datasets": ["sphere"], "grid": {"N": [20000, 40000, 80000], "M": [4096], "B": [0, 1]}}]}
JSON
runs=12
"$pcrt" sweep "$dir/c.json" --out "$dir/ref" >/dev/null

# Every line of a runs.jsonl parses; prints how many.
complete_lines() {
  /usr/bin/python3 - "$1" <<'PY'
import json, sys
n = 0
for line in open(sys.argv[1]).read().split("\n"):
    if line:
        json.loads(line)
        n += 1
print(n)
PY
}
# Same runs with the same counters as the uninterrupted sweep.
same_as_ref() {
  /usr/bin/python3 - "$dir/ref" "$1" <<'PY'
import json, sys
def runs(d):
    out = {}
    for r in map(json.loads, open(d + "/runs.jsonl")):
        s = dict(r["spec"]); s.pop("dataset_path", None)
        out[json.dumps(s, sort_keys=True)] = (r["status"], r["counters"], r.get("prepare_counters"))
    return out
a, b = runs(sys.argv[1]), runs(sys.argv[2])
assert a == b, (len(a), len(b), [k for k in a if a[k] != b.get(k)][:2])
PY
}
# One stderr line, exit status 1, naming $2.
one_line_error() {
  local status=$1 err=$2 name=$3
  test "$status" -eq 1 || fail "exit status $status, not 1: $(cat "$err")"
  test "$(wc -l <"$err")" -eq 1 || fail "not one line: $(cat "$err")"
  grep -q -- "$name" "$err" || fail "does not name $name: $(cat "$err")"
}

# Kills while run 1, 4, 8 and 12 are in flight.
for before in 0 3 7 11; do
  out="$dir/kill$before"
  "$pcrt" sweep "$dir/c.json" --out "$out" >/dev/null 2>&1 &
  sweep=$!
  for _ in $(seq 600); do
    [ -f "$out/runs.jsonl" ] && [ "$(wc -l <"$out/runs.jsonl")" -ge "$before" ] && break
    sleep 0.02
  done
  sleep 0.05
  children=$(cat /proc/"$sweep"/task/*/children 2>/dev/null || true)
  kill -9 "$sweep"
  wait "$sweep" 2>/dev/null || true
  for child in $children; do
    for _ in $(seq 100); do kill -0 "$child" 2>/dev/null || break; sleep 0.05; done
    kill -0 "$child" 2>/dev/null && fail "run $child outlived its sweep killed after $before runs"
  done
  done_before=$(complete_lines "$out/runs.jsonl")
  [ "$done_before" -ge "$before" ] || fail "lost runs: $done_before after $before"
  "$pcrt" sweep "$dir/c.json" --out "$out" --resume >"$dir/resume.txt"
  grep -q "$((runs - done_before)) runs done ($done_before already done" "$dir/resume.txt" ||
    fail "resume after $before: $(cat "$dir/resume.txt")"
  same_as_ref "$out"
done

# A run whose child is killed by a signal (SIGKILL: the OOM killer, a node's cleanup) is recorded
# as failed and the sweep goes on; --resume does that run again instead of keeping it as done.
# The first run in flight after two are recorded is killed; the kill can come too late (the run
# ended in between), so up to three sweeps are tried.
kill_a_run() {
  rm -rf "$out"
  "$pcrt" sweep "$dir/c.json" --out "$out" >/dev/null 2>&1 &
  local sweep=$! child state
  for _ in $(seq 2000); do
    if [ -f "$out/runs.jsonl" ] && [ "$(wc -l <"$out/runs.jsonl")" -ge 2 ]; then
      child=$(cat /proc/"$sweep"/task/*/children 2>/dev/null | head -n 1 || true)
      state=$(awk '{print $3}' /proc/"$child"/stat 2>/dev/null || true)
      if [ -n "$child" ] && [ "$state" != Z ] && kill -9 "$child" 2>/dev/null; then break; fi
    fi
    sleep 0.01
  done
  wait "$sweep" || fail "the sweep failed after one of its runs was killed"
  grep -q '"error":"killed by signal 9"' "$out/runs.jsonl"
}
out="$dir/killed_child"
kill_a_run || kill_a_run || kill_a_run || fail "no run was caught in flight and killed"
"$pcrt" sweep "$dir/c.json" --out "$out" --resume >"$dir/resume.txt"
grep -q "1 runs done ($((runs - 1)) already done" "$dir/resume.txt" ||
  fail "resume after a killed run: $(cat "$dir/resume.txt")"
same_as_ref "$out"

# A file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored) cuts writes short like a full disk: the
# result that does not fit is not appended in part.
set +e
(
  ulimit -f 8
  trap '' XFSZ
  exec "$pcrt" sweep "$dir/c.json" --out "$dir/fsize"
) >/dev/null 2>"$dir/err"
status=$?
set -e
one_line_error "$status" "$dir/err" "$dir/fsize/"
n=$(complete_lines "$dir/fsize/runs.jsonl")
[ "$n" -lt "$runs" ] || fail "the size limit never bit"
"$pcrt" sweep "$dir/c.json" --out "$dir/fsize" --resume >/dev/null
same_as_ref "$dir/fsize"

# A full and a read-only file system, in a mount namespace of our own (needs root or user
# namespaces; said when skipped).
if ! unshare -m true 2>/dev/null; then
  echo "sweep_faults: full and read-only file systems skipped: no mount namespace here"
  exit 0
fi
mkdir -p "$dir/full" "$dir/ro"
cp -r "$dir/kill3" "$dir/ro/out"
head -n 5 "$dir/ref/runs.jsonl" >"$dir/ro/out/runs.jsonl"
cp "$dir/ro/out/runs.jsonl" "$dir/ro_before.jsonl"
export pcrt dir
set +e
unshare -m bash -c '
  mount -t tmpfs -o size=8k tmpfs "$dir/full" || exit 99
  "$pcrt" sweep "$dir/c.json" --out "$dir/full/out" >/dev/null 2>"$dir/err_full"
  echo $? >"$dir/status_full"
  cp -r "$dir/full/out" "$dir/full_copy"
  mount --bind "$dir/ro" "$dir/ro" && mount -o remount,ro,bind "$dir/ro" || exit 99
  "$pcrt" sweep "$dir/c.json" --out "$dir/ro/out" --resume >/dev/null 2>"$dir/err_ro"
  echo $? >"$dir/status_ro"
  "$pcrt" sweep "$dir/c.json" --out "$dir/ro/new" >/dev/null 2>"$dir/err_ro_new"
  echo $? >"$dir/status_ro_new"'
ns=$?
set -e
[ "$ns" -eq 0 ] || fail "mount namespace setup failed ($ns)"
one_line_error "$(cat "$dir/status_full")" "$dir/err_full" "$dir/full/out/"
n=$(complete_lines "$dir/full_copy/runs.jsonl")
[ "$n" -lt "$runs" ] || fail "the 8 KiB file system never filled"
"$pcrt" sweep "$dir/c.json" --out "$dir/full_copy" --resume >/dev/null
same_as_ref "$dir/full_copy"
one_line_error "$(cat "$dir/status_ro")" "$dir/err_ro" "$dir/ro/out/"
cmp -s "$dir/ro/out/runs.jsonl" "$dir/ro_before.jsonl" || fail "read-only runs.jsonl changed"
one_line_error "$(cat "$dir/status_ro_new")" "$dir/err_ro_new" "$dir/ro/new"
cat "$dir/err" "$dir/err_full" "$dir/err_ro" "$dir/err_ro_new"
echo "sweep_faults: 4 kill points, a killed run redone, a size limit, a full and a read-only file system: ok"
