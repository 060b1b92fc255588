#!/usr/bin/python3
"""What the operation counters cost in time: the same work timed with a counting pcrt (ON) and
one built with -DPCRT_COUNTERS=OFF, runs alternated (pair p runs ON then OFF for even p, OFF then
ON for odd p; every case once per pair, so load from other processes falls on both builds alike).

Per case and ray set the overhead of one pair is time(ON) / time(OFF). For `pcrt anchor` cases
the times are normalised by Embree's, timed in the same process (Embree's own path does the same
work in both builds: a few counts per ray), so the pair's ratio is
    (ours_OFF / embree_OFF) / (ours_ON / embree_ON)  in rays per second,
and the raw ratio rate_OFF / rate_ON is kept beside it. For `pcrt render` cases (methods that
anchor does not time, such as the MLS ones) it is the render phase's wall time ON / OFF.

  cmake -S . -B build-nocount -G Ninja -DCMAKE_BUILD_TYPE=Release -DPCRT_COUNTERS=OFF
  cmake --build build-nocount --target pcrt
  scripts/counter_overhead.py --on build/bin/pcrt --off build-nocount/bin/pcrt \
      --pairs 7 --out results/anchor/counters    # runs (appended to OUT), then the table
  scripts/counter_overhead.py --out results/anchor/counters --summary-only

Writes OUT/raw/CASE_{on,off}_PAIR.json, OUT/runs.jsonl (command, load average, time of each run)
and OUT/summary.json; prints the table as markdown. Refuses an OFF binary that counts.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

SPHERE = "sphere:n=1000000"
BUILDING = "data/cgal/points_3/building.ply"
MESH = "data/cgal/meshes/armadillo.off"

# name -> (kind, arguments after the command); anchor cases time primary, bounce and shadow rays.
CASES = {
    "sphere_reference_splat_bvh": ("anchor", ["--data", SPHERE, "--method", "reference_splat",
                                              "--structure", "bvh"]),
    "sphere_reference_splat_kd_tree": ("anchor", ["--data", SPHERE, "--method", "reference_splat",
                                                  "--structure", "kd_tree"]),
    "sphere_goradia_2010_octree": ("anchor", ["--data", SPHERE, "--method", "goradia_2010",
                                              "--structure", "octree"]),
    "building_reference_splat_bvh": ("anchor", ["--data", BUILDING, "--method", "reference_splat",
                                                "--structure", "bvh"]),
    "building_reference_splat_kd_tree": ("anchor", ["--data", BUILDING, "--method",
                                                    "reference_splat", "--structure", "kd_tree"]),
    "building_goradia_2010_octree": ("anchor", ["--data", BUILDING, "--method", "goradia_2010",
                                                "--structure", "octree"]),
    "armadillo_triangle_bvh": ("anchor", ["--mesh", MESH]),
    # adamson_alexa_2003 (iterated MLS, sphere_tree): primary rays only, then a full frame
    # (primary, one bounce and shadow rays).
    "sphere_adamson_alexa_2003_primary": ("render", ["--method", "adamson_alexa_2003", "--data",
                                                     SPHERE, "--bounces", "0", "--no-light"]),
    "sphere_adamson_alexa_2003_frame": ("render", ["--method", "adamson_alexa_2003", "--data",
                                                   SPHERE]),
}
RAY_SETS = ("primary", "bounce", "shadow")


def run_one(binary, case, build, pair, args):
    kind, case_args = CASES[case]
    base = os.path.join(args.out, "raw", f"{case}_{build}_{pair}")
    if kind == "anchor":
        cmd = [binary, "anchor", *case_args, "--reps", str(args.reps), "--threads",
               str(args.threads), "--json"]
    else:
        cmd = [binary, "render", *case_args, "--width", str(args.render_size), "--height",
               str(args.render_size), "--threads", str(args.threads), "--out", "/tmp/co.png",
               "--stats", base + ".json"]
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    if kind == "anchor":
        with open(base + ".json", "w") as f:
            f.write(out)
    return {"case": case, "build": build, "pair": pair, "loadavg_1min": float(load),
            "command": " ".join(cmd), "utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def run_all(args):
    os.makedirs(os.path.join(args.out, "raw"), exist_ok=True)
    log_path = os.path.join(args.out, "runs.jsonl")
    cases = args.cases or list(CASES)
    with open(log_path, "a") as log:
        for pair in range(args.first_pair, args.first_pair + args.pairs):
            order = [("on", args.on), ("off", args.off)]
            if pair % 2:
                order.reverse()
            for case in cases:
                for build, binary in order:
                    rec = run_one(binary, case, build, pair, args)
                    log.write(json.dumps(rec) + "\n")
                    log.flush()
                    print(f"pair {pair} {case} {build} load {rec['loadavg_1min']}", flush=True)


def anchor_rates(j, ray_set):
    """(ours, ours/embree) in rays per second for one anchor JSON and ray set."""
    c = j[ray_set] if "mesh" in j else j["candidates"][0][ray_set]
    return c["mrays_per_s"], c["references"][0]["ratio"]


def counts(j):
    """The operation counts a run reported (render stats, or anchor's first ray set's work)."""
    if "counters" in j:
        return j["counters"]
    first = j if "mesh" in j else j["candidates"][0]
    return first["primary"].get("work_per_ray") or {}


def check_counting(j, case, pair):
    if not counts(j["on"]) or counts(j["off"]):
        sys.exit(f"counter_overhead: pair {pair} of {case}: the ON run must count and the OFF run "
                 "must not (is --off built with -DPCRT_COUNTERS=OFF?)")


def pair_ratios(out, case, pair):
    """{ray set: (normalised ON/OFF time ratio, raw ratio)} of one pair, None if incomplete."""
    files = {b: os.path.join(out, "raw", f"{case}_{b}_{pair}.json") for b in ("on", "off")}
    if not all(os.path.exists(p) for p in files.values()):
        return None
    j = {b: json.load(open(p)) for b, p in files.items()}
    check_counting(j, case, pair)
    if CASES[case][0] == "render":
        t = {b: j[b]["timings"]["render"] for b in j}
        return {"frame": (t["on"] / t["off"], t["on"] / t["off"])}
    res = {}
    for s in RAY_SETS:
        (r_on, q_on), (r_off, q_off) = anchor_rates(j["on"], s), anchor_rates(j["off"], s)
        res[s] = (q_off / q_on, r_off / r_on)
    return res


def quartiles(v):
    if len(v) < 4:
        return min(v), max(v)
    q = statistics.quantiles(v, n=4, method="inclusive")
    return q[0], q[2]


def median_ci(v):
    """A distribution-free 95% confidence interval of the median: order statistics k and n-1-k,
    k the largest with P(Binomial(n, 1/2) <= k) <= 2.5%; None below 6 pairs (no such k)."""
    n, v = len(v), sorted(v)
    cdf, k = 0.0, -1
    for i in range(n):
        cdf += math.comb(n, i) / 2**n
        if cdf > 0.025:
            break
        k = i
    return (v[k], v[n - 1 - k]) if k >= 0 else None


def summary_rows(out):
    runs = [json.loads(line) for line in open(os.path.join(out, "runs.jsonl"))]
    rows = []
    for case in CASES:
        pairs = sorted({r["pair"] for r in runs if r["case"] == case})
        per = [p for p in (pair_ratios(out, case, k) for k in pairs) if p]
        loads = [r["loadavg_1min"] for r in runs if r["case"] == case]
        for s in (per[0].keys() if per else []):
            norm = [p[s][0] for p in per]
            raw = [p[s][1] for p in per]
            rows.append({"case": case, "rays": s, "pairs": len(per),
                         "median": statistics.median(norm), "min": min(norm), "max": max(norm),
                         "iqr": quartiles(norm), "ci95": median_ci(norm),
                         "raw_median": statistics.median(raw),
                         "raw_min": min(raw), "raw_max": max(raw),
                         "load": (min(loads), statistics.median(loads), max(loads))})
    return rows


def pct(x):
    return f"{(x - 1) * 100:+.1f}%"


def markdown(rows):
    lines = ["| case | rays | pairs | overhead, median | 95% CI of median | IQR | min .. max "
             "| raw median (min .. max) | load avg min / median / max |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ci = f"{pct(r['ci95'][0])} .. {pct(r['ci95'][1])}" if r["ci95"] else "-"
        lines.append(
            f"| {r['case']} | {r['rays']} | {r['pairs']} | {pct(r['median'])} | {ci} | "
            f"{pct(r['iqr'][0])} .. {pct(r['iqr'][1])} | {pct(r['min'])} .. {pct(r['max'])} | "
            f"{pct(r['raw_median'])} ({pct(r['raw_min'])} .. {pct(r['raw_max'])}) | "
            f"{r['load'][0]:.2f} / {r['load'][1]:.2f} / {r['load'][2]:.2f} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--on", default="build/bin/pcrt", help="pcrt with counters (default build)")
    ap.add_argument("--off", default="build-nocount/bin/pcrt", help="pcrt built -DPCRT_COUNTERS=OFF")
    ap.add_argument("--out", default="results/anchor/counters")
    ap.add_argument("--pairs", type=int, default=7)
    ap.add_argument("--first-pair", type=int, default=0, help="index of the first pair (to add)")
    ap.add_argument("--reps", type=int, default=7, help="anchor's passes per run")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--render-size", type=int, default=256)
    ap.add_argument("--cases", nargs="*", choices=list(CASES), help="default: all")
    ap.add_argument("--summary-only", action="store_true")
    args = ap.parse_args()
    if not args.summary_only:
        run_all(args)
    rows = summary_rows(args.out)
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print(markdown(rows))


if __name__ == "__main__":
    sys.exit(main())
