#!/usr/bin/env python3
"""The material cost table from scripts/material_cost.sh's stats: per method, for glass, mirror
and glossy, the ratio to the diffuse frame of rays cast, items visited (both exact, the same every
rep) and the median render seconds, and the diffuse median seconds; beside each time ratio, the range of the ratios of
the reps paired within one pass of the loop. Writes OUT.md and OUT.json
beside it (per method and material: the counters, the median seconds and the ratios). A missing
or unreadable stats file is an error naming it.
Usage: material_cost.py DIR REPS OUT.md
"""
import json
import os
import pathlib
import statistics
import sys

SPECULAR = ("glass", "mirror", "glossy")
MATERIALS = SPECULAR + ("diffuse",)
# Exact counters: a fixed seed gives every rep the same paths, so any difference is a bug.
COUNTERS = ("rays_cast", "items_visited", "shadow_rays", "bounce_rays", "csm_photon_rays")


def load(path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"material_cost: {path}: {e}")


def run_of(path):
    """(exact counters, render seconds, caustic map seconds) of one stats file."""
    j = load(path)
    try:
        # None where the method does not count it (Embree's own structure has no items).
        counters = {k: j["counters"].get(k) for k in COUNTERS}
        return counters, float(j["timings"]["render"]), float(j["timings"].get("csm", 0.0))
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        sys.exit(f"material_cost: {path}: not a pcrt stats file ({type(e).__name__}: {e})")


def measure(folder, method, reps):
    """{material: {counter: value or None, "render_seconds": median}} of one method."""
    out = {}
    for mat in MATERIALS:
        runs = [run_of(folder / f"{method}.{mat}.{r}.json") for r in range(1, reps + 1)]
        row = runs[0][0]
        if any(c != row for c, _, _ in runs):
            sys.exit(f"material_cost: {method} {mat}: counters differ between reps")
        # The render phase includes a caustic map prepass (goradia_2011 before a delta object).
        out[mat] = {**row, "render_seconds": statistics.median(r[1] for r in runs),
                    "csm_seconds": statistics.median(r[2] for r in runs),
                    "rep_seconds": [r[1] for r in runs]}
    return out


def ratios(row, diffuse):
    keys = COUNTERS[:4] + ("render_seconds",)
    out = {k: row[k] / diffuse[k] if row[k] is not None and diffuse[k] else None for k in keys}
    # Rep r of every material ran in the same pass of the loop: the spread of these paired
    # ratios is how far the machine moved the median's.
    paired = [a / b for a, b in zip(row["rep_seconds"], diffuse["rep_seconds"])]
    out["render_seconds_range"] = [min(paired), max(paired)]
    return out


def fmt(x):
    return "-" if x is None else f"{x:.2f}"


def table(results):
    head = ["method"] + [f"{m} {q}" for m in SPECULAR for q in ("rays", "items", "s")]
    lines = ["| " + " | ".join(head + ["diffuse s (median)"]) + " |",
             "|" + "---|" * (len(head) + 1)]
    for method, mats in results.items():
        cells = [method]
        for m in SPECULAR:
            r = mats[m]["ratio_to_diffuse"]
            lo, hi = r["render_seconds_range"]
            cells += [fmt(r["rays_cast"]), fmt(r["items_visited"]),
                      f"{fmt(r['render_seconds'])} ({fmt(lo)}-{fmt(hi)})"]
        cells.append(f"{mats['diffuse']['render_seconds']:.3f}")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def csm_notes(results):
    """One line per frame whose render phase holds a caustic map prepass: how much of it."""
    notes = []
    for method, mats in results.items():
        for m in SPECULAR:
            row, diffuse_s = mats[m], mats["diffuse"]["render_seconds"]
            if row["csm_photon_rays"]:
                rest = (row["render_seconds"] - row["csm_seconds"]) / diffuse_s
                notes.append(f"{method} {m}: {row['csm_photon_rays']} photon rays, "
                             f"{row['csm_seconds']:.3f} of its {row['render_seconds']:.3f} s "
                             f"(without the prepass {rest:.2f} of the diffuse frame's s)")
    if not notes:
        return []
    return ["", "The render phase includes the caustic sample map prepass of a method that "
            "declares one, before a frame with a delta object (mirror, glass): " +
            "; ".join(notes) + "."]


def main():
    if len(sys.argv) != 4 or not sys.argv[2].isdigit() or int(sys.argv[2]) < 1:
        sys.exit("usage: material_cost.py DIR REPS OUT.md")
    folder, reps, out = pathlib.Path(sys.argv[1]), int(sys.argv[2]), pathlib.Path(sys.argv[3])
    methods = sorted({f.name.split(".")[0] for f in folder.glob("*.json")})
    if not methods:
        sys.exit(f"material_cost: {folder}: no stats")
    results = {}
    for method in methods:
        mats = measure(folder, method, reps)
        for m in SPECULAR:
            mats[m]["ratio_to_diffuse"] = ratios(mats[m], mats["diffuse"])
        results[method] = mats
    p = load(folder / f"{methods[0]}.diffuse.1.json").get("params", {})
    # The load when the table is written: the run's own 2 threads are in it, other jobs on top.
    load_avg = [round(x, 2) for x in os.getloadavg()]
    footer = (f"{p.get('width')}x{p.get('height')} pixels, S = {p.get('S')}, B = {p.get('B')}, "
              f"{reps} reps alternated glass (dielectric, eta 1.5)/mirror/glossy (rough_conductor, "
              "roughness 0.15)/diffuse (albedo 0.75) in one loop; each cell is the "
              "material's value over the diffuse frame's: rays cast, items visited (exact; - "
              "where the method does not count them) and median render seconds, with the range "
              "of the ratios of the reps paired in one pass of the loop (render phase only: the "
              "structure build is the same for every material). Load average "
              f"(1/5/15 min) when written: {' / '.join(map(str, load_avg))}.")
    out.write_text("\n".join(table(results) + csm_notes(results) + ["", footer, ""]))
    summary = {"params": {k: p.get(k) for k in ("width", "height", "S", "B", "threads")},
               "reps": reps, "load_average": load_avg, "methods": results}
    out.with_suffix(".json").write_text(json.dumps(summary, indent=1) + "\n")


if __name__ == "__main__":
    main()
