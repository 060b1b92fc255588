#!/usr/bin/env bash
# The sweep harness end to end on a tiny config: outputs and their shapes, --resume, shards and
# merge, fits, the calibration in operation counts, the op-count gate catching a change, and
# config errors as one line naming the key.
set -euo pipefail
pcrt=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat >"$dir/tiny.json" <<'JSON'
{
  "name": "tiny",
  "threads": 2,
  "experiments": [
    {"name": "query", "kind": "render", "methods": ["reference_splat"], "structures": ["kd_tree", "grid"],
     "datasets": ["sphere"], "grid": {"N": [500, 1000, 2000, 4000, 8000], "M": [64], "B": [0]},
     "fits": [{"claim": "{structure}/query", "variable": "N", "metric": "ops_nodes_visited", "per": "ops_rays_cast", "free": ["K"]}]},
    {"name": "worst", "kind": "reconstruct", "reconstructions": ["delaunay"], "datasets": ["skew_lines"],
     "grid": {"N": [25, 50, 100, 200, 400, 800, 1600, 2500]},
     "fits": [{"claim": "delaunay/worst", "variable": "N", "metric": "ops_cells"}]}
  ]
}
JSON
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --fit >/dev/null

test "$(wc -l <"$dir/a/runs.jsonl")" -eq 18
# The resumed folder's context keeps the first sweep's (its commit and its 18 runs, one of them
# since torn and redone); the resumes that ran nothing, or only the redone run, add no entry.
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --resume | grep -q "0 runs done (18 already done"
/usr/bin/python3 -c 'import json, sys; e = json.load(open(sys.argv[1]))["earlier"]
assert [x["runs"] for x in e] == [18] and "config" not in e[0], e' "$dir/a/context.json" ||
  { echo "FAIL: --resume lost the earlier runs' context"; exit 1; }
head -1 "$dir/a/runs.csv" | python3 -c '
import sys
cols = sys.stdin.read().strip().split(",")
need = ["method", "structure", "dataset", "N", "M", "S", "B", "K", "k", "I", "ops_nodes_visited",
        "time_median_s", "time_min_s", "time_max_s"]
assert all(c in cols for c in need), [c for c in need if c not in cols]'
python3 - "$dir/a" <<'PY'
import json, sys
d = sys.argv[1]
ctx = json.load(open(d + "/context.json"))
assert {"machine", "compiler", "flags", "dependencies", "git_commit", "git_dirty", "build_commit",
        "build_dirty", "config"} <= set(ctx), ctx.keys()
# The binary's own revision, generated at build time (a commit, or "unknown" without git).
assert ctx["build_commit"] == "unknown" or len(ctx["build_commit"]) == 40, ctx["build_commit"]
assert ctx["build_dirty"] in (True, False, None), ctx["build_dirty"]
assert {"cpu", "cores", "memory", "governor"} <= set(ctx["machine"])
fits = json.load(open(d + "/fits.json"))
assert len(fits) == 3, len(fits)
for f in fits:
    assert {"claim", "method", "variable", "metric", "exponent", "ci_low", "ci_high", "best_model", "r2", "verdict",
            "reason", "faster_terms", "tolerance", "tightness", "about", "akaike_weights"} <= set(f), f
    assert f["verdict"] in ("holds", "exceeds", "inconclusive", "loop_check", "drifted", "not_judged"), f
    assert all({"model", "share", "low95", "high95", "low99"} <= set(t) for t in f["faster_terms"]), f
worst = [f for f in fits if f["claim"] == "delaunay/worst"][0]
assert worst["best_model"] == "x^2" and worst["verdict"] == "holds" and worst["hidden_at_most"] < 0.25, worst
PY
# A relative dataset file is the config's neighbour (or under its dataset_dir), wherever pcrt
# runs; the run's identity keeps the name as written, so a moved checkout resumes.
mkdir -p "$dir/cfg/scans" "$dir/elsewhere"
"$pcrt" convert sphere:n=3000 --out "$dir/cfg/scans/s.ply" >/dev/null
printf '%s' '{"name": "rel", "experiments": [{"name": "e", "kind": "build", "datasets": ["scans/s.ply"],
  "grid": {"N": [1000, 2000]}}]}' >"$dir/cfg/rel.json"
