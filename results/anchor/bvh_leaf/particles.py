#!/usr/bin/env python3
"""Table of particles.sh's runs: per method and leaf size, the median render time over the
rounds, its range, the ratio of the median to leaf_size=8's, and the leaves and items visited per
ray cast (primary, bounce and shadow rays; exact, so every round's counts must be the same).
Usage: particles.py [DIR] (default: particles/ beside this file)."""
import glob
import json
import os
import re
import statistics
import sys

BAD = (OSError, ValueError, KeyError, TypeError, AttributeError, ZeroDivisionError)


def fail(msg):
    sys.exit("particles.py: " + msg)


def context(here):
    path = os.path.join(here, "context.json")
    try:
        ctx = json.load(open(path))
        return ctx["build_commit"][:7] + (" (uncommitted changes)" if ctx["build_dirty"] else "")
    except BAD as e:
        fail("%s is no binary context: %r" % (path, e))


def run(path):
    """(render seconds, (leaves, items) per ray cast) of one --stats file."""
    try:
        d = json.load(open(path))
        c = d["counters"]
        rays = c["rays_cast"]
        return float(d["timings"]["render"]), (c["leaves_visited"] / rays, c["items_visited"] / rays)
    except BAD as e:
        fail("%s is no `pcrt render --stats` file with counters: %r" % (path, e))


def main():
    here = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "particles")
    commit = context(here)
    runs = {}
    for path in sorted(glob.glob(os.path.join(here, "*_leaf_size=*.json"))):
        m = re.match(r"(\w+)_leaf_size=(\d+)_(\d+)\.json$", os.path.basename(path))
        if not m:
            fail("%s is not METHOD_leaf_size=S_R.json" % path)
        runs.setdefault((m.group(1), int(m.group(2))), []).append((path, run(path)))
    if not runs:
        fail("no runs in %s" % here)
    print("| method | leaf_size | commit | runs | render s, median (range) | / leaf_size=8 | "
          "leaves per ray cast | items per ray cast |")
    print("|---|---|---|---|---|---|---|---|")
    for (method, size), rs in sorted(runs.items()):
        base = runs.get((method, 8))
        if base is None:
            fail("%s has no leaf_size=8 runs to compare with" % method)
        work = {w for _, (_, w) in rs}
        if len(work) != 1:
            fail("%s leaf_size=%d: the rounds' counts differ (%s)" % (
                method, size, ", ".join(p for p, _ in rs)))
        leaves, items = work.pop()
        t = [s for _, (s, _) in rs]
        print("| %s | %s | %s | %d | %.4f (%.4f-%.4f) | %.2f | %.2f | %.1f |" % (
            method, size if size else "0 (auto)", commit, len(t), statistics.median(t), min(t),
            max(t), statistics.median(t) / statistics.median([s for _, (s, _) in base]), leaves,
            items))


if __name__ == "__main__":
    main()
