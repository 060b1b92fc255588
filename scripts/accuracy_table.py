#!/usr/bin/python3
"""The real-shape accuracy table from `scripts/accuracy_meshes.sh` output.

Usage: scripts/accuracy_table.py [DIR=results/accuracy] [--csv FILE] [--markdown FILE]
                                 [--before DIR2]

Reads DIR/<shape>/<method>.json (one `pcrt accuracy --truth ... --json` each), writes every figure
as CSV and a markdown summary: per method the worst rate over the shapes (and which shape), the
median distance and normal error, and how many shapes meet all bounds. Rates are in percent.
A second table gives the failure rate (holes + see-through + phantom, of the judged hits) by the
normal spread at the exact hit (`normal_spread` in the JSON), and the bands where a method stays
under 1% on every shape.
With --before, a second table gives each method's worst rates in DIR2 (an earlier build's results)
beside DIR's.
"""
import csv
import json
import sys
from pathlib import Path

BOUND = 1.0  # percent: the bound on holes, see-through and phantom hits
FIELDS = ["shape", "method", "structure", "N", "mean_spacing", "judged_hits", "judged_misses",
          "hole_rate", "see_through_rate", "see_through_smooth_rate", "see_through_open_rate",
          "hole_open_rate", "early_rate", "phantom_rate", "false_hit_rate",
          "distance_median_h", "distance_p95_h", "normal_median_deg", "normal_judged",
          "smooth_normal_median_deg", "faceting_floor_deg", "meets_bounds",
          "secondary_outward_self_hit_rate", "secondary_outward_missed_occluder_rate",
          "secondary_outward_false_occluder_rate", "secondary_inward_self_hit_rate",
          "secondary_inward_missed_occluder_rate", "secondary_inward_false_occluder_rate",
          "sample", "truth"]
# The normal-spread bands of `pcrt accuracy` (render/accuracy.hpp, kSpreadEdgesDeg), in degrees.
SPREAD_BANDS = [(0, 5), (5, 15), (15, 30), (30, 60), (60, 180)]
SPREAD_KEYS = ["judged_share", "failure_rate", "hole_rate", "see_through_rate", "phantom_rate"]
FIELDS += [f"spread_{lo}_{hi}_{k}" for lo, hi in SPREAD_BANDS for k in SPREAD_KEYS]
# A band's rate is left out of a worst-over-shapes cell below this many judged hits there (one
# failure in 50 hits would read 2%).
MIN_BAND_HITS = 200


def load(directory):
    rows = []
    for f in sorted(Path(directory).glob("*/*.json")):
        j = json.loads(f.read_text())
        j["shape"] = f.parent.name
        for side, v in j.get("secondary", {}).items():  # flattened for the CSV and the table
            for k in ("self_hit_rate", "missed_occluder_rate", "false_occluder_rate"):
                j[f"secondary_{side}_{k}"] = v[k]
        causes = j.get("causes")
        if causes:  # failures on open smooth surface, as rates of the judged hits
            for kind, key in (("see_through", "see_through_open_rate"), ("holes", "hole_open_rate")):
                j[key] = causes[kind]["open"] / j["judged_hits"] if j["judged_hits"] else 0.0
        flatten_spread(j)
        rows.append(j)
    if not rows:
        sys.exit(f"accuracy_table.py: no results under {directory}")
    return rows


def flatten_spread(j):
    """spread_<lo>_<hi>_<key> columns from the JSON's normal_spread bands (absent before them)."""
    for b in j.get("normal_spread", {}).get("bands", []):
        key = f"spread_{b['lo_deg']:g}_{b['hi_deg']:g}"
        j[f"{key}_judged_hits"] = b["judged_hits"]
        j[f"{key}_judged_share"] = b["judged_hits"] / j["judged_hits"] if j["judged_hits"] else 0.0
        for k in SPREAD_KEYS[1:]:
            j[f"{key}_{k}"] = b[k]


def spread(rows):
    """Per method the worst failure rate over the shapes in each normal-spread band."""
    rows = [r for r in rows if "normal_spread" in r]
    shares = []
    for lo, hi in SPREAD_BANDS:
        v = sorted(pct(r[f"spread_{lo}_{hi}_judged_share"]) for r in rows)
        shares.append(f"{v[0]:.0f}-{v[-1]:.0f}%")
    reach = rows[0]["normal_spread"]["reach_h"]
    out = [f"Failures (holes + see-through + phantom, % of the judged hits in the band) by the "
           f"normal spread at the exact hit: the largest angle between face normals within "
           f"{reach} h. Worst over the shapes, leaving out a shape with fewer than {MIN_BAND_HITS} "
           f"judged hits in the band; the header gives the band's share of all judged hits over "
           f"the shapes. Faces more than 15 degrees apart are the causes table's creases.",
           "",
           "| method | " + " | ".join(f"{lo}-{hi} deg ({s})" for (lo, hi), s in
                                     zip(SPREAD_BANDS, shares)) + " | under 1% on every shape |",
           "|---|" + "---|" * (len(SPREAD_BANDS) + 1)]
    for m in sorted({r["method"] for r in rows}):
        rs = [r for r in rows if r["method"] == m]
        cells, under = [], []
        for lo, hi in SPREAD_BANDS:
            key = f"spread_{lo}_{hi}"
            ok = [r for r in rs if r[f"{key}_judged_hits"] >= MIN_BAND_HITS]
            if not ok:
                cells.append("-")
                continue
            w = max(ok, key=lambda r: r[f"{key}_failure_rate"])
            cells.append(f"{pct(w[key + '_failure_rate']):.2f} ({w['shape']})")
            if pct(w[key + "_failure_rate"]) < BOUND:
                under.append(f"{lo}-{hi}")
        out.append(f"| {m} | " + " | ".join(cells) + f" | {', '.join(under) or 'none'} |")
    return "\n".join(out) + "\n"


