#!/usr/bin/python3
"""Table of results/anchor/layouts: reference_splat's ratio to Embree's discs (pcrt anchor's
median of pass-by-pass ratios), per data set, structure, variant and ray kind; the median over the
three alternated repetitions, with their range."""
import glob, json, os, statistics, sys

here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for f in sorted(glob.glob(os.path.join(here, "*_*_*_[0-9].json"))):
    data, rest = os.path.basename(f).split("_", 1)
    structure, variant, _ = rest.rsplit("_", 2)
    d = json.load(open(f))
    for kind in ("primary", "bounce", "shadow"):
        r = d["best"][kind]["references"][0]["ratio"]
        rows.setdefault((data, structure, kind), {}).setdefault(variant, []).append(r)
print("| data | structure | rays | before (item-order copy) | disc_blocks=0 (item order, no copy) | disc_blocks=1 (leaf order) |")
print("|---|---|---|---|---|---|")
for (data, structure, kind), v in sorted(rows.items()):
    cell = lambda xs: f"{statistics.median(xs):.2f} ({min(xs):.2f}-{max(xs):.2f})"
    print(f"| {data} | {structure} | {kind} | {cell(v['before'])} | {cell(v['item'])} | {cell(v['leaf'])} |")
