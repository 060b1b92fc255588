#!/usr/bin/env python3
"""The glass-against-diffuse cost table from scripts/glass_cost.sh's stats: per method the rays
cast (exact, the same every rep) and the median render seconds of each material, and their
ratios. A missing or unreadable stats file is an error naming it."""
import json
import pathlib
import statistics
import sys


def load(path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"glass_cost: {path}: {e}")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: glass_cost.py DIR REPS")
    folder, reps = pathlib.Path(sys.argv[1]), int(sys.argv[2])
    methods = sorted({f.name.split(".")[0] for f in folder.glob("*.json")})
    if not methods:
        sys.exit(f"glass_cost: {folder}: no stats")
    print("| method | rays cast, glass / diffuse | ratio | shadow rays, ratio | bounce rays, ratio "
          "| items visited, ratio | render s, glass / diffuse (median) | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for m in methods:
        runs = {mat: [load(folder / f"{m}.{mat}.{r}.json") for r in range(1, reps + 1)]
                for mat in ("glass", "diffuse")}
        rays = {mat: runs[mat][0]["counters"]["rays_cast"] for mat in runs}
        for mat in runs:
            if any(j["counters"]["rays_cast"] != rays[mat] for j in runs[mat]):
                sys.exit(f"glass_cost: {m} {mat}: rays_cast differs between reps")
        secs = {mat: statistics.median(j["timings"]["render"] for j in runs[mat]) for mat in runs}
        def ratio_of(k):  # "-" where the method does not count it (its own structure)
            g, d = (runs[mat][0]["counters"].get(k, 0) for mat in ("glass", "diffuse"))
            return f"{g / d:.2f}" if d else "-"
        ratio = {k: ratio_of(k) for k in ("shadow_rays", "bounce_rays", "items_visited")}
        print(f"| {m} | {rays['glass']} / {rays['diffuse']} | {rays['glass'] / rays['diffuse']:.2f}"
              f" | {ratio['shadow_rays']} | {ratio['bounce_rays']} | "
              f"{ratio['items_visited']} | {secs['glass']:.3f} / {secs['diffuse']:.3f} | "
              f"{secs['glass'] / secs['diffuse']:.2f} |")
    p = load(folder / f"{methods[0]}.glass.1.json")["params"]
    print(f"\n{p['width']}x{p['height']} pixels, S = {p['S']}, B = {p['B']}, {reps} reps "
          "alternated glass/diffuse in one loop, render phase only (the structure build is the "
          "same for both).")


if __name__ == "__main__":
    main()