(cd "$dir/elsewhere" && "$pcrt" sweep ../cfg/rel.json --out rel >/dev/null)
grep -q '"dataset":"scans/s.ply"' "$dir/elsewhere/rel/runs.jsonl"
grep -q "\"dataset_dir\": \"$dir/cfg\"" "$dir/elsewhere/rel/context.json"
printf '%s' '{"name": "rel", "dataset_dir": "cfg", "experiments": [{"name": "e", "kind": "build",
  "datasets": ["scans/s.ply"], "grid": {"N": [1000, 2000]}}]}' >"$dir/rel2.json"
mv "$dir/elsewhere/rel" "$dir/rel_moved"
"$pcrt" sweep "$dir/rel2.json" --out "$dir/rel_moved" --resume | grep -q "0 runs done (2 already done"
"$pcrt" fit "$dir/rel_moved" >/dev/null
if (cd "$dir" && "$pcrt" sweep cfg/rel.json --out rel3 >/dev/null 2>&1); then :; else
  echo "FAIL: a config in cfg/ does not find its neighbour scans/s.ply"; exit 1
fi
printf '%s' '{"name": "rel", "experiments": [{"name": "e", "kind": "build", "datasets": ["cfg/scans/s.ply"],
  "grid": {"N": [1000]}}]}' >"$dir/cfg/wrong.json"
err=$(cd "$dir" && "$pcrt" sweep cfg/wrong.json --out rel4 2>&1 >/dev/null || true)
grep -q "cfg/cfg/scans/s.ply: no such file" <<<"$err" ||
  { echo "FAIL: a relative dataset resolved against the current folder: $err"; exit 1; }
# A results folder is fitted from its runs alone: without the scan it was made from.
mv "$dir/cfg/scans/s.ply" "$dir/s.ply.away"
"$pcrt" fit "$dir/rel_moved" >/dev/null || { echo "FAIL: fit needs the dataset files"; exit 1; }
mv "$dir/s.ply.away" "$dir/cfg/scans/s.ply"
# --resume skips what is done; a truncated last line (a killed sweep) is redone.
head -c -20 "$dir/a/runs.jsonl" >"$dir/t" && mv "$dir/t" "$dir/a/runs.jsonl"
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --resume | grep -q "1 runs done (17 already done"
test "$(wc -l <"$dir/a/runs.jsonl")" -eq 18
# The resumed folder's context keeps the first sweep's (its commit and its 18 runs, one of them
# since torn and redone); the resumes that ran nothing, or only the redone run, add no entry.
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --resume | grep -q "0 runs done (18 already done"
/usr/bin/python3 -c 'import json, sys; e = json.load(open(sys.argv[1]))["earlier"]
assert [x["runs"] for x in e] == [18] and "config" not in e[0], e' "$dir/a/context.json" ||
  { echo "FAIL: --resume lost the earlier runs' context"; exit 1; }
# Shards and merge give the same runs.
"$pcrt" sweep "$dir/tiny.json" --out "$dir/s0" --shard 0/2 >/dev/null
"$pcrt" sweep "$dir/tiny.json" --out "$dir/s1" --shard 1/2 >/dev/null
"$pcrt" merge "$dir/s0" "$dir/s1" --out "$dir/m" >/dev/null
test "$(wc -l <"$dir/m/runs.jsonl")" -eq 18
"$pcrt" fit "$dir/m" >/dev/null && test -s "$dir/m/fits.csv"
# Merged shards hold the same runs and counters as the whole sweep, whatever the shard count.
for i in 0 1 2; do "$pcrt" sweep "$dir/tiny.json" --out "$dir/t$i" --shard $i/3 >/dev/null; done
"$pcrt" merge "$dir/t0" "$dir/t1" "$dir/t2" --out "$dir/m3" >/dev/null
python3 - "$dir/a" "$dir/m" "$dir/m3" <<'PY'
import json, sys
def runs(d):
    return {json.dumps(r["spec"], sort_keys=True): (r["counters"], r.get("prepare_counters"))
            for r in map(json.loads, open(d + "/runs.jsonl"))}
