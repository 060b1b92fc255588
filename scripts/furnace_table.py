#!/usr/bin/env python3
"""The furnace table (markdown) from scripts/furnace_table.sh's JSON: per method and case the
share of object pixels that lost a path (dark) and the mean radiance over object pixels (1: none
lost). Missing or unreadable files are an error naming the file, never a blank cell."""
import json
import pathlib
import sys

CASES = ["sphere_b1", "bunny_b16", "bunny_scan_b1", "bunny_scan_b16"]


def load(path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"furnace_table: {path}: {e}")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: furnace_table.py OUT")
    out = pathlib.Path(sys.argv[1])
    rows = {}
    for case in CASES:
        folder = out / case
        if not folder.is_dir():
            sys.exit(f"furnace_table: {folder}: missing")
        for f in sorted(folder.glob("*.json")):
            rows.setdefault(f.stem, {})[case] = load(f)
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


if __name__ == "__main__":
    main()