def pct(v):
    return 100.0 * v


def worst(rows, key):
    r = max(rows, key=lambda r: r.get(key, 0))
    return f"{pct(r[key]):.2f} ({r['shape']})" if r.get(key, 0) > 0 else "0"


def before_after(before, after):
    out = ["| method | see-through before -> after | phantom before -> after | "
           "holes before -> after |", "|---|---|---|---|"]
    for m in sorted({r["method"] for r in after}):
        b = [r for r in before if r["method"] == m]
        a = [r for r in after if r["method"] == m]
        cells = [f"{worst(b, k)} -> {worst(a, k)}"
                 for k in ("see_through_rate", "phantom_rate", "hole_rate")]
        out.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def split_cell(split, base):
    """'crease / thin / open' shares of the failures, and of all judged hits in brackets."""
    def shares(s):
        total = sum(s.values())
        return " / ".join(f"{100.0 * s[k] / total:.0f}" for k in ("crease", "thin", "open")) if total else "-"
    return f"{shares(split)} ({shares(base)})"


def causes(rows):
    """Where each method's worst failures happen, against where the judged rays land."""
    c0 = next(r["causes"] for r in rows if "causes" in r)
    out = [f"Causes at each method's worst shape: the failures' shares (%) on a crease (faces more "
           f"than 15 degrees apart within {c0['feature_reach_h']} h), a thin wall (back side within "
           f"{c0['thin_wall_h']} h along the inward normal) or open smooth surface; in brackets the "
           f"same shares of all judged hits on that shape. A failure share well above its bracket "
           f"is where the method fails. Phantoms: share with a crease within "
           f"{c0['feature_reach_h']} h of their nearest surface point.",
           "",
           "| method | see-through | crease / thin / open | holes | crease / thin / open | "
           "phantom | near a crease |",
           "|---|---|---|---|---|---|---|"]
    for m in sorted({r["method"] for r in rows}):
        rs = [r for r in rows if r["method"] == m and "causes" in r]
        if not rs:
            continue
        cells = []
        for key, kind in (("see_through_rate", "see_through"), ("hole_rate", "holes")):
            w = max(rs, key=lambda r: r[key])
            cells += [worst(rs, key),
                      split_cell(w["causes"][kind], w["causes"]["judged_hits"]) if w[key] else "-"]
        w = max(rs, key=lambda r: r["phantom_rate"])
        near = (f"{100.0 * w['causes']['phantom_near_crease'] / w['phantom']:.0f}%"
                if w["phantom"] else "-")
        out.append(f"| {m} | " + " | ".join(cells) + f" | {worst(rs, 'phantom_rate')} | {near} |")
    return "\n".join(out) + "\n"


def markdown(rows):
    shapes = sorted({r["shape"] for r in rows})
    methods = sorted({r["method"] for r in rows})
    out = [f"Worst over {len(shapes)} shapes ({', '.join(shapes)}); rates in % of judged rays, "
           f"distances in h, normals in degrees (median over shapes of the per-shape median).",
           "",
           "| method | see-through | of which on open smooth surface | phantom | holes | "
           "holes on open smooth surface | "
           "early (fattened) | distance median | normal median | faceting floor | "
           "shapes meeting every bound | secondary self-hits out / in | "
           "secondary missed occluders out / in |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for m in methods:
        rs = [r for r in rows if r["method"] == m]

        def med(key):
            v = sorted(r[key] for r in rs if r[key] is not None)
            return f"{v[len(v) // 2]:.3f}" if v else "-"
        meets = sum(1 for r in rs if r["meets_bounds"])
        out.append(f"| {m} | {worst(rs, 'see_through_rate')} | "
                   f"{worst(rs, 'see_through_open_rate')} | {worst(rs, 'phantom_rate')} | "
                   f"{worst(rs, 'hole_rate')} | {worst(rs, 'hole_open_rate')} | "
                   f"{worst(rs, 'early_rate')} | "
                   f"{med('distance_median_h')} | {med('normal_median_deg')} | "
                   f"{med('faceting_floor_deg')} | {meets}/{len(rs)} | "
                   f"{worst(rs, 'secondary_outward_self_hit_rate')} / "
                   f"{worst(rs, 'secondary_inward_self_hit_rate')} | "
                   f"{worst(rs, 'secondary_outward_missed_occluder_rate')} / "
                   f"{worst(rs, 'secondary_inward_missed_occluder_rate')} |")
    return "\n".join(out) + "\n"


def main():
    args = sys.argv[1:]
    directory = args[0] if args and not args[0].startswith("--") else "results/accuracy"
    rows = load(directory)
    if "--csv" in args:
        with open(args[args.index("--csv") + 1], "w", newline="") as f:
            w = csv.DictWriter(f, FIELDS, extrasaction="ignore")
            w.writeheader()
            for r in rows:
                w.writerow({k: r.get(k) for k in FIELDS})
    text = markdown(rows)
    if any("causes" in r for r in rows):
        text += "\n" + causes(rows)
    if any("normal_spread" in r for r in rows):
        text += "\n" + spread(rows)
    if "--before" in args:
        text += "\nWorst over the shapes, before -> after:\n\n"
        text += before_after(load(args[args.index("--before") + 1]), rows)
    if "--markdown" in args:
        Path(args[args.index("--markdown") + 1]).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
