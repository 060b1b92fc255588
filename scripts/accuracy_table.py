#!/usr/bin/python3
"""The real-shape accuracy table from `scripts/accuracy_meshes.sh` output.

Usage: scripts/accuracy_table.py [DIR=results/accuracy] [--csv FILE] [--markdown FILE]
                                 [--before DIR2] [--plot PNG]

Reads DIR/<shape>/<method>.json (one `pcrt accuracy --truth ... --json` each), writes every figure
as CSV and a markdown summary: per method the worst rate over the shapes (and which shape), the
median distance and normal error, and how many shapes meet all bounds. Rates are in percent.
Two more tables give the failure rate (holes + see-through + phantom, of the judged hits) by the
normal spread at the exact hit (`normal_spread` in the JSON), with and without the hits on thin
walls, and per band whether a method stays under 1% on every shape by the 95% bounds; --plot
draws the second, pooled over the shapes.
With --before, a second table gives each method's worst rates in DIR2 (an earlier build's results)
beside DIR's.
"""
import csv
import json
import math
import statistics
import sys
from pathlib import Path

# Folders of DIR that hold a study of their own (scripts/kernel_width.sh), not a shape.
STUDIES = {"kernel_width"}
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


def load(directory):
    rows = []
    for f in sorted(Path(directory).glob("*/*.json")):
        if f.parent.name in STUDIES:
            continue
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


def wilson(k, n, z):
    """The Wilson score interval of a rate k / n at z standard errors, in percent."""
    if n == 0:
        return 0.0, 100.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return pct(max(0.0, centre - half)), pct(min(1.0, centre + half))


def band_counts(r, lo, hi, thin):
    """(failures, judged hits) of shape r in a band; without its thin walls unless `thin`."""
    b = next(b for b in r["normal_spread"]["bands"] if (b["lo_deg"], b["hi_deg"]) == (lo, hi))
    fails = b["holes"] + b["see_through"] + b["phantom"]
    if thin:
        return fails, b["judged_hits"]
    return fails - b["thin_failures"], b["judged_hits"] - b["thin_hits"]


def band_cell(rs, lo, hi, thin):
    """A method's band over its shapes: 'over' when some shape's lower bound is above BOUND,
    'under' when the upper bound of every shape that could show it (zero failures there would put
    the upper bound below BOUND) is below it, else 'inconclusive'. The intervals are 95% for the
    band as a whole (Bonferroni over the shapes: one shape in eight would otherwise cross the
    bound by chance more often than one time in twenty). The cell names the deciding shape (the
    highest lower bound for 'over', else the highest upper bound of the shapes that could decide)
    and how many shapes had too few hits in the band to decide 'under'."""
    judged = [(r["shape"],) + band_counts(r, lo, hi, thin) for r in rs]
    judged = [(shape, k, n) for shape, k, n in judged if n > 0]
    if not judged:
        return "no hits"
    z = statistics.NormalDist().inv_cdf(1 - 0.025 / len(judged))
    bounds = [(wilson(k, n, z), shape, k, n) for shape, k, n in judged]
    able = [b for b in bounds if wilson(0, b[3], z)[1] < BOUND]
    small = len(bounds) - len(able)
    over = any(low > BOUND for (low, _), *_ in bounds)
    # The worst rate of the shapes that take part: all for 'over', else those that could decide.
    worst = max(bounds if over or not able else able, key=lambda b: b[2] / b[3])
    worst_text = f"worst {100.0 * worst[2] / worst[3]:.2f} {worst[1]} ({worst[2]}/{worst[3]})"
    if over:
        (low, _), shape, *_ = max(bounds, key=lambda b: b[0][0])
        return f"over (lower bound {low:.2f}, {shape}); {worst_text}"
    if not able:
        return f"inconclusive ({len(bounds)} shapes, each with too few hits)"
    (_, up), shape, *_ = max(able, key=lambda b: b[0][1])
    verdict = "under" if up < BOUND else "inconclusive"
    note = f"; {small} shape{'s' if small > 1 else ''} with too few hits" if small else ""
    return f"{verdict} (upper bound {up:.2f}, {shape}{note}); {worst_text}"


