#!/usr/bin/env python3
"""The furnace table (markdown) from scripts/furnace_table.sh's JSON: per method and case the
share of object pixels that lost a path (dark) and the mean radiance over object pixels (1: none
lost); then the split of the dark pixels by cause at S = 1 (a false camera-ray hit, or a path
lost after a true one), with the exact surface or the mesh as the floor row. Missing or unreadable
files are an error naming the file, never a blank cell."""
import json
import pathlib
import sys

CASES = ["sphere_b1", "bunny_b16", "bunny_scan_b1", "bunny_scan_b16"]
SPLIT_CASES = ["split_sphere", "split_torus", "split_bunny"]
FLOOR = "exact"  # the exact surface (generators) or the mesh (bunny): no method in between


def load(path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"furnace_table: {path}: {e}")


def read_cases(out, cases):
    rows = {}
    for case in cases:
        folder = out / case
        if not folder.is_dir():
            sys.exit(f"furnace_table: {folder}: missing")
        for f in sorted(folder.glob("*.json")):
            rows.setdefault(f.stem, {})[case] = load(f)
    return rows


def dark_table(out):
    rows = read_cases(out, CASES)
    methods = sorted(m for m in rows if m != "mesh") + (["mesh"] if "mesh" in rows else [])
    for m in methods:
        if m != "mesh" and set(rows[m]) != set(CASES):
            sys.exit(f"furnace_table: {m}: missing cases {sorted(set(CASES) - set(rows[m]))}")
    print("| method | " + " | ".join(f"{c}: dark / mean" for c in CASES) + " |")
    print("|---|" + "---|" * len(CASES))
    for m in methods:
        cells = []
        for c in CASES:
            r = rows[m].get(c)
            cells.append("" if r is None else f"{100 * r['dark_share']:.2f}% / {r['mean']:.4f}")
        print(f"| {m} | " + " | ".join(cells) + " |")
    any_row = next(iter(rows["reference_splat"].values()))
    p = any_row["params"]
    print(f"\nM = {p['M']} pixels, S = {p['S']}; dark: an object pixel that lost at least one of "
          "its S paths. mesh: the bunny's own triangles on Embree (the floor geometry sets).")


def split_cell(path, r):
    """dark = false camera-ray hit + lost after a true one, in % of object pixels."""
    n = r["object_pixels"]
    if not n:
        sys.exit(f"furnace_table: {path}: no object pixels")
    primary, secondary = r["dark_primary"], r["dark_secondary"]
    if primary is None:
        if path.stem != FLOOR:  # only the mesh floor has no truth: its triangles are the truth
            sys.exit(f"furnace_table: {path}: no split by cause")
        primary, secondary = 0, r["dark_pixels"]
    if primary + secondary != r["dark_pixels"]:
        sys.exit(f"furnace_table: {path}: causes do not add up to the dark pixels")
    return f"{100 * r['dark_share']:.2f}% = {100 * primary / n:.2f} + {100 * secondary / n:.2f}"


def split_table(out):
    rows = read_cases(out, SPLIT_CASES)
    methods = sorted(m for m in rows if m != FLOOR) + [FLOOR]
    for m in methods:
        if set(rows.get(m, {})) != set(SPLIT_CASES):
            sys.exit(f"furnace_table: {m}: missing split cases")
    print("\n| method | " + " | ".join(f"{c[6:]}: dark = false camera hit + lost after"
                                      for c in SPLIT_CASES) + " |")
    print("|---|" + "---|" * len(SPLIT_CASES))
    for m in methods:
        cells = [split_cell(out / c / f"{m}.json", rows[m][c]) for c in SPLIT_CASES]
        print(f"| {m} | " + " | ".join(cells) + " |")
    p = rows["reference_splat"]["split_torus"]["params"]
    print(f"\nM = {p['M']} pixels, S = {p['S']}, B = {p['B']}; one path per pixel, through its "
          "centre, judged against the exact surface (the bunny: its mesh). exact: the generator's "
          "own surface traced (`pcrt furnace --exact`), and for the bunny its mesh on Embree: "
          "what the shape loses to its own concavity at B = 1.")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: furnace_table.py OUT")
    out = pathlib.Path(sys.argv[1])
    dark_table(out)
    split_table(out)


if __name__ == "__main__":
    main()
