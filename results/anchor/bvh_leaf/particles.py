#!/usr/bin/env python3
"""Table of particles.sh's runs: per method and leaf size, the median render time over the
rounds, its range, the ratio of the median to leaf_size=8's, and the work per primary ray
(exact: the same in every round)."""
import glob
import json
import os
import re
import statistics
import sys

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "particles")
try:
    ctx = json.load(open(os.path.join(here, "context.json")))
    commit = ctx["build_commit"][:7] + (" (uncommitted changes)" if ctx["build_dirty"] else "")
except (OSError, ValueError, KeyError) as e:
    sys.exit("particles.py: no binary context in %s: %r" % (here, e))
runs = {}
for path in sorted(glob.glob(os.path.join(here, "*_leaf_size=*.json"))):
    m = re.match(r"(\w+)_leaf_size=(\d+)_(\d+)\.json$", os.path.basename(path))
    if not m:
        sys.exit("particles.py: %s is not METHOD_leaf_size=S_R.json" % path)
    try:
        d = json.load(open(path))
        runs.setdefault((m.group(1), int(m.group(2))), []).append(
            (d["timings"]["render"], d["counters"], commit))
    except (OSError, ValueError, KeyError) as e:
        sys.exit("particles.py: cannot read %s: %r" % (path, e))
if not runs:
    sys.exit("particles.py: no runs in %s" % here)
print("| method | leaf_size | commit | runs | render s, median (range) | / leaf_size=8 | "
      "leaves per ray | items per ray |")
print("|---|---|---|---|---|---|---|---|")
for (method, size), rs in sorted(runs.items()):
    base = runs.get((method, 8))
    if base is None:
        sys.exit("particles.py: %s has no leaf_size=8 runs to compare with" % method)
    t = [r[0] for r in rs]
    c = rs[0][1]
    rays = c.get("rays_cast", 0)
    if not rays:
        sys.exit("particles.py: %s leaf_size=%d: no rays_cast counter" % (method, size))
    print("| %s | %s | %s | %d | %.4f (%.4f-%.4f) | %.2f | %.2f | %.1f |" % (
        method, size if size else "0 (auto)", rs[0][2], len(t), statistics.median(t), min(t),
        max(t), statistics.median(t) / statistics.median([r[0] for r in base]),
        c.get("leaves_visited", 0) / rays, c.get("items_visited", 0) / rays))