def spread_table(rows, thin):
    """Per method and band: the verdict against BOUND and the shape that decides it."""
    reach = rows[0]["normal_spread"]["reach_h"]
    shares = []
    for lo, hi in SPREAD_BANDS:
        v = sorted(100.0 * band_counts(r, lo, hi, thin)[1] / r["judged_hits"] for r in rows)
        shares.append(f"{v[0]:.0f}-{v[-1]:.0f}%")
    what = "all judged hits" if thin else "the judged hits not on a thin wall"
    out = [f"Failures (holes + see-through + phantom) as % of {what} in the band, by the normal "
           f"spread at the exact hit (the largest angle between face normals within {reach} h). "
           f"Per method and band, against {BOUND:g}%: over (some shape's lower bound above it), "
           f"under (the upper bound below it on every shape with hits enough to show that) or "
           f"inconclusive, with 95% Wilson intervals for the band as a whole (Bonferroni over the "
           f"shapes); then the deciding bound and its shape, how many shapes had too few hits in "
           f"the band to take part in 'under', and the worst rate over the shapes that take part (failures/hits). The header gives the band's share of those hits, "
           f"lowest to highest over the shapes.",
           "",
           "| method | " + " | ".join(f"{lo}-{hi} deg ({s})" for (lo, hi), s in
                                     zip(SPREAD_BANDS, shares)) + " |",
           "|---|" + "---|" * len(SPREAD_BANDS)]
    for m in sorted({r["method"] for r in rows}):
        rs = [r for r in rows if r["method"] == m]
        cells = [band_cell(rs, lo, hi, thin) for lo, hi in SPREAD_BANDS]
        out.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def spread(rows):
    """The normal-spread tables: all judged hits, then without the thin walls."""
    rows = [r for r in rows if "normal_spread" in r]
    return spread_table(rows, True) + "\n" + spread_table(rows, False)


def spread_plot(rows, path):
    """Failure rate against the normal spread, pooled over the shapes, one line per method."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [r for r in rows if "normal_spread" in r]
    fig, ax = plt.subplots(figsize=(10, 4.8))
    x = range(len(SPREAD_BANDS))
    methods = sorted({r["method"] for r in rows})
    for i, m in enumerate(methods):
        rs = [r for r in rows if r["method"] == m]
        k = [sum(band_counts(r, lo, hi, False)[0] for r in rs) for lo, hi in SPREAD_BANDS]
        n = [sum(band_counts(r, lo, hi, False)[1] for r in rs) for lo, hi in SPREAD_BANDS]
        ax.plot(x, [max(100.0 * a / b, 1e-3) if b else float("nan") for a, b in zip(k, n)],
                marker="osD^v"[i % 5], color=plt.cm.tab20(i % 20), label=m)
    ax.axhline(BOUND, color="black", linestyle="--", linewidth=1)
    ax.set_yscale("log")
    ax.set_xticks(list(x), [f"{lo}-{hi}" for lo, hi in SPREAD_BANDS])
    ax.set_xlabel("normal spread at the exact hit (degrees between faces within 3.5 h)")
    ax.set_ylabel("holes + see-through + phantom (%)")
    ax.set_title("Failures by normal spread, thin walls left out, pooled over the shapes")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def pct(v):
    return 100.0 * v


def worst(rows, key):
    if not rows:
        return "-"  # a method the earlier run did not have
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
        if "--plot" in args:
            spread_plot(rows, args[args.index("--plot") + 1])
    if "--before" in args:
        text += "\nWorst over the shapes, before -> after:\n\n"
        text += before_after(load(args[args.index("--before") + 1]), rows)
    if "--markdown" in args:
        Path(args[args.index("--markdown") + 1]).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
