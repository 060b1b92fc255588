#!/usr/bin/env python3
"""Issue 31 before and after: the runs in before/ (the binary of c733a89, when the issue was
filed, whose anchor files record neither their build nor the load) and after/ (their context names
the build), alternated by scripts/anchor_binaries.sh. Prints, per data set, method and structure,
the median over the rounds of the ratio against Embree's single rays, before -> after, and the
after runs' range; then, per data set and ray kind, the best method against Embree's packets of 16
(after only: the before binary had no packet reference); then our triangle BVH against Embree's
triangles on the armadillo, mesh_c733_R.json (before) and mesh_a9_R.json (after), alternated
round by round (the after files name a clean build, the before files none). Usage: table.py
[DIR] (default: this file's directory). A file it cannot read is refused in one line naming it,
and a run missing from one side or one cell missing from a run in one line, with status 1."""
import glob
import json
import os
import statistics
import sys

KINDS = ("primary", "bounce", "shadow")
BEFORE = "c733a89"
PAPER = {}  # method -> its paper's structure, as the after runs report it


def after_context(j):
    """The build and the 1-minute loads an after file records; KeyError/TypeError if absent."""
    c, la = j["context"], j["load_average"]
    if not isinstance(c["build_commit"], str) or c["build_dirty"] is not False:
        raise ValueError("no clean build named: %r" % c)
    names = j["references"]
    if names[0] != "embree_oriented_disc morton_order=1" or "packets of 16" not in names[3]:
        raise ValueError("references are not single rays (0) and packets of 16 (3): %r" % names)
    return c["build_commit"][:7], [float(la["before"][0]), float(la["after"][0])]


def runs(pattern, after):
    """{(dataset, method, structure): {kind: [ratios per reference index, one per run]}}, the
    number of files per data set, and for the after side the builds and loads named."""
    cells, files, builds, loads = {}, {}, set(), []
    paths = sorted(glob.glob(pattern))
    if not paths:
        sys.exit("table.py: no runs match %s" % pattern)
    for path in paths:
        try:
            with open(path) as f:
                j = json.load(f)
            if after:
                build, load = after_context(j)
                builds.add(build)
                loads += load
            files[j["dataset"]] = files.get(j["dataset"], 0) + 1
            for c in j["candidates"]:
                key = (j["dataset"], c["method"], c["structure"])
                for k in KINDS:
                    refs = [float(r["ratio"]) for r in c[k]["references"]]
                    cells.setdefault(key, {}).setdefault(k, []).append(refs)
                if "frame_vs_paper" in c:  # the after runs name each blend's paper structure
                    PAPER[c["method"]] = c["frame_vs_paper"]["paper_structure"]
        except (OSError, ValueError, KeyError, TypeError, AttributeError, IndexError) as e:
            sys.exit("table.py: %s is no `pcrt anchor` file of this directory: %r" % (path, e))
    for key, kinds in cells.items():  # every cell in every run of its data set
        if any(len(v) != files[key[0]] for v in kinds.values()) or len(kinds) != len(KINDS):
            sys.exit("table.py: %s: %s is missing from some of the %d runs" % (
                pattern, " ".join(key), files[key[0]]))
    return cells, files, builds, loads


def median_at(values, ref, where):
    r = [v[ref] for v in values if ref < len(v)]
    if len(r) != len(values):
        sys.exit("table.py: %s: a run without reference %d" % (where, ref))
    return statistics.median(r), min(r), max(r)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    before, bfiles, _, _ = runs(os.path.join(d, "before", "*.json"), False)
    after, afiles, builds, loads = runs(os.path.join(d, "after", "*.json"), True)
    if len(builds) != 1 or bfiles != afiles or set(before) - set(after):
        sys.exit("table.py: %s: the after runs name builds %s; runs per data set %s before, %s "
                 "after; cells only before: %s" % (d, sorted(builds), bfiles, afiles,
                                                   sorted(set(before) - set(after))))
    print("before: %s; after: %s; runs per data set: %s; after's 1-minute load %.2f-%.2f" % (
        BEFORE, builds.pop(), ", ".join("%s %d" % kv for kv in sorted(afiles.items())),
        min(loads), max(loads)))
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
                c = j.get("context")
                if j["reference"] != "embree" or (side == "a9") != (c is not None) or (
                        c is not None and (not isinstance(c["build_commit"], str) or
                                           c["build_dirty"] is not False)):
                    raise ValueError("not Embree's triangles, or not this side's build")
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
            if len(a) != len(b):
                sys.exit("table.py: %s %s: %d runs before, %d after" % (mesh, k, len(b), len(a)))
            n = len(a)
            cells.append("%.2f -> %.2f (%.2f-%.2f)" % (statistics.median(b), statistics.median(a),
                                                      min(a), max(a)))
        print("| %s | %d | %s |" % (mesh, n, " | ".join(cells)))


if __name__ == "__main__":
    main()
