#!/usr/bin/env bash
# Hubo et al.'s compression against the uncompressed method (issue 16): for each variant
# (hubo_2006 with quantized=0 and =1, hubo_2007 with compressed=0 and =1), its accuracy against exact surfaces (`pcrt accuracy`: the
# generated sphere and torus, and the bunny mesh sampled by area) and, on a real scan without a
# true surface (CGAL's building.ply), the hits of the two variants on the same rays compared with
# each other (`pcrt trace`), with, for scale, how far the uncompressed method's hits move when only
# its structure changes. Writes OUT/accuracy.jsonl, OUT/trace_pairs.json and OUT/summary.md.
# Usage: scripts/hubo_compression.sh OUT [build/bin/pcrt] [DATA_DIR]
set -euo pipefail
out=$1
pcrt=${2:-build/bin/pcrt}
data=${3:-data}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
: >"$out/accuracy.jsonl"
variants=("hubo_2006 quantized=0" "hubo_2006 quantized=1" "hubo_2007 compressed=0"
  "hubo_2007 compressed=1")
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
# Per method: 0 uncompressed on its structure, 1 compressed, 2 uncompressed on another structure
# (how much the hits move when only the leaves the search runs in change, for scale).
trace() {  # METHOD TAG ARGS...
  local m=$1 tag=$2
  shift 2
  "$pcrt" trace --method "$m" "$@" --data "$scan" --rays "$tmp/rays.csv" --out "$tmp/hits_$tag.csv" \
    --threads 2 --stats "$tmp/trace_$tag.json" >/dev/null
}
trace hubo_2006 hubo_2006_0 --set quantized=0
trace hubo_2006 hubo_2006_1 --set quantized=1
trace hubo_2006 hubo_2006_2 --set quantized=0 --structure octree
trace hubo_2007 hubo_2007_0 --set compressed=0
trace hubo_2007 hubo_2007_1 --set compressed=1
trace hubo_2007 hubo_2007_2 --set compressed=0 --structure kd_tree
# hubo_2007's loss against the number of representatives, up to one per patch (the codec alone).
patches=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["prepare_counters"]["implicit_patches"])' "$tmp/trace_hubo_2007_1.json")
for k in 2048 "$patches"; do
  trace hubo_2007 "codebook_$k" --set compressed=1 --set codebook="$k"
done
echo "$patches" >"$tmp/patches"
/usr/bin/python3 - "$tmp" "$out/trace_pairs.json" "$scan" <<'PY'
import json, sys
from pathlib import Path
import numpy as np
tmp, out, scan = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
info = json.loads((tmp / "info.json").read_text())
h = info["mean_spacing"]
def pair(a, b):
    both = (a["hit"] == 1) & (b["hit"] == 1)
    dt = np.abs(a["t"][both] - b["t"][both]) / h
    na = np.stack([a["nx"], a["ny"], a["nz"]], 1)[both]
    nb = np.stack([b["nx"], b["ny"], b["nz"]], 1)[both]
    ang = np.degrees(np.arccos(np.clip(np.abs(np.sum(na * nb, 1)), -1, 1)))
    return {"hits": [int(a["hit"].sum()), int(b["hit"].sum())],
            "hit_only_one": int(((a["hit"] == 1) != (b["hit"] == 1)).sum()),
            "dt_h_median": float(np.median(dt)), "dt_h_p95": float(np.percentile(dt, 95)),
            "dt_h_p99": float(np.percentile(dt, 99)), "dt_over_1h": int((dt > 1).sum()),
            "normal_deg_median": float(np.median(ang)),
            "normal_deg_p95": float(np.percentile(ang, 95))}
res = {"data": scan, "h": h, "points": int(info["points"])}
for m, other in (("hubo_2006", "octree"), ("hubo_2007", "kd_tree")):
    hits = [np.genfromtxt(tmp / f"hits_{m}_{q}.csv", delimiter=",", names=True) for q in (0, 1, 2)]
    stats = [json.loads((tmp / f"trace_{m}_{q}.json").read_text()) for q in (0, 1, 2)]
    res["rays"] = int(len(hits[0]))
    res[m] = {"compressed_vs_uncompressed": pair(hits[0], hits[1]),
              "uncompressed_other_structure": other,
              "other_structure_vs_uncompressed": pair(hits[0], hits[2]),
              "prepare_counters": [s["prepare_counters"] for s in stats[:2]],
              "structure_bytes": [s.get("structure_bytes") for s in stats[:2]],
              "counters": [s["counters"] for s in stats[:2]]}
patches = int((tmp / "patches").read_text())
res["hubo_2007"]["codebook_sweep"] = {
    str(k): pair(hits0, np.genfromtxt(tmp / f"hits_codebook_{k}.csv", delimiter=",", names=True))
    for hits0 in [np.genfromtxt(tmp / "hits_hubo_2007_0.csv", delimiter=",", names=True)]
    for k in (2048, patches)}
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
def sentence(p, what):
    return (f"{what}: hits {p['hits'][0]} and {p['hits'][1]}, {p['hit_only_one']} rays hit in one only; "
            f"|t difference| median {p['dt_h_median']:.4f} h, p95 {p['dt_h_p95']:.4f} h, p99 {p['dt_h_p99']:.3f} h, "
            f"{p['dt_over_1h']} rays over 1 h; normal difference median {p['normal_deg_median']:.3f}, "
            f"p95 {p['normal_deg_p95']:.3f} degrees.")
lines += ["", f"Real scan {t['data']} ({t['rays']} rays, h = {t['h']:.4f}), the same rays traced by each variant:", ""]
for m in ("hubo_2006", "hubo_2007"):
    r = t[m]
    lines += ["* " + sentence(r["compressed_vs_uncompressed"], f"{m} uncompressed vs compressed"),
              "* " + sentence(r["other_structure_vs_uncompressed"],
                              f"for scale, {m} uncompressed vs uncompressed on {r['uncompressed_other_structure']}")]
for k, p in t["hubo_2007"]["codebook_sweep"].items():
    lines += ["* " + sentence(p, f"hubo_2007 uncompressed vs compressed with codebook={k}")]
pc = [t[m]["prepare_counters"][1] for m in ("hubo_2006", "hubo_2007")]
lines += ["", f"Compressed, held per point on it: hubo_2006 quantized kd-tree {pc[0]['qkd_bytes'] / t['points']:.1f} B "
          f"(qkd_bytes), hubo_2007 instances, representatives and patch spheres "
          f"{pc[1]['codebook_bytes'] / t['points']:.1f} B (codebook_bytes, {pc[1]['implicit_patches']} patches)."]
(out / "summary.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
PY