a = runs(sys.argv[1])
for d in sys.argv[2:]:
    assert runs(d) == a, d
PY
# Shards of another build do not merge.
cp -r "$dir/s1" "$dir/s1_other"
python3 - "$dir/s1_other/context.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1])); c["git_commit"] = "0" * 40; json.dump(c, open(sys.argv[1], "w"))
PY
# The fitter on workloads of known complexity, in exact operation counts.
"$pcrt" calibrate --json >"$dir/cal.json" || true
python3 - "$dir/cal.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
ops = [x for x in c if x["metric"] == "operations"]
assert {x["workload"] for x in ops} == {"sort", "nth_element", "binary_search", "triple_loop", "hash_lookup"}
for x in ops:
    assert x["best_model"] == x["expected"], x
PY
# The gate: an unchanged sweep passes, a changed counter fails and is named.
"$pcrt" check --config "$dir/tiny.json" --baseline "$dir/base.json" --update >/dev/null
"$pcrt" check --config "$dir/tiny.json" --baseline "$dir/base.json" >/dev/null
sed -i '0,/"nodes_visited": [0-9]*/s//"nodes_visited": 1/' "$dir/base.json"
if "$pcrt" check --config "$dir/tiny.json" --baseline "$dir/base.json" >"$dir/check.out"; then
  echo "FAIL: check passed a changed counter"; exit 1
