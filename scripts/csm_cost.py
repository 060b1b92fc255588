#!/usr/bin/env python3
"""Fits the caustic sample map's cost from scripts/csm_cost.sh's stats (see that script).

Prepass: its ray-object work W (nodes, items, leaf work and triangle tests of every ray it traced:
the frame's work less the P = 0 frame's) per photon against log2 N at P = 10^6, and W against P at
N = 10^5 (log-log exponent: 1 for O(P)). Lookup: CSM octree nodes plus entries visited per lookup
against log2 E (E the map's entries, through P) at k = 64, and against k at P = 10^6 (exponent 1 for
O(k)). Writes a markdown table and csm_cost.json beside it.
Usage: csm_cost.py STATS_DIR OUT.md
"""
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

WORK = ["nodes_visited", "items_visited", "implicit_march_steps", "implicit_cells_marched",
        "triangle_tests"]


def load(d):
    runs = {}
    for f in sorted(Path(d).glob("*.stats.json")):
        m = re.match(r"N(\d+)_P(\d+)(?:_k(\d+))?(_r1)?\.stats\.json", f.name)
        s = json.loads(f.read_text())
        c = s["counters"]
        runs[f.name.split(".")[0]] = {
            "N": int(m[1]), "P": int(m[2]), "k": int(m[3] or 64), "c": c, "r1": bool(m[4]),
            "work": sum(c.get(w, 0) for w in WORK), "csm_seconds": s["timings"].get("csm", 0.0),
            "lookup": (c.get("csm_nodes_visited", 0) + c.get("csm_entries_visited", 0))
            / max(c.get("csm_lookups", 1), 1), "E": c.get("csm_entries", 0)}
    return runs


def fit(x, y):
    """Least squares y = a + b x; returns a, b, R^2."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    A = np.vstack([np.ones_like(x), x]).T
    (a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
    r2 = 1 - np.sum((y - a - b * x) ** 2) / max(np.sum((y - y.mean()) ** 2), 1e-300)
    return float(a), float(b), float(r2)


def main(d, out):
    runs = load(d)
    rows, res = [], {}
    base = {r["N"]: r for r in runs.values() if r["P"] == 0}
    prep = [(r["N"], r["P"], r["work"] - base[r["N"]]["work"], r["csm_seconds"], r["E"])
            for r in runs.values() if r["P"] > 0 and r["k"] == 64 and r["N"] in base and not r["r1"]]
    byN = sorted(p for p in prep if p[1] == 1000000)
    a, b, r2 = fit([math.log2(p[0]) for p in byN], [p[2] / p[1] for p in byN])
    res["prepass_work_per_photon_vs_log2N"] = {"a": a, "b": b, "r2": r2}
    rows.append(f"| prepass work per photon vs log2 N (P = 10^6) | {a:.1f} + {b:.2f} log2 N | "
                f"R^2 = {r2:.3f} |")
    # W against P at N = 1e5: the P = 0 base of N = 1e5 is the frame's own work.
    byP = sorted((r["P"], r["work"] - base[100000]["work"], r["csm_seconds"], r["E"])
                 for r in runs.values() if r["N"] == 100000 and r["P"] > 0 and r["k"] == 64
                 and not r["r1"])
    _, e_w, r2w = fit([math.log(p[0]) for p in byP], [math.log(p[1]) for p in byP])
    _, e_t, r2t = fit([math.log(p[0]) for p in byP], [math.log(p[2]) for p in byP])
    res["prepass_work_vs_P_exponent"] = {"exponent": e_w, "r2": r2w}
    res["prepass_seconds_vs_P_exponent"] = {"exponent": e_t, "r2": r2t}
    rows.append(f"| prepass work vs P (N = 10^5) | P^{e_w:.3f} | R^2 = {r2w:.4f} |")
    rows.append(f"| prepass seconds vs P (N = 10^5) | P^{e_t:.3f} | R^2 = {r2t:.4f} |")
    look = sorted((r["E"], r["lookup"]) for r in runs.values() if r["r1"] and r["k"] == 64)
    a, b, r2 = fit([math.log2(e) for e, _ in look], [v for _, v in look])
    _, e_l, _ = fit([math.log(e) for e, _ in look], [math.log(v) for _, v in look])
    res["lookup_vs_log2E"] = {"a": a, "b": b, "r2": r2, "loglog_exponent": e_l}
    rows.append(f"| lookup work vs E (k = 64, no radius bound) | {a:.1f} + {b:.2f} log2 E (E^{e_l:.3f}) | "
                f"R^2 = {r2:.3f} |")
    byk = sorted((r["k"], r["lookup"]) for r in runs.values() if r["r1"] and r["P"] == 1000000)
    _, e_k, r2k = fit([math.log(k) for k, _ in byk], [math.log(v) for _, v in byk])
    res["lookup_vs_k_exponent"] = {"exponent": e_k, "r2": r2k}
    _, b_k, r2lin = fit([k for k, _ in byk], [v for _, v in byk])
    res["lookup_vs_k_linear"] = {"per_k": b_k, "r2": r2lin}
    rows.append(f"| lookup work vs k (P = 10^6, no radius bound), linear | {b_k:.2f} per k | "
                f"R^2 = {r2lin:.4f} |")
    rows.append(f"| lookup work vs k (P = 10^6, no radius bound) | k^{e_k:.3f} | R^2 = {r2k:.4f} |")
    table = ["| run (r1: no radius bound) | N | P | k | E | prepass work | prepass s | lookup work |",
             "|---|---|---|---|---|---|---|---|"]
    for name, r in sorted(runs.items(), key=lambda t: (t[1]["N"], t[1]["P"], t[1]["k"])):
        w = r["work"] - base[r["N"]]["work"] if r["N"] in base else float("nan")
        table.append(f"| {name} | {r['N']} | {r['P']} | {r['k']} | {r['E']} | {w:.0f} | "
                     f"{r['csm_seconds']:.3f} | {r['lookup']:.1f} |")
    text = ["# Caustic sample map cost (scripts/csm_cost.sh)", "",
            "| claim's quantity | fit | quality |", "|---|---|---|", *rows, "", *table, ""]
    Path(out).write_text("\n".join(text))
    Path(out).with_suffix(".json").write_text(json.dumps(res, indent=1) + "\n")
    print("\n".join(rows))


if __name__ == "__main__":
    main(*sys.argv[1:3])
