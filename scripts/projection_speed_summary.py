#!/usr/bin/python3
"""Table of scripts/projection_speed.sh's runs: per data set, method and structure, the median
render time of each binary as frames per second, and the median of the pair-by-pair speed-ups
(before time / after time, pairs run back to back). Also checks that both binaries report the same
operation counts in every pair. Usage: scripts/projection_speed_summary.py OUT"""
import glob
import json
import os
import statistics
import sys

out = sys.argv[1]
runs = {}
for path in glob.glob(os.path.join(out, "*.json")):
    name, method, structure, side, pair = os.path.basename(path)[:-5].split(".")
    with open(path) as f:
        r = json.load(f)
    runs.setdefault((name, method, structure), {}).setdefault(int(pair), {})[side] = r

print("| data | method | structure | pairs | fps before | fps after | speed-up (median of pairs) | counters equal |")
print("|---|---|---|---|---|---|---|---|")
for (name, method, structure), pairs in sorted(runs.items()):
    full = [p for p in pairs.values() if "before" in p and "after" in p]
    tb = [p["before"]["timings"]["render"] for p in full]
    ta = [p["after"]["timings"]["render"] for p in full]
    ratio = [b / a for b, a in zip(tb, ta)]
    same = all(p["before"]["counters"] == p["after"]["counters"] for p in full)
    print(f"| {name} | {method} | {structure} | {len(full)} | {1 / statistics.median(tb):.2f} | "
          f"{1 / statistics.median(ta):.2f} | {statistics.median(ratio):.2f} "
          f"({min(ratio):.2f}-{max(ratio):.2f}) | {'yes' if same else 'NO'} |")
