"""Python's Scene.trace against `pcrt trace` on the same 10^6 rays (issue 18): passes alternated,
three each; Python's time is the whole call (array conversion in and out included), the CLI's is
its "trace" timer (CSV parsing and writing excluded). Writes results/python/trace_timing.json.

    PYTHONPATH=build/python /usr/bin/python3 scripts/python_trace_timing.py [build/bin/pcrt]
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import pcrt

exe = sys.argv[1] if len(sys.argv) > 1 else "build/bin/pcrt"
data, method, structure, n = "sphere:n=1000000", "reference_splat", "kd_tree", 1_000_000
rng = np.random.default_rng(1)
o = rng.normal(size=(n, 3))
o = (3 * o / np.linalg.norm(o, axis=1, keepdims=True)).astype(np.float32)
d = (rng.normal(scale=0.4, size=(n, 3)) - o).astype(np.float32)
tmp = tempfile.mkdtemp()
rays, hits, stats = (os.path.join(tmp, f) for f in ("rays.csv", "hits.csv", "stats.json"))
with open(rays, "w") as f:
    f.write("ox,oy,oz,dx,dy,dz\n")
    np.savetxt(f, np.hstack([o, d]), fmt="%.9g", delimiter=",")
scene = pcrt.Scene(pcrt.load(data), method=method, structure=structure)
py, cli = [], []
for _ in range(3):
    start = time.perf_counter()
    result = scene.trace(o, d)
    py.append(time.perf_counter() - start)
    subprocess.run([exe, "trace", "--method", method, "--structure", structure, "--data", data,
                    "--rays", rays, "--out", hits, "--stats", stats], check=True,
                   capture_output=True)
    cli.append(json.load(open(stats))["timings"]["trace"])
out = {"data": data, "method": method, "structure": structure, "rays": n,
       "python_s": py, "cli_trace_s": cli, "python_median_s": sorted(py)[1],
       "cli_median_s": sorted(cli)[1], "hit_fraction": float(result["hit"].mean()),
       "counters_equal": scene.counters == json.load(open(stats))["counters"],
       "load_average": os.getloadavg()[0]}
os.makedirs("results/python", exist_ok=True)
json.dump(out, open("results/python/trace_timing.json", "w"), indent=1)
print(json.dumps(out))
