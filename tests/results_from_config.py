#!/usr/bin/env python3
"""Exit 1 unless RESULTS/runs.jsonl holds exactly the runs CONFIG plans, so that the committed
results are the committed config's (a config regenerated from the declarations that reorders
experiments or methods keeps them; one that adds, drops or changes a run does not).
Runs are compared by their spec, the key --resume and merges use, without the machine's paths.
Usage: results_from_config.py PCRT CONFIG RESULTS"""
import json, os, subprocess, sys, tempfile

pcrt, config, results = sys.argv[1:4]


def key(spec):
    spec = dict(spec)
    # Where this machine keeps the scan or the scene file is not the run's identity (run_key in
    # harness/run_spec.cpp drops the same two).
    spec.pop("dataset_path", None)
    spec.pop("scene_path", None)
    return json.dumps(spec, sort_keys=True)


scan = os.path.join(os.path.dirname(os.path.abspath(config)), "../data/cgal/points_3/building.ply")
if not os.path.exists(scan):  # the config's scan (scripts/fetch_data.sh): ctest reports skipped
    print(f"{scan}: not fetched; cannot expand {config}", file=sys.stderr)
    sys.exit(77)
with tempfile.TemporaryDirectory() as tmp:
    subprocess.run([pcrt, "cluster", "submit", config, "--out", tmp, "--shards", "1", "--dry-run"],
                   check=True, capture_output=True)
    plan = json.load(open(f"{tmp}/slurm/plan.json"))
planned = {key(spec) for shard in plan["shards"] for spec in shard["runs"]}
done = {key(json.loads(line)["spec"]) for line in open(f"{results}/runs.jsonl") if line.strip()}
missing, extra = planned - done, done - planned
for name, keys in (("planned but not in", missing), ("in but not planned by", extra)):
    for k in sorted(keys)[:5]:
        print(f"{results}/runs.jsonl: run {name} {config}: {k}", file=sys.stderr)
if missing or extra:
    sys.exit(f"{results}: {len(missing)} runs of {config} missing, {len(extra)} runs it does not plan")
print(f"{results}: the {len(done)} runs of {config}")
