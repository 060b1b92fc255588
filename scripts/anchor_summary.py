#!/usr/bin/env python3
"""Before/after tables of `pcrt anchor` JSON files (results/anchor/): per method and structure, the
median pass-by-pass ratio against Embree's discs in Morton order (and in cloud order) on primary,
bounce and shadow rays, and the disc tests per ray.

Usage: anchor_summary.py BEFORE.json AFTER.json
       anchor_summary.py --ratios [--reference K] BEFORE.json AFTER.json
       anchor_summary.py --table [--reference K] FILE.json [FILE.json ...]
       anchor_summary.py --frames FILE.json [FILE.json ...]
       anchor_summary.py --mesh FILE.json [FILE.json ...]
       anchor_summary.py --rounds [--reference K] FILE.json [FILE.json ...]
--ratios prints one table of "before -> after" ratios per ray kind against reference K (0: Embree
ray by ray in Morton order, the default; 3: Embree in packets of 16 where the files have it), with
each file's load average, so that the README and docs quote the files and nothing else. --table
prints one table of several files (one data set each, one column each: primary / bounce / shadow)
with each file's commit, CPU and load average. --frames prints, for the blend methods, how far
each structure's primary hits lie from those on the method's paper structure (recorded since the
anchor's frame_vs_paper): "same" or the distance along the normal in mean spacings h and the
normals' angle in degrees, median / 95th percentile, and the rays only one of them hits. --mesh
reads `pcrt anchor --mesh` files, groups them by the binary that made them (build commit) and the
mesh, and prints per group and ray kind the runs with rays, the median of their ratios against
Embree's triangles, their range, and the work per ray (identical across one binary's runs on one
mesh: the counts are exact). --rounds does the same for point-cloud anchor files (several rounds
of two binaries, scripts/anchor_binaries.sh, or of parameter values, scripts/anchor_sweep.sh): per
binary and --set parameters, data set, method and structure, the median of the runs' ratios
against reference K and their range, per ray kind."""
import argparse
import json
import statistics
import sys

KINDS = ("primary", "bounce", "shadow")


def rows(path):
    j = json.load(open(path))
    out = {}
    for c in j["candidates"]:
        out[(c["method"], c["structure"])] = c
    return j, out


def cell(c, k):
    if c is None:
        return "-"
    r = c[k]
    if not r["references"]:
        return "no rays"
    tests = r["work_per_ray"].get("splat_tests", 0)
    return "%.2f / %.2f (%.1f)" % (r["references"][0]["ratio"], r["references"][1]["ratio"], tests)


def ratio(c, k, ref):
    """The median ratio of candidate c on ray kind k against reference ref, or None."""
    if c is None:
        return None
    refs = c[k]["references"]
    return refs[ref]["ratio"] if ref < len(refs) else None


def fmt(x):
    return "-" if x is None else "%.2f" % x


def load(j):
    la = j.get("load_average")
    if not la:
        return "not recorded"
    return "%.2f -> %.2f" % (la["before"][0], la["after"][0])


def reference_name(j, ref):
    names = j.get("references", [])
    return names[ref] if ref < len(names) else "reference %d (absent)" % ref


def ratios_table(bj, before, aj, after, ref):
    print("%s, N = %d; ratio against %s, before -> after" % (aj["dataset"], aj["N"],
                                                           reference_name(aj, ref)))
    print("1-minute load average at the start -> end of each run: before %s; after %s\n" % (
        load(bj), load(aj)))
    print("| method | structure | primary | bounce | shadow |")
    print("|---|---|---|---|---|")
    for key in sorted(set(before) | set(after)):
        b, a = before.get(key), after.get(key)
        cells = ["%s -> %s" % (fmt(ratio(b, k, ref)), fmt(ratio(a, k, ref))) for k in KINDS]
        print("| %s | %s | %s |" % (key[0], key[1], " | ".join(cells)))


