#!/usr/bin/env python3
"""results/anchor/shadow16: the anchor of a33ee04 (before/: each shadow ray traced alone) and of
0fa5752 (after/: a frame's shadow rays sixteen at a time, the bvh walking them together), three
rounds alternated by scripts/anchor_binaries.sh. Prints, per data set and ray kind, the best
candidate's ratio against Embree's packets of 16 (reference 3) and against Embree's single rays
in Morton order (reference 0), the median over the rounds (range), before -> after; then the
papers' octree cells (the three blend methods on the octree) against single rays, lowest and
highest median. Each file must name a clean build, the two sides one build each. Usage:
table.py [DIR]. A file it cannot read, or a run missing on one side, is refused in one line."""
import glob
import json
import os
import statistics
import sys

KINDS = ("primary", "bounce", "shadow")
PAPERS = ("goradia_2010", "kashyap_2010_splat", "linsen_2007")


def load(path):
    try:
        j = json.load(open(path))
        c = j["context"]
        if not isinstance(c["build_commit"], str) or c["build_dirty"] is not False:
            raise ValueError("no clean build named")
        if "packets of 16" not in j["references"][3]:
            raise ValueError("reference 3 is not Embree's packets of 16")
        cells = {(d["method"], d["structure"]): {k: [r["ratio"] for r in d[k]["references"]]
                                                 for k in KINDS} for d in j["candidates"]}
        return j["dataset"], c["build_commit"][:7], float(j["load_average"]["after"][0]), cells
    except (OSError, ValueError, KeyError, TypeError, IndexError) as e:
        sys.exit("table.py: %s: %s" % (path, e))


def side(d, name):
    runs = {}  # dataset -> list of cells per round
    builds, loads = set(), []
    for f in sorted(glob.glob(os.path.join(d, name, "*.json"))):
        ds, build, load_1m, cells = load(f)
        runs.setdefault(ds, []).append(cells)
        builds.add(build)
        loads.append(load_1m)
    if len(builds) != 1:
        sys.exit("table.py: %s/%s: not one build: %s" % (d, name, sorted(builds)))
    return runs, builds.pop(), loads


def med(values):
    return "%.2f (%.2f-%.2f)" % (statistics.median(values), min(values), max(values))


def best(rounds, kind, ref):
    """Per round the best candidate's ratio; the candidate best by the median."""
    per = {}
    for cells in rounds:
        for key, c in cells.items():
            per.setdefault(key, []).append(c[kind][ref])
    key = max(per, key=lambda k: statistics.median(per[k]))
    return per[key], key


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    (b, bb, bl), (a, ab, al) = side(d, "before"), side(d, "after")
    if set(b) != set(a) or any(len(b[k]) != len(a[k]) for k in b):
        sys.exit("table.py: %s: before and after hold different runs" % d)
    print("before: %s; after: %s; rounds per data set: %s; 1-minute load %.2f-%.2f" %
          (bb, ab, ", ".join("%s %d" % (k, len(b[k])) for k in sorted(b)), min(bl + al),
           max(bl + al)))
    for ref, label in ((3, "Embree's packets of 16"), (0, "Embree's single rays (Morton order)")):
        print("\nThe best candidate against %s, median of the rounds (range), before -> after:\n"
              % label)
        print("| data | ray kind | before | after |")
        print("|---|---|---|---|")
        for ds in sorted(b):
            for kind in KINDS:
                vb, kb = best(b[ds], kind, ref)
                va, ka = best(a[ds], kind, ref)
                print("| %s | %s | %s %s, %s | %s %s, %s |" %
                      (ds, kind, med(vb), kb[0], kb[1], med(va), ka[0], ka[1]))
    print("\nThe papers' octree (%s), lowest and highest of its 9 cells' medians against Embree's"
          " single rays, before -> after:\n" % ", ".join(PAPERS))
    print("| data | before | after |")
    print("|---|---|---|")
    for ds in sorted(b):
        row = []
        for rounds in (b[ds], a[ds]):
            cells = [statistics.median([r[(m, "octree")][k][0] for r in rounds])
                     for m in PAPERS for k in KINDS]
            row.append("%.2f / %.2f" % (min(cells), max(cells)))
        print("| %s | %s | %s |" % (ds, row[0], row[1]))


main()
