#!/usr/bin/python3
"""The table of results/accuracy/structures/summary.md from its JSON files: per method and
structure, the median over the 8 shapes of each shape's distance and normal medians and p95s, and
the worst shape's hole and false-hit rates (% of judged rays). A missing file is an error."""
import json
import pathlib
import statistics
import sys

HERE = pathlib.Path(__file__).resolve().parent
SHAPES = ["bunny", "cow", "elk", "camel", "blade", "bear", "homer", "bunny_scan"]
VARIANTS = [("octree", "octree (the papers' cells)"), ("octree_loose", "octree loose=1"),
            ("bvh", "bvh (leaves of up to 16)"), ("bvh_leaf8", "bvh leaf_size=8")]
METHODS = ["goradia_2010", "kashyap_2010_splat", "linsen_2007", "reference_splat"]


def load(variant, shape, method):
    path = HERE / variant / shape / f"{method}.json"
    if not path.exists():
        sys.exit(f"summary.py: {path}: missing (run run.sh)")
    return json.loads(path.read_text())


def row(method, variant, label):
    runs = [load(variant, s, method) for s in SHAPES]
    med = lambda k: statistics.median(r[k] for r in runs)
    worst = lambda k: max((100 * r[k], s) for r, s in zip(runs, SHAPES))
    holes, false = worst("hole_rate"), worst("false_hit_rate")
    return (f"| {method} | {label} | {med('distance_median_h'):.3f} | {med('distance_p95_h'):.3f} "
            f"| {med('normal_median_deg'):.2f} | {med('normal_p95_deg'):.2f} "
            f"| {holes[0]:.2f} ({holes[1]}) | {false[0]:.2f} ({false[1]}) |")


def main():
    print("| method | structure | distance median (h) | distance p95 (h) | normal median (deg) "
          "| normal p95 (deg) | holes, worst (%) | false hits, worst (%) |")
    print("|---|---|---|---|---|---|---|---|")
    for m in METHODS:
        for v, label in VARIANTS:
            print(row(m, v, label))


if __name__ == "__main__":
    main()