def detail_table(bj, before, aj, after):
    print("%s, N = %d, %s lanes after; cells: ratio vs Embree Morton order / cloud order "
          "(disc tests per ray)\n" % (aj["dataset"], aj["N"], aj.get("leaf_simd", "?")))
    print("| method | structure | primary before | primary after | bounce before | bounce after "
          "| shadow before | shadow after |")
    print("|---|---|---|---|---|---|---|---|")
    for key in sorted(set(before) | set(after)):
        b, a = before.get(key), after.get(key)
        print("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
            key[0], key[1], cell(b, "primary"), cell(a, "primary"), cell(b, "bounce"),
            cell(a, "bounce"), cell(b, "shadow"), cell(a, "shadow")))
    for label, j in (("before", bj), ("after", aj)):
        for k in ("best", "best_same_discs"):
            b = j.get(k)
            if b:
                print("\n%s %s: %s on %s, primary x%.3f (Morton order)" % (
                    label, k, b["method"], b["structure"], b["primary"]["references"][0]["ratio"]))


def build_note(c):
    """Where the binary's own revision (recorded since 3e87a8b) is not the tree's."""
    build = c.get("build_commit")
    if build is None or (build == c.get("git_commit") and c.get("build_dirty") == c.get("git_dirty")):
        return ""
    return ", built from %s%s" % (build[:7], " with uncommitted changes" if c.get("build_dirty") else "")


def files_table(paths, ref):
    """One column per file (data set), cells primary / bounce / shadow against reference ref."""
    files = [rows(path) for path in paths]
    for path, (j, _) in zip(paths, files):
        c = j.get("context", {})
        print("- %s: %s, N = %d, commit %s%s, %s, %d threads, load %s" % (
            path, j["dataset"], j["N"], c.get("git_commit", "?")[:7],
            " (uncommitted changes)" if c.get("git_dirty") else "",
            c.get("machine", {}).get("cpu", "?"), j.get("threads", 0), load(j)) + build_note(c))
    print("\nRatio against %s, primary / bounce / shadow:\n" % reference_name(files[0][0], ref))
    print("| method | structure | %s |" % " | ".join(j["dataset"] for j, _ in files))
    print("|---|---|%s" % ("---|" * len(files)))
    for key in sorted(set().union(*(set(r) for _, r in files))):
        cells = [" / ".join(fmt(ratio(r.get(key), k, ref)) for k in KINDS) for _, r in files]
        if all(c == "- / - / -" for c in cells):
            continue
        print("| %s | %s | %s |" % (key[0], key[1], " | ".join(cells)))


def frame_cell(c):
    f = None if c is None else c.get("frame_vs_paper")
    if f is None:
        return "-"
    if f["same_frame"]:
        return "same"
    if "apart_h_p95" not in f:
        return "%d one-sided, no ray hit on both" % f["one_only"]
    return "%.3f / %.3f h, %.2f / %.2f deg, %d one-sided" % (
        f["apart_h_median"], f["apart_h_p95"], f["normal_deg_median"], f["normal_deg_p95"],
        f["one_only"])


def frames_table(paths):
    """One column per file: each blend candidate's frame against its paper structure's."""
    files = [rows(path) for path in paths]
    print("| method | structure | %s |" % " | ".join(j["dataset"] for j, _ in files))
    print("|---|---|%s" % ("---|" * len(files)))
    for key in sorted(set().union(*(set(r) for _, r in files))):
        cells = [frame_cell(r.get(key)) for _, r in files]
        if any(c != "-" for c in cells):
            print("| %s | %s | %s |" % (key[0], key[1], " | ".join(cells)))


def mesh_runs(paths):
    """The files grouped by (binary, mesh): the build commit and the mesh each ran."""
    groups = {}
    for path in paths:
        try:
            with open(path) as f:
                j = json.load(f)
            c = j["context"]
            build = c["build_commit"][:7] + (" (uncommitted changes)" if c["build_dirty"] else "")
            key = (build, j["mesh"])
            for k in KINDS:
                int(j[k]["rays"])  # each ray kind is there, with its count
        except (OSError, ValueError, KeyError, TypeError, IndexError) as e:
            sys.exit("anchor_summary.py: %s is no `pcrt anchor --mesh` file: %r" % (path, e))
        groups.setdefault(key, []).append((path, j))
    return groups


