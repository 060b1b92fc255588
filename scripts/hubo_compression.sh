#!/usr/bin/env bash
# Hubo et al.'s compression against the uncompressed method (issue 16): for each variant
# (hubo_2006 with quantized=0 and =1), its accuracy against exact surfaces (`pcrt accuracy`: the
# generated sphere and torus, and the bunny mesh sampled by area) and, on a real scan without a
# true surface (CGAL's building.ply), the hits of the two variants on the same rays compared with
# each other (`pcrt trace`), with what each variant holds there: the quantized kd-tree's bytes
# (prepare counter qkd_bytes) and the uncompressed kd-tree's structure_bytes.
# Writes OUT/accuracy.jsonl, OUT/trace_pairs.json and OUT/summary.md.
# Usage: scripts/hubo_compression.sh OUT [build/bin/pcrt] [DATA_DIR]
set -euo pipefail
out=$1
pcrt=${2:-build/bin/pcrt}
data=${3:-data}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
: >"$out/accuracy.jsonl"
variants=("hubo_2006 quantized=0" "hubo_2006 quantized=1")
accuracy() {  # LABEL ARGS...
  local label=$1
  shift
  for v in "${variants[@]}"; do
    read -r m set <<<"$v"
    "$pcrt" accuracy --method "$m" --set "$set" "$@" --rays 20000 --seed 1 --threads 2 --json \
      >"$tmp/acc.json"
    /usr/bin/python3 - "$tmp" "$label" "$m" "$set" >>"$out/accuracy.jsonl" <<'PY'
import json, sys
from pathlib import Path
tmp, label, m, s = Path(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
acc = json.loads((tmp / "acc.json").read_text())
print(json.dumps({"data": label, "method": m, "set": s, "accuracy": acc}))
PY
  done
}
accuracy "sphere:n=100000" --data sphere:n=100000,seed=1
accuracy "torus:n=100000" --data torus:n=100000,seed=1
accuracy "bunny.off n=100000" --truth "$data/bunny/bunny.off" --sample n=100000,seed=1

# The real scan: the same rays traced by both variants.
scan=$data/cgal/points_3/building.ply
"$pcrt" info "$scan" --json >"$tmp/info.json"
/usr/bin/python3 - "$tmp/info.json" "$tmp/rays.csv" <<'PY'
import json, sys
import numpy as np
info = json.load(open(sys.argv[1]))
lo, hi = np.array(info["bounds"]["min"]), np.array(info["bounds"]["max"])
c, r = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
rng = np.random.default_rng(1)
n = 20000
o = rng.normal(size=(n, 3))
o = c + 1.5 * r * o / np.linalg.norm(o, axis=1, keepdims=True)
target = lo + (hi - lo) * (0.2 + 0.6 * rng.random((n, 3)))
d = target - o
d /= np.linalg.norm(d, axis=1, keepdims=True)
np.savetxt(sys.argv[2], np.hstack([o, d]), delimiter=",", header="ox,oy,oz,dx,dy,dz",
           comments="", fmt="%.7g")
PY
for q in 0 1; do
  "$pcrt" trace --method hubo_2006 --set quantized=$q --data "$scan" --rays "$tmp/rays.csv" \
    --out "$tmp/hits$q.csv" --threads 2 --stats "$tmp/trace$q.json" >/dev/null
done
/usr/bin/python3 - "$tmp" "$out/trace_pairs.json" "$scan" <<'PY'
import json, sys
from pathlib import Path
import numpy as np
tmp, out, scan = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
h = json.loads((tmp / "info.json").read_text())["mean_spacing"]
a = np.genfromtxt(tmp / "hits0.csv", delimiter=",", names=True)
b = np.genfromtxt(tmp / "hits1.csv", delimiter=",", names=True)
both = (a["hit"] == 1) & (b["hit"] == 1)
dt = np.abs(a["t"][both] - b["t"][both]) / h
na = np.stack([a["nx"], a["ny"], a["nz"]], 1)[both]
nb = np.stack([b["nx"], b["ny"], b["nz"]], 1)[both]
ang = np.degrees(np.arccos(np.clip(np.abs(np.sum(na * nb, 1)), -1, 1)))
stats = [json.loads((tmp / f"trace{q}.json").read_text()) for q in (0, 1)]
res = {"data": scan, "rays": int(len(a)), "h": h,
       "hits_uncompressed": int(a["hit"].sum()), "hits_quantized": int(b["hit"].sum()),
       "hit_only_one": int(((a["hit"] == 1) != (b["hit"] == 1)).sum()),
       "dt_h_median": float(np.median(dt)), "dt_h_p95": float(np.percentile(dt, 95)),
       "dt_h_p99": float(np.percentile(dt, 99)), "dt_over_1h": int((dt > 1).sum()),
       "normal_deg_median": float(np.median(ang)), "normal_deg_p95": float(np.percentile(ang, 95)),
       "points": int(json.loads((tmp / "info.json").read_text())["points"]),
       "qkd_bytes": stats[1]["prepare_counters"].get("qkd_bytes"),
       "structure_bytes_uncompressed": stats[0].get("structure_bytes"),
       "counters": [s["counters"] for s in stats]}
out.write_text(json.dumps(res, indent=1) + "\n")
PY

/usr/bin/python3 - "$out" <<'PY'
import json, sys
from pathlib import Path
out = Path(sys.argv[1])
rows = [json.loads(l) for l in (out / "accuracy.jsonl").read_text().splitlines() if l.strip()]
lines = ["| data | variant | holes % | see-through % | false hits % | distance median (h) | p95 (h) | normal median (deg) | p95 (deg) |",
         "|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    a = r["accuracy"]
    lines.append(f"| {r['data']} | {r['set']} | {100*a['hole_rate']:.3f} | {100*a.get('see_through_rate', 0):.3f} | "
                 f"{100*a['false_hit_rate']:.3f} | {a['distance_median_h']:.4f} | {a['distance_p95_h']:.4f} | "
                 f"{a['normal_median_deg']:.3f} | {a['normal_p95_deg']:.3f} |")
t = json.loads((out / "trace_pairs.json").read_text())
# The uncompressed method's splat layout per point (methods/kernels/splat_set.hpp): point index 4,
# centre 12, normal 12, radius 4, half extents 12, packed record 32.
layout = 4 + 12 + 12 + 4 + 12 + 32
lines += ["", f"Real scan {t['data']} ({t['rays']} rays, h = {t['h']:.4f}): hits {t['hits_uncompressed']} "
          f"uncompressed, {t['hits_quantized']} quantized, {t['hit_only_one']} rays hit in one only; "
          f"|t difference| median {t['dt_h_median']:.4f} h, p95 {t['dt_h_p95']:.4f} h, p99 {t['dt_h_p99']:.4f} h, "
          f"{t['dt_over_1h']} rays over 1 h; normal difference median {t['normal_deg_median']:.3f}, "
          f"p95 {t['normal_deg_p95']:.3f} degrees.",
          "", f"Held on it per point: quantized kd-tree {t['qkd_bytes'] / t['points']:.1f} B "
          f"(qkd_bytes); uncompressed splat layout {layout} B + kd-tree "
          f"{t['structure_bytes_uncompressed'] / t['points']:.1f} B (structure_bytes)."]
(out / "summary.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
PY
