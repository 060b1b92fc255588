#!/usr/bin/python3
"""3DGRT's trade-offs measured (methods/grt_2024): the k-buffer's size k against walks and wasted
inserts, and the bounding proxy against tests, on the same rays as the splat oracle; and EVER's
exact integral over constant-density ellipsoids (methods/ever_2024) with the same march.

For each cloud (the generated sphere, the bunny, CGAL's building scan) and each variant (grt_2024
with each proxy, ever_2024) and k, the counters per ray on the BVH, and the time per ray of it and
of reference_splat on the same BVH (medians of alternated repetitions, in one process). Writes
OUT/tradeoffs.json and OUT/tradeoffs.md.

usage: PYTHONPATH=build/python scripts/gaussian_tradeoffs.py OUT [--rays N] [--repetitions R]
"""
import argparse
import json
import os
import pathlib
import statistics
import sys
import time

import numpy as np
import pcrt

ROOT = pathlib.Path(__file__).resolve().parent.parent
CLOUDS = ["sphere:n=100000,seed=1", str(ROOT / "data/bunny/bunny.ply"),
          str(ROOT / "data/cgal/points_3/building.ply")]
KS = [1, 2, 4, 8, 16, 32, 64]
# (name, method, parameters): 3DGRT with each bounding proxy, and EVER.
VARIANTS = [("icosahedron", "grt_2024", {"proxy": 0}), ("box", "grt_2024", {"proxy": 1}),
            ("ellipsoid", "grt_2024", {"proxy": 2}), ("EVER", "ever_2024", {})]
COUNTERS = ["gaussian_proxy_tests", "gaussian_proxy_hits", "kbuffer_inserts", "particles_blended",
            "ellipsoid_events", "kbuffer_wasted", "kbuffer_retraces", "nodes_visited", "rays_cast",
            "ray_hits"]


def rays(cloud, n, seed=1):
    """Origins on the sphere three bounding radii around the cloud, aimed within half a radius of
    its centre: rays that cross the surface, as the accuracy rays do."""
    p = cloud.positions
    centre = (p.min(0) + p.max(0)) / 2
    radius = float(np.linalg.norm(p.max(0) - p.min(0))) / 2
    rng = np.random.default_rng(seed)
    o = rng.normal(size=(n, 3))
    o = centre + 3 * radius * o / np.linalg.norm(o, axis=1)[:, None]
    aim = centre + 0.5 * radius * (rng.uniform(size=(n, 3)) - 0.5)
    d = aim - o
    d /= np.linalg.norm(d, axis=1)[:, None]
    return o.astype(np.float32), d.astype(np.float32)


def timed(scene, o, d):
    start = time.perf_counter()
    hits = scene.trace(o, d)
    return time.perf_counter() - start, hits


def measure(cloud, o, d, repetitions):
    ref = pcrt.Scene(cloud, method="reference_splat", structure="bvh")
    out = []
    for name, method, params in VARIANTS:
        for k in KS:
            grt = pcrt.Scene(cloud, method=method, k=k, **params)
            t_grt, t_ref = [], []
            for _ in range(repetitions):  # alternated, so that load falls on both alike
                t, hits = timed(grt, o, d)
                t_grt.append(t)
                t_ref.append(timed(ref, o, d)[0])
            c = grt.counters
            n = len(o)
            row = {"proxy": name, "method": method, "k": k, "rays": n,
                   "hit_rate": float(np.mean(hits["hit"])),
                   "ns_per_ray": 1e9 * statistics.median(t_grt) / n,
                   "reference_splat_ns_per_ray": 1e9 * statistics.median(t_ref) / n}
            row["time_ratio_to_reference_splat"] = row["ns_per_ray"] / row["reference_splat_ns_per_ray"]
            for name_ in COUNTERS:
                row[name_ + "_per_ray"] = c.get(name_, 0) / n
            # What the march used: responses blended (3DGRT) or entries and exits integrated (EVER);
            # inserts never used were evicted by nearer ones, or lay beyond the surface.
            row["used_per_ray"] = row["particles_blended_per_ray"] + row["ellipsoid_events_per_ray"]
            row["wasted_inserts_per_ray"] = row["kbuffer_inserts_per_ray"] - row["used_per_ray"]
            row["walks_per_ray"] = 1 + row["kbuffer_retraces_per_ray"]
            out.append(row)
            print(f"  {name:11s} k={k:2d}: {row['ns_per_ray']:8.0f} ns/ray "
                  f"({row['time_ratio_to_reference_splat']:.2f}x reference_splat), "
                  f"walks {row['walks_per_ray']:.2f}, inserts {row['kbuffer_inserts_per_ray']:.1f}, "
                  f"used {row['used_per_ray']:.1f}, "
                  f"proxy tests {row['gaussian_proxy_tests_per_ray']:.0f}", flush=True)
    return out


def markdown(results):
    lines = ["# 3DGRT's k-buffer and proxies, measured", "",
             "Written by scripts/gaussian_tradeoffs.py; per ray, grt_2024 (with each proxy) and "
             "ever_2024 (EVER: constant-density ellipsoids, their entries and exits integrated) "
             "on the BVH, flat particles made from the cloud's normals and splat radii. 'used' is "
             "the responses blended (grt_2024) or the events integrated (ever_2024). Time ratios "
             "are against reference_splat on the same BVH and rays, alternated in one process.", ""]
    for r in results:
        lines += [f"## {r['cloud']} ({r['points']} points, {r['threads']} threads)", "",
                  "| variant | k | walks | inserts | used | wasted inserts | proxy tests | "
                  "proxy hits | ns/ray | x reference_splat |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for row in r["rows"]:
            lines.append(
                f"| {row['proxy']} | {row['k']} | {row['walks_per_ray']:.2f} | "
                f"{row['kbuffer_inserts_per_ray']:.2f} | {row['used_per_ray']:.2f} | "
                f"{row['wasted_inserts_per_ray']:.2f} | {row['gaussian_proxy_tests_per_ray']:.1f} | "
                f"{row['gaussian_proxy_hits_per_ray']:.2f} | {row['ns_per_ray']:.0f} | "
                f"{row['time_ratio_to_reference_splat']:.2f} |")
        lines.append("")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--rays", type=int, default=100000)
    ap.add_argument("--repetitions", type=int, default=3)
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    results = []
    for spec in CLOUDS:
        if not spec.startswith("sphere") and not pathlib.Path(spec).exists():
            sys.exit(f"gaussian_tradeoffs.py: {spec}: missing (run scripts/fetch_data.sh)")
        cloud = pcrt.load(spec)
        print(f"{spec}: {len(cloud.positions)} points", flush=True)
        o, d = rays(cloud, a.rays)
        name = spec if spec.startswith("sphere") else str(pathlib.Path(spec).relative_to(ROOT))
        results.append({"cloud": name, "points": int(len(cloud.positions)), "threads": os.cpu_count(),
                        "rows": measure(cloud, o, d, a.repetitions)})
    (out / "tradeoffs.json").write_text(json.dumps(results, indent=1) + "\n")
    (out / "tradeoffs.md").write_text(markdown(results))


if __name__ == "__main__":
    main()