def mesh_table(paths):
    """Runs of `pcrt anchor --mesh` grouped by binary and mesh: median ratio, range, work per ray
    (from a run with rays of that kind; the counts are exact, so every such run has the same)."""
    groups = mesh_runs(paths)
    print("| binary | mesh | ray kind | runs | median ratio | range | nodes / leaves / triangle tests per ray |")
    print("|---|---|---|---|---|---|---|")
    for (build, mesh), runs in groups.items():
        for k in KINDS:
            used = [(path, j) for path, j in runs if j[k]["rays"] > 0]
            if not used:
                print("| %s | %s | %s | %d | no rays | | |" % (build, mesh, k, len(runs)))
                continue
            try:
                r = [float(j[k]["references"][0]["ratio"]) for _, j in used]
                w = used[0][1][k]["work_per_ray"]
                work = "%.2f / %.2f / %.2f" % (w["nodes_visited"], w["leaves_visited"], w["triangle_tests"])
            except (KeyError, TypeError, IndexError, ValueError) as e:
                sys.exit("anchor_summary.py: %s: %s rays without a ratio or work: %r" % (used[0][0], k, e))
            print("| %s | %s | %s | %d | %.3f | %.3f-%.3f | %s |" % (
                build, mesh, k, len(used), statistics.median(r), min(r), max(r), work))


def rounds_table(paths, ref):
    """Point-cloud anchor runs grouped by binary, parameters set (--set) and data set: per
    candidate and ray kind the median of the runs' ratios against reference ref, and their
    range."""
    groups = {}
    for path in paths:
        try:
            j, cands = rows(path)
            c = j["context"]
            build = c["build_commit"][:7] + (" (uncommitted changes)" if c["build_dirty"] else "")
            sets = " ".join("%s=%g" % kv for kv in sorted(j["set"].items()))
            if sets:
                build += " " + sets
            groups.setdefault((build, j["dataset"]), []).append((path, cands))
        except (OSError, ValueError, KeyError, TypeError) as e:
            sys.exit("anchor_summary.py: %s is no `pcrt anchor` file: %r" % (path, e))
    print("| binary | data | method | structure | runs | primary | bounce | shadow |")
    print("|---|---|---|---|---|---|---|---|")
    for (build, data), runs in groups.items():
        for key in sorted(set().union(*(set(cands) for _, cands in runs))):
            cells = []
            for k in KINDS:
                try:
                    r = [ratio(cands.get(key), k, ref) for _, cands in runs]
                except (KeyError, TypeError, IndexError) as e:
                    sys.exit("anchor_summary.py: %s %s %s: a run without its ray kind (%s): %r" % (
                        data, " ".join(key), k, ", ".join(p for p, _ in runs), e))
                if any(x is None for x in r):
                    sys.exit("anchor_summary.py: %s %s %s: a run without a ratio (%s)" % (
                        data, " ".join(key), k, ", ".join(p for p, _ in runs)))
                cells.append("%.2f (%.2f-%.2f)" % (statistics.median(r), min(r), max(r)))
            print("| %s | %s | %s | %s | %d | %s |" % (build, data, key[0], key[1], len(runs),
                                                       " | ".join(cells)))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("files", nargs="+", help="BEFORE.json AFTER.json, or with --table any number")
    p.add_argument("--ratios", action="store_true", help="before -> after ratios per ray kind")
    p.add_argument("--table", action="store_true", help="one table of several files")
    p.add_argument("--frames", action="store_true", help="the blend methods' frames vs their paper's")
    p.add_argument("--mesh", action="store_true", help="pcrt anchor --mesh files, by binary")
    p.add_argument("--rounds", action="store_true", help="rounds of point-cloud runs, by binary")
    p.add_argument("--reference", type=int, default=0, help="with --ratios, --table or --rounds: reference index")
    a = p.parse_args()
    if a.mesh:
        mesh_table(a.files)
        return
    if a.rounds:
        rounds_table(a.files, a.reference)
        return
    if a.table or a.frames:
        try:
            frames_table(a.files) if a.frames else files_table(a.files, a.reference)
        except (OSError, ValueError, KeyError) as e:
            sys.exit("anchor_summary.py: cannot read %s: %s" % (" ".join(a.files), e))
        return
    if len(a.files) != 2:
        sys.exit("anchor_summary.py: give BEFORE.json AFTER.json (or --table FILE...)")
    a.before, a.after = a.files
    try:
        bj, before = rows(a.before)
        aj, after = rows(a.after)
    except (OSError, ValueError, KeyError) as e:
        sys.exit("anchor_summary.py: cannot read %s / %s: %s" % (a.before, a.after, e))
    if a.ratios:
        ratios_table(bj, before, aj, after, a.reference)
    else:
        detail_table(bj, before, aj, after)


main()
