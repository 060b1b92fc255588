#!/usr/bin/env bash
# Issue 29, finding 9: pcrt merge took a truncated or empty shard (15 of 18 runs, exit 0, no
# word), and fit took any number as a counter (-5000 wrapped to 1.8e19). Now a shard whose
# runs.jsonl does not match its plan (runs missing, runs not in the plan, a run twice, a torn
# last line) is refused in one line naming the file, exit 1, no output touched; --keep-partial
# merges what is whole and lists what is missing. A counter that is not a non-negative integer
# within uint64 is one line naming the file, the line and the counter.
set -euo pipefail
pcrt=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
# Exit 1, exactly one stderr line, holding every further argument.
expect_error() {
  local args=$1; shift
  set +e
  # shellcheck disable=SC2086
  "$pcrt" $args >"$dir/out" 2>"$dir/err"
  local rc=$?
  set -e
  [ $rc = 1 ] || fail "pcrt $args: exit $rc, not 1: $(cat "$dir/err")"
  [ "$(wc -l <"$dir/err")" = 1 ] || fail "pcrt $args: not one line: $(cat "$dir/err")"
  for want in "$@"; do
    grep -qF -- "$want" "$dir/err" || fail "pcrt $args: '$want' not in: $(cat "$dir/err")"
  done
  echo "ok: refused: $(cat "$dir/err")"
}
cat >"$dir/c.json" <<'JSON'
{"name": "m", "threads": 1, "experiments": [
  {"name": "b", "kind": "build", "methods": ["reference_splat"], "structures": ["kd_tree", "grid"],
   "datasets": ["sphere"], "grid": {"N": [500, 1000, 2000]}}]}
JSON
for i in 0 1; do "$pcrt" sweep "$dir/c.json" --out "$dir/s$i" --shard $i/2 >/dev/null; done
"$pcrt" merge "$dir/s0" "$dir/s1" --out "$dir/whole" >/dev/null
test "$(wc -l <"$dir/whole/runs.jsonl")" = 6 || fail "the whole merge has not 6 runs"
n1=$(wc -l <"$dir/s1/runs.jsonl")
[ "$n1" -ge 2 ] || fail "shard 1 has $n1 runs; the cases below need 2"
cp "$dir/whole/runs.jsonl" "$dir/whole_before.jsonl"

# Each case: a copy of shard 1 damaged one way, merged onto an existing output.
damaged() {
  rm -rf "$dir/d1" && cp -r "$dir/s1" "$dir/d1"
  /usr/bin/python3 - "$dir/d1/runs.jsonl" "$dir/s0/runs.jsonl" "$1" <<'PY'
import sys
path, other, how = sys.argv[1:]
text = open(path).read()
lines = text.splitlines(keepends=True)
if how == "truncated": text = "".join(lines[:-1])
elif how == "empty": text = ""
elif how == "torn": text = text[:-20]
elif how == "no_newline": text = text[:-1]
elif how == "duplicate": text = text + lines[0]
elif how == "unplanned": text = text + open(other).readline()
open(path, "w").write(text)
PY
}
for how in truncated empty torn no_newline duplicate unplanned; do
  damaged $how
  expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "$dir/d1/runs.jsonl" "--keep-partial"
  cmp -s "$dir/whole/runs.jsonl" "$dir/whole_before.jsonl" || fail "$how: the output changed"
done
damaged truncated
expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "1 of its $n1 planned runs missing"
damaged empty
expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "$n1 of its $n1 planned runs missing"
damaged torn
expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "last line torn"
damaged unplanned
expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "1 run not in its plan"
damaged duplicate
expect_error "merge $dir/s0 $dir/d1 --out $dir/whole" "1 run recorded twice"
# The same shard twice holds every run twice.
expect_error "merge $dir/s0 $dir/s1 $dir/s1 --out $dir/whole" "$dir/s1/runs.jsonl" "earlier directory"
# A whole sweep (no shard record) is planned as its whole config.
"$pcrt" merge "$dir/whole" --out "$dir/again" >/dev/null
head -n 5 "$dir/whole/runs.jsonl" >"$dir/five" && mkdir -p "$dir/cut" &&
  cp "$dir/whole/context.json" "$dir/cut/" && mv "$dir/five" "$dir/cut/runs.jsonl"
expect_error "merge $dir/cut --out $dir/again" "$dir/cut/runs.jsonl" "1 of its 6 planned runs missing"

# --keep-partial: what is whole is merged, and what is missing is listed.
damaged torn
"$pcrt" merge "$dir/s0" "$dir/d1" --out "$dir/partial" --keep-partial >"$dir/out"
grep -q "$dir/d1/runs.jsonl: kept $((n1 - 1)) of $n1 planned runs; 1 of its $n1 planned runs missing, its last line torn" "$dir/out" ||
  fail "--keep-partial said: $(cat "$dir/out")"
test "$(grep -c '^  missing: {' "$dir/out")" = 1 || fail "the missing run is not listed: $(cat "$dir/out")"
test "$(wc -l <"$dir/partial/runs.jsonl")" = 5 || fail "--keep-partial did not keep the 5 whole runs"
grep -q "5 runs from 2 directories" "$dir/out" || fail "no summary: $(cat "$dir/out")"
damaged duplicate
"$pcrt" merge "$dir/s0" "$dir/d1" --out "$dir/partial2" --keep-partial >/dev/null
test "$(wc -l <"$dir/partial2/runs.jsonl")" = 6 || fail "--keep-partial kept a duplicate"

# Counters: a non-negative JSON integer within uint64, else one line naming file, line, counter.
counter() {
  rm -rf "$dir/f" && cp -r "$dir/whole" "$dir/f"
  /usr/bin/python3 - "$dir/f/runs.jsonl" "$1" <<'PY'
import json, sys
path, value = sys.argv[1:]
lines = open(path).read().splitlines()
r = json.loads(lines[1])
r["prepare_counters"]["knn_queries"] = "@VALUE@"
lines[1] = json.dumps(r).replace('"@VALUE@"', value)
open(path, "w").write("\n".join(lines) + "\n")
PY
}
"$pcrt" fit "$dir/whole" >/dev/null || fail "fit refused a good sweep"
for value in -5000 -1 1e308 5.5 1e19 18446744073709551616 '"12"' null; do
  counter "$value"
  expect_error "fit $dir/f" "$dir/f/runs.jsonl: line 2" "knn_queries"
done
counter 18446744073709551615
"$pcrt" fit "$dir/f" >/dev/null || fail "fit refused the largest uint64 counter"
counter -5000
expect_error "merge $dir/f --out $dir/fm" "$dir/f/runs.jsonl: line 2" "knn_queries"
echo "merge_shards: damaged shards refused or kept partially, bad counters refused: ok"
