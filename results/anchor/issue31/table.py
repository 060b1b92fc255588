#!/usr/bin/env python3
"""Issue 31 before and after: the runs in before/ (the binary of c733a89, when the issue was
filed, whose anchor files record neither their build nor the load) and after/ (their context names
the build), alternated by scripts/anchor_binaries.sh. Prints, per data set, method and structure,
the median over the rounds of the ratio against Embree's single rays, before -> after, and the
after runs' range; then, per data set and ray kind, the best method against Embree's packets of 16
(after only: the before binary had no packet reference); then our triangle BVH against Embree's
triangles on the armadillo, mesh_c733_R.json (before) and mesh_a9_R.json (after), alternated
round by round. Usage: table.py [DIR] (default: this file's directory). A file it cannot read is
refused in one line naming it, with status 1."""
import glob
import json
import os
import statistics
import sys

KINDS = ("primary", "bounce", "shadow")
BEFORE = "c733a89"
PAPER = {}  # method -> its paper's structure, as the after runs report it


def runs(pattern):
    """{(dataset, method, structure): {kind: [ratio per reference index, per run]}} and the
    after runs' contexts and loads."""
    cells, contexts = {}, []
    paths = sorted(glob.glob(pattern))
    if not paths:
        sys.exit("table.py: no runs match %s" % pattern)
    for path in paths:
        try:
            with open(path) as f:
                j = json.load(f)
            for c in j["candidates"]:
                key = (j["dataset"], c["method"], c["structure"])
                for k in KINDS:
                    refs = [float(r["ratio"]) for r in c[k]["references"]]
                    cells.setdefault(key, {}).setdefault(k, []).append(refs)
            for c in j["candidates"]:  # the after runs name each blend's paper structure
                if "frame_vs_paper" in c:
                    PAPER[c["method"]] = c["frame_vs_paper"]["paper_structure"]
            contexts.append((j.get("context"), j.get("load_average")))
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
            sys.exit("table.py: %s is no `pcrt anchor` file: %r" % (path, e))
    return cells, contexts, len(paths)


def median_at(values, ref, where):
    r = [v[ref] for v in values if ref < len(v)]
    if len(r) != len(values):
        sys.exit("table.py: %s: a run without reference %d" % (where, ref))
    return statistics.median(r), min(r), max(r)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    before, _, nb = runs(os.path.join(d, "before", "*.json"))
    after, contexts, na = runs(os.path.join(d, "after", "*.json"))
    builds = {(c or {}).get("build_commit", "none")[:7] + ("" if (c or {}).get("build_dirty") is False
                                                          else " (dirty or unknown)")
              for c, _ in contexts}
    loads = [x for _, la in contexts if la for x in (la["before"][0], la["after"][0])]
    if len(builds) != 1 or not loads:
        sys.exit("table.py: the after runs name %s and %d loads" % (sorted(builds), len(loads)))
    after_build = builds.pop()
    print("before: %s, %d files; after: %s, %d files, 1-minute load %.2f-%.2f" % (
        BEFORE, nb, after_build, na, min(loads), max(loads)))
    print()
    print("Against Embree's single rays (Morton order), median of the rounds, before -> after "
          "(after's range):")
    print()
    print("| data | method | structure | primary | bounce | shadow |")
    print("|---|---|---|---|---|---|")
    for key in sorted(after):
        cells = []
        for k in KINDS:
            where = "%s %s %s %s" % (*key, k)
            m, lo, hi = median_at(after[key][k], 0, where)
            b = "%.2f" % median_at(before[key][k], 0, where)[0] if key in before else "-"
            cells.append("%s -> %.2f (%.2f-%.2f)" % (b, m, lo, hi))
        print("| %s | %s | %s | %s |" % (*key, " | ".join(cells)))
    print()
    print("The papers' structures (%s), the lowest and highest of their cells per data set against "
          "Embree's single rays, before -> after:" % ", ".join(
              "%s %s" % kv for kv in sorted(PAPER.items())))
    print()
    print("| data | cells | lowest | highest |")
    print("|---|---|---|---|")
    for data in sorted({key[0] for key in after}):
        keys = [key for key in after if key[0] == data and PAPER.get(key[1]) == key[2]]
        if not keys or any(key not in before for key in keys):
            sys.exit("table.py: %s: papers' structures missing from a side" % data)
        pairs = [(median_at(before[key][k], 0, "")[0], median_at(after[key][k], 0, "")[0])
                 for key in keys for k in KINDS]
        print("| %s | %d | %.2f -> %.2f | %.2f -> %.2f |" % (
            data, len(pairs), min(b for b, _ in pairs), min(a for _, a in pairs),
            max(b for b, _ in pairs), max(a for _, a in pairs)))
    print()
    print("The best candidate against Embree's packets of 16 (reference 3), after:")
    print()
    print("| data | primary | bounce | shadow |")
    print("|---|---|---|---|")
    for data in sorted({key[0] for key in after}):
        cells = []
        for k in KINDS:
            best = max((median_at(after[key][k], 3, "%s %s %s %s" % (*key, k)), key)
                       for key in after if key[0] == data)
            (m, lo, hi), key = best
            cells.append("%.2f (%.2f-%.2f) %s, %s" % (m, lo, hi, key[1], key[2]))
        print("| %s | %s |" % (data, " | ".join(cells)))
    mesh_table(d)


def mesh_table(d):
    print()
    print("Our triangle BVH against Embree's triangles (one thread), median of the rounds, before "
          "-> after (after's range):")
    print()
    print("| mesh | runs | primary | bounce | shadow |")
    print("|---|---|---|---|---|")
    ratios = {}
    for side in ("c733", "a9"):
        paths = sorted(glob.glob(os.path.join(d, "mesh_%s_*.json" % side)))
        if not paths:
            sys.exit("table.py: no mesh_%s_*.json in %s" % (side, d))
        for path in paths:
            try:
                with open(path) as f:
                    j = json.load(f)
                for k in KINDS:
                    ratios.setdefault((side, j["mesh"], k), []).append(
                        float(j[k]["references"][0]["ratio"]))
            except (OSError, ValueError, KeyError, TypeError, IndexError) as e:
                sys.exit("table.py: %s is no `pcrt anchor --mesh` file: %r" % (path, e))
    for mesh in sorted({m for _, m, _ in ratios}):
        cells, n = [], 0
        for k in KINDS:
            b, a = ratios.get(("c733", mesh, k)), ratios.get(("a9", mesh, k))
            if not b or not a:
                sys.exit("table.py: %s %s: runs of one binary only" % (mesh, k))
            n = len(a)
            cells.append("%.2f -> %.2f (%.2f-%.2f)" % (statistics.median(b), statistics.median(a),
                                                      min(a), max(a)))
        print("| %s | %d | %s |" % (mesh, n, " | ".join(cells)))


if __name__ == "__main__":
    main()