fi
grep -q "nodes_visited: 1 ->" "$dir/check.out"
# Config errors: one line naming the key, exit 1.
expect_error() {
  local want=$1; shift
  if "$pcrt" "$@" >/dev/null 2>"$dir/err"; then echo "FAIL: pcrt $* succeeded"; exit 1; fi
  test "$(wc -l <"$dir/err")" -eq 1 || { echo "FAIL: more than one line"; cat "$dir/err"; exit 1; }
  grep -qF -- "$want" "$dir/err" || { echo "FAIL: wanted '$want'"; cat "$dir/err"; exit 1; }
}
bad() { python3 -c "import json,sys; c=json.load(open('$dir/tiny.json')); exec(sys.argv[1]); json.dump(c, open('$dir/bad.json','w'))" "$1"; }
bad 'c["bogus"] = 1';                                   expect_error "unknown key 'bogus'" sweep "$dir/bad.json"
bad 'c["experiments"][0]["methods"] = ["nope"]';         expect_error "unknown method 'nope'" sweep "$dir/bad.json"
bad 'c["experiments"][0]["grid"]["N"] = [0, 10, 20]';     expect_error "N = 0 is impossible" sweep "$dir/bad.json"
bad 'c["experiments"][0]["set.radius_k"] = -3';          expect_error "radius_k=-3 is outside" sweep "$dir/bad.json"
bad 'c["experiments"][0]["datasets"] = ["'"$dir"'/tiny.json"]'; expect_error "tiny.json" sweep "$dir/bad.json"
bad 'c["experiments"][0]["datasets"] = ["sphere:n=5"]';  expect_error "experiments[0].datasets: 'sphere:n=5' sets n" sweep "$dir/bad.json"
bad 'c["experiments"][0]["datasets"] = ["sphere:seed=2,n=5"]'; expect_error "'sphere:seed=2,n=5' sets n" sweep "$dir/bad.json"
bad 'c["experiments"][1]["kind"] = "dance"';             expect_error "kind must be" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["variable"] = "Q"';  expect_error "variable 'Q'" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["claim"] = "{method}/frame"'; expect_error "unknown claim 'reference_splat/frame'" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["metric"] = "ops_rays_cast"'; expect_error "counts rays only" sweep "$dir/bad.json"
bad 'c["experiments"][1]["fits"][0]["claim"] = "gift_wrapping/worst"'; expect_error "is not tested: pcrt has no gift-wrapping" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["free"] = ["Q"]';    expect_error "'Q' is not one of K, k, I_run" sweep "$dir/bad.json"
bad 'c["experiments"][0]["repetitions"] = 1e20';         expect_error "experiments[0]: repetitions = 1e+20 is impossible" sweep "$dir/bad.json"
bad 'c["experiments"][0]["repetitions"] = 0.5';          expect_error "repetitions = 0.5 is impossible" sweep "$dir/bad.json"
bad 'c["repetitions"] = -3';                             expect_error "repetitions = -3 is impossible" sweep "$dir/bad.json"
bad 'c["experiments"][0]["replicates"] = 1.5';           expect_error "replicates = 1.5 is impossible" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["covariate"] = "k"'; expect_error "only K can be a covariate" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["metric"] = "ops_nodes_visted"'; expect_error "fits[0].metric: 'ops_nodes_visted' is not a counter" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["per"] = "rays"';    expect_error ".per: 'rays' is not a counter" sweep "$dir/bad.json"
bad 'c["experiments"][0]["fits"][0]["x"] = "Q"';         expect_error ".x: 'Q' is not one of" sweep "$dir/bad.json"
bad 'c["experiments"][0]["camera"] = "under"';           expect_error "camera must be" sweep "$dir/bad.json"
printf '{"experiments": [' >"$dir/trunc.json";            expect_error "not valid JSON" sweep "$dir/trunc.json"
expect_error "--shard 2/2" sweep "$dir/tiny.json" --shard 2/2
echo '{"runs": 3}' >"$dir/notbase.json"; expect_error "notbase.json: not a baseline" check --config "$dir/tiny.json" --baseline "$dir/notbase.json"
# A damaged baseline is an error, never a pass: its verdicts gone, or a counter not a count; and
# verdicts it lacks are differences.
damage() { python3 -c "import json,sys; b=json.load(open('$dir/base.json')); exec(sys.argv[1]); json.dump(b, open('$dir/damaged.json','w'))" "$1"; }
damage 'del b["verdicts"]'; expect_error "damaged.json: not a baseline" check --config "$dir/tiny.json" --baseline "$dir/damaged.json"
damage 'r = next(iter(b["runs"].values())); r[next(k for k in r if k != "status")] = "5"'
expect_error "not a count" check --config "$dir/tiny.json" --baseline "$dir/damaged.json"
damage 'b["verdicts"] = {}'
if "$pcrt" check --config "$dir/tiny.json" --baseline "$dir/damaged.json" >"$dir/check.out" ||
  ! grep -q "new verdict (not in the baseline)" "$dir/check.out"; then
  echo "FAIL: check passed a baseline without its verdicts"; exit 1
fi
mkdir -p "$dir/nosweep" && echo '{"x": 1}' >"$dir/nosweep/context.json"; expect_error "has no \"config\"" fit "$dir/nosweep"
expect_error "runs.jsonl: cannot open" merge "$dir/nosweep" --out "$dir/merged"
expect_error "only shards of one build merge" merge "$dir/s0" "$dir/s1_other" --out "$dir/merged"
bad 'c["name"] = "other"'; "$pcrt" sweep "$dir/bad.json" --out "$dir/o1" --shard 1/2 >/dev/null
expect_error "only shards of one sweep merge" merge "$dir/s0" "$dir/o1" --out "$dir/merged"
# A merge never writes over an earlier merge's runs, nor into one of its shards; --overwrite
# moves the earlier merge's files (and its fits) to previous.N.
expect_error "--out $dir/m holds an earlier merge's runs" merge "$dir/s0" "$dir/s1" --out "$dir/m"
expect_error "--out $dir/s0: is also the shard $dir/s0" merge "$dir/s0" "$dir/s1" --out "$dir/s0" --overwrite
"$pcrt" merge "$dir/s0" --out "$dir/m" --overwrite >/dev/null
test "$(wc -l <"$dir/m/runs.jsonl")" -lt 18 && test "$(wc -l <"$dir/m/previous.1/runs.jsonl")" -eq 18 &&
  test -s "$dir/m/previous.1/fits.csv" && test ! -e "$dir/m/fits.csv" ||
  { echo "FAIL: merge --overwrite did not move the earlier merge aside"; exit 1; }
# A cut or retyped fits.json, context.json or runs.csv: report's one line names the folder.
for cut in 'head -c 100 "$d/fits.json" >"$d/x" && mv "$d/x" "$d/fits.json"' \
  'echo "{\"not\": \"a list\"}" >"$d/fits.json"' 'sed -i "s/\"git_commit\": *\"[^\"]*\"/\"git_commit\": 5/" "$d/context.json"' \
  'rm "$d/runs.csv"'; do
  d="$dir/bad_report"; rm -rf "$d"; cp -r "$dir/m/previous.1" "$d"; eval "$cut"
  expect_error "report: report.py: $d: missing or malformed results" report "$d"
done
expect_error "--plan and --costs need --shard" sweep "$dir/tiny.json" --plan "$dir/a/context.json"
echo '{"shards": [{"runs": []}]}' >"$dir/plan.json"; expect_error "plans 1 shards, not 2" sweep "$dir/tiny.json" --shard 0/2 --plan "$dir/plan.json"
# pcrt cluster without Slurm: --dry-run writes the scripts and plan; submitting says plainly that
# sbatch is missing. (tests/cluster_slurm.sh runs it on a real cluster.)
mkdir "$dir/nopath"
PATH=$dir/nopath "$pcrt" cluster submit "$dir/tiny.json" --out "$dir/cl" --shards 2 --dry-run >/dev/null
test -x "$dir/cl/slurm/shard.sbatch" && test -x "$dir/cl/slurm/merge.sbatch"
grep -q -- "--kill-on-invalid-dep=yes" "$dir/cl/slurm/merge.sbatch"
python3 -c "import json,sys; p = json.load(open(sys.argv[1])); assert len(p['shards']) == 2 and sum(len(s['runs']) for s in p['shards']) == 18" "$dir/cl/slurm/plan.json"
if PATH=$dir/nopath "$pcrt" cluster submit "$dir/tiny.json" --out "$dir/cl2" --shards 2 2>"$dir/err"; then
  echo "FAIL: cluster submit without sbatch succeeded"; exit 1
fi
grep -q "sbatch was not found" "$dir/err" && test "$(wc -l <"$dir/err")" -eq 1
# A runs.jsonl without end (a link to /dev/zero) is read up to a bound (issue 14).
mkdir -p "$dir/zero" && ln -s /dev/zero "$dir/zero/runs.jsonl"
cp "$dir/a/context.json" "$dir/zero/"
expect_error "runs.jsonl: more than 268435456 bytes" fit "$dir/zero"
# Appended to by --resume, it is an output: a device is refused before anything is read.
expect_error "is a device, FIFO or socket" sweep "$dir/tiny.json" --out "$dir/zero" --resume
# A sweep's files never overwrite its config or a file of its names it did not write.
mkdir -p "$dir/own" && cp "$dir/tiny.json" "$dir/own/fits.json"
expect_error "is also the input CONFIG" sweep "$dir/own/fits.json" --out "$dir/own" --fit
cmp -s "$dir/own/fits.json" "$dir/tiny.json" || { echo "FAIL: the config was overwritten"; exit 1; }
mkdir -p "$dir/theirs" && echo precious >"$dir/theirs/runs.csv"
expect_error "holds the runs of an earlier sweep" sweep "$dir/tiny.json" --out "$dir/theirs"
grep -q precious "$dir/theirs/runs.csv" || { echo "FAIL: runs.csv was overwritten"; exit 1; }
# A results folder is owned: without --resume an earlier sweep's runs are refused, not emptied;
# --overwrite moves them to previous.N first; a folder another sweep holds (its flock) is refused.
cp "$dir/a/runs.jsonl" "$dir/a_runs.before"
expect_error "holds the runs of an earlier sweep" sweep "$dir/tiny.json" --out "$dir/a"
cmp -s "$dir/a/runs.jsonl" "$dir/a_runs.before" || { echo "FAIL: runs.jsonl changed"; exit 1; }
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --overwrite >/dev/null
cmp -s "$dir/a/previous.1/runs.jsonl" "$dir/a_runs.before"
test "$(wc -l <"$dir/a/runs.jsonl")" -eq 18
# The resumed folder's context keeps the first sweep's (its commit and its 18 runs, one of them
# since torn and redone); the resumes that ran nothing, or only the redone run, add no entry.
"$pcrt" sweep "$dir/tiny.json" --out "$dir/a" --resume | grep -q "0 runs done (18 already done"
/usr/bin/python3 -c 'import json, sys; e = json.load(open(sys.argv[1]))["earlier"]
assert [x["runs"] for x in e] == [18] and "config" not in e[0], e' "$dir/a/context.json" ||
  { echo "FAIL: --resume lost the earlier runs' context"; exit 1; }
expect_error "--resume" sweep "$dir/tiny.json" --out "$dir/a" --resume --overwrite
# --resume continues or extends the sweep that made the folder: a config that does not plan its
# runs is refused, as merge refuses another config's shards, and the folder is left as it was.
sed 's/"M": \[64\]/"M": [256]/' "$dir/tiny.json" >"$dir/tiny_m.json"
cp "$dir/a/runs.jsonl" "$dir/a_runs.before"
expect_error "--out $dir/a: holds a run tiny does not plan" sweep "$dir/tiny_m.json" --out "$dir/a" --resume
cmp -s "$dir/a/runs.jsonl" "$dir/a_runs.before" || { echo "FAIL: a refused --resume changed runs.jsonl"; exit 1; }
# An experiment added to the config is run into the folder, the runs done are kept.
cp -r "$dir/a" "$dir/ext"
python3 -c 'import json, sys; c = json.load(open(sys.argv[1])); e = dict(c["experiments"][0]); e["name"] = "added"; c["experiments"].append(e); json.dump(c, open(sys.argv[2], "w"))' "$dir/tiny.json" "$dir/tiny_ext.json"
"$pcrt" sweep "$dir/tiny_ext.json" --out "$dir/ext" --resume | grep -q "10 runs done (18 already done" ||
  { echo "FAIL: an extended config was not resumed"; exit 1; }
mkdir -p "$dir/held"
(flock -x 9; echo 4242 >&9; sleep 30) 9>"$dir/held/.lock" &
holder=$!
for _ in $(seq 200); do flock -n "$dir/held/.lock" true 2>/dev/null || break; sleep 0.02; done
expect_error "another sweep (pid 4242" sweep "$dir/tiny.json" --out "$dir/held" --resume
kill "$holder" 2>/dev/null || true
wait "$holder" 2>/dev/null || true
test ! -e "$dir/a/.lock"  # released and removed when the sweep ends
# A gate with no successful run compares nothing: refused, not "0 differences".
printf '{"experiments": [{"kind": "render", "methods": ["reference_splat"], "datasets": ["sphere"], "grid": {"N": [100], "M": [16], "B": [1]}}]}' >"$dir/one.json"
"$pcrt" check --config "$dir/one.json" --baseline "$dir/one_base.json" --update >/dev/null
sed 's/^{/{"time_limit_s": 1e-300, /' "$dir/one.json" >"$dir/none_ok.json"
expect_error "every one of its 1 runs failed or timed out" check --config "$dir/none_ok.json" --baseline "$dir/one_base.json"
echo "sweep harness ok"
